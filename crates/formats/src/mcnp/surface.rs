//! Surface cards: `j [n] mnemonic values`, and the bodies each surface
//! lowers to.
//!
//! A surface's negative side is its body's inside: `PX D` is the
//! half-space x < D (an `YZP`), `P A B C D` the half-space Ax+By+Cz < D (a
//! `HAF`), spheres, cylinders, cones and quadrics the side where their
//! equation is negative (`SPH`, `XCC`…`ZCC`, `QUA`), a circular torus a
//! `TOR`. A one-sheet cone (the ±1 entry) is the double cone cut by the
//! plane through its apex: two bodies whose intersection is the negative
//! side. `X`, `Y` and `Z` surfaces given by points become the plane,
//! cylinder, one-sheet cone or quadric the points make. Macrobodies are in
//! [`super::macrobody`].

use super::cell::{identifier, MAX_NUMBER};
use super::input::Card;
use super::number::{integer, Expander};
use super::{Loc, Log};
use crate::did_you_mean;
use sv_geom::{Body, BodyKind, Op};
use sv_math::{orthonormal_basis, DAffine3, DMat3, DVec3};

/// What a surface number's prefix says about its boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Boundary {
    /// Nothing special.
    Plain,
    /// `*j`: reflecting.
    Reflecting,
    /// `+j`: white.
    White,
    /// `j -k`: periodic with surface k.
    Periodic,
}

/// A surface card.
#[derive(Clone, Debug)]
pub(crate) struct SurfaceCard {
    /// Its number.
    pub number: i64,
    /// Where the number is.
    pub at: Loc,
    /// Reflecting, white, periodic or plain.
    pub boundary: Boundary,
    /// `TRn` moving it, and where `n` is.
    pub transform: Option<(i64, Loc)>,
    /// The mnemonic, lower case.
    pub mnemonic: String,
    /// Where the mnemonic is.
    pub mnemonic_at: Loc,
    /// Its values, shorthand expanded.
    pub values: Vec<f64>,
}

/// One body of a surface: the side of it that belongs to the surface's
/// negative side, its kind and values, and the suffix of its name after
/// the surface number.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Part {
    /// Inside or outside of the body.
    pub op: Op,
    /// Body type.
    pub kind: BodyKind,
    /// Its values.
    pub params: Vec<f64>,
    /// Name suffix (`""`, `".1"`, `":sheet"`).
    pub suffix: String,
}

impl Part {
    /// The whole negative side as one body's inside.
    pub fn body(kind: BodyKind, params: Vec<f64>) -> Part {
        Part {
            op: Op::Inside,
            kind,
            params,
            suffix: String::new(),
        }
    }
}

/// Every mnemonic and the counts of values it takes.
const MNEMONICS: &[(&str, &[usize])] = &[
    ("p", &[4, 9]),
    ("px", &[1]),
    ("py", &[1]),
    ("pz", &[1]),
    ("so", &[1]),
    ("s", &[4]),
    ("sx", &[2]),
    ("sy", &[2]),
    ("sz", &[2]),
    ("c/x", &[3]),
    ("c/y", &[3]),
    ("c/z", &[3]),
    ("cx", &[1]),
    ("cy", &[1]),
    ("cz", &[1]),
    ("k/x", &[4, 5]),
    ("k/y", &[4, 5]),
    ("k/z", &[4, 5]),
    ("kx", &[2, 3]),
    ("ky", &[2, 3]),
    ("kz", &[2, 3]),
    ("sq", &[10]),
    ("gq", &[10]),
    ("tx", &[6]),
    ("ty", &[6]),
    ("tz", &[6]),
    ("x", &[2, 4, 6]),
    ("y", &[2, 4, 6]),
    ("z", &[2, 4, 6]),
    ("box", &[12]),
    ("rpp", &[6]),
    ("sph", &[4]),
    ("rcc", &[7]),
    ("rhp", &[9, 15]),
    ("hex", &[9, 15]),
    ("rec", &[10, 12]),
    ("trc", &[8]),
    ("ell", &[7]),
    ("wed", &[12]),
    ("arb", &[30]),
];

/// Whether a mnemonic names a macrobody.
pub(crate) fn is_macrobody(mnemonic: &str) -> bool {
    matches!(
        mnemonic,
        "box" | "rpp" | "sph" | "rcc" | "rhp" | "hex" | "rec" | "trc" | "ell" | "wed" | "arb"
    )
}

/// Whether `text` is a surface mnemonic (any case).
pub(crate) fn is_mnemonic(text: &str) -> bool {
    let lower = text.to_ascii_lowercase();
    MNEMONICS.iter().any(|(m, _)| *m == lower)
}

/// Read a surface card; `None` (reported) when it cannot be used.
pub(crate) fn read(card: &Card, log: &mut Log) -> Option<SurfaceCard> {
    let words = &card.words;
    let first = &words[0];
    let (boundary, skip) = match first.text.chars().next() {
        Some('*') => (Boundary::Reflecting, 1),
        Some('+') => (Boundary::White, 1),
        _ => (Boundary::Plain, 0),
    };
    let digits = first.part(skip, first.text.chars().count() - skip);
    let number = identifier(&digits, "a surface number", log)?;
    let mut surface = SurfaceCard {
        number,
        at: first.at,
        boundary,
        transform: None,
        mnemonic: String::new(),
        mnemonic_at: first.at,
        values: Vec::new(),
    };
    let mut next = 1;
    if let Some(n) = words.get(1).and_then(|w| integer(&w.text)) {
        let at = words[1].at;
        match n {
            1..=MAX_NUMBER => surface.transform = Some((n, at)),
            n if (-MAX_NUMBER..0).contains(&n) => surface.boundary = Boundary::Periodic,
            _ => {
                log.error(at, format!("`{n}` is no transformation number"));
                return None;
            }
        }
        next = 2;
    }
    let Some(m) = words.get(next) else {
        log.error(first.at, format!("surface {number} has no type"));
        return None;
    };
    surface.mnemonic = m.text.to_ascii_lowercase();
    surface.mnemonic_at = m.at;
    let Some((_, counts)) = MNEMONICS.iter().find(|(name, _)| *name == surface.mnemonic) else {
        let hint = did_you_mean(&m.text, MNEMONICS.iter().map(|(n, _)| *n))
            .map(|s| format!("did you mean `{}`?", s.to_ascii_uppercase()));
        log.error(m.at, format!("unknown surface type `{}`", m.text))
            .hint = hint;
        return None;
    };
    let mut e = Expander::default();
    for w in &words[next + 1..] {
        if let Err(msg) = e.push(w) {
            log.error(w.at, msg);
            return None;
        }
    }
    let entries = match e.finish() {
        Ok(v) => v,
        Err((at, msg)) => {
            log.error(at, msg);
            return None;
        }
    };
    for (v, at) in &entries {
        match v {
            Some(v) => surface.values.push(*v),
            None => {
                log.error(*at, "a surface takes no `J`: every value must be given");
                return None;
            }
        }
    }
    if !counts.contains(&surface.values.len()) {
        let want = counts
            .iter()
            .map(|c| c.to_string())
            .collect::<Vec<_>>()
            .join(" or ");
        log.error(
            m.at,
            format!(
                "surface {number} ({}) takes {want} values, not {}",
                m.text.to_ascii_uppercase(),
                surface.values.len()
            ),
        );
        return None;
    }
    Some(surface)
}

/// The QUA values of the quadric whose values are `local` in a frame with
/// its z axis along `axis` and its origin at `at`, moved into place as
/// sv-geom moves bodies.
fn about_axis(local: [f64; 10], axis: DVec3, at: DVec3) -> Vec<f64> {
    let n = axis.normalize();
    let (u, w) = orthonormal_basis(n);
    placed(local, DMat3::from_cols(u, w, n), at)
}

/// The QUA values `local` in the frame whose axes are the columns of the
/// rotation `frame`, at origin `at`.
pub(crate) fn placed(local: [f64; 10], frame: DMat3, at: DVec3) -> Vec<f64> {
    let quadric = Body::new("", BodyKind::Qua, local.to_vec());
    let xf = DAffine3::from_mat3_translation(frame, at);
    // A rotation and a translation are what every body takes.
    quadric
        .transformed(&xf)
        .map_or_else(|_| local.to_vec(), |b| b.params)
}

/// The infinite cylinder of radius `r` about the line through `v` along
/// `axis`.
pub(crate) fn cylinder(v: DVec3, axis: DVec3, r: f64) -> Vec<f64> {
    about_axis(
        [1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -r * r],
        axis,
        v,
    )
}

/// The double cone with apex `v`, axis `axis` and `t²` the square of the
/// tangent of its half-angle.
pub(crate) fn double_cone(v: DVec3, axis: DVec3, t2: f64) -> Vec<f64> {
    about_axis([1.0, 1.0, -t2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], axis, v)
}

/// The half-space on the `side` of the plane through `apex` normal to
/// axis `a` (0 = x) that a one-sheet cone keeps: `+1` above the apex.
fn sheet(a: usize, apex: f64, side: f64) -> Part {
    let kind = [BodyKind::Yzp, BodyKind::Xzp, BodyKind::Xyp][a];
    Part {
        // The axis plane's body is the side below it.
        op: if side > 0.0 { Op::Outside } else { Op::Inside },
        kind,
        params: vec![apex],
        suffix: ":sheet".into(),
    }
}

/// A cone along axis `a` (0 = x): double, or one sheet with `side` ±1.
fn cone(a: usize, apex: DVec3, t2: f64, side: Option<f64>) -> Result<Vec<Part>, String> {
    if t2 <= 0.0 {
        return Err(format!("t² must be positive, not {t2}"));
    }
    let mut axis = DVec3::ZERO;
    axis[a] = 1.0;
    let mut parts = vec![Part::body(BodyKind::Qua, double_cone(apex, axis, t2))];
    match side {
        None | Some(0.0) => {}
        Some(s) if s.abs() == 1.0 => parts.push(sheet(a, apex[a], s)),
        Some(s) => return Err(format!("the sheet entry must be 1 or -1, not {s}")),
    }
    Ok(parts)
}

/// The axis (0 = x) of a mnemonic's last letter.
fn axis_of(m: &str) -> usize {
    match m.chars().last() {
        Some('x') => 0,
        Some('y') => 1,
        _ => 2,
    }
}

/// The bodies of an ordinary (not macrobody) surface.
pub(crate) fn parts(m: &str, v: &[f64]) -> Result<Vec<Part>, String> {
    let a = axis_of(m);
    let on_axis = |x: f64| {
        let mut p = DVec3::ZERO;
        p[a] = x;
        p
    };
    let one = |kind, params| Ok(vec![Part::body(kind, params)]);
    let plane_kind = [BodyKind::Yzp, BodyKind::Xzp, BodyKind::Xyp][a];
    match m {
        "px" | "py" | "pz" => one(plane_kind, vec![v[0]]),
        "p" if v.len() == 4 => one(BodyKind::Haf, v.to_vec()),
        "p" => one(BodyKind::Haf, plane_by_points(v)?),
        "so" => one(BodyKind::Sph, vec![0.0, 0.0, 0.0, v[0]]),
        "s" => one(BodyKind::Sph, v.to_vec()),
        "sx" | "sy" | "sz" => {
            let c = on_axis(v[0]);
            one(BodyKind::Sph, vec![c.x, c.y, c.z, v[1]])
        }
        "c/x" => one(BodyKind::Xcc, vec![v[0], v[1], v[2]]),
        "c/y" => one(BodyKind::Ycc, vec![v[1], v[0], v[2]]),
        "c/z" => one(BodyKind::Zcc, vec![v[0], v[1], v[2]]),
        "cx" => one(BodyKind::Xcc, vec![0.0, 0.0, v[0]]),
        "cy" => one(BodyKind::Ycc, vec![0.0, 0.0, v[0]]),
        "cz" => one(BodyKind::Zcc, vec![0.0, 0.0, v[0]]),
        "k/x" | "k/y" | "k/z" => cone(a, DVec3::new(v[0], v[1], v[2]), v[3], v.get(4).copied()),
        "kx" | "ky" | "kz" => cone(a, on_axis(v[0]), v[1], v.get(2).copied()),
        "sq" => {
            // A(x−x̄)² + … + 2D(x−x̄) + … + G, expanded.
            let (sq, lin, c) = (&v[0..3], &v[3..6], &v[7..10]);
            let mut q = [0.0; 10];
            q[..3].copy_from_slice(sq);
            for i in 0..3 {
                q[6 + i] = 2.0 * (lin[i] - sq[i] * c[i]);
                q[9] += sq[i] * c[i] * c[i] - 2.0 * lin[i] * c[i];
            }
            q[9] += v[6];
            one(BodyKind::Qua, q.to_vec())
        }
        "gq" => one(
            BodyKind::Qua,
            vec![v[0], v[1], v[2], v[3], v[5], v[4], v[6], v[7], v[8], v[9]],
        ),
        "tx" | "ty" | "tz" => torus(a, v),
        "x" | "y" | "z" => by_points(a, v),
        _ => Err(format!("`{m}` is a macrobody")),
    }
}

/// `TX`/`TY`/`TZ x y z A B C`: a circular torus when B = C.
fn torus(a: usize, v: &[f64]) -> Result<Vec<Part>, String> {
    let (major, along, across) = (v[3], v[4], v[5]);
    if (along - across).abs() > 1e-12 * along.abs().max(across.abs()) {
        return Err(format!(
            "this torus is elliptic (B = {along}, C = {across}); SynthaVision's TOR holds circular tori (B = C) only"
        ));
    }
    let mut n = DVec3::ZERO;
    n[a] = 1.0;
    Ok(vec![Part::body(
        BodyKind::Tor,
        vec![v[0], v[1], v[2], n.x, n.y, n.z, major, along],
    )])
}

/// `P x1 y1 z1 x2 y2 z2 x3 y3 z3`: the plane through three points, its
/// sense set as MCNP sets it: the origin on the negative side, or if the
/// plane holds it, the point (0, 0, ∞) on the positive side, then
/// (0, ∞, 0), then (∞, 0, 0).
fn plane_by_points(v: &[f64]) -> Result<Vec<f64>, String> {
    let p = [0, 3, 6].map(|i| DVec3::new(v[i], v[i + 1], v[i + 2]));
    let mut n = (p[1] - p[0]).cross(p[2] - p[0]);
    let scale = (p[1] - p[0]).length() * (p[2] - p[0]).length();
    if n.length() <= 1e-12 * scale || scale == 0.0 {
        return Err("the three points are on one line".into());
    }
    n /= n.length();
    let mut d = n.dot(p[0]);
    let tiny = 1e-12 * (1.0 + p.iter().map(|q| q.length()).fold(0.0, f64::max));
    let flip = if d.abs() > tiny {
        d < 0.0
    } else if n.z.abs() > 1e-12 {
        n.z < 0.0
    } else if n.y.abs() > 1e-12 {
        n.y < 0.0
    } else {
        n.x < 0.0
    };
    if flip {
        n = -n;
        d = -d;
    }
    Ok(vec![n.x, n.y, n.z, d])
}

/// `X x1 r1 [x2 r2 [x3 r3]]` (and `Y`, `Z`): points (coordinate along
/// the axis, distance from it) of a surface of revolution about axis `a`;
/// its negative side is the one nearer the axis (below the plane for a
/// plane).
fn by_points(a: usize, v: &[f64]) -> Result<Vec<Part>, String> {
    let plane_kind = [BodyKind::Yzp, BodyKind::Xzp, BodyKind::Xyp][a];
    let mut axis = DVec3::ZERO;
    axis[a] = 1.0;
    match v.len() {
        2 => Ok(vec![Part::body(plane_kind, vec![v[0]])]),
        4 => {
            let ((x1, r1), (x2, r2)) = ((v[0], v[1]), (v[2], v[3]));
            if r1 < 0.0 || r2 < 0.0 {
                return Err("a distance from the axis cannot be negative".into());
            }
            if x1 == x2 {
                if r1 == r2 {
                    return Err("the two points are the same".into());
                }
                return Ok(vec![Part::body(plane_kind, vec![x1])]);
            }
            if r1 == r2 {
                return Ok(vec![Part::body(
                    BodyKind::Qua,
                    cylinder(DVec3::ZERO, axis, r1),
                )]);
            }
            let slope = (r2 - r1) / (x2 - x1);
            let apex = x1 - r1 / slope;
            let far = if (x1 - apex).abs() > (x2 - apex).abs() {
                x1
            } else {
                x2
            };
            let mut at = DVec3::ZERO;
            at[a] = apex;
            cone(
                a,
                at,
                slope * slope,
                Some(if far > apex { 1.0 } else { -1.0 }),
            )
        }
        _ => {
            // r² = p x² + q x + s through three points.
            if v[0] == v[2] || v[2] == v[4] || v[0] == v[4] {
                return Err("the three points must lie at different places along the axis".into());
            }
            let m = DMat3::from_cols(
                DVec3::new(v[0] * v[0], v[2] * v[2], v[4] * v[4]),
                DVec3::new(v[0], v[2], v[4]),
                DVec3::ONE,
            );
            let k = m.inverse() * DVec3::new(v[1] * v[1], v[3] * v[3], v[5] * v[5]);
            // The distance² from the axis less p x² + q x + s.
            let mut q = [1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -k.z];
            q[a] = -k.x;
            q[6 + a] = -k.y;
            Ok(vec![Part::body(BodyKind::Qua, q.to_vec())])
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The QUA polynomial `Axx x² + Ayy y² + Azz z² + Axy xy + Axz xz + Ayz yz
    /// + Ax x + Ay y + Az z + A0` at `p`, term by term.
    fn value(q: &[f64], p: DVec3) -> f64 {
        let (x, y, z) = (p.x, p.y, p.z);
        let squares = q[0] * x * x + q[1] * y * y + q[2] * z * z;
        let crossed = q[3] * x * y + q[4] * x * z + q[5] * y * z;
        squares + crossed + q[6] * x + q[7] * y + q[8] * z + q[9]
    }

    #[test]
    fn quadrics_have_their_negative_side_inside() {
        let sq = parts("sq", &[1.0, 1.0, 1.0, 0.0, 0.0, 0.0, -4.0, 1.0, 2.0, 3.0]).unwrap();
        assert!(value(&sq[0].params, DVec3::new(1.0, 2.0, 3.0)) < 0.0);
        assert!(value(&sq[0].params, DVec3::new(1.0, 2.0, 5.5)) > 0.0);
        let k = parts("k/z", &[0.0, 0.0, 1.0, 0.25, 1.0]).unwrap();
        assert_eq!(k.len(), 2);
        assert!(value(&k[0].params, DVec3::new(0.4, 0.0, 2.0)) < 0.0);
        assert!(value(&k[0].params, DVec3::new(0.6, 0.0, 2.0)) > 0.0);
        assert_eq!((k[1].kind, k[1].op), (BodyKind::Xyp, Op::Outside));
        let x3 = parts("x", &[0.0, 2.0, 1.0, 1.0, -1.0, 1.0]).unwrap();
        // r² = 4 − 3x²/…: through (0,2), (1,1), (−1,1): an ellipsoid.
        assert!(value(&x3[0].params, DVec3::new(0.0, 1.9, 0.0)) < 0.0);
        assert!(value(&x3[0].params, DVec3::new(0.0, 0.0, 2.1)) > 0.0);
        let cone2 = parts("x", &[1.0, 1.0, 3.0, 2.0]).unwrap();
        assert!(value(&cone2[0].params, DVec3::new(-1.0, 0.0, 0.0)) < 1e-9);
    }

    #[test]
    fn planes_by_points_follow_mcnp_senses() {
        let p = plane_by_points(&[0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0, 1.0, 1.0]).unwrap();
        assert_eq!(p, vec![0.0, 0.0, 1.0, 1.0]);
        let through = plane_by_points(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]).unwrap();
        assert!(through[1] > 0.0);
        assert!(plane_by_points(&[0.0; 9]).is_err());
    }
}
