//! The v5 deck writer.

use std::fmt::Write as _;
use sv_geom::{Body, BodyKind, Op, Region};
use sv_math::DVec3;
use sv_scene::{RegionProps, Scene};

/// Most zones a region with groups may expand to when written.
pub const MAX_WRITTEN_ZONES: usize = 4096;

/// Why a scene cannot be written as a COMGEOM deck.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WriteError {
    /// A body type that COMGEOM has no card for (the FLUKA bodies).
    #[error("body {name} is a {kind}, which a COMGEOM deck cannot express")]
    Unsupported {
        /// Body name.
        name: String,
        /// Its type.
        kind: BodyKind,
    },
    /// A body has the wrong number of values for its type.
    #[error("body {name} ({kind}) has {found} values, expected {expected}")]
    WrongCount {
        /// Body name.
        name: String,
        /// Its type.
        kind: BodyKind,
        /// Values present.
        found: usize,
        /// Values the type takes.
        expected: usize,
    },
    /// A value is infinite or NaN (or an ELL's foci are farther apart than
    /// its major axis).
    #[error("body {name} ({kind}) has a value that is not a finite number")]
    NotFinite {
        /// Body name.
        name: String,
        /// Its type.
        kind: BodyKind,
    },
    /// More bodies than the 5-column signed body number of a region card holds.
    #[error("a v5 deck holds at most 9999 bodies, the scene has {0}")]
    TooManyBodies(usize),
    /// More regions than the 5-column region number holds.
    #[error("a v5 deck holds at most 99999 regions, the scene has {0}")]
    TooManyRegions(usize),
    /// A region whose groups expand to more zones than a deck should hold
    /// (a deck cannot nest, so groups are written as zones of body terms).
    #[error("region {region}: its parenthesised groups expand to more than {limit} zones, which a COMGEOM deck cannot nest")]
    TooNested {
        /// Region name.
        region: String,
        /// The most zones written for one region.
        limit: usize,
    },
    /// A region filled by a universe or a lattice.
    #[error("region {region} is filled by another universe or a lattice, which a COMGEOM deck cannot express")]
    Filled {
        /// Region name.
        region: String,
    },
    /// A zone without terms cannot be written.
    #[error("region {region}: zone {zone} has no terms")]
    EmptyZone {
        /// Region name.
        region: String,
        /// 1-based zone number.
        zone: usize,
    },
    /// A term refers to a body index that does not exist.
    #[error("region {region} refers to body index {body}, but the scene has {count} bodies")]
    BadBodyIndex {
        /// Region name.
        region: String,
        /// The index.
        body: usize,
        /// Number of bodies.
        count: usize,
    },
    /// An ident-table value does not fit its 5 columns.
    #[error("region {region}: {what} {value} does not fit in 5 columns")]
    FieldTooWide {
        /// Region name.
        region: String,
        /// Which field.
        what: &'static str,
        /// The value.
        value: i64,
    },
}

/// A written deck and what could not be carried over exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct WrittenDeck {
    /// The v5 deck.
    pub text: String,
    /// One line per approximation or loss: values rounded to fit 10 columns,
    /// ELL foci converted to the centre form, names replaced by numbers,
    /// transparency without an air code.
    pub notes: Vec<String>,
}

/// Convert an ELL given by foci `F1`, `F2` and major-axis length `L` to the
/// centre form `V, A, r` of ELL1 (`FORMATS.md` §1):
/// `V = (F1+F2)/2`, `A = (F2−F1)·L/(2|F2−F1|)`, `r = sqrt(|A|² − (|F2−F1|/2)²)`.
/// Coincident foci give a sphere of radius `L/2` (A along x).
pub fn ell_foci_to_centre(p: &[f64]) -> [f64; 7] {
    let d = [p[3] - p[0], p[4] - p[1], p[5] - p[2]];
    let m = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let half = p[6] / 2.0;
    let a = if m == 0.0 {
        [half, 0.0, 0.0]
    } else {
        d.map(|c| c * p[6] / (2.0 * m))
    };
    let a2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    let r = (a2 - (m / 2.0) * (m / 2.0)).sqrt();
    [
        (p[0] + p[3]) / 2.0,
        (p[1] + p[4]) / 2.0,
        (p[2] + p[5]) / 2.0,
        a[0],
        a[1],
        a[2],
        r,
    ]
}

/// A value in at most 10 columns, with a decimal point (so Fortran readers
/// with implied decimals read it right too). Returns the text and whether it
/// reads back as exactly `v`.
fn fmt_value(v: f64) -> (String, bool) {
    let with_point = |s: &str| -> String {
        if s.contains('.') {
            return s.to_string();
        }
        match s.find(['e', 'E']) {
            Some(i) => format!("{}.{}", &s[..i], &s[i..]),
            None => format!("{s}."),
        }
    };
    let shortest = |forms: [String; 2]| {
        forms
            .into_iter()
            .filter(|s| s.len() <= 10)
            .min_by_key(String::len)
    };
    // Shortest representations that read back exactly, with a point when
    // it fits (a 10-digit integer only fits without one).
    let (plain, exp) = (format!("{v}"), format!("{v:e}"));
    if let Some(s) =
        shortest([with_point(&plain), with_point(&exp)]).or_else(|| shortest([plain, exp.clone()]))
    {
        return (s, true);
    }
    // Too long: the most precise rounding that fits and stays finite.
    for prec in (0..=16).rev() {
        for s in [format!("{v:.prec$}"), format!("{v:.prec$e}")] {
            let s = with_point(&s);
            match s.parse::<f64>() {
                Ok(r) if s.len() <= 10 && r.is_finite() => return (s, r == v),
                _ => {}
            }
        }
    }
    // Rounding overflows (near f64::MAX): cut the mantissa instead.
    let (m, x) = exp.split_once('e').unwrap_or((&exp, "0"));
    let keep = 10usize.saturating_sub(x.len() + 1).min(m.len());
    let s = with_point(&format!("{}e{x}", &m[..keep]));
    let exact = s.parse::<f64>().ok() == Some(v);
    (s, exact)
}

/// FLUKA's half-spaces (XYP, XZP, YZP, PLA) as the HAF body that is the
/// same half-space (`N·x <= D`, N the unit outward normal), written as
/// every HAF is; `None` for any other body, or one whose values do not
/// make a plane.
fn fluka_half_space_as_haf(b: &Body) -> Option<Body> {
    let (normal, point) = match (b.kind, b.params.as_slice()) {
        (BodyKind::Xyp, &[z]) => (DVec3::Z, DVec3::new(0.0, 0.0, z)),
        (BodyKind::Xzp, &[y]) => (DVec3::Y, DVec3::new(0.0, y, 0.0)),
        (BodyKind::Yzp, &[x]) => (DVec3::X, DVec3::new(x, 0.0, 0.0)),
        (BodyKind::Pla, &[nx, ny, nz, px, py, pz]) => {
            (DVec3::new(nx, ny, nz), DVec3::new(px, py, pz))
        }
        _ => return None,
    };
    let unit = normal.try_normalize()?;
    let distance = unit.dot(point);
    Some(Body::new(
        b.name.clone(),
        BodyKind::Haf,
        vec![unit.x, unit.y, unit.z, distance],
    ))
}

fn card_name(kind: BodyKind) -> Option<&'static str> {
    use BodyKind::*;
    Some(match kind {
        Ell | Ell1 => "ELL1",
        Sph | Rcc | Rec | Trc | Tec | Ellg | Rpp | Box | Raw | Arb4 | Arb5 | Arb6 | Arb7 | Arb8
        | Tgc | Tor | Haf | Ars => kind.name(),
        _ => return None,
    })
}

fn one_line(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect::<String>()
        .trim()
        .to_string()
}

/// Append `comment` to a card, from column `column + 1` on (right after
/// the card's text when that is longer); nothing for an empty comment.
fn with_comment(line: &mut String, column: usize, comment: &str) {
    if !comment.is_empty() {
        let _ = write!(
            line,
            "{:width$}{comment}",
            "",
            width = column.saturating_sub(line.len())
        );
    }
}

/// A deck being written: its text and the notes on what it could not keep
/// exactly.
#[derive(Default)]
struct Deck {
    out: String,
    notes: Vec<String>,
}

impl Deck {
    /// Append value cards: six 10-column fields per card; the first card is
    /// `first` (number and type already written), later ones continue it.
    fn value_cards(
        &mut self,
        first: String,
        number: usize,
        vals: &[f64],
        comment: &str,
        what: &str,
    ) {
        let mut line = first;
        for (i, chunk) in vals.chunks(6).enumerate() {
            if i > 0 {
                line = format!("{number:>5}     ");
            }
            for (j, &v) in chunk.iter().enumerate() {
                let (s, exact) = fmt_value(v);
                if !exact {
                    self.notes.push(format!(
                        "{what}: value {} ({v}) written as {s} to fit 10 columns",
                        i * 6 + j + 1
                    ));
                }
                let _ = write!(line, "{s:>10}");
            }
            if i == 0 {
                with_comment(&mut line, 70, comment);
            }
            self.out.push_str(line.trim_end());
            self.out.push('\n');
        }
    }

    /// The cards of body `number`.
    fn body(&mut self, number: usize, b: &Body) -> Result<(), WriteError> {
        let half_space = fluka_half_space_as_haf(b);
        if let Some(haf) = &half_space {
            self.notes.push(format!(
                "body {}: the {} half-space is written as HAF",
                b.name, b.kind
            ));
            return self.body(number, haf);
        }
        let Some(ty) = card_name(b.kind) else {
            return Err(WriteError::Unsupported {
                name: b.name.clone(),
                kind: b.kind,
            });
        };
        let comment = if b.name == number.to_string() {
            String::new()
        } else {
            one_line(&b.name)
        };
        if !comment.is_empty() {
            self.notes
                .push(format!("body {} is written as number {number}", b.name));
        }
        if b.params.iter().any(|v| !v.is_finite()) {
            return Err(WriteError::NotFinite {
                name: b.name.clone(),
                kind: b.kind,
            });
        }
        if b.kind == BodyKind::Ars {
            return self.ars(number, ty, b, &comment);
        }
        let expected = b.kind.info().value_count();
        if b.params.len() != expected {
            return Err(WriteError::WrongCount {
                name: b.name.clone(),
                kind: b.kind,
                found: b.params.len(),
                expected,
            });
        }
        let vals: Vec<f64> = if b.kind == BodyKind::Ell {
            let centre_form = ell_foci_to_centre(&b.params);
            if centre_form.iter().any(|v| !v.is_finite()) {
                return Err(WriteError::NotFinite {
                    name: b.name.clone(),
                    kind: b.kind,
                });
            }
            self.notes.push(format!("body {number}: ELL given by its foci is written as ELL1 (centre, semi-major axis, radius)"));
            centre_form.to_vec()
        } else {
            super::body_to_card_params(b.kind, b.params.clone())
        };
        let what = format!("body {number} ({ty})");
        self.value_cards(
            format!("{number:>5}{ty:<5}"),
            number,
            &vals,
            &comment,
            &what,
        );
        Ok(())
    }

    /// An ARS: curve and point counts on the first card, then three values
    /// per point, each curve starting a new card.
    fn ars(&mut self, number: usize, ty: &str, b: &Body, comment: &str) -> Result<(), WriteError> {
        let wrong_count = |expected| WriteError::WrongCount {
            name: b.name.clone(),
            kind: b.kind,
            found: b.params.len(),
            expected,
        };
        let (curves, points) = match b.params.get(0..2) {
            Some(&[c, p])
                if c >= 1.0 && p >= 1.0 && c.fract() == 0.0 && p.fract() == 0.0 && c * p <= 1e9 =>
            {
                (c as usize, p as usize)
            }
            _ => return Err(wrong_count(2)),
        };
        if b.params.len() != 2 + 3 * curves * points {
            return Err(wrong_count(2 + 3 * curves * points));
        }
        let mut line = format!("{number:>5}{ty:<5}{curves:>10}{points:>10}");
        with_comment(&mut line, 70, comment);
        self.out.push_str(line.trim_end());
        self.out.push('\n');
        let what = format!("body {number} ({ty})");
        for curve in b.params[2..].chunks(3 * points) {
            for chunk in curve.chunks(6) {
                self.value_cards(format!("{number:>5}     "), number, chunk, "", &what);
            }
        }
        Ok(())
    }

    /// The cards of region `number`: nine fields a card, `OR` before the
    /// first term of every zone but the first.
    fn region(&mut self, number: usize, r: &Region, body_count: usize) -> Result<(), WriteError> {
        if r.fill.is_some() {
            return Err(WriteError::Filled {
                region: r.name.clone(),
            });
        }
        let flat;
        let zones = if r.is_nested() {
            flat = r
                .flattened(MAX_WRITTEN_ZONES)
                .ok_or(WriteError::TooNested {
                    region: r.name.clone(),
                    limit: MAX_WRITTEN_ZONES,
                })?;
            &flat
        } else {
            &r.zones
        };
        let mut fields = Vec::new();
        for (zi, z) in zones.iter().enumerate() {
            if z.terms.is_empty() {
                return Err(WriteError::EmptyZone {
                    region: r.name.clone(),
                    zone: zi + 1,
                });
            }
            for (ti, t) in z.terms.iter().enumerate() {
                if t.body >= body_count {
                    return Err(WriteError::BadBodyIndex {
                        region: r.name.clone(),
                        body: t.body,
                        count: body_count,
                    });
                }
                let signed = (t.body + 1) as i64 * if t.op == Op::Outside { -1 } else { 1 };
                let op = if zi > 0 && ti == 0 { "OR" } else { "  " };
                fields.push(format!("{op}{signed:>5}"));
            }
        }
        let comment = if r.name == number.to_string() {
            String::new()
        } else {
            one_line(&r.name)
        };
        if !comment.is_empty() {
            self.notes
                .push(format!("region {} is written as number {number}", r.name));
        }
        let mut chunks: Vec<&[String]> = fields.chunks(9).collect();
        if chunks.is_empty() {
            chunks.push(&[]);
        }
        for (ci, chunk) in chunks.iter().enumerate() {
            let mut line = if ci == 0 {
                format!("{number:>5} ")
            } else {
                "      ".to_string()
            };
            for f in *chunk {
                line.push_str(f);
            }
            if ci == 0 {
                with_comment(&mut line, 69, &comment);
            }
            self.out.push_str(line.trim_end());
            self.out.push('\n');
        }
        Ok(())
    }

    /// The ident card of region `number`.
    fn ident(&mut self, number: usize, r: &Region, p: &RegionProps) -> Result<(), WriteError> {
        if p.transparent && p.air == 0 {
            self.notes.push(format!(
                "region {}: transparency without an air code is not kept",
                r.name
            ));
        }
        let mut line = format!("{number:>5}");
        for (what, v) in [
            ("ident code", p.ident),
            ("air code", p.air),
            ("material", p.material),
            ("line of sight", p.los),
        ] {
            let field = format!("{v:>5}");
            if field.len() > 5 {
                return Err(WriteError::FieldTooWide {
                    region: r.name.clone(),
                    what,
                    value: v,
                });
            }
            line.push_str(&field);
        }
        let desc = one_line(&p.description);
        if !desc.is_empty() {
            let _ = write!(line, "     {desc}");
        }
        self.out.push_str(&line);
        self.out.push('\n');
        Ok(())
    }
}

/// Write a scene's geometry and region metadata as a v5 deck.
///
/// Values are written in the shortest form that reads back to the same
/// number; only a value that needs more than 10 columns is rounded, and each
/// such rounding is listed in [`WrittenDeck::notes`]. An ELL in foci form is
/// written as ELL1 ([`ell_foci_to_centre`]). Body types COMGEOM has no card
/// for (the FLUKA bodies) are an error.
pub fn write(scene: &Scene) -> Result<WrittenDeck, WriteError> {
    let geometry = &scene.geometry;
    if geometry.bodies.len() > 9999 {
        return Err(WriteError::TooManyBodies(geometry.bodies.len()));
    }
    if geometry.regions.len() > 99999 {
        return Err(WriteError::TooManyRegions(geometry.regions.len()));
    }
    let mut deck = Deck::default();
    let _ = writeln!(
        deck.out,
        "{:<2} {}",
        scene.units.abbrev(),
        one_line(&scene.title)
    );
    let _ = writeln!(
        deck.out,
        "{:>5}{:>5}",
        geometry.bodies.len(),
        geometry.regions.len()
    );
    for (i, b) in geometry.bodies.iter().enumerate() {
        deck.body(i + 1, b)?;
    }
    for (i, r) in geometry.regions.iter().enumerate() {
        deck.region(i + 1, r, geometry.bodies.len())?;
    }
    deck.out.push_str("   -1\n");
    let default_props = RegionProps::default();
    for (i, r) in geometry.regions.iter().enumerate() {
        deck.ident(i + 1, r, scene.regions.get(i).unwrap_or(&default_props))?;
    }
    Ok(WrittenDeck {
        text: deck.out,
        notes: deck.notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_short_exact_and_fit_ten_columns() {
        assert_eq!(fmt_value(-303.0232), ("-303.0232".into(), true));
        assert_eq!(fmt_value(3.0), ("3.".into(), true));
        assert_eq!(fmt_value(1e20), ("1.e20".into(), true));
        assert_eq!(fmt_value(1e-7), ("1.e-7".into(), true));
        assert_eq!(fmt_value(-0.5), ("-0.5".into(), true));
        let (s, exact) = fmt_value(0.1 + 0.2);
        assert!(!exact && s.len() <= 10, "{s}");
        assert_eq!(s.parse::<f64>().unwrap(), 0.30000000);
        let (s, exact) = fmt_value(-123456.789012345);
        assert!(!exact && s.len() <= 10, "{s}");
        assert_eq!(fmt_value(1234567890.0), ("1234567890".into(), true));
        let (s, exact) = fmt_value(f64::MAX);
        assert!(
            !exact && s.len() <= 10 && s.parse::<f64>().unwrap().is_finite(),
            "{s}"
        );
        let (s, exact) = fmt_value(-f64::MAX);
        assert!(
            !exact && s.len() <= 10 && s.parse::<f64>().unwrap().is_finite(),
            "{s}"
        );
        assert_eq!(fmt_value(5e-324), ("5.e-324".into(), true));
    }

    #[test]
    fn foci_convert_to_centre_form() {
        // GIFT sample target body 5: F1 (20,0,48), F2 (-20,0,48), L 50.
        assert_eq!(
            ell_foci_to_centre(&[20.0, 0.0, 48.0, -20.0, 0.0, 48.0, 50.0]),
            [0.0, 0.0, 48.0, -25.0, 0.0, 0.0, 15.0]
        );
    }
}
