//! POV-Ray 3.7 scene writer, so that a model can be taken on to POV-Ray and
//! so that benchmarks trace exactly the same geometry in both programs.
//!
//! What is written:
//! - every body used by an opaque region as a POV-Ray primitive: `sphere`
//!   (SPH), `cylinder`/`cone` (RCC, TRC, and REC, TEC and similar-ended TGC
//!   through a `matrix` on the unit cylinder or cone), `box` (RPP, and BOX
//!   through a `matrix` on the unit cube), `intersection` of `plane`s (RAW,
//!   ARB4…ARB8, FLUKA ARB: the planes of the convex hull of the vertices, as
//!   the tracer uses them), scaled spheres (ELL, ELL1, ELLG), `torus` with a
//!   `matrix` (TOR), `plane` (HAF, PLA, XYP, XZP, YZP), `quadric` (QUA and
//!   the infinite cylinders XCC…ZEC), a quartic `poly` clipped by two planes
//!   (TGC whose top is not similar to its base) and `mesh` (ARS). All of
//!   these are exact;
//! - every opaque region as CSG: a zone is the `intersection` of its `+`
//!   bodies with its `-` bodies taken away (`difference`), zones joined by
//!   `union`. Transparent regions are left out (they stop no ray);
//! - the camera (perspective with POV-Ray's horizontal `angle`, or
//!   orthographic), the lights (a parallel light is a far `parallel`
//!   light; `shadowless` when the scene's shadows are off), the shading
//!   model `finish { ambient A₀ diffuse k }` with the region colour as
//!   pigment, `assumed_gamma 1` and the background.
//!
//! One thing is approximated: a point light whose intensity decays as
//! `R⁻ⁿ` (n > 0) becomes POV-Ray's `fade_power n` with a tiny
//! `fade_distance` ε, which gives `R⁻ⁿ / (1 + (ε/R)ⁿ)`: a relative error
//! below 10⁻⁸ at a tenth of the model's size from the light.
//!
//! Coordinates: ours are right-handed with `z` up, POV-Ray's are
//! left-handed with `y` up, so `y` and `z` are swapped on the way out and
//! the picture is the same.

use std::fmt::Write as _;
use sv_geom::shape::Shape;
use sv_geom::{Body, BodyKind, Op, Zone};
use sv_math::{orthonormal_basis, Aabb, DVec3};
use sv_scene::{Background, Camera, Lens, LightKind, Scene};
use sv_trace::{PrepareOptions, Prepared};

/// Write `scene` as a POV-Ray 3.7 scene for a `width`×`height` picture.
///
/// The scene must have a camera and at least one light (the `export`
/// command fills in the renderer's default framing and light first).
/// Errors name every body that cannot be written and why.
pub fn write(scene: &Scene, width: u32, height: u32) -> Result<String, String> {
    if width == 0 || height == 0 {
        return Err(format!("picture size {width}x{height} is empty"));
    }
    let cam = scene.camera.ok_or(
        "the scene has no camera; set one (CAMERA …) or let `synthavision export` frame it",
    )?;
    if scene.lights.is_empty() {
        return Err(
            "the scene has no light; add one (LIGHT …) or let `synthavision export` add it".into(),
        );
    }
    let g = &scene.geometry;
    let (prepared, warnings) =
        Prepared::new(g, &PrepareOptions::default()).map_err(|e| e.to_string())?;

    let opaque: Vec<usize> = (0..g.regions.len())
        .filter(|&r| !scene.regions.get(r).is_some_and(|p| p.transparent))
        .collect();
    // How often each body is mentioned by the regions written: bodies used
    // once are written in place, the others are declared once.
    let mut uses = vec![0usize; g.bodies.len()];
    for &r in &opaque {
        g.regions[r].for_each_term(&mut |t| uses[t.body] += 1);
    }

    let mut bodies: Vec<Option<String>> = vec![None; g.bodies.len()];
    let mut problems = Vec::new();
    for (i, b) in g.bodies.iter().enumerate() {
        if uses[i] == 0 {
            continue;
        }
        match body(b, prepared.shape(i), prepared.body_bounds(i)) {
            Ok(s) => bodies[i] = Some(s),
            Err(e) => problems.push(format!("{} `{}`: {e}", b.kind, b.name)),
        }
    }
    if !problems.is_empty() {
        return Err(problems.join("\n"));
    }

    let mut out = String::with_capacity(200 + 120 * g.bodies.len());
    header(&mut out, scene, width, height);
    for w in &warnings {
        let _ = writeln!(out, "// warning: {}", one_line(&w.to_string()));
    }
    camera(&mut out, &cam, width, height);
    lights(&mut out, scene, prepared.bounds());
    out.push('\n');
    let written = Written { uses, bodies };
    written.declarations(&mut out, scene);
    written.regions(&mut out, scene, &opaque);
    Ok(out)
}

/// The camera: POV-Ray's perspective camera takes the horizontal angle.
fn camera(out: &mut String, cam: &Camera, width: u32, height: u32) {
    let (_, up, forward) = cam.basis();
    let aspect = width as f64 / height as f64;
    let at = cam.eye + forward;
    match cam.lens {
        Lens::Ortho { height: h } => {
            let _ = writeln!(
                out,
                "camera {{\n  orthographic\n  location {}\n  right x*{}\n  up y*{}\n  sky {}\n  look_at {}\n}}",
                pv(cam.eye),
                num(h * aspect),
                num(h),
                pv(up),
                pv(at)
            );
        }
        _ => {
            let hfov = 2.0 * (cam.tan_half_fov() * aspect).atan().to_degrees();
            let _ = writeln!(
                out,
                "camera {{\n  perspective\n  location {}\n  right x*{}\n  up y\n  sky {}\n  angle {}  // horizontal; vertical {}\n  look_at {}\n}}",
                pv(cam.eye),
                num(aspect),
                pv(up),
                num(hfov),
                num(2.0 * cam.tan_half_fov().atan().to_degrees()),
                pv(at)
            );
        }
    }
}

/// The lights; a parallel light is a far `parallel` light, placed from the
/// model's `bounds`.
fn lights(out: &mut String, scene: &Scene, bounds: Aabb) {
    let (centre, size) = if bounds.is_empty() || !bounds.is_finite() {
        (DVec3::ZERO, 1.0)
    } else {
        (bounds.center(), bounds.diagonal().max(1e-6))
    };
    for l in &scene.lights {
        let col = l.colour.map(|c| c * l.intensity);
        let shadow = if scene.shadows { "" } else { " shadowless" };
        match l.kind {
            LightKind::Parallel { dir } => {
                let d = dir.normalize();
                let far = (1000.0 * size).max(1e4);
                let _ = writeln!(
                    out,
                    "light_source {{ {} color {} parallel point_at {}{shadow} }}  // {}",
                    pv(centre - d * far),
                    rgb(col),
                    pv(centre),
                    one_line(&l.name)
                );
            }
            LightKind::Point { pos, decay: 0.0 } => {
                let _ = writeln!(
                    out,
                    "light_source {{ {} color {}{shadow} }}  // {}",
                    pv(pos),
                    rgb(col),
                    one_line(&l.name)
                );
            }
            LightKind::Point { pos, decay } => {
                // POV-Ray attenuates by 2 / (1 + (R/ε)ⁿ) = 2 εⁿ R⁻ⁿ / (1 + (ε/R)ⁿ).
                let eps = 1e-4 * size;
                let scale = 1.0 / (2.0 * eps.powf(decay));
                let _ = writeln!(
                    out,
                    "light_source {{ {} color {} fade_distance {} fade_power {}{shadow} }}  // {}: R^-{}",
                    pv(pos),
                    rgb(col.map(|c| c * scale)),
                    num(eps),
                    num(decay),
                    one_line(&l.name),
                    num(decay)
                );
            }
        }
    }
}

/// The bodies as POV-Ray text, and how often the written regions use each.
struct Written {
    uses: Vec<usize>,
    bodies: Vec<Option<String>>,
}

impl Written {
    /// `#declare`s for the bodies used more than once.
    fn declarations(&self, out: &mut String, scene: &Scene) {
        let mut declared = false;
        for (i, b) in scene.geometry.bodies.iter().enumerate() {
            if self.uses[i] > 1 {
                if !declared {
                    out.push_str("// bodies used by more than one term\n");
                    declared = true;
                }
                let text = self.bodies[i].as_deref().unwrap_or_default();
                let _ = writeln!(
                    out,
                    "#declare B{i} = {text}  // {} {}",
                    b.kind,
                    one_line(&b.name)
                );
            }
        }
        if declared {
            out.push('\n');
        }
    }

    /// A body where a zone uses it: its declaration, or its text in place.
    fn body_ref(&self, i: usize) -> String {
        if self.uses[i] > 1 {
            format!("object {{ B{i} }}")
        } else {
            self.bodies[i].clone().unwrap_or_default()
        }
    }

    /// The opaque regions as CSG with their material.
    fn regions(&self, out: &mut String, scene: &Scene, opaque: &[usize]) {
        let body_ref = |i: usize| self.body_ref(i);
        for &r in opaque {
            let region = &scene.geometry.regions[r];
            let props = scene.regions.get(r);
            let colour = props.and_then(|p| p.colour).unwrap_or([1.0; 3]);
            let k = props.map_or(0.8, |p| p.k);
            let _ = writeln!(out, "// region {}", one_line(&region.name));
            let zones: Vec<String> = region.zones.iter().map(|z| zone(z, &body_ref)).collect();
            let material = format!(
                "pigment {{ {} }} finish {{ ambient {} diffuse {} specular 0 phong 0 brilliance 1 }}",
                rgb(colour),
                num(scene.ambient),
                num(k)
            );
            if zones.len() == 1 {
                // Wrap the zone so the material applies to all of it.
                let _ = writeln!(out, "object {{ {}\n  {material} }}", zones[0]);
            } else {
                out.push_str("union {\n");
                for z in &zones {
                    let _ = writeln!(out, "  {z}");
                }
                let _ = writeln!(out, "  {material}\n}}");
            }
        }
    }
}

fn header(s: &mut String, scene: &Scene, width: u32, height: u32) {
    s.push_str("#version 3.7;\n");
    if !scene.title.is_empty() {
        let _ = writeln!(s, "// {}", one_line(&scene.title));
    }
    let _ = writeln!(
        s,
        "// Written by `synthavision export --format pov` for a {width}x{height} picture:\n\
         //   povray +I<this file> +W{width} +H{height} -A +FN File_Gamma=1.0\n\
         // SynthaVision's right-handed z-up coordinates (x, y, z) are written as\n\
         // POV-Ray's left-handed y-up <x, z, y>, so the picture is the same.\n\
         // Shading: I = colour * (sum of I0 k cos(theta) + A0): finish {{ ambient A0 diffuse k }}."
    );
    let Background::Colour(bg) = scene.background;
    let _ = writeln!(
        s,
        "global_settings {{ assumed_gamma 1.0 ambient_light 1 max_trace_level 5 }}\nbackground {{ {} }}",
        rgb(bg)
    );
}

/// One zone: `+` bodies and groups intersected, `-` ones taken away (a
/// group is the union of its zones).
fn zone(z: &Zone, body_ref: &dyn Fn(usize) -> String) -> String {
    let side = |op: Op| -> Vec<String> {
        let bodies = z
            .terms
            .iter()
            .filter(|t| t.op == op)
            .map(|t| body_ref(t.body));
        let groups = z.groups.iter().filter(|g| g.op == op).map(|g| {
            let inner: Vec<String> = g.zones.iter().map(|z| zone(z, body_ref)).collect();
            if inner.len() == 1 {
                inner[0].clone()
            } else {
                format!("union {{ {} }}", inner.join(" "))
            }
        });
        bodies.chain(groups).collect()
    };
    let (plus, minus) = (side(Op::Inside), side(Op::Outside));
    let base = match plus.len() {
        0 => None,
        1 => Some(plus[0].clone()),
        _ => Some(format!("intersection {{ {} }}", plus.join(" "))),
    };
    match (base, minus.is_empty()) {
        (Some(b), true) => b,
        (Some(b), false) => format!("difference {{ {b} {} }}", minus.join(" ")),
        // Only `-` terms: everything outside those bodies.
        (None, _) => format!(
            "intersection {{ {} }}",
            minus
                .iter()
                .map(|m| format!("object {{ {m} inverse }}"))
                .collect::<Vec<_>>()
                .join(" ")
        ),
    }
}

/// The POV-Ray primitive for one body.
fn body(b: &Body, shape: &Shape, bounds: Aabb) -> Result<String, String> {
    use BodyKind::*;
    let v = |i: usize| b.vec3(i);
    let s = |i: usize| b.params[i];
    Ok(match b.kind {
        Sph => format!("sphere {{ {}, {} }}", pv(v(0)), num(s(3))),
        Rcc => format!(
            "cylinder {{ {}, {}, {} }}",
            pv(v(0)),
            pv(v(0) + v(3)),
            num(s(6))
        ),
        Trc if s(6) == s(7) => format!(
            "cylinder {{ {}, {}, {} }}",
            pv(v(0)),
            pv(v(0) + v(3)),
            num(s(6))
        ),
        Trc => format!(
            "cone {{ {}, {}, {}, {} }}",
            pv(v(0)),
            num(s(6)),
            pv(v(0) + v(3)),
            num(s(7))
        ),
        Rec => format!(
            "cylinder {{ <0, 0, 0>, <0, 0, 1>, 1 {} }}",
            matrix(v(6), v(9), v(3), v(0))
        ),
        Tec => unit_cone(1.0 / s(12), v(6), v(9), v(3), v(0)),
        Tgc => {
            let (a, bb, h) = (v(6), v(9), v(3));
            let (ra, rb) = (s(12) / a.length(), s(13) / bb.length());
            if (ra - rb).abs() <= 1e-12 * ra.max(rb) {
                unit_cone(ra, a, bb, h, v(0))
            } else {
                general_cone(ra, rb, a, bb, h, v(0), bounds)
            }
        }
        Ell | Ell1 | Ellg => match shape {
            Shape::Sphere(_) => {
                // ELL with coincident foci.
                let c = (v(0) + v(3)) * 0.5;
                format!("sphere {{ {}, {} }}", pv(c), num(s(6) / 2.0))
            }
            _ => {
                let (c, a, bb, cc) = ellipsoid_axes(b);
                format!("sphere {{ <0, 0, 0>, 1 {} }}", matrix(a, bb, cc, c))
            }
        },
        Rpp => format!(
            "box {{ {}, {} }}",
            pv(DVec3::new(s(0), s(2), s(4))),
            pv(DVec3::new(s(1), s(3), s(5)))
        ),
        Box => format!(
            "box {{ <0, 0, 0>, <1, 1, 1> {} }}",
            matrix(v(3), v(6), v(9), v(0))
        ),
        Raw | Arb4 | Arb5 | Arb6 | Arb7 | Arb8 | ArbF => {
            let Shape::Polyhedron(p) = shape else {
                return Err("expected a convex polyhedron".into());
            };
            let mut t = String::from("intersection {");
            for pl in p.planes() {
                let _ = write!(t, " plane {{ {}, {} }}", pv(pl.n), num(pl.d));
            }
            let _ = write!(t, " {} }}", bounded_by(bounds));
            t
        }
        Tor => {
            let n = v(3).normalize();
            let (u, w) = orthonormal_basis(n);
            // POV-Ray's torus lies in its x-z plane around the y axis.
            format!(
                "torus {{ {}, {} {} }}",
                num(s(6)),
                num(s(7)),
                matrix(u, n, w, v(0))
            )
        }
        Haf => plane(v(0), s(3)),
        Xyp => plane(DVec3::Z, s(0)),
        Xzp => plane(DVec3::Y, s(0)),
        Yzp => plane(DVec3::X, s(0)),
        Pla => plane(v(0), v(0).dot(v(3))),
        Xcc | Ycc | Zcc | Xec | Yec | Zec => quadric(&b.as_quadric()),
        Qua => quadric(&b.params),
        Ars => ars_mesh(b)?,
    })
}

/// Centre and three semi-axis vectors of an ellipsoid body, as the tracer
/// builds them.
fn ellipsoid_axes(b: &Body) -> (DVec3, DVec3, DVec3, DVec3) {
    let v = |i: usize| b.vec3(i);
    let revolution = |c: DVec3, a: DVec3, r: f64| {
        let (u, w) = orthonormal_basis(a.normalize());
        (c, a, u * r, w * r)
    };
    match b.kind {
        BodyKind::Ell => {
            let (f1, f2, l) = (v(0), v(3), b.params[6]);
            let fd = (f2 - f1).length();
            let a = (f2 - f1) * (l / (2.0 * fd));
            let r = (a.length_squared() - (fd / 2.0).powi(2)).sqrt();
            revolution((f1 + f2) * 0.5, a, r)
        }
        BodyKind::Ell1 => revolution(v(0), v(3), b.params[6]),
        _ => (v(0), v(3), v(6), v(9)),
    }
}

/// A cone (or cylinder) on the unit circle, top radius `top`, mapped so
/// local x, y, z go to `a`, `b`, `h` and the origin to `v`.
fn unit_cone(top: f64, a: DVec3, b: DVec3, h: DVec3, v: DVec3) -> String {
    if top == 1.0 {
        format!(
            "cylinder {{ <0, 0, 0>, <0, 0, 1>, 1 {} }}",
            matrix(a, b, h, v)
        )
    } else {
        format!(
            "cone {{ <0, 0, 0>, 1, <0, 0, 1>, {} {} }}",
            num(top),
            matrix(a, b, h, v)
        )
    }
}

/// A TGC whose top is not similar to its base. In local coordinates the
/// lateral surface is `x²/sa² + y²/sb² = 1` with `sa = 1 + (ra-1)z`,
/// `sb = 1 + (rb-1)z`, i.e. the quartic `x²sb² + y²sa² - sa²sb² = 0`
/// (negative inside), clipped by the planes `z = 0` and `z = 1`.
fn general_cone(ra: f64, rb: f64, a: DVec3, b: DVec3, h: DVec3, v: DVec3, bounds: Aabb) -> String {
    let (p, q) = (ra - 1.0, rb - 1.0);
    // Coefficients by powers (i, j, k) of x, y, z.
    let terms: [((u32, u32, u32), f64); 11] = [
        ((2, 0, 0), 1.0),
        ((2, 0, 1), 2.0 * q),
        ((2, 0, 2), q * q),
        ((0, 2, 0), 1.0),
        ((0, 2, 1), 2.0 * p),
        ((0, 2, 2), p * p),
        ((0, 0, 0), -1.0),
        ((0, 0, 1), -2.0 * (p + q)),
        ((0, 0, 2), -((p + q) * (p + q) + 2.0 * p * q)),
        ((0, 0, 3), -2.0 * p * q * (p + q)),
        ((0, 0, 4), -(p * p * q * q)),
    ];
    let coeffs = poly_coefficients(4, &terms);
    let m = matrix(a, b, h, v);
    format!(
        "intersection {{ poly {{ 4, <{}> sturm {m} }} plane {{ <0, 0, -1>, 0 {m} }} plane {{ <0, 0, 1>, 1 {m} }} {} }}",
        coeffs.iter().map(|c| num(*c)).collect::<Vec<_>>().join(", "),
        bounded_by(bounds)
    )
}

/// POV-Ray's `poly` coefficient list of degree `n`: terms `xⁱ yʲ zᵏ` with
/// `i` from `n` down, then `j`, then `k` (so `x⁴, x³y, x³z, x³, …, z, 1`).
fn poly_coefficients(n: u32, terms: &[((u32, u32, u32), f64)]) -> Vec<f64> {
    let mut out = Vec::new();
    for i in (0..=n).rev() {
        for j in (0..=n - i).rev() {
            for k in (0..=n - i - j).rev() {
                out.push(
                    terms
                        .iter()
                        .filter(|(e, _)| *e == (i, j, k))
                        .map(|(_, c)| c)
                        .sum(),
                );
            }
        }
    }
    out
}

/// The half-space `n·x <= d`.
fn plane(n: DVec3, d: f64) -> String {
    let len = n.length();
    format!("plane {{ {}, {} }}", pv(n / len), num(d / len))
}

/// Our quadric `Axx x² + Ayy y² + Azz z² + Axy xy + Axz xz + Ayz yz + Ax x +
/// Ay y + Az z + A0 < 0` with y and z swapped.
fn quadric(q: &[f64]) -> String {
    format!(
        "quadric {{ <{}, {}, {}>, <{}, {}, {}>, <{}, {}, {}>, {} }}",
        num(q[0]),
        num(q[2]),
        num(q[1]),
        num(q[4]),
        num(q[3]),
        num(q[5]),
        num(q[6]),
        num(q[8]),
        num(q[7]),
        num(q[9])
    )
}

/// ARS: the triangles the tracer builds, as a closed `mesh` with an inside
/// vector so that it can take part in CSG.
fn ars_mesh(b: &Body) -> Result<String, String> {
    let tris = sv_geom::ars_triangles(b);
    let scale = Aabb::from_points(tris.iter().flatten().copied()).diagonal();
    let mut t = String::from("mesh {");
    let mut n = 0;
    for [a, bq, c] in &tris {
        // POV-Ray drops degenerate triangles with a warning; leave them out.
        if (*bq - *a).cross(*c - *a).length() <= 1e-18 * scale * scale {
            continue;
        }
        let _ = write!(t, " triangle {{ {}, {}, {} }}", pv(*a), pv(*bq), pv(*c));
        n += 1;
    }
    if n < 4 {
        return Err("the curves span no surface (degenerate ARS)".into());
    }
    // An irrational direction, unlikely to graze an edge.
    t.push_str(" inside_vector <0.5773, 0.6071, 0.5461> }");
    Ok(t)
}

fn bounded_by(b: Aabb) -> String {
    if b.is_empty() || !b.is_finite() {
        return String::new();
    }
    let b = b.padded(1e-6 * b.diagonal().max(1e-12));
    format!("bounded_by {{ box {{ {}, {} }} }}", pv(b.min), pv(b.max))
}

/// `matrix` taking local x, y, z to `a`, `b`, `c` and the origin to `t`
/// (all in our coordinates; the rows are written swapped).
fn matrix(a: DVec3, b: DVec3, c: DVec3, t: DVec3) -> String {
    let row = |v: DVec3| format!("{}, {}, {}", num(v.x), num(v.z), num(v.y));
    format!("matrix <{}, {}, {}, {}>", row(a), row(b), row(c), row(t))
}

/// A point or direction in POV-Ray's coordinates (y and z swapped).
fn pv(p: DVec3) -> String {
    format!("<{}, {}, {}>", num(p.x), num(p.z), num(p.y))
}

fn rgb(c: [f64; 3]) -> String {
    format!("rgb <{}, {}, {}>", num(c[0]), num(c[1]), num(c[2]))
}

/// A number exactly as stored (shortest round-trip form), with an exponent
/// when it is very large or very small.
fn num(x: f64) -> String {
    let x = if x == 0.0 { 0.0 } else { x };
    let a = x.abs();
    if x == 0.0 || (1e-5..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

fn one_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poly_coefficients_follow_povray_order() {
        // x⁴ first, x³y second, constant last; 35 terms in all.
        let c = poly_coefficients(4, &[((4, 0, 0), 1.0), ((3, 1, 0), 2.0), ((0, 0, 0), 3.0)]);
        assert_eq!(c.len(), 35);
        assert_eq!((c[0], c[1], c[34]), (1.0, 2.0, 3.0));
        // z is the second to last.
        let z = poly_coefficients(4, &[((0, 0, 1), 5.0)]);
        assert_eq!(z[33], 5.0);
        // x²y² is the fifth.
        let xy = poly_coefficients(4, &[((2, 2, 0), 7.0)]);
        assert_eq!(xy[4], 7.0);
    }

    #[test]
    fn numbers_round_trip_and_use_exponents_only_at_extremes() {
        assert_eq!(num(0.1), "0.1");
        assert_eq!(num(-0.0), "0");
        assert_eq!(num(1e-7), "1e-7");
        assert_eq!(num(123456.5), "123456.5");
        assert_eq!(num(1e-7).parse::<f64>().unwrap(), 1e-7);
    }
}
