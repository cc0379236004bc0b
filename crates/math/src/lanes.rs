//! Rays and vectors in the lanes of a [`Simd`] instruction set: a packet's
//! rays one vector per coordinate, and the vector arithmetic the bodies'
//! lane forms and the packet tracer share. Each helper computes exactly what
//! glam computes for one ray (the same operations in the same order), so a
//! lane's answer is bit for bit the scalar one.

use crate::simd::Simd;
use crate::{Aabb, DMat3, DVec3};

/// The widest packet of any instruction set.
pub const MAX_LANES: usize = 8;

/// The rays of a packet, one vector per coordinate.
pub struct Lanes<S: Simd> {
    /// Origins.
    pub o: [S::F; 3],
    /// Unit directions.
    pub d: [S::F; 3],
    /// Reciprocals of the directions.
    pub inv: [S::F; 3],
}

/// `a · b` as glam computes it: `(x + y) + z`.
#[inline(always)]
pub fn dot<S: Simd>(s: S, a: [S::F; 3], b: [S::F; 3]) -> S::F {
    s.add(
        s.add(s.mul(a[0], b[0]), s.mul(a[1], b[1])),
        s.mul(a[2], b[2]),
    )
}

/// `a × b` as glam computes it.
#[inline(always)]
pub fn cross<S: Simd>(s: S, a: [S::F; 3], b: [S::F; 3]) -> [S::F; 3] {
    [
        s.sub(s.mul(a[1], b[2]), s.mul(b[1], a[2])),
        s.sub(s.mul(a[2], b[0]), s.mul(b[2], a[0])),
        s.sub(s.mul(a[0], b[1]), s.mul(b[0], a[1])),
    ]
}

/// `m v` as glam computes it: the columns scaled by `v`'s coordinates and
/// added left to right.
#[inline(always)]
pub fn mat_vec<S: Simd>(s: S, m: &DMat3, v: [S::F; 3]) -> [S::F; 3] {
    let (x, y, z) = (m.x_axis, m.y_axis, m.z_axis);
    [
        row(s, x.x, y.x, z.x, v),
        row(s, x.y, y.y, z.y, v),
        row(s, x.z, y.z, z.z, v),
    ]
}

/// One coordinate of [`mat_vec`].
#[inline(always)]
fn row<S: Simd>(s: S, a: f64, b: f64, c: f64, v: [S::F; 3]) -> S::F {
    s.add(
        s.add(s.mul(s.splat(a), v[0]), s.mul(s.splat(b), v[1])),
        s.mul(s.splat(c), v[2]),
    )
}

/// `v.normalize()` as glam computes it: `v` times one over its length.
#[inline(always)]
pub fn normalize<S: Simd>(s: S, v: [S::F; 3]) -> [S::F; 3] {
    let r = s.div(s.splat(1.0), s.sqrt(dot(s, v, v)));
    [s.mul(v[0], r), s.mul(v[1], r), s.mul(v[2], r)]
}

/// `p - c` in every lane.
#[inline(always)]
pub fn sub_point<S: Simd>(s: S, p: [S::F; 3], c: DVec3) -> [S::F; 3] {
    [
        s.sub(p[0], s.splat(c.x)),
        s.sub(p[1], s.splat(c.y)),
        s.sub(p[2], s.splat(c.z)),
    ]
}

/// `a + b t` in every lane.
#[inline(always)]
pub fn along<S: Simd>(s: S, a: [S::F; 3], b: [S::F; 3], t: S::F) -> [S::F; 3] {
    [
        s.add(a[0], s.mul(b[0], t)),
        s.add(a[1], s.mul(b[1], t)),
        s.add(a[2], s.mul(b[2], t)),
    ]
}

/// `a - b t` in every lane.
#[inline(always)]
pub fn back<S: Simd>(s: S, a: [S::F; 3], b: [S::F; 3], t: S::F) -> [S::F; 3] {
    [
        s.sub(a[0], s.mul(b[0], t)),
        s.sub(a[1], s.mul(b[1], t)),
        s.sub(a[2], s.mul(b[2], t)),
    ]
}

/// A point or vector in every lane.
#[inline(always)]
pub fn splat3<S: Simd>(s: S, v: DVec3) -> [S::F; 3] {
    [s.splat(v.x), s.splat(v.y), s.splat(v.z)]
}

/// Lanes not set in `m`.
#[inline(always)]
pub fn not<S: Simd>(s: S, m: S::M) -> S::M {
    s.andnot(s.mask(u32::MAX), m)
}

/// Lanes whose value is not a number.
#[inline(always)]
pub fn nan<S: Simd>(s: S, x: S::F) -> S::M {
    not(s, s.eq(x, x))
}

/// `x.min(y)` as `f64::min` computes it: a number beats one that is not.
#[inline(always)]
pub fn min_num<S: Simd>(s: S, x: S::F, y: S::F) -> S::F {
    s.select(nan(s, x), y, s.select(nan(s, y), x, s.min(x, y)))
}

/// `x.max(y)` as `f64::max` computes it: a number beats one that is not.
#[inline(always)]
pub fn max_num<S: Simd>(s: S, x: S::F, y: S::F) -> S::F {
    s.select(nan(s, x), y, s.select(nan(s, y), x, s.max(x, y)))
}

/// `x.clamp(lo, hi)` as `f64::clamp` computes it, for `lo <= hi`: `lo`
/// where `x` is below it, then `hi` where above.
#[inline(always)]
pub fn clamp<S: Simd>(s: S, x: S::F, lo: S::F, hi: S::F) -> S::F {
    let x = s.select(s.lt(x, lo), lo, x);
    s.select(s.gt(x, hi), hi, x)
}

/// [`Aabb::ray_range`] of `b` in every lane, for the rays `o + t·d`,
/// operation for operation: each lane's range, and the lanes that meet
/// the box.
#[inline(always)]
pub fn ray_range_lanes<S: Simd>(s: S, b: &Aabb, o: [S::F; 3], d: [S::F; 3]) -> (S::F, S::F, S::M) {
    let (zero, one) = (s.splat(0.0), s.splat(1.0));
    let mut t0 = s.splat(f64::NEG_INFINITY);
    let mut t1 = s.splat(f64::INFINITY);
    let mut miss = s.none();
    for a in 0..3 {
        let (low, high) = (s.splat(b.min[a]), s.splat(b.max[a]));
        let level = s.eq(d[a], zero);
        let outside = s.or(s.lt(o[a], low), s.gt(o[a], high));
        miss = s.or(miss, s.and(level, outside));
        let inv = s.div(one, d[a]);
        let ta = s.mul(s.sub(low, o[a]), inv);
        let tb = s.mul(s.sub(high, o[a]), inv);
        let swap = s.gt(ta, tb);
        let (ta, tb) = (s.select(swap, tb, ta), s.select(swap, ta, tb));
        t0 = s.select(level, t0, max_num(s, t0, ta));
        t1 = s.select(level, t1, min_num(s, t1, tb));
    }
    (t0, t1, s.andnot(not(s, s.gt(t0, t1)), miss))
}

/// The lanes whose rays meet `b` within `[tmin, tmax]`: the slab test of
/// the hierarchy's box test for one ray (sv-trace's `hits`), operation for
/// operation.
#[inline(always)]
pub fn box_lanes<S: Simd>(s: S, b: &Aabb, r: &Lanes<S>, tmin: S::F, tmax: S::F) -> S::M {
    let (lo, hi) = (b.min.to_array(), b.max.to_array());
    slab_lanes(s, lo, hi, r, tmin, tmax).1
}

/// The slab test of the box `lo`..`hi` in every lane: each lane's entry
/// (the greatest of `tmin` and the slabs' near ends) and the lanes whose
/// ray meets the box within `[tmin, tmax]`.
#[inline(always)]
pub fn slab_lanes<S: Simd>(
    s: S,
    lo: [f64; 3],
    hi: [f64; 3],
    r: &Lanes<S>,
    tmin: S::F,
    tmax: S::F,
) -> (S::F, S::M) {
    let mut t0 = tmin;
    let mut t1 = tmax;
    for a in 0..3 {
        let x0 = s.mul(s.sub(s.splat(lo[a]), r.o[a]), r.inv[a]);
        let x1 = s.mul(s.sub(s.splat(hi[a]), r.o[a]), r.inv[a]);
        t0 = s.max(s.min(x0, x1), t0);
        t1 = s.min(s.max(x0, x1), t1);
    }
    (t0, s.le(t0, t1))
}
