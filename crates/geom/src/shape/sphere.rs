use super::Seg;
use super::SegLanes;
use crate::body::{positive, Warning};
use crate::Body;
use sv_math::lanes::{back, dot, normalize, not, sub_point, Lanes};
use sv_math::simd::Simd;
use sv_math::{Aabb, DVec3, Ray};

/// A sphere.
#[derive(Clone, Debug)]
pub struct Sphere {
    /// Centre.
    pub c: DVec3,
    /// Radius.
    pub r: f64,
    r2: f64,
    inv_r: f64,
}

impl Sphere {
    /// A sphere of radius `r > 0`.
    pub fn new(c: DVec3, r: f64) -> Sphere {
        Sphere {
            c,
            r,
            r2: r * r,
            inv_r: 1.0 / r,
        }
    }

    /// Append the segments of the ray inside the body to `out` (see
    /// [`super::Shape::shoot`]).
    #[inline]
    pub fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        let oc = ray.origin - self.c;
        // |dir| = 1: the ray comes closest to the centre at `t = -b`, a
        // distance |f| away, and meets the sphere half a chord either side.
        // Measured from the closest approach, the half chord stays accurate
        // for distant spheres (Haines et al., Ray Tracing Gems ch. 7), and
        // takes one square root and no division.
        let b = oc.dot(ray.dir);
        let f = oc - ray.dir * b;
        let disc = self.r2 - f.length_squared();
        if disc < 0.0 {
            return;
        }
        let h = disc.sqrt();
        out.push(Seg {
            t0: -b - h,
            t1: -b + h,
            f0: 0,
            f1: 0,
        });
    }

    /// [`Sphere::shoot`] in every lane, operation for operation.
    #[inline(always)]
    pub fn shoot_lanes<S: Simd>(&self, s: S, r: &Lanes<S>) -> SegLanes<S> {
        let oc = sub_point(s, r.o, self.c);
        let b = dot(s, oc, r.d);
        let f = back(s, oc, r.d, b);
        let disc = s.sub(s.splat(self.r2), dot(s, f, f));
        let h = s.sqrt(disc);
        let nb = s.neg(b);
        let zero = s.splat(0.0);
        SegLanes {
            t0: s.sub(nb, h),
            t1: s.add(nb, h),
            f0: zero,
            f1: zero,
            hit: not(s, s.lt(disc, zero)),
            scalar: s.none(),
        }
    }

    /// Outward unit normal at a point of the surface.
    pub fn normal(&self, p: DVec3) -> DVec3 {
        ((p - self.c) * self.inv_r).normalize()
    }

    /// [`Sphere::normal`] in every lane, operation for operation.
    #[inline(always)]
    pub fn normal_lanes<S: Simd>(&self, s: S, p: [S::F; 3]) -> [S::F; 3] {
        let q = sub_point(s, p, self.c);
        let r = s.splat(self.inv_r);
        normalize(s, [s.mul(q[0], r), s.mul(q[1], r), s.mul(q[2], r)])
    }

    /// True when `p` is strictly inside.
    pub fn contains(&self, p: DVec3) -> bool {
        (p - self.c).length_squared() < self.r2
    }

    /// Bounds (infinite sides where the body is unbounded).
    pub fn bounds(&self) -> Aabb {
        Aabb::new(self.c - DVec3::splat(self.r), self.c + DVec3::splat(self.r))
    }
}

/// SPH: centre V, radius R.
pub(crate) fn prepare_sph(b: &Body, _: &mut Vec<Warning>) -> Result<(super::Shape, Aabb), String> {
    let sphere = Sphere::new(b.vec3(0), positive(b.params[3], "radius")?);
    let bounds = sphere.bounds();
    Ok((super::Shape::Sphere(sphere), bounds))
}
