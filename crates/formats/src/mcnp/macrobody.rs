//! Macrobodies and their facets.
//!
//! A macrobody used whole is one body (`BOX`, `RPP`, `SPH`, `RCC`, `REC`,
//! `TRC`, an `ELLG` for `ELL`, a `RAW` for `WED`, an `ARBF` for `ARB`),
//! except the hexagonal prism (`RHP`/`HEX`), which is the intersection of
//! its eight facets' half-spaces. A facet `n.k` used as a surface is the
//! plane, cylinder or cone it lies on, its negative side toward the
//! macrobody's inside:
//!
//! | body | facets |
//! |---|---|
//! | `BOX` | 1, 2: the faces at the end and at the start of the first edge; 3, 4 and 5, 6 likewise for the second and third |
//! | `RPP` | 1 x max, 2 x min, 3 y max, 4 y min, 5 z max, 6 z min |
//! | `SPH`, `ELL` | 1: the body's own surface |
//! | `RCC`, `REC`, `TRC` | 1: the side (cylinder, elliptic cylinder, the cone's sheet holding the frustum), 2: the top (end of the height vector), 3: the base |
//! | `RHP`/`HEX` | 1, 2: the faces at +r and −r; 3, 4 at ±s; 5, 6 at ±t; 7 the top, 8 the base |
//! | `WED` | 1: the slanted face, 2: the face holding the second leg and the height, 3: the face holding the first leg and the height, 4 the top, 5 the base |
//! | `ARB` | k: the face of the k-th vertex code |

use super::surface::{cylinder, double_cone, placed, Part};
use sv_geom::{BodyKind, Op};
use sv_math::{orthonormal_basis, DMat3, DQuat, DVec3};

fn vec3(v: &[f64], i: usize) -> DVec3 {
    DVec3::new(v[i], v[i + 1], v[i + 2])
}

fn flat(points: &[DVec3]) -> Vec<f64> {
    points.iter().flat_map(|p| p.to_array()).collect()
}

/// The half-space behind the plane through `p` with outward normal `n`.
fn plane(n: DVec3, p: DVec3, k: usize) -> Part {
    Part {
        op: Op::Inside,
        kind: BodyKind::Pla,
        params: flat(&[n, p]),
        suffix: format!(".{k}"),
    }
}

/// `n` turned to point the way `toward` does.
fn facing(n: DVec3, toward: DVec3) -> DVec3 {
    if n.dot(toward) < 0.0 {
        -n
    } else {
        n
    }
}

/// The bodies of macrobody `m` used whole.
pub(crate) fn parts(m: &str, v: &[f64]) -> Result<Vec<Part>, String> {
    let one = |kind, params| Ok(vec![Part::body(kind, params)]);
    match m {
        "box" => one(BodyKind::Box, v.to_vec()),
        "rpp" => one(BodyKind::Rpp, v.to_vec()),
        "sph" => one(BodyKind::Sph, v.to_vec()),
        "rcc" => one(BodyKind::Rcc, v.to_vec()),
        "trc" => one(BodyKind::Trc, v.to_vec()),
        "rec" => {
            let (a, b) = rec_axes(v)?;
            one(BodyKind::Rec, flat(&[vec3(v, 0), vec3(v, 3), a, b]))
        }
        "ell" => one(BodyKind::Ellg, ellipsoid(v)?),
        "wed" => one(BodyKind::Raw, v.to_vec()),
        "arb" => {
            let mut params = v[..24].to_vec();
            for code in &v[24..] {
                params.push(
                    arb_face(*code)?
                        .iter()
                        .fold(0.0, |acc, d| acc * 10.0 + *d as f64),
                );
            }
            one(BodyKind::ArbF, params)
        }
        _ => hexagon(v),
    }
}

/// Facet `k` of macrobody `m`.
pub(crate) fn facet(m: &str, v: &[f64], k: usize) -> Result<Vec<Part>, String> {
    let count = match m {
        "box" | "rpp" => 6,
        "sph" | "ell" => 1,
        "rcc" | "rec" | "trc" => 3,
        "wed" => 5,
        "arb" => 6,
        _ => 8,
    };
    if k == 0 || k > count {
        return Err(format!(
            "{} has facets 1 to {count}, not {k}",
            m.to_ascii_uppercase()
        ));
    }
    match m {
        "box" => Ok(vec![box_facet(v, k)]),
        "rpp" => {
            let kind = [BodyKind::Yzp, BodyKind::Xzp, BodyKind::Xyp][(k - 1) / 2];
            Ok(vec![Part {
                // Odd facets are the upper planes: their body is the inside.
                op: if k % 2 == 1 { Op::Inside } else { Op::Outside },
                kind,
                params: vec![v[if k % 2 == 1 { k } else { k - 2 }]],
                suffix: format!(".{k}"),
            }])
        }
        "sph" | "ell" => parts(m, v),
        "rcc" | "rec" | "trc" => end_or_side(m, v, k),
        "wed" => Ok(vec![wedge_facet(v, k)]),
        "arb" => arb_facet(v, k).map(|p| vec![p]),
        _ => Ok(vec![hexagon(v)?.swap_remove(k - 1)]),
    }
}

fn box_facet(v: &[f64], k: usize) -> Part {
    let o = vec3(v, 0);
    let edges = [vec3(v, 3), vec3(v, 6), vec3(v, 9)];
    let e = (k - 1) / 2;
    let n = facing(edges[(e + 1) % 3].cross(edges[(e + 2) % 3]), edges[e]);
    if k % 2 == 1 {
        plane(n, o + edges[e], k)
    } else {
        plane(-n, o, k)
    }
}

/// The side, top or base of an RCC, REC or TRC.
fn end_or_side(m: &str, v: &[f64], k: usize) -> Result<Vec<Part>, String> {
    let (base, h) = (vec3(v, 0), vec3(v, 3));
    match k {
        2 => return Ok(vec![plane(h, base + h, k)]),
        3 => return Ok(vec![plane(-h, base, k)]),
        _ => {}
    }
    let side = |kind, params| Part {
        op: Op::Inside,
        kind,
        params,
        suffix: ".1".into(),
    };
    match m {
        "rcc" => Ok(vec![axis_cylinder(base, h, v[6])]),
        "rec" => {
            let (a, b) = rec_axes(v)?;
            // (x/|a|)² + (y/|b|)² < 1 in the frame of the axes.
            let uh = h.normalize();
            let ua = (a - uh * a.dot(uh)).normalize();
            let local = [
                1.0 / a.length_squared(),
                1.0 / b.length_squared(),
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                -1.0,
            ];
            let quadric = placed(local, DMat3::from_cols(ua, uh.cross(ua), uh), base);
            Ok(vec![side(BodyKind::Qua, quadric)])
        }
        _ => {
            let (r1, r2) = (v[6], v[7]);
            if r1 == r2 {
                return Ok(vec![axis_cylinder(base, h, r1)]);
            }
            let apex = base + h * (r1 / (r1 - r2));
            let t = (r1 - r2).abs() / h.length();
            // The sheet on the side of the apex where the frustum is.
            let toward = facing(h, base - apex).normalize_or_zero();
            Ok(vec![
                side(BodyKind::Qua, double_cone(apex, h, t * t)),
                Part {
                    suffix: ".1:sheet".into(),
                    ..plane(-toward, apex, 1)
                },
            ])
        }
    }
}

/// The infinite cylinder an RCC's side lies on (an axis-aligned body when
/// it can be one).
fn axis_cylinder(base: DVec3, h: DVec3, r: f64) -> Part {
    let aligned = |a: usize| (0..3).all(|i| i == a || h[i] == 0.0) && h[a] != 0.0;
    let (kind, params) = if aligned(0) {
        (BodyKind::Xcc, vec![base.y, base.z, r])
    } else if aligned(1) {
        (BodyKind::Ycc, vec![base.z, base.x, r])
    } else if aligned(2) {
        (BodyKind::Zcc, vec![base.x, base.y, r])
    } else {
        (BodyKind::Qua, cylinder(base, h, r))
    };
    Part {
        op: Op::Inside,
        kind,
        params,
        suffix: ".1".into(),
    }
}

/// An REC's two semi-axes: given, or the second of length `v[9]` at right
/// angles to the height and the first.
fn rec_axes(v: &[f64]) -> Result<(DVec3, DVec3), String> {
    let a = vec3(v, 6);
    if v.len() == 12 {
        return Ok((a, vec3(v, 9)));
    }
    let across = vec3(v, 3).cross(a);
    if across.length_squared() == 0.0 {
        return Err("the semi-axis must not lie along the height vector".into());
    }
    Ok((a, across.normalize() * v[9]))
}

/// ELL as centre and three semi-axes. With R > 0 the first six values are
/// two foci and R the semi-major axis; MCNP then takes the semi-minor axis
/// as √(R² − (R − c)²), c being half the distance between the foci (what
/// the code does, as the converter t4_geom_convert's authors found by
/// comparing with MCNP, rather than the √(R² − c²) of an ellipse with those
/// foci). With R < 0 they are the centre and the semi-major axis vector
/// and |R| the semi-minor axis.
fn ellipsoid(v: &[f64]) -> Result<Vec<f64>, String> {
    let (p1, p2, r) = (vec3(v, 0), vec3(v, 3), v[6]);
    let (centre, major, minor) = if r > 0.0 {
        let centre = (p1 + p2) / 2.0;
        let c = (p1 - centre).length();
        if c >= 2.0 * r {
            return Err(format!(
                "the foci are too far apart for a major radius of {r}"
            ));
        }
        let dir = (p2 - p1).try_normalize().unwrap_or(DVec3::X);
        let minor = if c == 0.0 {
            r
        } else {
            (r * r - (r - c) * (r - c)).sqrt()
        };
        (centre, dir * r, minor)
    } else if r < 0.0 {
        (p1, p2, -r)
    } else {
        return Err("the last value (the radius) must not be 0".into());
    };
    let (u, w) = orthonormal_basis(major.try_normalize().ok_or("the major axis is zero")?);
    Ok(flat(&[centre, major, u * minor, w * minor]))
}

fn wedge_facet(v: &[f64], k: usize) -> Part {
    let (o, a, b, h) = (vec3(v, 0), vec3(v, 3), vec3(v, 6), vec3(v, 9));
    let up = facing(a.cross(b), h);
    match k {
        1 => plane(facing((a - b).cross(h), a), o + a, k),
        2 => plane(facing(b.cross(h), -a), o, k),
        3 => plane(facing(a.cross(h), -b), o, k),
        4 => plane(up, o + h, k),
        _ => plane(-up, o, k),
    }
}

/// An ARB face code's vertex numbers (zeros left out), or why it is wrong.
fn arb_face(code: f64) -> Result<Vec<usize>, String> {
    if code.fract() != 0.0 || !(0.0..=8888.0).contains(&code) {
        return Err(format!(
            "`{code}` is no face code: four digits, each a vertex 1 to 8 or 0"
        ));
    }
    let mut digits = Vec::new();
    let mut n = code as u32;
    while n > 0 {
        let d = (n % 10) as usize;
        if d > 8 {
            return Err(format!("face code {code} names vertex {d}: an ARB has 8"));
        }
        if d > 0 {
            digits.push(d);
        }
        n /= 10;
    }
    digits.reverse();
    Ok(digits)
}

fn arb_facet(v: &[f64], k: usize) -> Result<Part, String> {
    let vertices: Vec<DVec3> = (0..8).map(|i| vec3(v, 3 * i)).collect();
    let faces: Vec<Vec<usize>> = v[24..]
        .iter()
        .map(|c| arb_face(*c))
        .collect::<Result<_, _>>()?;
    let face = &faces[k - 1];
    if face.len() < 3 {
        return Err(format!("face {k} of the ARB has fewer than 3 vertices"));
    }
    let mut used: Vec<usize> = faces.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    let centroid = used.iter().map(|&i| vertices[i - 1]).sum::<DVec3>() / used.len() as f64;
    let q = [0, 1, 2].map(|i| vertices[face[i] - 1]);
    let n = (q[1] - q[0]).cross(q[2] - q[0]);
    if n.length_squared() == 0.0 {
        return Err(format!(
            "the first three vertices of face {k} are on one line"
        ));
    }
    Ok(plane(facing(n, q[0] - centroid), q[0], k))
}

/// RHP/HEX: base `v`, height `h`, and `r` (with `s`, `t` given or `r`
/// turned by 60° and 120° about the height) from the axis to the middle of
/// the first, third and fifth faces.
fn hexagon(v: &[f64]) -> Result<Vec<Part>, String> {
    let (base, h, r) = (vec3(v, 0), vec3(v, 3), vec3(v, 6));
    let axis = h.try_normalize().ok_or("the height vector is zero")?;
    let (s, t) = if v.len() == 15 {
        (vec3(v, 9), vec3(v, 12))
    } else {
        let turn = |deg: f64| DQuat::from_axis_angle(axis, deg.to_radians()) * r;
        (turn(60.0), turn(120.0))
    };
    let mut out = Vec::with_capacity(8);
    for (i, e) in [r, s, t].into_iter().enumerate() {
        if e.length_squared() == 0.0 {
            return Err("a face vector of the hexagonal prism is zero".into());
        }
        out.push(plane(e, base + e, 2 * i + 1));
        out.push(plane(-e, base - e, 2 * i + 2));
    }
    out.push(plane(h, base + h, 7));
    out.push(plane(-h, base, 8));
    Ok(out)
}
