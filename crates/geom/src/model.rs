//! Bodies and regions as the user wrote them (before `prepare`).

use crate::region::{Region, Universe};
use crate::table::{BodyKind, ParamKind};
use sv_math::{DAffine3, DMat3, DVec3};

/// A body as written: its type and its values in card order (see
/// [`crate::table::BODY_TYPES`]). ARS values are `curves, points_per_curve`
/// followed by every point's three coordinates, curve by curve.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Name or number as the user refers to it (`"1"`, `"fuselage"`).
    pub name: String,
    /// Body type.
    pub kind: BodyKind,
    /// Values in card order.
    pub params: Vec<f64>,
}

/// Bodies and regions: the whole Combinatorial Geometry model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Geometry {
    /// Every body.
    pub bodies: Vec<Body>,
    /// Every region, of every universe.
    pub regions: Vec<Region>,
    /// The universes other regions fill ([`crate::Fill`]), by index; the
    /// root (index 0, the model itself) need not be listed: an empty list
    /// means a model of one universe.
    pub universes: Vec<Universe>,
}

/// A transform that a body cannot take.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TransformError {
    /// Shear or unequal scaling would turn the body into another shape.
    #[error("only rotations, translations and uniform expansions can be applied to bodies")]
    NotSimilarity,
}

impl Body {
    /// A new body.
    pub fn new(name: impl Into<String>, kind: BodyKind, params: Vec<f64>) -> Body {
        Body {
            name: name.into(),
            kind,
            params,
        }
    }

    /// The point value starting at `i`.
    pub fn vec3(&self, i: usize) -> DVec3 {
        DVec3::new(self.params[i], self.params[i + 1], self.params[i + 2])
    }

    /// The body moved by `xf`, which must be a similarity (rotation,
    /// translation and uniform scale), as MOVE, TURN and the FLUKA
    /// `$start_transform`/`$start_expansion` directives need. Axis-aligned
    /// bodies that are turned off their axes become their general forms
    /// (RPP → BOX, XYP → PLA, XCC → QUA).
    pub fn transformed(&self, xf: &DAffine3) -> Result<Body, TransformError> {
        let m = xf.matrix3;
        let det = m.determinant();
        if det <= 0.0 {
            return Err(TransformError::NotSimilarity);
        }
        let s = det.cbrt();
        let rot = m * (1.0 / s);
        if !(rot.transpose() * rot).abs_diff_eq(DMat3::IDENTITY, 1e-9) {
            return Err(TransformError::NotSimilarity);
        }
        let axis_aligned = rot.abs_diff_eq(DMat3::IDENTITY, 0.0);
        let t = xf.translation;
        use BodyKind::*;
        let mut b = self.clone();
        match self.kind {
            Rpp if axis_aligned => {
                for a in 0..3 {
                    b.params[2 * a] = self.params[2 * a] * s + t[a];
                    b.params[2 * a + 1] = self.params[2 * a + 1] * s + t[a];
                }
            }
            Rpp => {
                let min = DVec3::new(self.params[0], self.params[2], self.params[4]);
                let max = DVec3::new(self.params[1], self.params[3], self.params[5]);
                let d = max - min;
                let mut p = vec![
                    min.x, min.y, min.z, d.x, 0.0, 0.0, 0.0, d.y, 0.0, 0.0, 0.0, d.z,
                ];
                b.kind = Box;
                std::mem::swap(&mut b.params, &mut p);
                return b.transformed(xf);
            }
            Haf => {
                let n = self.vec3(0);
                let len = n.length();
                let n2 = rot * n;
                // Plane N·x = D; a point on it is D N/|N|².
                let p0 = xf.transform_point3(n * (self.params[3] / (len * len)));
                b.params = vec![n2.x, n2.y, n2.z, n2.dot(p0)];
            }
            Xyp | Xzp | Yzp if axis_aligned => {
                let a = match self.kind {
                    Xyp => 2,
                    Xzp => 1,
                    _ => 0,
                };
                b.params[0] = self.params[0] * s + t[a];
            }
            Xyp | Xzp | Yzp => {
                let a = match self.kind {
                    Xyp => 2,
                    Xzp => 1,
                    _ => 0,
                };
                let mut n = DVec3::ZERO;
                n[a] = 1.0;
                let p = n * self.params[0];
                let pla = Body::new(self.name.clone(), Pla, vec![n.x, n.y, n.z, p.x, p.y, p.z]);
                return pla.transformed(xf);
            }
            Xcc | Ycc | Zcc | Xec | Yec | Zec if axis_aligned => {
                let (a1, a2) = cyl_axes(self.kind);
                b.params[0] = self.params[0] * s + t[a1];
                b.params[1] = self.params[1] * s + t[a2];
                for v in &mut b.params[2..] {
                    *v *= s;
                }
            }
            Xcc | Ycc | Zcc | Xec | Yec | Zec => {
                let q = Body::new(self.name.clone(), Qua, self.as_quadric().to_vec());
                return q.transformed(xf);
            }
            Qua => {
                b.params = transform_quadric(&self.params, xf).to_vec();
            }
            Ars => {
                for i in (2..self.params.len()).step_by(3) {
                    let q = xf.transform_point3(self.vec3(i));
                    b.params[i..i + 3].copy_from_slice(&q.to_array());
                }
            }
            _ => {
                let mut i = 0;
                for prm in self.kind.info().params {
                    match prm.kind {
                        ParamKind::Point => {
                            let q = xf.transform_point3(self.vec3(i));
                            b.params[i..i + 3].copy_from_slice(&q.to_array());
                        }
                        ParamKind::Vector => {
                            let q = m * self.vec3(i);
                            b.params[i..i + 3].copy_from_slice(&q.to_array());
                        }
                        ParamKind::Length => b.params[i] *= s,
                        ParamKind::Number => {}
                    }
                    i += prm.kind.width();
                }
            }
        }
        Ok(b)
    }

    /// The ten QUA coefficients of an axis-aligned infinite cylinder
    /// (`XCC`…`ZEC`); panics for other kinds.
    pub fn as_quadric(&self) -> [f64; 10] {
        let (a1, a2) = cyl_axes(self.kind);
        let (c1, c2) = (self.params[0], self.params[1]);
        let (l1, l2) = match self.kind {
            BodyKind::Xcc | BodyKind::Ycc | BodyKind::Zcc => (self.params[2], self.params[2]),
            _ => (self.params[2], self.params[3]),
        };
        // (x1-c1)²/l1² + (x2-c2)²/l2² - 1 < 0
        let mut q = [0.0; 10];
        q[a1] = 1.0 / (l1 * l1);
        q[a2] = 1.0 / (l2 * l2);
        q[6 + a1] = -2.0 * c1 / (l1 * l1);
        q[6 + a2] = -2.0 * c2 / (l2 * l2);
        q[9] = c1 * c1 / (l1 * l1) + c2 * c2 / (l2 * l2) - 1.0;
        q
    }
}

/// The two coordinate axes (0 = x) that give the centre of an axis-aligned
/// infinite cylinder, in FLUKA's cyclic order (XCC: y z, YCC: z x, ZCC: x y).
pub fn cyl_axes(kind: BodyKind) -> (usize, usize) {
    use BodyKind::*;
    match kind {
        Xcc | Xec => (1, 2),
        Ycc | Yec => (2, 0),
        Zcc | Zec => (0, 1),
        _ => panic!("{kind} is not an axis-aligned cylinder"),
    }
}

/// Symmetric matrix form of a quadric: `x·Mx + 2 b·x + c`.
pub fn quadric_matrix(q: &[f64]) -> (DMat3, DVec3, f64) {
    let m = DMat3::from_cols(
        DVec3::new(q[0], q[3] / 2.0, q[4] / 2.0),
        DVec3::new(q[3] / 2.0, q[1], q[5] / 2.0),
        DVec3::new(q[4] / 2.0, q[5] / 2.0, q[2]),
    );
    (m, DVec3::new(q[6], q[7], q[8]) / 2.0, q[9])
}

fn transform_quadric(q: &[f64], xf: &DAffine3) -> [f64; 10] {
    // Q'(y) = Q(x) with x = inv(y): x = A y + t.
    let inv = xf.inverse();
    let (m, b, c) = quadric_matrix(q);
    let a = inv.matrix3;
    let t = inv.translation;
    let m2 = a.transpose() * m * a;
    let b2 = a.transpose() * (m * t + b);
    let c2 = t.dot(m * t) + 2.0 * b.dot(t) + c;
    [
        m2.x_axis.x,
        m2.y_axis.y,
        m2.z_axis.z,
        2.0 * m2.y_axis.x,
        2.0 * m2.z_axis.x,
        2.0 * m2.z_axis.y,
        2.0 * b2.x,
        2.0 * b2.y,
        2.0 * b2.z,
        c2,
    ]
}

impl Geometry {
    /// Index of the body called `name`.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// Index of the region called `name`.
    pub fn region_index(&self, name: &str) -> Option<usize> {
        self.regions.iter().position(|r| r.name == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quadric_value(q: &[f64], p: DVec3) -> f64 {
        let (m, b, c) = quadric_matrix(q);
        p.dot(m * p) + 2.0 * b.dot(p) + c
    }

    #[test]
    fn turned_cylinder_becomes_an_equivalent_quadric() {
        let xcc = Body::new("c", BodyKind::Ycc, vec![1.0, 2.0, 0.5]); // axis through z=1, x=2
        let xf =
            DAffine3::from_rotation_z(0.3) * DAffine3::from_translation(DVec3::new(0.0, 0.0, 1.0));
        let q = xcc.transformed(&xf).unwrap();
        assert_eq!(q.kind, BodyKind::Qua);
        // A point on the original surface maps to a point on the new one.
        let p = DVec3::new(2.5, 7.0, 1.0);
        assert!(quadric_value(&xcc.as_quadric(), p).abs() < 1e-12);
        assert!(quadric_value(&q.params, xf.transform_point3(p)).abs() < 1e-9);
        let inside = DVec3::new(2.1, -3.0, 1.1);
        assert!(quadric_value(&q.params, xf.transform_point3(inside)) < 0.0);
    }

    #[test]
    fn shear_is_refused() {
        let b = Body::new("s", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0]);
        let shear = DAffine3::from_mat3(DMat3::from_cols(
            DVec3::X,
            DVec3::new(0.5, 1.0, 0.0),
            DVec3::Z,
        ));
        assert_eq!(b.transformed(&shear), Err(TransformError::NotSimilarity));
    }

    #[test]
    fn turned_rpp_becomes_box_and_half_space_keeps_its_plane() {
        let rpp = Body::new("r", BodyKind::Rpp, vec![0.0, 1.0, 0.0, 2.0, 0.0, 3.0]);
        let xf = sv_math::rotation_about_axis(DVec3::ZERO, DVec3::Z, 90.0);
        let bx = rpp.transformed(&xf).unwrap();
        assert_eq!(bx.kind, BodyKind::Box);
        assert!((bx.vec3(3) - DVec3::new(0.0, 1.0, 0.0)).length() < 1e-12);
        let haf = Body::new("h", BodyKind::Haf, vec![0.0, 0.0, 2.0, 4.0]); // z <= 2
        let moved = haf
            .transformed(&DAffine3::from_translation(DVec3::new(0.0, 0.0, 1.0)))
            .unwrap();
        // Now z <= 3: N=(0,0,2), D=6.
        assert!((moved.params[3] / moved.params[2] - 3.0).abs() < 1e-12);
    }
}
