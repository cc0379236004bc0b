use super::Seg;
use super::SegLanes;
use crate::body::Warning;
use crate::Body;
use sv_math::lanes::{not, Lanes};
use sv_math::simd::Simd;
use sv_math::{Aabb, DVec3, Ray};

/// An axis-aligned box (RPP), cast by the slab method with the faces
/// crossed tracked. Faces: 0 −x, 1 +x, 2 −y, 3 +y, 4 −z, 5 +z.
#[derive(Clone, Debug)]
pub struct Rpp {
    b: Aabb,
}

impl Rpp {
    /// The box.
    pub fn new(b: Aabb) -> Rpp {
        Rpp { b }
    }

    /// Append the segments of the ray inside the body to `out` (see
    /// [`super::Shape::shoot`]).
    #[inline]
    pub fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        let (o, d, inv, b) = (ray.origin, ray.dir, ray.inv_dir, &self.b);
        let mut c = Clip {
            t0: f64::NEG_INFINITY,
            t1: f64::INFINITY,
            f0: 0,
            f1: 0,
        };
        // Axis by axis, written out: no indexing in the hot loop.
        if c.slab(o.x, d.x, inv.x, b.min.x, b.max.x, 0)
            && c.slab(o.y, d.y, inv.y, b.min.y, b.max.y, 2)
            && c.slab(o.z, d.z, inv.z, b.min.z, b.max.z, 4)
            && c.t0 < c.t1
        {
            out.push(Seg {
                t0: c.t0,
                t1: c.t1,
                f0: c.f0,
                f1: c.f1,
            });
        }
    }

    /// [`Rpp::shoot`] in every lane, operation for operation: each axis's
    /// `Clip::slab`, with the faces held as `f64`.
    #[inline(always)]
    pub fn shoot_lanes<S: Simd>(&self, s: S, r: &Lanes<S>) -> SegLanes<S> {
        let zero = s.splat(0.0);
        let (mut t0, mut t1) = (s.splat(f64::NEG_INFINITY), s.splat(f64::INFINITY));
        let (mut f0, mut f1) = (zero, zero);
        let mut miss = s.none();
        for a in 0..3 {
            let (o, d, inv) = (r.o[a], r.d[a], r.inv[a]);
            let (lo, hi) = (s.splat(self.b.min[a]), s.splat(self.b.max[a]));
            let flat = s.eq(d, zero);
            // Parallel to the slab: a miss outside it, else no change.
            miss = s.or(miss, s.and(flat, s.or(s.lt(o, lo), s.gt(o, hi))));
            let (x0, x1) = (s.mul(s.sub(lo, o), inv), s.mul(s.sub(hi, o), inv));
            let up = s.gt(d, zero);
            let (face, next) = (s.splat(2.0 * a as f64), s.splat(2.0 * a as f64 + 1.0));
            let (near, far) = (s.select(up, x0, x1), s.select(up, x1, x0));
            let (fnear, ffar) = (s.select(up, face, next), s.select(up, next, face));
            let n0 = s.andnot(s.gt(near, t0), flat);
            let n1 = s.andnot(s.lt(far, t1), flat);
            t0 = s.select(n0, near, t0);
            f0 = s.select(n0, fnear, f0);
            t1 = s.select(n1, far, t1);
            f1 = s.select(n1, ffar, f1);
            miss = s.or(miss, s.andnot(not(s, s.le(t0, t1)), flat));
        }
        SegLanes {
            t0,
            t1,
            f0,
            f1,
            hit: s.andnot(s.lt(t0, t1), miss),
            scalar: s.none(),
        }
    }

    /// Outward unit normal at a point of the surface.
    pub fn normal(&self, face: u32) -> DVec3 {
        let mut n = DVec3::ZERO;
        n[(face / 2) as usize] = if face.is_multiple_of(2) { -1.0 } else { 1.0 };
        n
    }

    /// [`Rpp::normal`] in every lane (faces held as `f64`).
    #[inline(always)]
    pub fn normal_lanes<S: Simd>(&self, s: S, face: S::F) -> [S::F; 3] {
        [
            unit_axis(s, face, 0.0),
            unit_axis(s, face, 1.0),
            unit_axis(s, face, 2.0),
        ]
    }

    /// True when `p` is strictly inside.
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpgt(self.b.min).all() && p.cmplt(self.b.max).all()
    }

    /// Bounds (infinite sides where the body is unbounded).
    pub fn bounds(&self) -> Aabb {
        self.b
    }
}

/// One coordinate of [`Rpp::normal_lanes`]: -1 on the low face of axis
/// `a`, 1 on its high face, else 0.
#[inline(always)]
fn unit_axis<S: Simd>(s: S, face: S::F, a: f64) -> S::F {
    let (low, high) = (
        s.eq(face, s.splat(2.0 * a)),
        s.eq(face, s.splat(2.0 * a + 1.0)),
    );
    s.select(
        low,
        s.splat(-1.0),
        s.select(high, s.splat(1.0), s.splat(0.0)),
    )
}

/// The stretch of the ray inside the slabs seen so far, with the faces
/// that bound it.
struct Clip {
    t0: f64,
    t1: f64,
    f0: u32,
    f1: u32,
}

impl Clip {
    /// Narrow to the slab `lo <= x <= hi` of one axis (origin `o`,
    /// direction `d`, `inv = 1/d`), whose faces are `face` (low side) and
    /// `face + 1`. False when the ray misses: either it runs parallel
    /// outside the slab (a ray in a face's plane counts as inside, as in
    /// the general polyhedron, which misses only when `dist < 0`) or the
    /// stretch is empty.
    #[inline(always)]
    fn slab(&mut self, o: f64, d: f64, inv: f64, lo: f64, hi: f64, face: u32) -> bool {
        if d == 0.0 {
            return !(o < lo || o > hi);
        }
        let (a, b) = ((lo - o) * inv, (hi - o) * inv);
        let (near, far, fn_, ff) = if d > 0.0 {
            (a, b, face, face + 1)
        } else {
            (b, a, face + 1, face)
        };
        if near > self.t0 {
            self.t0 = near;
            self.f0 = fn_;
        }
        if far < self.t1 {
            self.t1 = far;
            self.f1 = ff;
        }
        self.t0 <= self.t1
    }
}

/// RPP: xmin xmax ymin ymax zmin zmax, each minimum below its maximum.
pub(crate) fn prepare_rpp(b: &Body, _: &mut Vec<Warning>) -> Result<(super::Shape, Aabb), String> {
    let p = &b.params;
    let min = DVec3::new(p[0], p[2], p[4]);
    let max = DVec3::new(p[1], p[3], p[5]);
    for (a, n) in ["x", "y", "z"].iter().enumerate() {
        if min[a] >= max[a] {
            return Err(format!(
                "{n}min ({}) must be less than {n}max ({})",
                min[a], max[a]
            ));
        }
    }
    let bounds = Aabb::new(min, max);
    Ok((super::Shape::Rpp(Rpp::new(bounds)), bounds))
}
