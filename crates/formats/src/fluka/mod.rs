//! FLUKA geometry: name-based free format and numbered fixed format.
//!
//! [`read`] finds `GEOBEGIN … GEOEND` in a FLUKA input and turns its bodies
//! and regions into a [`Scene`](sv_scene::Scene) in centimetres. Both of
//! FLUKA's geometry layouts are read: the name-based free format (GEOBEGIN
//! SDUM `COMBNAME`) and the numbered fixed-column format (SDUM blank or
//! `COMBINAT`, FLUKA's default: bodies `(2X,A3,I5,6D10.3)` or, for IDBG
//! −10/−100, `(2X,A3,I5,3D22.15)`; regions `(2X,A3,I5,9(A2,I5))` or, for
//! IDBG ±100, `(2X,A3,I5,7(A2,I7))`, with `OR` in the operator fields),
//! whose bodies and regions are named by their numbers. The geometry may
//! also be read from a separate file (GEOBEGIN WHAT(3) a logical unit,
//! the file named on the next card, relative to the input). The physics
//! cards around it are skipped, except those that shape the picture:
//!
//! * `TITLE` gives the scene title (else the geometry title line does);
//! * `ROT-DEFI` cards (anywhere in the input) define the roto-translations
//!   used by `$start_transform`, `LATTICE` and `VOXELS` (convention below);
//!   a card without a name is `ROT#n` after its index `n`;
//! * `ASSIGNMA` cards give each region its material (by name, and by
//!   FLUKA's material number, the predefined materials included): `BLCKHOLE`
//!   regions are outside the model, and `BLCKHOLE`, `VACUUM` and `AIR`
//!   regions are transparent (air code 1 for the last two, shown by
//!   `render --show-air`);
//! * `MATERIAL` and `COMPOUND` cards list the materials with their
//!   densities (and their elements, when every component is one);
//! * `VOXELS`, right after GEOBEGIN, adds a voxel structure read from its
//!   `.vxl` file beside the input (see `voxels.rs`);
//! * `FREE`, `FIXED` and `GLOBAL` switch between fixed-column and free cards.
//!
//! The preprocessor (`#define`, `#undef`, `#if`/`#ifdef`/`#ifndef`, `#elif`,
//! `#else`, `#endif`, `#include`, and `$name` replaced by a defined value)
//! runs first over the whole input. Bodies may be moved by
//! `$start_translat`, `$start_expansion` and `$start_transform` (nested in
//! any order). Regions are kept as written: parentheses become groups of
//! zones (no expansion into sums of products), so a region costs what its
//! text is long; a line that does not start a new region (a name and its
//! NAZ) continues the one before, whatever it starts with.
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
//!   WHAT(4…6) the offset t. A point r becomes `Rθ · Rφ · (r + t)`,
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
//! * A `LATTICE` transformation brings a point of the lattice cell to the
//!   corresponding point of the prototype (the manual's words), so the
//!   cell is filled with the whole model moved by its inverse
//!   ([`Fill::Universe`](sv_geom::Fill::Universe) of universe 0): what
//!   FLUKA tracks in the cell. A `VOXELS` transformation likewise brings a
//!   point of the model into the voxel structure's own frame.
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
//! assert!(scene.regions[0].outside && scene.regions[0].transparent);
//! ```

mod bodies;
mod card;
mod fixed;
mod geometry;
mod lattice;
mod materials;
mod preprocess;
mod regions;
mod rotdefi;
mod scene;
mod voxels;

pub use crate::text::region::MAX_DEPTH;
pub use preprocess::MAX_INCLUDE_DEPTH;
pub use voxels::{MAX_VOXELS, MAX_VOXEL_BOXES};

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

/// Read the geometry of a FLUKA input. `#include`d files, a geometry read
/// from a separate file and `.vxl` voxel files are read relative to the
/// directory of `src.name`.
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
        material_cards: Vec::new(),
        title: None,
        geo_title: String::new(),
        bodies: Vec::new(),
        body_index: HashMap::new(),
        body_lines: Vec::new(),
        bad_bodies: HashSet::new(),
        empty_bodies: HashSet::new(),
        regions: Vec::new(),
        region_index: HashMap::new(),
        region_lines: Vec::new(),
        region_labels: HashMap::new(),
        lattices: Vec::new(),
        voxels: None,
        assign_budget: 10_000_000,
        hints_left: std::cell::Cell::new(5),
        suppressed,
        sink: Diagnostic::error(src, 0, 0, ""),
        out: pre,
    };
    reader.run();
    if !reader.errors.is_empty() || reader.suppressed > 0 {
        return Err(reader.into_errors());
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
    /// MATERIAL and COMPOUND cards, in input order.
    material_cards: Vec<(usize, Card)>,
    title: Option<String>,
    geo_title: String,
    bodies: Vec<Body>,
    body_index: HashMap<String, usize>,
    /// Line index of each body's definition.
    body_lines: Vec<usize>,
    /// Bodies defined with errors: references to them are not reported again.
    bad_bodies: HashSet<String>,
    /// Bodies known to be empty (a voxel cage whose file is missing).
    empty_bodies: HashSet<String>,
    regions: Vec<Region>,
    region_index: HashMap<String, usize>,
    /// Line index of each region's definition.
    region_lines: Vec<usize>,
    /// The labels of numbered regions (columns 3–5), by region.
    region_labels: HashMap<usize, String>,
    /// Lattice cells.
    lattices: Vec<lattice::Cell>,
    /// The VOXELS card, when there is one.
    voxels: Option<voxels::Voxels>,
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
        let (col, len) = l.written_span(col, len);
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
        self.warn_hinted(line, col, len, msg, None);
    }

    /// A warning with a hint (when there is one).
    fn warn_hinted(
        &mut self,
        line: usize,
        col: usize,
        len: usize,
        msg: impl Into<String>,
        hint: Option<String>,
    ) {
        if self.warnings.len() >= MAX_ERRORS {
            return;
        }
        let l = &self.lines[line];
        let (col, len) = l.written_span(col, len);
        let mut d = self.out.error(l.file, l.line, col, len, msg).warning();
        d.hint = hint;
        self.warnings.push(d);
    }

    /// The errors, in file order, with the count of those not kept.
    fn into_errors(mut self) -> Diagnostics {
        let files: HashMap<String, usize> = self
            .out
            .files
            .iter()
            .enumerate()
            .map(|(i, f)| (f.name.clone(), i))
            .collect();
        self.errors
            .sort_by_key(|d| (files.get(&d.source.name).copied().unwrap_or(0), d.offset));
        if self.suppressed > 0 {
            let last = self
                .errors
                .last()
                .cloned()
                .unwrap_or_else(|| self.sink.clone());
            self.errors.push(Diagnostic {
                message: format!(
                    "… and {}",
                    count(self.suppressed, "more error", "more errors")
                ),
                hint: None,
                unlisted_errors: self.suppressed,
                ..last
            });
        }
        Diagnostics { items: self.errors }
    }

    fn run(&mut self) {
        let line_count = self.lines.len();
        let mut free = false;
        let mut geometry: Option<(usize, usize, Card)> = None;
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
                // FLUKA reads nothing after STOP.
                "STOP" => break,
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
                    geometry = Some((i, end, card));
                    i = end + 1;
                    continue;
                }
                k if k.starts_with("ROT-DEFI") => self.rotdefi(i, &card),
                k if k.starts_with("ASSIGNMA") => self.assigns.push((i, card)),
                "MATERIAL" | "COMPOUND" => self.material_cards.push((i, card)),
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
        if let Some((begin, end, card)) = geometry {
            self.geometry(begin, end, &card, free);
        }
    }
}
