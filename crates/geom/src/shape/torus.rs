use super::poly::roots_in;
use super::{segments_by_classification, Seg};
use crate::body::{nonzero, positive, Warning};
use crate::Body;
use sv_math::{Aabb, DMat3, DVec3, Ray};

/// A torus: centre, unit axis, major radius `r1`, minor radius `r2 < r1`.
/// A ray may cross it four times, so it can give two segments.
#[derive(Clone, Debug)]
pub struct Torus {
    c: DVec3,
    /// Rows are the local x, y, z (= axis) directions: local = rot·(p − c).
    rot: DMat3,
    r1: f64,
    r2: f64,
    axis: DVec3,
}

impl Torus {
    /// A torus about the line through `c` along `axis`.
    pub fn new(c: DVec3, axis: DVec3, r1: f64, r2: f64) -> Torus {
        let n = axis.normalize();
        let (u, v) = sv_math::orthonormal_basis(n);
        let rot = DMat3::from_cols(u, v, n).transpose();
        Torus {
            c,
            rot,
            r1,
            r2,
            axis: n,
        }
    }

    fn inside_local(&self, q: DVec3) -> bool {
        let rho = (q.x * q.x + q.y * q.y).sqrt() - self.r1;
        rho * rho + q.z * q.z < self.r2 * self.r2
    }

    pub(crate) fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        let o = self.rot * (ray.origin - self.c);
        let d = self.rot * ray.dir;
        let e = self.r1 + self.r2;
        let lb = Aabb::new(DVec3::new(-e, -e, -self.r2), DVec3::new(e, e, self.r2));
        let Some((lo, hi)) = lb.ray_range(&Ray {
            origin: o,
            dir: d,
            inv_dir: d.recip(),
        }) else {
            return;
        };
        // Shift the origin to the box entry so the quartic is well scaled.
        let o = o + d * lo;
        let (a2, b2) = (self.r1 * self.r1, self.r2 * self.r2);
        let f = o.dot(d);
        let g = o.length_squared() - a2 - b2;
        let coef = [
            g * g - 4.0 * a2 * (b2 - o.z * o.z),
            4.0 * f * g + 8.0 * a2 * o.z * d.z,
            2.0 * g + 4.0 * f * f + 4.0 * a2 * d.z * d.z,
            4.0 * f,
            1.0,
        ];
        let mut roots = [0.0; 4];
        let n = roots_in(&coef, 0.0, hi - lo, &mut roots);
        if n == 0 {
            return;
        }
        let mut cands = [(0.0, 0u32); 4];
        for i in 0..n {
            cands[i] = (roots[i] + lo, 0);
        }
        let inside = |p: DVec3| self.inside_local(self.rot * (p - self.c));
        segments_by_classification(&mut cands[..n], ray, inside, out);
    }

    pub(crate) fn normal(&self, p: DVec3) -> DVec3 {
        let q = self.rot * (p - self.c);
        let ring = DVec3::new(q.x, q.y, 0.0).normalize_or_zero() * self.r1;
        (self.rot.transpose() * (q - ring)).normalize()
    }

    pub(crate) fn contains(&self, p: DVec3) -> bool {
        self.inside_local(self.rot * (p - self.c))
    }

    pub(crate) fn bounds(&self) -> Aabb {
        // Extent along world axis i: r1·sqrt(1 − n_i²) + r2.
        let n = self.axis;
        let e = DVec3::new(
            self.r1 * (1.0 - n.x * n.x).max(0.0).sqrt() + self.r2,
            self.r1 * (1.0 - n.y * n.y).max(0.0).sqrt() + self.r2,
            self.r1 * (1.0 - n.z * n.z).max(0.0).sqrt() + self.r2,
        );
        Aabb::new(self.c - e, self.c + e)
    }
}

/// TOR: centre V, normal N, major radius R1 and a smaller minor radius R2.
pub(crate) fn prepare_tor(b: &Body, _: &mut Vec<Warning>) -> Result<(super::Shape, Aabb), String> {
    let n = nonzero(b.vec3(3), "normal")?;
    let (r1, r2) = (
        positive(b.params[6], "major radius")?,
        positive(b.params[7], "minor radius")?,
    );
    if r2 >= r1 {
        return Err(format!(
            "minor radius {r2} must be smaller than major radius {r1}"
        ));
    }
    let torus = Torus::new(b.vec3(0), n, r1, r2);
    let bounds = torus.bounds();
    Ok((super::Shape::Torus(torus), bounds))
}
