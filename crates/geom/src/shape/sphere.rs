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

    /// Bounds of the sphere's part of the box `within` (see
    /// [`super::Shape::bounds_within`]): along each axis, a point of both
    /// lies no farther from the centre than the radius leaves once the
    /// box's distances from the centre along the other two axes are
    /// taken.
    pub fn bounds_within(&self, within: &Aabb) -> Aabb {
        let gap = |a: usize| {
            let outside = (within.min[a] - self.c[a]).max(self.c[a] - within.max[a]);
            outside.max(0.0).powi(2)
        };
        let gaps = [gap(0), gap(1), gap(2)];
        if gaps[0] + gaps[1] + gaps[2] > self.r2 {
            return Aabb::EMPTY;
        }
        let mut part = self.bounds().intersection(within);
        for a in 0..3 {
            let half = (self.r2 - gaps[(a + 1) % 3] - gaps[(a + 2) % 3]).sqrt();
            part.min[a] = part.min[a].max(self.c[a] - half);
            part.max[a] = part.max[a].min(self.c[a] + half);
        }
        part
    }
}

/// SPH: centre V, radius R.
pub(crate) fn prepare_sph(b: &Body, _: &mut Vec<Warning>) -> Result<(super::Shape, Aabb), String> {
    let sphere = Sphere::new(b.vec3(0), positive(b.params[3], "radius")?);
    let bounds = sphere.bounds();
    Ok((super::Shape::Sphere(sphere), bounds))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn a_plane_through_the_centre_cuts_the_sphere_across_its_diameter() {
        let sphere = Sphere::new(DVec3::new(1.0, 2.0, 3.0), 2.0);
        let plane = Aabb::new(DVec3::new(-9.0, -9.0, 4.0), DVec3::new(9.0, 9.0, 4.0));
        let part = sphere.bounds_within(&plane);
        // The circle of radius √3 at z = 4.
        let half = 3f64.sqrt();
        assert!((part.min - DVec3::new(1.0 - half, 2.0 - half, 4.0)).length() < 1e-12);
        assert!((part.max - DVec3::new(1.0 + half, 2.0 + half, 4.0)).length() < 1e-12);
        let beside = Aabb::new(DVec3::new(-9.0, -9.0, 5.5), DVec3::new(9.0, 9.0, 5.5));
        assert!(sphere.bounds_within(&beside).is_empty());
    }

    proptest! {
        /// Every point of both the sphere and the box lies in the part:
        /// a point of the sphere, and a box about it (flat across one
        /// axis, or none).
        #[test]
        fn the_part_holds_every_point_of_both(
            centre in prop::array::uniform3(-1.0..1.0f64),
            r in 0.1..1.5f64,
            towards in prop::array::uniform3(-1.0..1.0f64),
            below in prop::array::uniform3(0.0..2.0f64),
            above in prop::array::uniform3(0.0..2.0f64),
            flat in 0usize..4,
        ) {
            let sphere = Sphere::new(DVec3::from(centre), r);
            let towards = DVec3::from(towards);
            prop_assume!(towards.length() <= 1.0);
            let p = sphere.c + towards * r;
            let mut within = Aabb::new(p - DVec3::from(below), p + DVec3::from(above));
            if flat < 3 {
                (within.min[flat], within.max[flat]) = (p[flat], p[flat]);
            }
            let part = sphere.bounds_within(&within);
            prop_assert!(part.padded(1e-12).contains(p), "{p} outside {part:?}");
        }
    }
}
