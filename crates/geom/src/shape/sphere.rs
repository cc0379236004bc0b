use super::Seg;
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

    #[inline]
    pub(crate) fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
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

    pub(crate) fn normal(&self, p: DVec3) -> DVec3 {
        ((p - self.c) * self.inv_r).normalize()
    }

    pub(crate) fn contains(&self, p: DVec3) -> bool {
        (p - self.c).length_squared() < self.r2
    }

    pub(crate) fn bounds(&self) -> Aabb {
        Aabb::new(self.c - DVec3::splat(self.r), self.c + DVec3::splat(self.r))
    }
}
