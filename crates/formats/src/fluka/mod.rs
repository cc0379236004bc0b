//! FLUKA geometry in free (name-based) format.
//!
//! [`read`] finds `GEOBEGIN … GEOEND` (SDUM `COMBNAME`) in a FLUKA input and
//! turns its bodies and regions into a [`Scene`](sv_scene::Scene) in centimetres. The physics
//! cards around it are skipped, except the few that shape the picture:
//!
//! * `TITLE` gives the scene title (else the geometry title line does);
//! * `ROT-DEFI` cards (anywhere in the input) define the roto-translations
//!   used by `$start_transform` (convention below);
//! * `ASSIGNMA` cards name each region's material: it is recorded in
//!   [`RegionProps::description`](sv_scene::RegionProps::description) as `material: NAME`, and `BLCKHOLE` regions
//!   are made transparent, and so are `VACUUM` regions (air code 1, shown
//!   by `render --show-air`);
//! * `FREE`, `FIXED` and `GLOBAL` switch between fixed-column and free cards.
//!
//! The preprocessor (`#define`, `#undef`, `#if`/`#ifdef`/`#ifndef`, `#elif`,
//! `#else`, `#endif`, `#include`) runs first over the whole input. Bodies
//! may be moved by `$start_translat`, `$start_expansion` and
//! `$start_transform` (nested in any order). Regions are put in disjunctive
//! normal form: each becomes a union of zones of signed body terms.
//!
//! # Transforms
//!
//! The ROT-DEFI convention is the FLUKA manual's (ROT-DEFIni), which
//! pyg4ometry's reader follows too:
//!
//! * WHAT(1) gives the axis j: `j + 1000 i` from 1000 on, `i + 100 j` from
//!   100 on, otherwise only the index i, with j = 0. j = 1 is x, 2 is y, 0 or 3
//!   is z. Any other j is an error.
//! * WHAT(2) is the polar angle θ, WHAT(3) the azimuthal angle φ (degrees),
//!   WHAT(4…6) the offset t. A body point r becomes `Rθ · Rφ · (r + t)`,
//!   with (rows) for z: `Rθ = [[cθ,0,−sθ],[0,1,0],[sθ,0,cθ]]`,
//!   `Rφ = [[cφ,sφ,0],[−sφ,cφ,0],[0,0,1]]`; for x:
//!   `Rθ = [[cθ,sθ,0],[−sθ,cθ,0],[0,0,1]]`, `Rφ = [[1,0,0],[0,cφ,sφ],[0,−sφ,cφ]]`;
//!   for y: `Rθ = [[1,0,0],[0,cθ,sθ],[0,−sθ,cθ]]`,
//!   `Rφ = [[cφ,0,−sφ],[0,1,0],[sφ,0,cφ]]`.
//! * Several ROT-DEFI cards with one name make one transformation, the first
//!   card acting first. `$start_transform -NAME` applies its inverse.
//! * Around a body, all `$start_expansion` factors act first (they
//!   multiply), then all `$start_translat` shifts (they add up), then the
//!   transforms, the innermost first (the manual's `r' = R2(R1(r))` for `R2`
//!   around `R1`), whatever the order the directives are nested in; an
//!   `$end_…` closes the innermost open directive of its kind.
//! * The result goes through [`Body::transformed`]: a turned RPP becomes a
//!   BOX, a turned XYP a PLA, a turned XCC…ZEC a QUA.
//!
//! `LATTICE` cards are read and checked; the container regions are drawn as
//! themselves and a note in [`Scene::notes`](sv_scene::Scene::notes) says the replicas are not drawn.
//! The fixed-format numbered geometry (`COMBINAT`) is not read: it is
//! reported as such.
//!
//! Every problem is reported at once, with file, line and column; no input
//! makes the reader panic, hang or allocate without bound.
//!
//! ```
//! use sv_formats::{fluka, LoadOptions, SourceFile};
//! let text = "GEOBEGIN                                                              COMBNAME\n\
//!     0    0          demo\n\
//! SPH ball 0 0 0 10\n\
//! RPP world -50 50 -50 50 -50 50\n\
//! END\n\
//! void 5 +world -ball\n\
//! ball 5 +ball\n\
//! END\n\
//! GEOEND\n\
//! ASSIGNMA    BLCKHOLE      void\n";
//! let loaded = fluka::read(&SourceFile::new("demo.inp", text), &LoadOptions::default()).unwrap();
//! let scene = loaded.scene;
//! assert_eq!(scene.title, "demo");
//! assert_eq!(scene.geometry.bodies.len(), 2);
//! assert_eq!(scene.geometry.regions[0].zones.len(), 1);
//! assert!(scene.regions[0].transparent);
//! ```

mod bodies;
mod card;
mod preprocess;
mod region;
mod regions;
mod rotdefi;
mod scene;

pub use preprocess::MAX_INCLUDE_DEPTH;
pub use region::{MAX_DEPTH, MAX_ZONES};

use crate::diag::count;
use crate::text;
use crate::{did_you_mean, Diagnostic, Diagnostics, LoadOptions, Loaded, SourceFile};
use card::Card;
use preprocess::Line;
use rotdefi::RotDefi;
use std::collections::{HashMap, HashSet};
use sv_geom::{Body, BodyKind, Region};

/// FLUKA body codes and the body kinds they become.
pub const BODY_CODES: [(&str, BodyKind); 21] = [
    ("RPP", BodyKind::Rpp),
    ("BOX", BodyKind::Box),
    ("SPH", BodyKind::Sph),
    ("RCC", BodyKind::Rcc),
    ("REC", BodyKind::Rec),
    ("TRC", BodyKind::Trc),
    ("ELL", BodyKind::Ell),
    ("WED", BodyKind::Raw),
    ("RAW", BodyKind::Raw),
    ("ARB", BodyKind::ArbF),
    ("XYP", BodyKind::Xyp),
    ("XZP", BodyKind::Xzp),
    ("YZP", BodyKind::Yzp),
    ("PLA", BodyKind::Pla),
    ("XCC", BodyKind::Xcc),
    ("YCC", BodyKind::Ycc),
    ("ZCC", BodyKind::Zcc),
    ("XEC", BodyKind::Xec),
    ("YEC", BodyKind::Yec),
    ("ZEC", BodyKind::Zec),
    ("QUA", BodyKind::Qua),
];

/// Read the geometry of a FLUKA input. `#include`d files are read relative
/// to the directory of `src.name`.
pub fn read(src: &SourceFile, _opts: &LoadOptions) -> Result<Loaded, Diagnostics> {
    let mut pre = preprocess::run(src);
    let lines = std::mem::take(&mut pre.lines);
    let errors = std::mem::take(&mut pre.errors);
    let suppressed = pre.suppressed;
    let mut reader = Reader {
        lines,
        errors,
        warnings: Vec::new(),
        rot: HashMap::new(),
        rot_index: HashMap::new(),
        assigns: Vec::new(),
        title: None,
        geo_title: String::new(),
        bodies: Vec::new(),
        body_index: HashMap::new(),
        body_lines: Vec::new(),
        bad_bodies: HashSet::new(),
        regions: Vec::new(),
        region_index: HashMap::new(),
        region_lines: Vec::new(),
        lattices: Vec::new(),
        expander: region::Expander::default(),
        assign_budget: 10_000_000,
        hints_left: std::cell::Cell::new(5),
        suppressed,
        sink: Diagnostic::error(src, 0, 0, ""),
        out: pre,
    };
    reader.run();
    if !reader.errors.is_empty() || reader.suppressed > 0 {
        let files: HashMap<String, usize> = reader
            .out
            .files
            .iter()
            .enumerate()
            .map(|(i, f)| (f.name.clone(), i))
            .collect();
        reader
            .errors
            .sort_by_key(|d| (files.get(&d.source.name).copied().unwrap_or(0), d.offset));
        if reader.suppressed > 0 {
            let last = reader
                .errors
                .last()
                .cloned()
                .unwrap_or_else(|| reader.sink.clone());
            reader.errors.push(Diagnostic {
                message: format!(
                    "… and {}",
                    count(reader.suppressed, "more error", "more errors")
                ),
                hint: None,
                unlisted_errors: reader.suppressed,
                ..last
            });
        }
        return Err(Diagnostics {
            items: reader.errors,
        });
    }
    Ok(Loaded {
        scene: reader.scene(),
        warnings: reader.warnings,
        format: crate::Format::Fluka,
    })
}

struct Reader {
    /// The files read and their line tables.
    out: preprocess::Output,
    lines: Vec<Line>,
    errors: Vec<Diagnostic>,
    warnings: Vec<Diagnostic>,
    /// ROT-DEFI cards by name, in input order.
    rot: HashMap<String, Vec<RotDefi>>,
    /// ROT-DEFI names by transformation index.
    rot_index: HashMap<i64, String>,
    assigns: Vec<(usize, Card)>,
    title: Option<String>,
    geo_title: String,
    bodies: Vec<Body>,
    body_index: HashMap<String, usize>,
    /// Line index of each body's definition.
    body_lines: Vec<usize>,
    /// Bodies defined with errors: references to them are not reported again.
    bad_bodies: HashSet<String>,
    regions: Vec<Region>,
    region_index: HashMap<String, usize>,
    /// Line index of each region's definition.
    region_lines: Vec<usize>,
    /// Lattice container regions (indices), with the card's line.
    lattices: Vec<(usize, usize)>,
    expander: region::Expander,
    /// How many more "did you mean" hints may be worked out.
    hints_left: std::cell::Cell<usize>,
    /// Region assignments ASSIGNMA and LATTICE ranges may still make (bounds
    /// the work).
    assign_budget: usize,
    /// Errors past [`MAX_ERRORS`]: counted, not kept.
    suppressed: usize,
    /// Where suppressed errors are written.
    sink: Diagnostic,
}

/// Most errors listed for one input; the rest are counted.
pub const MAX_ERRORS: usize = 100;

/// The text of a line without its comment: `*` in column 1 makes the whole
/// line a comment, `!` starts one.
fn clean(line: &str) -> &str {
    text::code(line, &text::FLUKA)
}

/// Words separated by blanks or commas, with their 1-based columns.
fn tokens(line: &str) -> Vec<(usize, &str)> {
    text::tokens(line, 0, &text::FLUKA)
        .into_iter()
        .map(|t| (t.span.col, t.text))
        .collect()
}

fn is_integer(s: &str) -> bool {
    let d = s.strip_prefix(['+', '-']).unwrap_or(s);
    !d.is_empty() && d.len() < 10 && d.bytes().all(|b| b.is_ascii_digit())
}

/// FLUKA names: a letter, then letters, digits and `_`.
fn is_name(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_alphabetic())
        && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// The geometry title from the line after GEOBEGIN: two integers (IVLFLG,
/// IDBG), then the title (column 21 on in fixed format).
fn geometry_title(text: &str) -> (i64, String) {
    let mut rest = text;
    let mut ivlflg = 0;
    for k in 0..2 {
        let t = rest.trim_start();
        let n = t
            .chars()
            .take_while(|c| c.is_ascii_digit() || *c == '-' || *c == '+')
            .count();
        if n == 0
            || !t[n..]
                .chars()
                .next()
                .is_none_or(|c| c.is_whitespace() || c == ',')
        {
            break;
        }
        if k == 0 {
            ivlflg = t[..n].parse().unwrap_or(0);
        }
        rest = &t[n..];
        rest = rest.trim_start_matches([' ', '\t']);
        rest = rest.strip_prefix(',').unwrap_or(rest);
    }
    (ivlflg, rest.trim().to_string())
}

impl Reader {
    fn err(
        &mut self,
        line: usize,
        col: usize,
        len: usize,
        msg: impl Into<String>,
    ) -> &mut Diagnostic {
        if self.errors.len() >= MAX_ERRORS {
            self.suppressed += 1;
            return &mut self.sink;
        }
        let l = &self.lines[line];
        let d = self.out.error(l.file, l.line, col, len, msg);
        self.errors.push(d);
        self.errors.last_mut().expect("just pushed")
    }

    /// "did you mean …?" for a mistyped name among `names`. Only the first
    /// few errors get one, and only names of about the same length are
    /// compared, so an input with many bad names stays cheap to check.
    fn hint_among<'a>(
        &self,
        word: &str,
        names: impl Iterator<Item = &'a String>,
    ) -> Option<String> {
        if self.hints_left.get() == 0 || self.full() {
            return None;
        }
        self.hints_left.set(self.hints_left.get() - 1);
        let n = word.chars().count();
        let near = names
            .map(String::as_str)
            .filter(|c| c.chars().count().abs_diff(n) <= n / 3 + 2);
        did_you_mean(word, near).map(|s| format!("did you mean `{s}`?"))
    }

    /// `line N` (with the file's name when it is an included file).
    fn where_is(&self, line: usize) -> String {
        let l = &self.lines[line];
        if l.file == 0 {
            format!("line {}", l.line)
        } else {
            format!("line {} of {}", l.line, self.out.files[l.file].name)
        }
    }

    /// True once [`MAX_ERRORS`] errors are kept (hints are then not
    /// worked out).
    fn full(&self) -> bool {
        self.errors.len() >= MAX_ERRORS
    }

    fn warn(&mut self, line: usize, col: usize, len: usize, msg: impl Into<String>) {
        if self.warnings.len() >= MAX_ERRORS {
            return;
        }
        let l = &self.lines[line];
        self.warnings
            .push(self.out.error(l.file, l.line, col, len, msg).warning());
    }

    fn run(&mut self) {
        let line_count = self.lines.len();
        let mut free = false;
        let mut geometry: Option<(usize, usize)> = None;
        let mut seen_geobegin = false;
        let mut i = 0;
        while i < line_count {
            let text = clean(&self.lines[i].text).to_string();
            if text.trim().is_empty() {
                i += 1;
                continue;
            }
            let card = card::split(&text, card::is_free(&text, free));
            match card.keyword.as_str() {
                "TITLE" => {
                    if i + 1 < line_count {
                        self.title = Some(self.lines[i + 1].text.trim().to_string());
                    }
                    i += 2;
                    continue;
                }
                "FREE" => free = true,
                "FIXED" => free = false,
                "GLOBAL"
                    if card.what[3]
                        .as_ref()
                        .and_then(|f| card::number(&f.text))
                        .is_some_and(|v| v >= 2.0) =>
                {
                    free = true
                }
                "GEOBEGIN" => {
                    if seen_geobegin {
                        self.err(i, 1, 8, "second GEOBEGIN card: an input holds one geometry");
                        i += 1;
                        continue;
                    }
                    seen_geobegin = true;
                    let end = (i + 1..line_count).find(|&j| {
                        tokens(clean(&self.lines[j].text))
                            .first()
                            .is_some_and(|(_, w)| w.eq_ignore_ascii_case("GEOEND"))
                    });
                    let Some(end) = end else {
                        self.err(i, 1, 8, "GEOBEGIN without GEOEND").hint =
                            Some("end the geometry with a GEOEND card".into());
                        break;
                    };
                    let ok = self.check_geobegin(i, &card);
                    geometry = ok.then_some((i, end));
                    i = end + 1;
                    continue;
                }
                k if k.starts_with("ROT-DEFI") => self.rotdefi(i, &card),
                k if k.starts_with("ASSIGNMA") => self.assigns.push((i, card)),
                _ => {}
            }
            i += 1;
        }
        if !seen_geobegin {
            let src = self.out.files[0].clone();
            self.errors.push(
                Diagnostic::error(&src, 0, 0, "no GEOBEGIN card: this input has no geometry")
                    .with_hint(
                        "a FLUKA geometry is written between GEOBEGIN (SDUM COMBNAME) and GEOEND",
                    ),
            );
            return;
        }
        if let Some((begin, end)) = geometry {
            self.geometry(begin, end, free);
        }
    }

    /// Check GEOBEGIN's options; false when the geometry cannot be read.
    fn check_geobegin(&mut self, i: usize, c: &Card) -> bool {
        if let Some(w3) = &c.what[2] {
            if card::number(&w3.text).is_some_and(|v| v > 0.0 && v != 5.0) {
                let (col, len) = (w3.col, w3.len());
                self.err(i, col, len, format!("geometry read from a separate logical unit (GEOBEGIN WHAT(3) = {}) is not supported", w3.text))
                    .hint = Some("put the geometry between GEOBEGIN and GEOEND".into());
                return false;
            }
        }
        // COMBNAME belongs in SDUM; a free-format card that leaves out the
        // blank WHATs puts it in an earlier field, which is accepted too.
        if c.sdum
            .iter()
            .chain(c.what.iter().flatten())
            .any(|f| f.text.eq_ignore_ascii_case("COMBNAME"))
        {
            return true;
        }
        let (col, len, shown) = match &c.sdum {
            Some(f) => (f.col, f.len(), format!("SDUM `{}`", f.text)),
            None => (1, 8, "blank SDUM, which means COMBINAT".to_string()),
        };
        self.err(
            i,
            col,
            len,
            format!("the fixed-format numbered geometry (GEOBEGIN {shown}) is not supported"),
        )
        .hint = Some(
            "write the geometry in free format with names: GEOBEGIN with SDUM COMBNAME".into(),
        );
        false
    }

    fn geometry(&mut self, begin: usize, end: usize, free: bool) {
        // The title line is the first line after GEOBEGIN that is not a
        // comment.
        let title_line = (begin + 1..end).find(|&k| !self.lines[k].text.starts_with('*'));
        let (ivlflg, title) =
            title_line.map_or((0, String::new()), |k| geometry_title(&self.lines[k].text));
        self.geo_title = title;
        let Some(regions_start) = self.bodies_section(title_line.map_or(end, |k| k + 1), end)
        else {
            self.err(end, 1, 6, "missing END after the bodies").hint =
                Some("the body list ends with a line holding END".into());
            return;
        };
        let Some(lattice_start) = self.regions_section(regions_start, end) else {
            self.err(end, 1, 6, "missing END after the regions").hint =
                Some("the region list ends with a line holding END".into());
            return;
        };
        if self.regions.is_empty() && self.errors.is_empty() {
            self.err(end, 1, 6, "the geometry has no regions");
        }
        for i in lattice_start..end {
            let text = clean(&self.lines[i].text).to_string();
            if text.trim().is_empty() {
                continue;
            }
            let card = card::split(&text, card::is_free(&text, free));
            if card.keyword == "LATTICE" {
                self.lattice(i, &card);
            } else if ivlflg == 0 {
                let (col, w) = tokens(&text)
                    .first()
                    .map_or((1, String::new()), |(c, w)| (*c, w.to_string()));
                self.err(
                    i,
                    col,
                    w.chars().count(),
                    format!("expected LATTICE or GEOEND after the regions, found `{w}`"),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometry_title_forms() {
        assert_eq!(
            geometry_title("    0    0          a beam line"),
            (0, "a beam line".to_string())
        );
        assert_eq!(
            geometry_title("0,0,et inside vacuum"),
            (0, "et inside vacuum".to_string())
        );
        assert_eq!(
            geometry_title("\t\t\t A simple Be target"),
            (0, "A simple Be target".to_string())
        );
        assert_eq!(geometry_title("    1    0"), (1, String::new()));
    }
}
