use super::poly::{quadratic_roots_in_lanes, quartic_roots_lanes, roots_in};
use super::SegLanes;
use super::Shape;
use super::{segments_by_classification, Seg};
use crate::body::{independent, nonzero, positive, with_bounds, Warning};
use crate::Body;
use sv_math::lanes::{
    along, dot, mat_vec, max_num, min_num, normalize, not, ray_range_lanes, sub_point, Lanes,
};
use sv_math::orthonormal_basis;
use sv_math::simd::Simd;
use sv_math::{Aabb, DMat3, DVec3, Ray};

/// Face numbers of cones.
pub(crate) const LATERAL: u32 = 0;
pub(crate) const BASE: u32 = 1;
pub(crate) const TOP: u32 = 2;

/// Bounds of the ellipse `c + a cosφ + b sinφ`.
fn ellipse_bounds(c: DVec3, a: DVec3, b: DVec3) -> Aabb {
    let e = DVec3::new(a.x.hypot(b.x), a.y.hypot(b.y), a.z.hypot(b.z));
    Aabb::new(c - e, c + e)
}

/// [`Frame::slab`]'s answer in every lane: entry, exit, their faces, and
/// the lanes that miss.
type SlabLanes<S> = (
    <S as Simd>::F,
    <S as Simd>::F,
    <S as Simd>::F,
    <S as Simd>::F,
    <S as Simd>::M,
);

/// Local frame shared by the cones: `x = v + M p` with the base semi-axes
/// and the height vector as the columns of `M`, so the base is the unit
/// disc at `p.z = 0` and the top lies at `p.z = 1`.
#[derive(Clone, Debug)]
struct Frame {
    v: DVec3,
    m: DMat3,
    inv: DMat3,
    inv_t: DMat3,
}

impl Frame {
    fn new(v: DVec3, a: DVec3, b: DVec3, h: DVec3) -> Frame {
        let m = DMat3::from_cols(a, b, h);
        let inv = m.inverse();
        Frame {
            v,
            m,
            inv,
            inv_t: inv.transpose(),
        }
    }

    #[inline]
    fn local(&self, ray: &Ray) -> (DVec3, DVec3) {
        (self.inv * (ray.origin - self.v), self.inv * ray.dir)
    }

    /// Parameter range inside the slab `0 <= z <= 1`, with entry/exit faces.
    #[inline]
    fn slab(o: DVec3, d: DVec3) -> Option<(f64, f64, u32, u32)> {
        if d.z == 0.0 {
            if o.z < 0.0 || o.z > 1.0 {
                return None;
            }
            return Some((f64::NEG_INFINITY, f64::INFINITY, LATERAL, LATERAL));
        }
        let ta = -o.z / d.z;
        let tb = (1.0 - o.z) / d.z;
        Some(if d.z > 0.0 {
            (ta, tb, BASE, TOP)
        } else {
            (tb, ta, TOP, BASE)
        })
    }

    /// [`Frame::slab`] in every lane: the range, its faces, and the lanes
    /// that miss the slab.
    #[inline(always)]
    fn slab_lanes<S: Simd>(s: S, o: [S::F; 3], d: [S::F; 3]) -> SlabLanes<S> {
        let (zero, one) = (s.splat(0.0), s.splat(1.0));
        let (inf, ninf) = (s.splat(f64::INFINITY), s.splat(f64::NEG_INFINITY));
        let (lat, base, top) = (
            s.splat(f64::from(LATERAL)),
            s.splat(f64::from(BASE)),
            s.splat(f64::from(TOP)),
        );
        let flat = s.eq(d[2], zero);
        let miss = s.and(flat, s.or(s.lt(o[2], zero), s.gt(o[2], one)));
        if s.all(flat) {
            // Every ray runs across the axis, as a grid's rays do across
            // an upright cylinder: the ends are never crossed, and the
            // divisions for them would be thrown away.
            return (ninf, inf, lat, lat, miss);
        }
        let ta = s.div(s.neg(o[2]), d[2]);
        let tb = s.div(s.sub(one, o[2]), d[2]);
        let up = s.gt(d[2], zero);
        (
            s.select(flat, ninf, s.select(up, ta, tb)),
            s.select(flat, inf, s.select(up, tb, ta)),
            s.select(flat, lat, s.select(up, base, top)),
            s.select(flat, lat, s.select(up, top, base)),
            miss,
        )
    }

    fn world_normal(&self, g: DVec3) -> DVec3 {
        (self.inv_t * g).normalize()
    }

    /// [`Frame::world_normal`] in every lane of faces `face` (as `f64`):
    /// the caps' gradients, and `lateral` on the lateral surface.
    #[inline(always)]
    fn normal_lanes<S: Simd>(&self, s: S, face: S::F, lateral: [S::F; 3]) -> [S::F; 3] {
        // `-DVec3::Z` is (-0, -0, -1): its zeros' signs kept.
        let (base, top) = (
            s.eq(face, s.splat(f64::from(BASE))),
            s.eq(face, s.splat(f64::from(TOP))),
        );
        let g = [
            s.select(base, s.splat(-0.0), s.select(top, s.splat(0.0), lateral[0])),
            s.select(base, s.splat(-0.0), s.select(top, s.splat(0.0), lateral[1])),
            s.select(base, s.splat(-1.0), s.select(top, s.splat(1.0), lateral[2])),
        ];
        normalize(s, mat_vec(s, &self.inv_t, g))
    }

    fn bounds(&self, ra: f64, rb: f64) -> Aabb {
        let (a, b, h) = (self.m.x_axis, self.m.y_axis, self.m.z_axis);
        ellipse_bounds(self.v, a, b).union(&ellipse_bounds(self.v + h, a * ra, b * rb))
    }
}

/// A truncated cone whose top ellipse is the base ellipse scaled by `ratio`
/// (RCC, REC, TRC, TEC; a TGC with equal axis ratios). Convex.
#[derive(Clone, Debug)]
pub struct Cone {
    f: Frame,
    /// `ratio - 1`: the cross-section at height z is scaled by `1 + k z`.
    k: f64,
}

impl Cone {
    /// Base centre `v`, base semi-axes `a`, `b`, height `h`, and the ratio of
    /// the top axes to the base axes.
    pub fn new(v: DVec3, a: DVec3, b: DVec3, h: DVec3, ratio: f64) -> Cone {
        Cone {
            f: Frame::new(v, a, b, h),
            k: ratio - 1.0,
        }
    }

    /// Corners of the parallelograms around its two end ellipses: their
    /// hull holds the cone.
    pub fn corners(&self) -> Vec<DVec3> {
        let (a, b, h) = (self.f.m.x_axis, self.f.m.y_axis, self.f.m.z_axis);
        let r = 1.0 + self.k;
        super::ends((self.f.v, a, b), (self.f.v + h, a * r, b * r))
    }

    /// Append the segments of the ray inside the body to `out` (see
    /// [`super::Shape::shoot`]).
    #[inline]
    pub fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        let (o, d) = self.f.local(ray);
        let Some((mut t0, mut t1, mut f0, mut f1)) = Frame::slab(o, d) else {
            return;
        };
        let Some((l0, l1)) = self.lateral(o, d, t0, t1) else {
            return;
        };
        if l0 > t0 {
            t0 = l0;
            f0 = LATERAL;
        }
        if l1 < t1 {
            t1 = l1;
            f1 = LATERAL;
        }
        if t0 < t1 {
            out.push(Seg { t0, t1, f0, f1 });
        }
    }

    /// [`Cone::shoot`] in every lane, operation for operation: the slab
    /// between base and top, then the lateral surface's cases, each lane
    /// taking the one its ray takes.
    #[inline(always)]
    pub fn shoot_lanes<S: Simd>(&self, s: S, r: &Lanes<S>) -> SegLanes<S> {
        let o = mat_vec(s, &self.f.inv, sub_point(s, r.o, self.f.v));
        let d = mat_vec(s, &self.f.inv, r.d);
        let (zero, one) = (s.splat(0.0), s.splat(1.0));
        let (inf, ninf) = (s.splat(f64::INFINITY), s.splat(f64::NEG_INFINITY));
        let lat = s.splat(f64::from(LATERAL));
        let (t0, t1, f0, f1, mut miss) = Frame::slab_lanes(s, o, d);
        // Cone::lateral.
        let k = self.k;
        let a = s.sub(
            s.add(s.mul(d[0], d[0]), s.mul(d[1], d[1])),
            s.mul(s.mul(s.splat(k * k), d[2]), d[2]),
        );
        let small = s.mul(s.splat(1e-12), dot(s, d, d));
        let cyl = if k == 0.0 { s.gt(a, small) } else { s.none() };
        let (mut l0, mut l1) = (zero, zero);
        let all = s.mask(u32::MAX);
        if s.any(cyl) {
            // A cylinder: the closest approach to the axis and half a chord.
            let inv = s.div(one, a);
            let tm = s.mul(s.neg(s.add(s.mul(o[0], d[0]), s.mul(o[1], d[1]))), inv);
            let fx = s.add(o[0], s.mul(d[0], tm));
            let fy = s.add(o[1], s.mul(d[1], tm));
            let disc = s.sub(one, s.add(s.mul(fx, fx), s.mul(fy, fy)));
            let h = s.sqrt(s.mul(disc, inv));
            l0 = s.sub(tm, h);
            l1 = s.add(tm, h);
            miss = s.or(miss, s.and(cyl, s.lt(disc, zero)));
        }
        let general = s.andnot(all, cyl);
        if s.any(general) {
            let kk = s.splat(k);
            let s0 = s.add(one, s.mul(kk, o[2]));
            let b = s.sub(
                s.add(s.mul(o[0], d[0]), s.mul(o[1], d[1])),
                s.mul(s.mul(kk, d[2]), s0),
            );
            let c = s.sub(s.add(s.mul(o[0], o[0]), s.mul(o[1], o[1])), s.mul(s0, s0));
            // Parallel to a generator: one crossing at most.
            let par = s.le(s.abs(a), small);
            let bz = s.eq(b, zero);
            let tp = s.div(s.neg(c), s.mul(s.splat(2.0), b));
            let bpos = s.gt(b, zero);
            let p0 = s.select(bz, ninf, s.select(bpos, ninf, tp));
            let p1 = s.select(bz, inf, s.select(bpos, tp, inf));
            let pmiss = s.and(bz, s.ge(c, zero));
            // Two roots.
            let disc = s.sub(s.mul(b, b), s.mul(a, c));
            let q = s.neg(s.add(b, s.copysign(s.sqrt(disc), b)));
            let qz = s.eq(q, zero);
            let r0 = s.select(qz, zero, s.div(q, a));
            let r1 = s.select(qz, zero, s.div(c, q));
            let ordered = s.lt(r0, r1);
            let (r0, r1) = (s.select(ordered, r0, r1), s.select(ordered, r1, r0));
            // Inside lies outside the roots when a < 0: within the slab only
            // the body's nappe exists, so keep the piece meeting it.
            let before = s.gt(r0, t0);
            let after = s.lt(r1, t1);
            let longer = s.ge(s.sub(r0, t0), s.sub(t1, r1));
            let lower = s.or(s.andnot(before, after), s.and(s.and(before, after), longer));
            let n0 = s.select(lower, ninf, r1);
            let n1 = s.select(lower, r0, inf);
            let nmiss = s.andnot(not(s, before), after);
            let open = s.gt(a, zero);
            let g0 = s.select(open, r0, n0);
            let g1 = s.select(open, r1, n1);
            let gmiss = s.or(s.lt(disc, zero), s.andnot(nmiss, open));
            l0 = s.select(general, s.select(par, p0, g0), l0);
            l1 = s.select(general, s.select(par, p1, g1), l1);
            let lmiss = s.or(s.and(par, pmiss), s.andnot(gmiss, par));
            miss = s.or(miss, s.and(general, lmiss));
        }
        let n0 = s.gt(l0, t0);
        let n1 = s.lt(l1, t1);
        let t0 = s.select(n0, l0, t0);
        let t1 = s.select(n1, l1, t1);
        SegLanes {
            t0,
            t1,
            f0: s.select(n0, lat, f0),
            f1: s.select(n1, lat, f1),
            hit: s.andnot(s.lt(t0, t1), miss),
            scalar: s.none(),
        }
    }

    /// The stretch of the local ray `o + t d` inside the lateral surface
    /// (infinite ends for a ray that stays inside), given its stretch
    /// `(t0, t1)` in the slab between base and top; `None` when it misses.
    #[inline(always)]
    fn lateral(&self, o: DVec3, d: DVec3, t0: f64, t1: f64) -> Option<(f64, f64)> {
        let k = self.k;
        let a = d.x * d.x + d.y * d.y - k * k * d.z * d.z;
        let scale = d.length_squared();
        if k == 0.0 && a > 1e-12 * scale {
            // A cylinder (RCC, REC): the closest approach of the ray's
            // projection to the axis, and half a chord either side, as for
            // a sphere: one division and one root.
            let inv = 1.0 / a;
            let tm = -(o.x * d.x + o.y * d.y) * inv;
            let (fx, fy) = (o.x + d.x * tm, o.y + d.y * tm);
            let disc = 1.0 - (fx * fx + fy * fy);
            if disc < 0.0 {
                return None;
            }
            let h = (disc * inv).sqrt();
            return Some((tm - h, tm + h));
        }
        let s0 = 1.0 + k * o.z;
        let b = o.x * d.x + o.y * d.y - k * d.z * s0;
        let c = o.x * o.x + o.y * o.y - s0 * s0;
        Some(if a.abs() <= 1e-12 * scale {
            // The ray runs parallel to a generator: one crossing at most.
            if b == 0.0 {
                if c >= 0.0 {
                    return None;
                }
                (f64::NEG_INFINITY, f64::INFINITY)
            } else {
                let t = -c / (2.0 * b);
                if b > 0.0 {
                    (f64::NEG_INFINITY, t)
                } else {
                    (t, f64::INFINITY)
                }
            }
        } else {
            let disc = b * b - a * c;
            if disc < 0.0 {
                return None;
            }
            let q = -(b + b.signum() * disc.sqrt());
            let (r0, r1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
            let (r0, r1) = if r0 < r1 { (r0, r1) } else { (r1, r0) };
            if a > 0.0 {
                (r0, r1)
            } else {
                // Inside is outside the roots; within the slab only the
                // nappe of the body exists, so keep the piece meeting it.
                let before = r0 > t0;
                let after = r1 < t1;
                match (before, after) {
                    (true, false) => (f64::NEG_INFINITY, r0),
                    (false, true) => (r1, f64::INFINITY),
                    (true, true) => {
                        // Both pieces reach the slab only through rounding
                        // near the apex: keep the longer one.
                        if r0 - t0 >= t1 - r1 {
                            (f64::NEG_INFINITY, r0)
                        } else {
                            (r1, f64::INFINITY)
                        }
                    }
                    (false, false) => return None,
                }
            }
        })
    }

    /// Outward unit normal at a point of the surface.
    pub fn normal(&self, face: u32, p: DVec3) -> DVec3 {
        match face {
            BASE => self.f.world_normal(-DVec3::Z),
            TOP => self.f.world_normal(DVec3::Z),
            _ => {
                let q = self.f.inv * (p - self.f.v);
                self.f
                    .world_normal(DVec3::new(q.x, q.y, -self.k * (1.0 + self.k * q.z)))
            }
        }
    }

    /// [`Cone::normal`] in every lane (faces held as `f64`), operation for
    /// operation: each lane takes its face's gradient.
    #[inline(always)]
    pub fn normal_lanes<S: Simd>(&self, s: S, face: S::F, p: [S::F; 3]) -> [S::F; 3] {
        let q = mat_vec(s, &self.f.inv, sub_point(s, p, self.f.v));
        let k = self.k;
        let z = s.mul(s.splat(-k), s.add(s.splat(1.0), s.mul(s.splat(k), q[2])));
        self.f.normal_lanes(s, face, [q[0], q[1], z])
    }

    /// True when `p` is strictly inside.
    pub fn contains(&self, p: DVec3) -> bool {
        let q = self.f.inv * (p - self.f.v);
        let s = 1.0 + self.k * q.z;
        q.z > 0.0 && q.z < 1.0 && q.x * q.x + q.y * q.y < s * s
    }

    /// Bounds (infinite sides where the body is unbounded).
    pub fn bounds(&self) -> Aabb {
        self.f.bounds(1.0 + self.k, 1.0 + self.k)
    }
}

/// A TGC whose top semi-axes are not in the base's proportion: the lateral
/// surface `x²/sa(z)² + y²/sb(z)² = 1` is a quartic along a ray and the
/// body need not be convex.
#[derive(Clone, Debug)]
pub struct GeneralCone {
    f: Frame,
    ka: f64,
    kb: f64,
}

/// Multiply polynomials (ascending powers) into `out`.
fn mul(a: &[f64], b: &[f64], out: &mut [f64]) {
    out.iter_mut().for_each(|v| *v = 0.0);
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
}

/// [`mul`] in every lane, operation for operation (the sums start from
/// zero, as `mul`'s do, which keeps their zeros' signs).
#[inline(always)]
fn mul_lanes<S: Simd, const A: usize, const C: usize>(
    s: S,
    a: &[S::F; A],
    b: &[S::F; A],
) -> [S::F; C] {
    let mut out = [s.splat(0.0); C];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] = s.add(out[i + j], s.mul(*x, *y));
        }
    }
    out
}

/// The lanes where `a` comes before `b` in `f64::total_cmp`'s order
/// (neither is a number that is not): below it, or `-0` against `+0`.
#[inline(always)]
fn sorts_before<S: Simd>(s: S, a: S::F, b: S::F) -> S::M {
    let one = s.splat(1.0);
    let zeros = s.and(s.eq(a, b), s.lt(s.copysign(one, a), s.copysign(one, b)));
    s.or(s.lt(a, b), zeros)
}

impl GeneralCone {
    /// Base centre `v`, base semi-axes `a`, `b`, height `h`; the top
    /// semi-axes are `a·ra` and `b·rb`.
    pub fn new(v: DVec3, a: DVec3, b: DVec3, h: DVec3, ra: f64, rb: f64) -> GeneralCone {
        GeneralCone {
            f: Frame::new(v, a, b, h),
            ka: ra - 1.0,
            kb: rb - 1.0,
        }
    }

    fn inside_local(&self, q: DVec3) -> bool {
        let sa = 1.0 + self.ka * q.z;
        let sb = 1.0 + self.kb * q.z;
        q.z > 0.0 && q.z < 1.0 && (q.x / sa).powi(2) + (q.y / sb).powi(2) < 1.0
    }

    /// Append the segments of the ray inside the body to `out` (see
    /// [`super::Shape::shoot`]).
    pub fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        self.shoot_with(ray, true, out);
    }

    /// The box of the two end ellipses in the local frame, which bounds
    /// the search for the lateral surface. z is left loose: the slab
    /// between the caps already bounds it, and a box face coinciding with
    /// a cap would steal its face label by rounding.
    fn local_box(&self) -> Aabb {
        let (ma, mb) = (m2(self.ka), m2(self.kb));
        Aabb::new(DVec3::new(-ma, -mb, -1.0), DVec3::new(ma, mb, 2.0))
    }

    /// [`GeneralCone::shoot`], passing the quartic over for rays along
    /// the axis that cannot cross the lateral surface when `quick`.
    fn shoot_with(&self, ray: &Ray, quick: bool, out: &mut Vec<Seg>) {
        let (o, d) = self.f.local(ray);
        let Some((t0, t1, f0, f1)) = Frame::slab(o, d) else {
            return;
        };
        let lb = self.local_box();
        let lray = Ray {
            origin: o,
            dir: d,
            inv_dir: d.recip(),
        };
        let Some((b0, b1)) = lb.ray_range(&lray) else {
            return;
        };
        let (lo, hi) = (t0.max(b0), t1.min(b1));
        if lo >= hi || lo.is_nan() || hi.is_nan() {
            return;
        }
        let mut cands = [(0.0, 0u32); 6];
        cands[0] = (lo, if lo == t0 { f0 } else { LATERAL });
        cands[1] = (hi, if hi == t1 { f1 } else { LATERAL });
        let world_inside = |p: DVec3| self.inside_local(self.f.inv * (p - self.f.v));
        if quick && d.x == 0.0 && d.y == 0.0 {
            match self.along_axis(o) {
                Some(false) => return,
                Some(true) => {
                    segments_by_classification(&mut cands[..2], ray, world_inside, out);
                    return;
                }
                None => {}
            }
        }
        // Shift the origin to `lo` for conditioning.
        let os = o + d * lo;
        let x = [os.x, d.x];
        let y = [os.y, d.y];
        let sa = [1.0 + self.ka * os.z, self.ka * d.z];
        let sb = [1.0 + self.kb * os.z, self.kb * d.z];
        let (mut x2, mut y2, mut sa2, mut sb2) = ([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
        mul(&x, &x, &mut x2);
        mul(&y, &y, &mut y2);
        mul(&sa, &sa, &mut sa2);
        mul(&sb, &sb, &mut sb2);
        let (mut p1, mut p2, mut p3) = ([0.0; 5], [0.0; 5], [0.0; 5]);
        mul(&x2, &sb2, &mut p1);
        mul(&y2, &sa2, &mut p2);
        mul(&sa2, &sb2, &mut p3);
        let poly: [f64; 5] = std::array::from_fn(|i| p1[i] + p2[i] - p3[i]);
        let mut roots = [0.0; 4];
        let n = roots_in(&poly, 0.0, hi - lo, &mut roots);
        for i in 0..n {
            cands[2 + i] = (roots[i] + lo, LATERAL);
        }
        segments_by_classification(&mut cands[..2 + n], ray, world_inside, out);
    }

    /// For a ray along the axis through `o` (local): `Some(false)` when it
    /// stays outside the lateral surface by more than a billionth all the
    /// way, `Some(true)` when it stays inside it so, `None` when it may
    /// cross it. Neither way does it cross the surface, so the quartic has
    /// no root to give, and the segments are those of the caps alone.
    fn along_axis(&self, o: DVec3) -> Option<bool> {
        // Where the ray is, against the cross-section at height z: convex
        // in z, so inside at both caps means inside between them.
        let against = |sa: f64, sb: f64| (o.x / sa).powi(2) + (o.y / sb).powi(2);
        if against(m2(self.ka), m2(self.kb)) > 1.0 + AXIS_MARGIN {
            return Some(false);
        }
        let (top_a, top_b) = (1.0 + self.ka, 1.0 + self.kb);
        let inside = top_a > 0.0
            && top_b > 0.0
            && against(1.0, 1.0) < 1.0 - AXIS_MARGIN
            && against(top_a, top_b) < 1.0 - AXIS_MARGIN;
        inside.then_some(true)
    }

    /// [`GeneralCone::shoot`] in every lane whose ray runs across the
    /// axis or along it, operation for operation; the lanes of rays at a
    /// slant are left to the scalar code. Across the axis the
    /// cross-section does not change along the ray, so the quartic is a
    /// quadratic; along it the quartic is solved as the torus's is (for
    /// rays near the lateral surface only). A section across the axis is
    /// convex, and so is the stretch along it that lies inside, so a ray
    /// gets one segment at most (a lane that rounding gives two is left to
    /// the scalar code too). A grid's rays through a TGC standing on an
    /// axis are all of these kinds.
    ///
    /// Its own frame where unoptimised, as the torus's is (see
    /// [`super::Torus::shoot_lanes_both`]): the quartic's many values
    /// would otherwise sit in [`Shape::shoot_lanes`]' frame beside every
    /// other shape's.
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[cfg_attr(debug_assertions, inline(never))]
    pub fn shoot_lanes<S: Simd>(&self, s: S, r: &Lanes<S>) -> SegLanes<S> {
        let o = mat_vec(s, &self.f.inv, sub_point(s, r.o, self.f.v));
        let d = mat_vec(s, &self.f.inv, r.d);
        let (zero, one) = (s.splat(0.0), s.splat(1.0));
        let along_axis = s.and(s.eq(d[0], zero), s.eq(d[1], zero));
        let across = s.andnot(s.eq(d[2], zero), along_axis);
        let mut out = SegLanes {
            t0: zero,
            t1: zero,
            f0: zero,
            f1: zero,
            hit: s.none(),
            scalar: not(s, s.or(across, along_axis)),
        };
        if s.all(out.scalar) {
            return out;
        }
        let lat = s.splat(f64::from(LATERAL));
        // `shoot_with`: the slab between the caps, the box of the end
        // ellipses, and the range in both.
        let (t0, t1, f0, f1, slab_miss) = Frame::slab_lanes(s, o, d);
        let local_box = self.local_box();
        let (b0, b1, in_box) = ray_range_lanes(s, &local_box, o, d);
        let (lo, hi) = (max_num(s, t0, b0), min_num(s, t1, b1));
        let met = s.andnot(s.and(in_box, s.lt(lo, hi)), slab_miss);
        let ends = [
            s.select(s.eq(lo, t0), f0, lat),
            s.select(s.eq(hi, t1), f1, lat),
        ];
        // `along_axis`: a ray beside the body misses; one inside it all
        // the way has the caps' segment; the others need the quartic.
        let against = |sa: f64, sb: f64| {
            let (x, y) = (s.div(o[0], s.splat(sa)), s.div(o[1], s.splat(sb)));
            s.add(s.mul(x, x), s.mul(y, y))
        };
        let along_axis = s.and(along_axis, met);
        // The box's sides: the end ellipses' larger semi-axes.
        let (ma, mb) = (local_box.max.x, local_box.max.y);
        let beside = s.gt(against(ma, mb), s.splat(1.0 + AXIS_MARGIN));
        let (top_a, top_b) = (1.0 + self.ka, 1.0 + self.kb);
        let within = if top_a > 0.0 && top_b > 0.0 {
            let margin = s.splat(1.0 - AXIS_MARGIN);
            s.and(
                s.lt(against(1.0, 1.0), margin),
                s.lt(against(top_a, top_b), margin),
            )
        } else {
            s.none()
        };
        let within = s.and(along_axis, s.andnot(within, beside));
        let near_side = s.andnot(s.andnot(along_axis, beside), within);
        // Across the axis, or along it near the lateral surface: the
        // quartic's coefficients as `shoot_with` builds them. Across the
        // axis the two highest are zero: a quadratic.
        let solve = s.or(s.and(across, met), near_side);
        let (mut roots, mut found) = ([zero; 4], zero);
        let mut solved = s.none();
        if s.any(solve) {
            // The roots are sought from `lo`, where the origin is moved.
            let reach = s.sub(hi, lo);
            let os = along(s, o, d, lo);
            let scale = |k: f64| {
                [
                    s.add(one, s.mul(s.splat(k), os[2])),
                    s.mul(s.splat(k), d[2]),
                ]
            };
            let (x, y, sa, sb) = ([os[0], d[0]], [os[1], d[1]], scale(self.ka), scale(self.kb));
            let (x2, y2) = (mul_lanes::<S, 2, 3>(s, &x, &x), mul_lanes(s, &y, &y));
            let (sa2, sb2) = (mul_lanes::<S, 2, 3>(s, &sa, &sa), mul_lanes(s, &sb, &sb));
            let p1 = mul_lanes::<S, 3, 5>(s, &x2, &sb2);
            let p2 = mul_lanes::<S, 3, 5>(s, &y2, &sa2);
            let p3 = mul_lanes::<S, 3, 5>(s, &sa2, &sb2);
            let mut poly = p1;
            for (i, c) in poly.iter_mut().enumerate() {
                *c = s.sub(s.add(p1[i], p2[i]), p3[i]);
            }
            // `roots_in`'s degree: below three across the axis, four
            // along it but for a ratio of one.
            let (low, zero2, zero1) = (
                s.and(s.eq(poly[4], zero), s.eq(poly[3], zero)),
                s.eq(poly[2], zero),
                s.eq(poly[1], zero),
            );
            let quadratic = s.and(solve, s.andnot(low, zero2));
            let linear = s.and(s.and(solve, low), s.andnot(zero2, zero1));
            let constant = s.and(s.and(solve, low), s.and(zero2, zero1));
            let quartic = s.andnot(solve, s.eq(poly[4], zero));
            // A cubic (a ratio of one along the axis) is left to the
            // scalar code.
            solved = s.or(s.or(quadratic, linear), s.or(constant, quartic));
            out.scalar = s.or(out.scalar, s.andnot(solve, solved));
            let c = [poly[0], poly[1], poly[2]];
            let (two_roots, two_found) = quadratic_roots_in_lanes(s, c, reach, quadratic);
            (roots[0], roots[1], found) = (two_roots[0], two_roots[1], two_found);
            let root = s.div(s.neg(poly[0]), poly[1]);
            let fits = s.and(s.ge(root, zero), s.le(root, reach));
            roots[0] = s.select(linear, root, roots[0]);
            found = s.select(s.and(linear, fits), one, found);
            if s.any(quartic) {
                let (four_roots, four_found) = quartic_roots_lanes(s, poly, reach, quartic);
                for (root, four) in roots.iter_mut().zip(four_roots) {
                    *root = s.select(quartic, four, *root);
                }
                found = s.select(quartic, four_found, found);
            }
            for root in &mut roots {
                *root = s.add(*root, lo);
            }
        }
        // `segments_by_classification`: the crossings in the stable
        // sort's order (`lo` first, then the roots before `hi`, then `hi`,
        // then the roots at or past it), and the stretches between them
        // whose midpoints are inside, joined where they follow one
        // another.
        let classify = s.or(within, solved);
        let mut before = [s.none(); 4];
        for (k, before) in before.iter_mut().enumerate() {
            let valid = s.lt(s.splat(k as f64), found);
            *before = s.and(valid, sorts_before(s, roots[k], hi));
        }
        let (mut crossings, mut faces) = ([lo; 6], [ends[0]; 6]);
        for i in 1..6 {
            // The `i`th crossing: root `i - 1` if it comes before `hi`,
            // else `hi` if root `i - 2` does (or there is none), else root
            // `i - 2`.
            let root_before = if i <= 4 { before[i - 1] } else { s.none() };
            let hi_here = if i == 1 {
                s.mask(u32::MAX)
            } else {
                before[i - 2]
            };
            let (earlier, later) = (roots[(i - 1).min(3)], roots[i.saturating_sub(2).min(3)]);
            crossings[i] = s.select(root_before, earlier, s.select(hi_here, hi, later));
            faces[i] = s.select(root_before, lat, s.select(hi_here, ends[1], lat));
        }
        let count = s.add(s.splat(2.0), found);
        let (mut open, mut broken, mut two) = (s.none(), s.none(), s.none());
        for w in 0..5 {
            let valid = s.and(classify, s.lt(s.splat((w + 1) as f64), count));
            if !s.any(valid) {
                break;
            }
            let (ta, tb) = (crossings[w], crossings[w + 1]);
            let gap = s.andnot(valid, s.le(tb, ta));
            let mid = along(s, r.o, r.d, s.mul(s.splat(0.5), s.add(ta, tb)));
            let inside = s.and(gap, self.inside_lanes(s, mid));
            // A stretch inside after one outside begins a second segment.
            two = s.or(two, s.and(inside, broken));
            broken = s.or(broken, s.and(s.andnot(gap, inside), open));
            let start = s.andnot(inside, open);
            out.t0 = s.select(start, ta, out.t0);
            out.f0 = s.select(start, faces[w], out.f0);
            out.t1 = s.select(inside, tb, out.t1);
            out.f1 = s.select(inside, faces[w + 1], out.f1);
            open = s.or(open, inside);
        }
        out.hit = s.andnot(open, two);
        out.scalar = s.or(out.scalar, two);
        out
    }

    /// The points `p` in every lane in the local frame, and the scales of
    /// the cross-section's two semi-axes at their height, as
    /// [`GeneralCone::inside_local`] and [`GeneralCone::normal`] work
    /// them out.
    #[inline(always)]
    fn local_scales_lanes<S: Simd>(&self, s: S, p: [S::F; 3]) -> ([S::F; 3], S::F, S::F) {
        let q = mat_vec(s, &self.f.inv, sub_point(s, p, self.f.v));
        let one = s.splat(1.0);
        let sa = s.add(one, s.mul(s.splat(self.ka), q[2]));
        let sb = s.add(one, s.mul(s.splat(self.kb), q[2]));
        (q, sa, sb)
    }

    /// [`GeneralCone::contains`] of the points `p` in every lane.
    #[inline(always)]
    fn inside_lanes<S: Simd>(&self, s: S, p: [S::F; 3]) -> S::M {
        let (q, sa, sb) = self.local_scales_lanes(s, p);
        let one = s.splat(1.0);
        let (x, y) = (s.div(q[0], sa), s.div(q[1], sb));
        let slab = s.and(s.gt(q[2], s.splat(0.0)), s.lt(q[2], one));
        s.and(slab, s.lt(s.add(s.mul(x, x), s.mul(y, y)), one))
    }

    /// [`GeneralCone::normal`] in every lane (faces held as `f64`),
    /// operation for operation.
    #[inline(always)]
    pub fn normal_lanes<S: Simd>(&self, s: S, face: S::F, p: [S::F; 3]) -> [S::F; 3] {
        let (q, sa, sb) = self.local_scales_lanes(s, p);
        let (sa2, sb2) = (s.mul(sa, sa), s.mul(sb, sb));
        let bend = |q: S::F, k: f64, s2: S::F, s1: S::F| {
            s.div(s.mul(s.mul(q, q), s.splat(k)), s.mul(s2, s1))
        };
        let z = s.neg(s.add(bend(q[0], self.ka, sa2, sa), bend(q[1], self.kb, sb2, sb)));
        self.f
            .normal_lanes(s, face, [s.div(q[0], sa2), s.div(q[1], sb2), z])
    }

    /// Outward unit normal at a point of the surface.
    pub fn normal(&self, face: u32, p: DVec3) -> DVec3 {
        match face {
            BASE => self.f.world_normal(-DVec3::Z),
            TOP => self.f.world_normal(DVec3::Z),
            _ => {
                let q = self.f.inv * (p - self.f.v);
                let sa = 1.0 + self.ka * q.z;
                let sb = 1.0 + self.kb * q.z;
                let g = DVec3::new(
                    q.x / (sa * sa),
                    q.y / (sb * sb),
                    -(q.x * q.x * self.ka / (sa * sa * sa) + q.y * q.y * self.kb / (sb * sb * sb)),
                );
                self.f.world_normal(g)
            }
        }
    }

    /// True when `p` is strictly inside.
    pub fn contains(&self, p: DVec3) -> bool {
        self.inside_local(self.f.inv * (p - self.f.v))
    }

    /// Bounds (infinite sides where the body is unbounded).
    pub fn bounds(&self) -> Aabb {
        self.f.bounds(1.0 + self.ka, 1.0 + self.kb)
    }
}

/// How far a ray along a general cone's axis must stay from its lateral
/// surface, relatively, for [`GeneralCone::along_axis`] to pass the
/// quartic over.
const AXIS_MARGIN: f64 = 1e-9;

/// Largest local half-width of a cross-section over `0 <= z <= 1`.
fn m2(k: f64) -> f64 {
    1.0f64.max(1.0 + k)
}

/// RCC: base centre V, height vector H, radius R.
pub(crate) fn prepare_rcc(b: &Body, _: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    let h = nonzero(b.vec3(3), "height vector")?;
    let r = positive(b.params[6], "radius")?;
    let (u, w) = orthonormal_basis(h.normalize());
    with_bounds(Shape::Cone(Cone::new(b.vec3(0), u * r, w * r, h, 1.0)))
}

/// The height vector H and the semi-axes A and B of an REC, TEC or TGC,
/// which must span a volume.
fn axes(b: &Body) -> Result<(DVec3, DVec3, DVec3), String> {
    let (h, a, bb) = (
        nonzero(b.vec3(3), "height vector")?,
        nonzero(b.vec3(6), "semi-axis A")?,
        nonzero(b.vec3(9), "semi-axis B")?,
    );
    independent(a, bb, h, "A, B and H")?;
    Ok((h, a, bb))
}

/// REC: base centre V, height H, semi-axes A and B.
pub(crate) fn prepare_rec(b: &Body, _: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    let (h, a, bb) = axes(b)?;
    with_bounds(Shape::Cone(Cone::new(b.vec3(0), a, bb, h, 1.0)))
}

/// TRC: base V, height H, radii R1 (base) and R2 (top), one of them
/// possibly zero (a cone with its apex at an end).
pub(crate) fn prepare_trc(b: &Body, _: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    let h = nonzero(b.vec3(3), "height vector")?;
    let (r1, r2) = (b.params[6], b.params[7]);
    if r1 < 0.0 || r2 < 0.0 || (r1 == 0.0 && r2 == 0.0) {
        return Err(format!(
            "radii must be non-negative and not both zero (are {r1} and {r2})"
        ));
    }
    let (u, w) = orthonormal_basis(h.normalize());
    with_bounds(Shape::Cone(if r1 > 0.0 {
        Cone::new(b.vec3(0), u * r1, w * r1, h, r2 / r1)
    } else {
        // Apex at the base: build it from the top down.
        Cone::new(b.vec3(0) + h, u * r2, w * r2, -h, 0.0)
    }))
}

/// TEC: base V, height H, base semi-axes A and B, top axes A/P and B/P.
pub(crate) fn prepare_tec(b: &Body, _: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    let (h, a, bb) = axes(b)?;
    let p = positive(b.params[12], "ratio P")?;
    with_bounds(Shape::Cone(Cone::new(b.vec3(0), a, bb, h, 1.0 / p)))
}

/// TGC: base V, height H, base semi-axes A and B, top semi-axes C and D
/// along them; a [`Cone`] when the top ellipse is similar to the base.
pub(crate) fn prepare_tgc(b: &Body, _: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    let (h, a, bb) = axes(b)?;
    let (c, d) = (b.params[12], b.params[13]);
    if c < 0.0 || d < 0.0 {
        return Err(format!(
            "top semi-axes must be non-negative (are {c} and {d})"
        ));
    }
    let (ra, rb) = (c / a.length(), d / bb.length());
    with_bounds(if (ra - rb).abs() <= 1e-12 * ra.max(rb) {
        Shape::Cone(Cone::new(b.vec3(0), a, bb, h, ra))
    } else {
        Shape::GeneralCone(GeneralCone::new(b.vec3(0), a, bb, h, ra, rb))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A TGC standing on the origin along `axis`, its base semi-axes along
    /// the next two axes.
    fn general_cone(axis: usize, (a, b, h): (f64, f64, f64), (ra, rb): (f64, f64)) -> GeneralCone {
        let along = |k: usize, len: f64| DVec3::AXES[k % 3] * len;
        GeneralCone::new(
            DVec3::new(0.5, -0.25, 1.0),
            along(axis + 1, a),
            along(axis + 2, b),
            along(axis, h),
            ra,
            rb,
        )
    }

    proptest! {
        /// Rays along the axis get the same segments whether or not the
        /// quartic is passed over.
        #[test]
        fn rays_along_the_axis_skip_the_quartic_unchanged(
            axis in 0usize..3,
            size in (0.5f64..10.0, 0.5f64..10.0, 0.5f64..20.0),
            ratios in (0.0f64..2.5, 0.0f64..2.5),
            across in prop::array::uniform2(-25.0f64..25.0),
            backwards in any::<bool>(),
        ) {
            let cone = general_cone(axis, size, ratios);
            let mut from = DVec3::new(0.5, -0.25, 1.0) - DVec3::AXES[axis] * 40.0;
            from[(axis + 1) % 3] += across[0];
            from[(axis + 2) % 3] += across[1];
            let mut dir = DVec3::AXES[axis];
            if backwards {
                from += dir * 100.0;
                dir = -dir;
            }
            let ray = Ray::new(from, dir);
            let (mut quick, mut full) = (Vec::new(), Vec::new());
            cone.shoot_with(&ray, true, &mut quick);
            cone.shoot_with(&ray, false, &mut full);
            prop_assert_eq!(quick, full);
        }
    }

    #[test]
    fn rays_along_the_axis_inside_and_outside_pass_the_quartic_over() {
        let cone = general_cone(2, (5.0, 8.0, 10.0), (0.4, 1.125));
        let (o, _) = cone
            .f
            .local(&Ray::new(DVec3::new(0.5, -0.25, -5.0), DVec3::Z));
        assert_eq!(cone.along_axis(o), Some(true));
        let (o, _) = cone
            .f
            .local(&Ray::new(DVec3::new(7.0, 8.5, -5.0), DVec3::Z));
        assert_eq!(cone.along_axis(o), Some(false));
        // Between the base's ellipse and the top's: it may cross.
        let (o, _) = cone
            .f
            .local(&Ray::new(DVec3::new(4.0, -0.25, -5.0), DVec3::Z));
        assert_eq!(cone.along_axis(o), None);
    }
}
