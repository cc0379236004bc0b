use super::{quadratic, Seg, Shape};
use crate::body::{positive, Warning};
use crate::model::{cyl_axes, quadric_matrix};
use crate::Body;
use sv_math::{Aabb, DMat3, DVec3, Ray};

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

/// XCC, YCC, ZCC, XEC, YEC, ZEC: infinite cylinders along an axis, bounded
/// across it by their radii.
pub(crate) fn prepare_axis_cylinder(
    b: &Body,
    _: &mut Vec<Warning>,
) -> Result<(Shape, Aabb), String> {
    let radii: &[f64] = &b.params[2..];
    for r in radii {
        positive(*r, "radius")?;
    }
    let (a1, a2) = cyl_axes(b.kind);
    let (r1, r2) = (radii[0], *radii.last().unwrap_or(&radii[0]));
    let mut bounds = Aabb::INFINITE;
    bounds.min[a1] = b.params[0] - r1;
    bounds.max[a1] = b.params[0] + r1;
    bounds.min[a2] = b.params[1] - r2;
    bounds.max[a2] = b.params[1] + r2;
    let (m, linear, c) = quadric_matrix(&b.as_quadric());
    Ok((Shape::Quadric(Quadric::new(m, linear, c)), bounds))
}

/// QUA: the ten coefficients of a quadric, not all zero.
pub(crate) fn prepare_qua(b: &Body, _: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    if b.params.iter().all(|x| *x == 0.0) {
        return Err("all coefficients are zero".into());
    }
    let (m, linear, c) = quadric_matrix(&b.params);
    Ok((Shape::Quadric(Quadric::new(m, linear, c)), Aabb::INFINITE))
}
