//! Bodies as written, checked and turned into their ray-casting form
//! ([`prepare`]): every rule a body's values must keep is tested here and
//! names the body and the rule broken.

use crate::model::{quadric_matrix, Body};
use crate::shape::polyhedron_hull as hull;
use crate::shape::{
    Cone, Ellipsoid, GeneralCone, Mesh, Plane, Polyhedron, Quadric, Shape, Sphere, Torus,
};
use crate::table::BodyKind;
use std::fmt;
use sv_math::{orthonormal_basis, Aabb, DMat3, DVec3};

/// Something wrong with a body that was nevertheless rendered.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// Body name.
    pub body: String,
    /// Body type.
    pub kind: BodyKind,
    /// What is off and what was done about it.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} `{}`: {}", self.kind, self.body, self.message)
    }
}

fn finite(b: &Body) -> Result<(), String> {
    for (i, v) in b.params.iter().enumerate() {
        if !v.is_finite() {
            return Err(format!("value {} is not a finite number", i + 1));
        }
    }
    Ok(())
}

/// The triangles of an ARS: each pair of neighbouring curves joined by two
/// triangles per point (curves are closed), and the first and last curves
/// closed by fans (which vanish where a curve is a single point). The
/// winding is consistent, so the mesh orients itself (see [`Mesh::new`]).
/// `b` must be a well-formed ARS (checked by `prepare`).
pub fn ars_triangles(b: &Body) -> Vec<[DVec3; 3]> {
    let (nc, np) = (b.params[0] as usize, b.params[1] as usize);
    let curve = |i: usize, j: usize| b.vec3(2 + 3 * (i * np + j % np));
    let mut tris = Vec::with_capacity(2 * nc * np + 2 * np);
    for i in 0..nc.saturating_sub(1) {
        for j in 0..np {
            let (a, bq, c, d) = (
                curve(i, j),
                curve(i, j + 1),
                curve(i + 1, j + 1),
                curve(i + 1, j),
            );
            tris.push([a, bq, c]);
            tris.push([a, c, d]);
        }
    }
    for j in 1..np.saturating_sub(1) {
        tris.push([curve(0, 0), curve(0, j + 1), curve(0, j)]);
        tris.push([curve(nc - 1, 0), curve(nc - 1, j), curve(nc - 1, j + 1)]);
    }
    tris
}

/// ARB4…ARB7 as the eight points of an ARB8 (BRL-CAD's conventions).
pub fn arb_points(b: &Body) -> Vec<DVec3> {
    let n = b.params.len() / 3;
    let p: Vec<DVec3> = (0..n).map(|i| b.vec3(3 * i)).collect();
    match b.kind {
        BodyKind::Arb4 => vec![p[0], p[1], p[2], p[0], p[3], p[3], p[3], p[3]],
        BodyKind::Arb5 => vec![p[0], p[1], p[2], p[3], p[4], p[4], p[4], p[4]],
        BodyKind::Arb6 => vec![p[0], p[1], p[2], p[3], p[4], p[4], p[5], p[5]],
        BodyKind::Arb7 => vec![p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[4]],
        _ => p,
    }
}

/// The six faces of an ARB8 by vertex numbers (1-based), as BRL-CAD names them.
const ARB_FACES: [[usize; 4]; 6] = [
    [1, 2, 3, 4],
    [5, 6, 7, 8],
    [1, 4, 8, 5],
    [2, 3, 7, 6],
    [1, 2, 6, 5],
    [4, 3, 7, 8],
];

fn polyhedron_from_points(
    b: &Body,
    pts: &[DVec3],
    warnings: &mut Vec<Warning>,
    check_faces: bool,
) -> Result<(Shape, Aabb), String> {
    let bounds = Aabb::from_points(pts.iter().copied());
    let size = bounds.diagonal();
    if size == 0.0 {
        return Err("all vertices coincide".into());
    }
    let eps = 1e-9 * size;
    if check_faces {
        for f in ARB_FACES {
            let v: Vec<DVec3> = f.iter().map(|&i| pts[i - 1]).collect();
            let mut distinct: Vec<DVec3> = Vec::new();
            for p in &v {
                if !distinct.iter().any(|q| (*q - *p).length() <= eps) {
                    distinct.push(*p);
                }
            }
            if distinct.len() == 4 {
                let n = (distinct[1] - distinct[0]).cross(distinct[2] - distinct[0]);
                if n.length() > 0.0 {
                    let off = (distinct[3] - distinct[0]).dot(n.normalize()).abs();
                    if off > 1e-6 * size {
                        warnings.push(Warning {
                            body: b.name.clone(),
                            kind: b.kind,
                            message: format!(
                                "face {}{}{}{} is not planar (a vertex is {:.4} off the plane of the other three); using the convex hull of the vertices",
                                f[0], f[1], f[2], f[3], off
                            ),
                        });
                    }
                }
            }
        }
    }
    let h = hull(pts, eps);
    if h.volume <= 1e-12 * size * size * size || h.planes.len() < 4 {
        return Err("the vertices span no volume (degenerate polyhedron)".into());
    }
    Ok((Shape::Polyhedron(Polyhedron::new(h.planes, bounds)), bounds))
}

fn half_space(n: DVec3, d: f64) -> Result<(Shape, Aabb), String> {
    let len = n.length();
    if len == 0.0 {
        return Err("normal vector is zero".into());
    }
    let n = n / len;
    let d = d / len;
    // Axis-aligned half-spaces have bounds open on one side only.
    let mut bounds = Aabb::INFINITE;
    for a in 0..3 {
        if n[a].abs() == 1.0 {
            if n[a] > 0.0 {
                bounds.max[a] = d;
            } else {
                bounds.min[a] = -d;
            }
        }
    }
    Ok((
        Shape::Polyhedron(Polyhedron::new(vec![Plane { n, d }], bounds)),
        bounds,
    ))
}

fn nonzero(v: DVec3, what: &str) -> Result<DVec3, String> {
    if v.length_squared() == 0.0 {
        Err(format!("{what} is zero"))
    } else {
        Ok(v)
    }
}

fn positive(x: f64, what: &str) -> Result<f64, String> {
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("{what} must be positive (is {x})"))
    }
}

fn independent(a: DVec3, b: DVec3, c: DVec3, what: &str) -> Result<(), String> {
    let det = a.cross(b).dot(c).abs();
    if det <= 1e-12 * a.length() * b.length() * c.length() {
        Err(format!("{what} are coplanar (zero volume)"))
    } else {
        Ok(())
    }
}

fn perpendicular(a: DVec3, b: DVec3, what: &str) -> Result<(), String> {
    if a.dot(b).abs() > 1e-5 * a.length() * b.length() {
        Err(format!("{what} are not perpendicular"))
    } else {
        Ok(())
    }
}

/// The prepared shape of body `b` and its bounds, or the rule its values
/// break. Warnings (a body rendered though something is off) go to
/// `warnings`.
pub fn prepare(b: &Body, warnings: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    use BodyKind::*;
    finite(b)?;
    let expect = b.kind.info().value_count();
    if b.kind == Ars {
        if b.params.len() < 2 {
            return Err("missing curve and point counts".into());
        }
        let (nc, np) = (b.params[0], b.params[1]);
        if nc.fract() != 0.0 || np.fract() != 0.0 || nc < 2.0 || np < 3.0 {
            return Err(format!(
                "needs at least 2 curves of at least 3 points (has {nc} curves of {np})"
            ));
        }
        if b.params.len() != 2 + 3 * (nc as usize) * (np as usize) {
            return Err(format!(
                "{nc} curves of {np} points need {} values, found {}",
                3.0 * nc * np,
                b.params.len() - 2
            ));
        }
    } else if b.params.len() != expect {
        return Err(format!("takes {expect} values, found {}", b.params.len()));
    }
    let v = |i: usize| b.vec3(i);
    let s = |i: usize| b.params[i];
    let shape = match b.kind {
        Sph => {
            let sp = Sphere::new(v(0), positive(s(3), "radius")?);
            let bb = sp.bounds();
            return Ok((Shape::Sphere(sp), bb));
        }
        Rcc => {
            let h = nonzero(v(3), "height vector")?;
            let r = positive(s(6), "radius")?;
            let (u, w) = orthonormal_basis(h.normalize());
            Shape::Cone(Cone::new(v(0), u * r, w * r, h, 1.0))
        }
        Rec => {
            let (h, a, bb) = (
                nonzero(v(3), "height vector")?,
                nonzero(v(6), "semi-axis A")?,
                nonzero(v(9), "semi-axis B")?,
            );
            independent(a, bb, h, "A, B and H")?;
            Shape::Cone(Cone::new(v(0), a, bb, h, 1.0))
        }
        Trc => {
            let h = nonzero(v(3), "height vector")?;
            let (r1, r2) = (s(6), s(7));
            if r1 < 0.0 || r2 < 0.0 || (r1 == 0.0 && r2 == 0.0) {
                return Err(format!(
                    "radii must be non-negative and not both zero (are {r1} and {r2})"
                ));
            }
            let (u, w) = orthonormal_basis(h.normalize());
            if r1 > 0.0 {
                Shape::Cone(Cone::new(v(0), u * r1, w * r1, h, r2 / r1))
            } else {
                // Apex at the base: build it from the top down.
                Shape::Cone(Cone::new(v(0) + h, u * r2, w * r2, -h, 0.0))
            }
        }
        Tec => {
            let (h, a, bb) = (
                nonzero(v(3), "height vector")?,
                nonzero(v(6), "semi-axis A")?,
                nonzero(v(9), "semi-axis B")?,
            );
            independent(a, bb, h, "A, B and H")?;
            let p = positive(s(12), "ratio P")?;
            Shape::Cone(Cone::new(v(0), a, bb, h, 1.0 / p))
        }
        Tgc => {
            let (h, a, bb) = (
                nonzero(v(3), "height vector")?,
                nonzero(v(6), "semi-axis A")?,
                nonzero(v(9), "semi-axis B")?,
            );
            independent(a, bb, h, "A, B and H")?;
            let (c, d) = (s(12), s(13));
            if c < 0.0 || d < 0.0 {
                return Err(format!(
                    "top semi-axes must be non-negative (are {c} and {d})"
                ));
            }
            let (ra, rb) = (c / a.length(), d / bb.length());
            if (ra - rb).abs() <= 1e-12 * ra.max(rb) {
                Shape::Cone(Cone::new(v(0), a, bb, h, ra))
            } else {
                Shape::GeneralCone(GeneralCone::new(v(0), a, bb, h, ra, rb))
            }
        }
        Ell => {
            let (f1, f2, l) = (v(0), v(3), s(6));
            let fd = (f2 - f1).length();
            if l <= fd {
                return Err(format!(
                    "major axis length {l} must exceed the distance between the foci ({fd})"
                ));
            }
            let c = (f1 + f2) * 0.5;
            if fd == 0.0 {
                let sp = Sphere::new(c, l / 2.0);
                let bb = sp.bounds();
                return Ok((Shape::Sphere(sp), bb));
            }
            let a = (f2 - f1) * (l / (2.0 * fd));
            let r = (a.length_squared() - (fd / 2.0).powi(2)).sqrt();
            ellipsoid_of_revolution(c, a, r)
        }
        Ell1 => {
            let a = nonzero(v(3), "semi-major axis")?;
            ellipsoid_of_revolution(v(0), a, positive(s(6), "radius of revolution")?)
        }
        Ellg => {
            let (a, bb, c) = (
                nonzero(v(3), "semi-axis A")?,
                nonzero(v(6), "semi-axis B")?,
                nonzero(v(9), "semi-axis C")?,
            );
            independent(a, bb, c, "semi-axes A, B and C")?;
            Shape::Ellipsoid(Ellipsoid::new(v(0), DMat3::from_cols(a, bb, c)))
        }
        Rpp => {
            let min = DVec3::new(s(0), s(2), s(4));
            let max = DVec3::new(s(1), s(3), s(5));
            for (a, n) in ["x", "y", "z"].iter().enumerate() {
                if min[a] >= max[a] {
                    return Err(format!(
                        "{n}min ({}) must be less than {n}max ({})",
                        min[a], max[a]
                    ));
                }
            }
            let bb = Aabb::new(min, max);
            return Ok((Shape::Rpp(crate::shape::Rpp::new(bb)), bb));
        }
        Box => {
            let (a, bb, c) = (
                nonzero(v(3), "edge A")?,
                nonzero(v(6), "edge B")?,
                nonzero(v(9), "edge C")?,
            );
            perpendicular(a, bb, "edges A and B")?;
            perpendicular(a, c, "edges A and C")?;
            perpendicular(bb, c, "edges B and C")?;
            let o = v(0);
            let pts: Vec<DVec3> = (0..8)
                .map(|i| {
                    o + a * (i & 1) as f64 + bb * ((i >> 1) & 1) as f64 + c * ((i >> 2) & 1) as f64
                })
                .collect();
            return polyhedron_from_points(b, &pts, warnings, false);
        }
        Raw => {
            let (a, bb, c) = (
                nonzero(v(3), "leg A")?,
                nonzero(v(6), "leg B")?,
                nonzero(v(9), "sweep C")?,
            );
            independent(a, bb, c, "A, B and C")?;
            let o = v(0);
            let pts = [o, o + a, o + bb, o + c, o + a + c, o + bb + c];
            return polyhedron_from_points(b, &pts, warnings, false);
        }
        Arb4 | Arb5 | Arb6 | Arb7 | Arb8 => {
            let pts = arb_points(b);
            return polyhedron_from_points(b, &pts, warnings, b.kind == Arb8);
        }
        ArbF => {
            let pts: Vec<DVec3> = (0..8).map(|i| v(3 * i)).collect();
            let mut used = [false; 8];
            for code in &b.params[24..30] {
                let c = code.abs().round() as u64;
                let mut x = c;
                while x > 0 {
                    let d = (x % 10) as usize;
                    if d == 0 || d > 8 {
                        return Err(format!(
                            "face code {code} names vertex {d}, which does not exist"
                        ));
                    }
                    used[d - 1] = true;
                    x /= 10;
                }
            }
            let pts: Vec<DVec3> = pts
                .iter()
                .zip(used)
                .filter(|(_, u)| *u)
                .map(|(p, _)| *p)
                .collect();
            if pts.len() < 4 {
                return Err("face codes use fewer than 4 vertices".into());
            }
            return polyhedron_from_points(b, &pts, warnings, false);
        }
        Tor => {
            let n = nonzero(v(3), "normal")?;
            let (r1, r2) = (
                positive(s(6), "major radius")?,
                positive(s(7), "minor radius")?,
            );
            if r2 >= r1 {
                return Err(format!(
                    "minor radius {r2} must be smaller than major radius {r1}"
                ));
            }
            let t = Torus::new(v(0), n, r1, r2);
            let bb = t.bounds();
            return Ok((Shape::Torus(t), bb));
        }
        Haf => return half_space(v(0), s(3)),
        Xyp => return half_space(DVec3::Z, s(0)),
        Xzp => return half_space(DVec3::Y, s(0)),
        Yzp => return half_space(DVec3::X, s(0)),
        Pla => {
            let n = nonzero(v(0), "normal")?;
            return half_space(n, n.dot(v(3)));
        }
        Xcc | Ycc | Zcc | Xec | Yec | Zec => {
            let radii: &[f64] = &b.params[2..];
            for r in radii {
                positive(*r, "radius")?;
            }
            let (a1, a2) = crate::model::cyl_axes(b.kind);
            let (r1, r2) = (radii[0], *radii.last().unwrap_or(&radii[0]));
            let mut bb = Aabb::INFINITE;
            bb.min[a1] = s(0) - r1;
            bb.max[a1] = s(0) + r1;
            bb.min[a2] = s(1) - r2;
            bb.max[a2] = s(1) + r2;
            let (m, bv, c) = quadric_matrix(&b.as_quadric());
            return Ok((Shape::Quadric(Quadric::new(m, bv, c)), bb));
        }
        Qua => {
            if b.params.iter().all(|x| *x == 0.0) {
                return Err("all coefficients are zero".into());
            }
            let (m, bv, c) = quadric_matrix(&b.params);
            return Ok((Shape::Quadric(Quadric::new(m, bv, c)), Aabb::INFINITE));
        }
        Ars => {
            let tris = ars_triangles(b);
            let m = Mesh::new(&tris);
            if m.triangle_count() < 4 {
                return Err("the curves span no surface (degenerate ARS)".into());
            }
            let bb = m.bounds();
            return Ok((Shape::Mesh(m), bb));
        }
    };
    let bb = shape.bounds();
    Ok((shape, bb))
}

fn ellipsoid_of_revolution(c: DVec3, a: DVec3, r: f64) -> Shape {
    let (u, w) = orthonormal_basis(a.normalize());
    Shape::Ellipsoid(Ellipsoid::new(c, DMat3::from_cols(a, u * r, w * r)))
}
