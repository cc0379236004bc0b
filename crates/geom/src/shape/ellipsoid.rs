use super::{Seg, SegLanes, Shape};
use crate::body::{independent, nonzero, positive, Warning};
use crate::Body;
use sv_math::lanes::{along, dot, mat_vec, normalize, not, sub_point, Lanes};
use sv_math::simd::Simd;
use sv_math::{orthonormal_basis, Aabb, DMat3, DVec3, Ray};

/// An ellipsoid: the image of the unit sphere under `x = c + M u`.
#[derive(Clone, Debug)]
pub struct Ellipsoid {
    c: DVec3,
    m: DMat3,
    inv: DMat3,
    inv_t: DMat3,
}

impl Ellipsoid {
    /// The ellipsoid with centre `c` and semi-axis vectors as the columns of
    /// `m` (which must be invertible).
    pub fn new(c: DVec3, m: DMat3) -> Ellipsoid {
        let inv = m.inverse();
        Ellipsoid {
            c,
            m,
            inv,
            inv_t: inv.transpose(),
        }
    }

    /// Corners of the parallelepiped spanned by its semi-axes: their hull
    /// holds the ellipsoid.
    pub fn corners(&self) -> Vec<DVec3> {
        let (a, b, h) = (self.m.x_axis, self.m.y_axis, self.m.z_axis);
        super::ends((self.c - h, a, b), (self.c + h, a, b))
    }

    /// Append the segments of the ray inside the body to `out` (see
    /// [`super::Shape::shoot`]).
    #[inline]
    pub fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        let o = self.inv * (ray.origin - self.c);
        let d = self.inv * ray.dir;
        // In the unit sphere's frame: the closest approach to the centre,
        // and half a chord either side, as for the sphere (one division,
        // one root).
        let dd = d.length_squared();
        if dd == 0.0 {
            return;
        }
        let inv = 1.0 / dd;
        let tc = -o.dot(d) * inv;
        let oc = o + d * tc;
        let disc = 1.0 - oc.length_squared();
        if disc < 0.0 {
            return;
        }
        let h = (disc * inv).sqrt();
        out.push(Seg {
            t0: tc - h,
            t1: tc + h,
            f0: 0,
            f1: 0,
        });
    }

    /// [`Ellipsoid::shoot`] in every lane, operation for operation.
    #[inline(always)]
    pub fn shoot_lanes<S: Simd>(&self, s: S, r: &Lanes<S>) -> SegLanes<S> {
        let o = mat_vec(s, &self.inv, sub_point(s, r.o, self.c));
        let d = mat_vec(s, &self.inv, r.d);
        let dd = dot(s, d, d);
        let (zero, one) = (s.splat(0.0), s.splat(1.0));
        let inv = s.div(one, dd);
        let tc = s.mul(s.neg(dot(s, o, d)), inv);
        let oc = along(s, o, d, tc);
        let disc = s.sub(one, dot(s, oc, oc));
        let h = s.sqrt(s.mul(disc, inv));
        SegLanes {
            t0: s.sub(tc, h),
            t1: s.add(tc, h),
            f0: zero,
            f1: zero,
            hit: not(s, s.or(s.eq(dd, zero), s.lt(disc, zero))),
            scalar: s.none(),
        }
    }

    /// Outward unit normal at a point of the surface.
    pub fn normal(&self, p: DVec3) -> DVec3 {
        (self.inv_t * (self.inv * (p - self.c))).normalize()
    }

    /// [`Ellipsoid::normal`] in every lane, operation for operation.
    #[inline(always)]
    pub fn normal_lanes<S: Simd>(&self, s: S, p: [S::F; 3]) -> [S::F; 3] {
        let q = mat_vec(s, &self.inv, sub_point(s, p, self.c));
        normalize(s, mat_vec(s, &self.inv_t, q))
    }

    /// True when `p` is strictly inside.
    pub fn contains(&self, p: DVec3) -> bool {
        (self.inv * (p - self.c)).length_squared() < 1.0
    }

    /// Bounds (infinite sides where the body is unbounded).
    pub fn bounds(&self) -> Aabb {
        // Half-extent along axis i is the length of row i of M.
        let r = self.m.transpose();
        let e = DVec3::new(r.x_axis.length(), r.y_axis.length(), r.z_axis.length());
        Aabb::new(self.c - e, self.c + e)
    }
}

/// ELL: an ellipsoid of revolution by its foci F1, F2 and the length L of
/// its major axis, which must exceed their distance (a sphere when they
/// coincide).
pub(crate) fn prepare_ell(b: &Body, _: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    let (f1, f2, length) = (b.vec3(0), b.vec3(3), b.params[6]);
    let focal = (f2 - f1).length();
    if length <= focal {
        return Err(format!(
            "major axis length {length} must exceed the distance between the foci ({focal})"
        ));
    }
    let c = (f1 + f2) * 0.5;
    if focal == 0.0 {
        let sphere = super::Sphere::new(c, length / 2.0);
        let bounds = sphere.bounds();
        return Ok((Shape::Sphere(sphere), bounds));
    }
    let a = (f2 - f1) * (length / (2.0 * focal));
    let r = (a.length_squared() - (focal / 2.0).powi(2)).sqrt();
    Ok(of_revolution(c, a, r))
}

/// ELL1: centre V, semi-major axis vector A, radius of revolution R.
pub(crate) fn prepare_ell1(b: &Body, _: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    let a = nonzero(b.vec3(3), "semi-major axis")?;
    Ok(of_revolution(
        b.vec3(0),
        a,
        positive(b.params[6], "radius of revolution")?,
    ))
}

/// ELLG: centre V, three semi-axis vectors A, B, C spanning a volume.
pub(crate) fn prepare_ellg(b: &Body, _: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    let (a, bb, c) = (
        nonzero(b.vec3(3), "semi-axis A")?,
        nonzero(b.vec3(6), "semi-axis B")?,
        nonzero(b.vec3(9), "semi-axis C")?,
    );
    independent(a, bb, c, "semi-axes A, B and C")?;
    let e = Ellipsoid::new(b.vec3(0), DMat3::from_cols(a, bb, c));
    let bounds = e.bounds();
    Ok((Shape::Ellipsoid(e), bounds))
}

/// The ellipsoid of revolution about semi-axis `a` with radius `r`.
fn of_revolution(c: DVec3, a: DVec3, r: f64) -> (Shape, Aabb) {
    let (u, w) = orthonormal_basis(a.normalize());
    let e = Ellipsoid::new(c, DMat3::from_cols(a, u * r, w * r));
    let bounds = e.bounds();
    (Shape::Ellipsoid(e), bounds)
}
