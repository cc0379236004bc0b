use super::SegLanes;
use super::{quadratic, Seg};
use sv_math::lanes::{along, dot, mat_vec, normalize, not, sub_point, Lanes};
use sv_math::simd::Simd;
use sv_math::{Aabb, DMat3, DVec3, Ray};

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

    #[inline]
    pub(crate) fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
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
        }
    }

    pub(crate) fn normal(&self, p: DVec3) -> DVec3 {
        (self.inv_t * (self.inv * (p - self.c))).normalize()
    }

    /// [`Ellipsoid::normal`] in every lane, operation for operation.
    #[inline(always)]
    pub fn normal_lanes<S: Simd>(&self, s: S, p: [S::F; 3]) -> [S::F; 3] {
        let q = mat_vec(s, &self.inv, sub_point(s, p, self.c));
        normalize(s, mat_vec(s, &self.inv_t, q))
    }

    pub(crate) fn contains(&self, p: DVec3) -> bool {
        (self.inv * (p - self.c)).length_squared() < 1.0
    }

    pub(crate) fn bounds(&self) -> Aabb {
        // Half-extent along axis i is the length of row i of M.
        let r = self.m.transpose();
        let e = DVec3::new(r.x_axis.length(), r.y_axis.length(), r.z_axis.length());
        Aabb::new(self.c - e, self.c + e)
    }
}

/// A general quadric `x·Mx + 2 b·x + c < 0` (QUA and the infinite
/// cylinders). May be unbounded and may give two segments.
#[derive(Clone, Debug)]
pub struct Quadric {
    m: DMat3,
    b: DVec3,
    c: f64,
}

impl Quadric {
    /// From the symmetric-matrix form.
    pub fn new(m: DMat3, b: DVec3, c: f64) -> Quadric {
        Quadric { m, b, c }
    }

    fn value(&self, p: DVec3) -> f64 {
        p.dot(self.m * p) + 2.0 * self.b.dot(p) + self.c
    }

    pub(crate) fn shoot(&self, ray: &Ray, out: &mut Vec<Seg>) {
        let (o, d) = (ray.origin, ray.dir);
        let md = self.m * d;
        let a = d.dot(md);
        let b = md.dot(o) + self.b.dot(d);
        let c = self.value(o);
        let inf = f64::INFINITY;
        let scale = self
            .m
            .x_axis
            .abs()
            .max_element()
            .max(self.m.y_axis.abs().max_element())
            .max(self.m.z_axis.abs().max_element());
        if a.abs() <= 1e-14 * scale {
            // Linear along the ray: 2 b t + c < 0.
            if b == 0.0 {
                if c < 0.0 {
                    out.push(Seg {
                        t0: -inf,
                        t1: inf,
                        f0: 0,
                        f1: 0,
                    });
                }
            } else {
                let t = -c / (2.0 * b);
                if b > 0.0 {
                    out.push(Seg {
                        t0: -inf,
                        t1: t,
                        f0: 0,
                        f1: 0,
                    });
                } else {
                    out.push(Seg {
                        t0: t,
                        t1: inf,
                        f0: 0,
                        f1: 0,
                    });
                }
            }
            return;
        }
        match quadratic(a, b, c) {
            Some((t0, t1)) if a > 0.0 && t1 > t0 => out.push(Seg {
                t0,
                t1,
                f0: 0,
                f1: 0,
            }),
            Some(_) if a > 0.0 => {}
            Some((t0, t1)) => {
                out.push(Seg {
                    t0: -inf,
                    t1: t0,
                    f0: 0,
                    f1: 0,
                });
                out.push(Seg {
                    t0: t1,
                    t1: inf,
                    f0: 0,
                    f1: 0,
                });
            }
            None if a < 0.0 => out.push(Seg {
                t0: -inf,
                t1: inf,
                f0: 0,
                f1: 0,
            }),
            None => {}
        }
    }

    pub(crate) fn normal(&self, p: DVec3) -> DVec3 {
        (self.m * p + self.b).normalize()
    }

    pub(crate) fn contains(&self, p: DVec3) -> bool {
        self.value(p) < 0.0
    }
}
