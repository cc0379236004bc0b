//! `<surface>` elements: each becomes one body whose inside is the
//! surface's negative side (OpenMC's `-id`), so that a half-space `-id` is
//! the body's inside and `+id` its outside.

use super::xml::{self, Sink, Xml};
use roxmltree::Node;
use sv_geom::{Body, BodyKind};

/// What happens to a particle crossing a surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Boundary {
    /// Crosses (OpenMC's default).
    Transmission,
    /// Leaves the problem: the far side is beyond the model.
    Vacuum,
    /// Is mirrored back.
    Reflective,
    /// Is sent back in a random (cosine) direction.
    White,
    /// Re-enters through the paired surface.
    Periodic,
}

/// A surface read: its id and the body it became.
pub(super) struct Surface {
    /// Its id.
    pub id: i64,
    /// The body (named by the id).
    pub body: Body,
    /// Its boundary condition.
    pub boundary: Boundary,
}

/// The surface types and their coefficient counts.
const TYPES: [(&str, usize); 15] = [
    ("x-plane", 1),
    ("y-plane", 1),
    ("z-plane", 1),
    ("plane", 4),
    ("x-cylinder", 3),
    ("y-cylinder", 3),
    ("z-cylinder", 3),
    ("sphere", 4),
    ("x-cone", 4),
    ("y-cone", 4),
    ("z-cone", 4),
    ("quadric", 10),
    ("x-torus", 6),
    ("y-torus", 6),
    ("z-torus", 6),
];

/// What each coefficient list holds, for the messages.
fn coefficient_names(kind: &str) -> &'static str {
    match kind {
        "x-plane" => "x0",
        "y-plane" => "y0",
        "z-plane" => "z0",
        "plane" => "A B C D (Ax + By + Cz = D)",
        "x-cylinder" => "y0 z0 R",
        "y-cylinder" => "x0 z0 R",
        "z-cylinder" => "x0 y0 R",
        "sphere" => "x0 y0 z0 R",
        "x-cone" | "y-cone" | "z-cone" => "x0 y0 z0 R²",
        "quadric" => "A B C D E F G H J K",
        _ => "x0 y0 z0 A B C",
    }
}

/// Read one `<surface>`; `None` after reporting its errors.
pub(super) fn read(xml: &Xml, sink: &mut Sink, node: Node) -> Option<Surface> {
    let Some(id_value) = xml.value(node, "id") else {
        sink.error(xml.error_tag(node, "surface without an id"));
        return None;
    };
    let id = xml::id_of(xml, sink, &id_value, "surface id");
    let boundary = boundary(xml, sink, node);
    let Some(type_value) = xml.value(node, "type") else {
        sink.error(xml.error_tag(node, "surface without a type"));
        return None;
    };
    let kind = type_value.trimmed();
    let Some(&(_, n)) = TYPES.iter().find(|(name, _)| *name == kind) else {
        let names = TYPES.iter().map(|(name, _)| *name);
        let mut d = xml.error(&type_value, format!("unknown surface type `{kind}`"));
        d = match crate::did_you_mean(kind, names) {
            Some(s) => d.with_hint(format!("did you mean `{s}`?")),
            None => d.with_hint(
                "OpenMC's surfaces: x-, y-, z-plane, plane, x-, y-, z-cylinder, sphere, \
                 x-, y-, z-cone, quadric, x-, y-, z-torus",
            ),
        };
        sink.error(d);
        return None;
    };
    let Some(coeffs_value) = xml.value(node, "coeffs") else {
        sink.error(
            xml.error_tag(node, format!("{kind} surface without coeffs"))
                .with_hint(format!("a {kind} takes {}", coefficient_names(kind))),
        );
        return None;
    };
    let what = format!("the coeffs of a {kind}");
    let coeffs = xml::reals(xml, sink, &coeffs_value, &what)?;
    if coeffs.len() != n {
        sink.error(
            xml.error(
                &coeffs_value,
                format!("a {kind} takes {n} coefficients, found {}", coeffs.len()),
            )
            .with_hint(format!("the coefficients are {}", coefficient_names(kind))),
        );
        return None;
    }
    let id = id?;
    let body = match body(id, kind, &coeffs) {
        Ok(b) => b,
        Err(msg) => {
            sink.error(xml.error(&coeffs_value, format!("surface {id}: {msg}")));
            return None;
        }
    };
    // The engine's own rules for the body (positive radii, a torus's tube
    // inside its ring, …), reported where the coefficients are written.
    let mut warnings = Vec::new();
    if let Err(msg) = sv_geom::prepare(&body, &mut warnings) {
        sink.error(xml.error(&coeffs_value, format!("{kind} {id}: {msg}")));
        return None;
    }
    for warning in warnings {
        let msg = format!("{kind} {id}: {}", warning.message);
        sink.warn(xml.error(&coeffs_value, msg));
    }
    Some(Surface {
        id,
        body,
        boundary: boundary?,
    })
}

fn boundary(xml: &Xml, sink: &mut Sink, node: Node) -> Option<Boundary> {
    let Some(value) = xml.value(node, "boundary") else {
        return Some(Boundary::Transmission);
    };
    Some(match value.trimmed().to_ascii_lowercase().as_str() {
        "" | "transmission" | "transmit" => Boundary::Transmission,
        "vacuum" => Boundary::Vacuum,
        "reflective" | "reflect" | "reflecting" => Boundary::Reflective,
        "white" => Boundary::White,
        "periodic" => Boundary::Periodic,
        other => {
            sink.error(
                xml.error(&value, format!("unknown boundary condition `{other}`"))
                    .with_hint(
                        "OpenMC's boundaries: transmission, vacuum, reflective, white, periodic",
                    ),
            );
            return None;
        }
    })
}

/// The body of a surface of type `kind` (a name of [`TYPES`]) with its
/// coefficients (as many as the type takes).
fn body(id: i64, kind: &str, c: &[f64]) -> Result<Body, String> {
    let name = id.to_string();
    let body = |kind, params: Vec<f64>| Ok(Body::new(name.clone(), kind, params));
    match kind {
        "x-plane" => body(BodyKind::Yzp, vec![c[0]]),
        "y-plane" => body(BodyKind::Xzp, vec![c[0]]),
        "z-plane" => body(BodyKind::Xyp, vec![c[0]]),
        "plane" => {
            let length_squared = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
            if length_squared == 0.0 {
                return Err("the plane's normal (A, B, C) is zero".into());
            }
            // The point of the plane nearest the origin: D N / |N|².
            let s = c[3] / length_squared;
            body(
                BodyKind::Pla,
                vec![c[0], c[1], c[2], s * c[0], s * c[1], s * c[2]],
            )
        }
        "x-cylinder" => body(BodyKind::Xcc, vec![c[0], c[1], c[2]]),
        // YCC's centre is written z, x.
        "y-cylinder" => body(BodyKind::Ycc, vec![c[1], c[0], c[2]]),
        "z-cylinder" => body(BodyKind::Zcc, vec![c[0], c[1], c[2]]),
        "sphere" => body(BodyKind::Sph, c.to_vec()),
        "x-cone" => body(BodyKind::Qua, cone(0, c).to_vec()),
        "y-cone" => body(BodyKind::Qua, cone(1, c).to_vec()),
        "z-cone" => body(BodyKind::Qua, cone(2, c).to_vec()),
        // OpenMC: A x² + B y² + C z² + D xy + E yz + F xz + G x + H y + J z + K;
        // QUA: xx yy zz xy xz yz x y z 1.
        "quadric" => body(
            BodyKind::Qua,
            vec![c[0], c[1], c[2], c[3], c[5], c[4], c[6], c[7], c[8], c[9]],
        ),
        _ => torus(kind, c).map(|params| Body::new(name.clone(), BodyKind::Tor, params)),
    }
}

/// The QUA coefficients of a double cone along `axis` (0 = x):
/// Σ_{other}(u - u0)² - R² (a - a0)² with coefficients x0 y0 z0 R².
fn cone(axis: usize, c: &[f64]) -> [f64; 10] {
    let r2 = c[3];
    let mut q = [0.0; 10];
    for i in 0..3 {
        let (square, linear, constant) = if i == axis {
            (-r2, 2.0 * r2 * c[i], -r2 * c[i] * c[i])
        } else {
            (1.0, -2.0 * c[i], c[i] * c[i])
        };
        q[i] = square;
        q[6 + i] += linear;
        q[9] += constant;
    }
    q
}

/// A circular torus as TOR values; OpenMC's tori are elliptic in general
/// (semi-axis B along the axis, C across it), which no body takes.
fn torus(kind: &str, c: &[f64]) -> Result<Vec<f64>, String> {
    let (a, b, cc) = (c[3], c[4], c[5]);
    if (b - cc).abs() > 1e-12 * b.abs().max(cc.abs()) {
        return Err(format!(
            "an elliptic torus (tube semi-axes B = {b} along the axis, C = {cc} across it) \
             cannot be drawn; only circular tori (B = C) can"
        ));
    }
    let normal = match kind {
        "x-torus" => [1.0, 0.0, 0.0],
        "y-torus" => [0.0, 1.0, 0.0],
        _ => [0.0, 0.0, 1.0],
    };
    Ok(vec![
        c[0], c[1], c[2], normal[0], normal[1], normal[2], a, b,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cone_is_its_quadric() {
        // (x-1)² + (y-2)² = 4 (z-3)²: the point (1, 2+2, 3+1) is on it.
        let q = cone(2, &[1.0, 2.0, 3.0, 4.0]);
        let f = |p: [f64; 3]| {
            q[0] * p[0] * p[0]
                + q[1] * p[1] * p[1]
                + q[2] * p[2] * p[2]
                + q[6] * p[0]
                + q[7] * p[1]
                + q[8] * p[2]
                + q[9]
        };
        assert!(f([1.0, 4.0, 4.0]).abs() < 1e-12);
        assert!(f([1.0, 2.0, 4.0]) < 0.0, "inside the cone is negative");
        assert!(f([5.0, 2.0, 3.0]) > 0.0);
    }
}
