//! FLUKA geometry in free (name-based) format.
//!
//! [`read`] finds `GEOBEGIN … GEOEND` (SDUM `COMBNAME`) in a FLUKA input and
//! turns its bodies and regions into a [`Scene`] in centimetres. The physics
//! cards around it are skipped, except the few that shape the picture:
//!
//! * `TITLE` gives the scene title (else the geometry title line does);
//! * `ROT-DEFI` cards (anywhere in the input) define the roto-translations
//!   used by `$start_transform` (convention below);
//! * `ASSIGNMA` cards name each region's material: it is recorded in
//!   [`RegionProps::description`] as `material: NAME`, and `BLCKHOLE` regions
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
//! themselves and a note in [`Scene::notes`] says the replicas are not drawn.
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

mod card;
mod preprocess;
mod region;
mod rotdefi;

pub use preprocess::MAX_INCLUDE_DEPTH;
pub use region::{MAX_DEPTH, MAX_ZONES};

use crate::{did_you_mean, Diagnostic, Diagnostics, LoadOptions, Loaded, SourceFile};
use card::Card;
use preprocess::Line;
use region::{Spanned, Tok};
use rotdefi::RotDefi;
use std::collections::{HashMap, HashSet};
use sv_geom::{Body, BodyKind, Geometry, Region};
use sv_math::{DAffine3, DVec3};
use sv_scene::{RegionProps, Scene, Units};

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

/// FLUKA body types this reader knows of but does not read.
const UNSUPPORTED_CODES: [&str; 4] = ["PYX", "PYY", "PYZ", "TET"];

const DIRECTIVES: [&str; 6] = [
    "$start_translat",
    "$end_translat",
    "$start_expansion",
    "$end_expansion",
    "$start_transform",
    "$end_transform",
];

/// Read the geometry of a FLUKA input. `#include`d files are read relative
/// to the directory of `src.name`.
pub fn read(src: &SourceFile, _opts: &LoadOptions) -> Result<Loaded, Diagnostics> {
    let mut pre = preprocess::run(src);
    let lines = std::mem::take(&mut pre.lines);
    let errors = std::mem::take(&mut pre.errors);
    let suppressed = pre.suppressed;
    let mut r = Reader {
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
    r.run();
    if !r.errors.is_empty() || r.suppressed > 0 {
        let files: HashMap<String, usize> = r
            .out
            .files
            .iter()
            .enumerate()
            .map(|(i, f)| (f.name.clone(), i))
            .collect();
        r.errors
            .sort_by_key(|d| (files.get(&d.source.name).copied().unwrap_or(0), d.offset));
        if r.suppressed > 0 {
            let last = r.errors.last().cloned().unwrap_or_else(|| r.sink.clone());
            r.errors.push(Diagnostic {
                message: format!(
                    "… and {} more error{}",
                    r.suppressed,
                    if r.suppressed == 1 { "" } else { "s" }
                ),
                hint: None,
                ..last
            });
        }
        return Err(Diagnostics { items: r.errors });
    }
    Ok(Loaded {
        scene: r.scene(),
        warnings: r.warnings,
        format: crate::Format::Fluka,
    })
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DirKind {
    Translat,
    Expansion,
    Transform,
}

impl DirKind {
    fn name(self) -> &'static str {
        match self {
            DirKind::Translat => "translat",
            DirKind::Expansion => "expansion",
            DirKind::Transform => "transform",
        }
    }
}

#[derive(Clone, Debug)]
struct Directive {
    kind: DirKind,
    factor: f64,
    shift: DVec3,
    xf: DAffine3,
    line: usize,
    col: usize,
    len: usize,
}

struct PendingBody {
    /// (line index, column, text) of each word.
    words: Vec<(usize, usize, String)>,
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
fn clean(text: &str) -> &str {
    if text.starts_with('*') {
        return "";
    }
    match text.find('!') {
        Some(i) => &text[..i],
        None => text,
    }
}

/// Words separated by blanks or commas, with their 1-based columns.
fn tokens(text: &str) -> Vec<(usize, &str)> {
    card::split_words(text, |c| c.is_whitespace() || c == ',')
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

fn starts_numeric(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_digit() || c == '+' || c == '-' || c == '.')
}

fn body_code(s: &str) -> Option<BodyKind> {
    BODY_CODES
        .iter()
        .find(|(c, _)| c.eq_ignore_ascii_case(s))
        .map(|(_, k)| *k)
}

/// The body code a mistyped one was meant to be: one with the same letters
/// in another order (`SHP` → `SPH`), else the closest by edit distance.
fn suggest_code(code: &str) -> Option<&'static str> {
    let mut letters: Vec<char> = code.to_ascii_uppercase().chars().collect();
    letters.sort_unstable();
    let anagram = BODY_CODES.iter().map(|(c, _)| *c).find(|c| {
        let mut l: Vec<char> = c.chars().collect();
        l.sort_unstable();
        l == letters
    });
    anagram.or_else(|| did_you_mean(code, BODY_CODES.iter().map(|(c, _)| *c)))
}

/// The name of value `i` of a body type (`V` components become `Vx`, `Vy`, `Vz`).
fn value_name(kind: BodyKind, i: usize) -> String {
    let mut at = 0;
    for p in kind.info().params {
        let w = p.kind.width();
        if i < at + w {
            return if w == 3 {
                format!("{}{}", p.name, ["x", "y", "z"][i - at])
            } else {
                p.name.to_string()
            };
        }
        at += w;
    }
    format!("#{}", i + 1)
}

/// `V(3) H(3) R` for a body type.
fn layout(kind: BodyKind) -> String {
    kind.info()
        .params
        .iter()
        .map(|p| {
            if p.kind.width() == 3 {
                format!("{}(3)", p.name)
            } else {
                p.name.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
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
        let n = self.lines.len();
        let mut free = false;
        let mut geo: Option<(usize, usize)> = None;
        let mut seen_geobegin = false;
        let mut i = 0;
        while i < n {
            let text = clean(&self.lines[i].text).to_string();
            if text.trim().is_empty() {
                i += 1;
                continue;
            }
            let c = card::split(&text, card::is_free(&text, free));
            match c.keyword.as_str() {
                "TITLE" => {
                    if i + 1 < n {
                        self.title = Some(self.lines[i + 1].text.trim().to_string());
                    }
                    i += 2;
                    continue;
                }
                "FREE" => free = true,
                "FIXED" => free = false,
                "GLOBAL"
                    if c.what[3]
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
                    let end = (i + 1..n).find(|&j| {
                        tokens(clean(&self.lines[j].text))
                            .first()
                            .is_some_and(|(_, w)| w.eq_ignore_ascii_case("GEOEND"))
                    });
                    let Some(end) = end else {
                        self.err(i, 1, 8, "GEOBEGIN without GEOEND").hint =
                            Some("end the geometry with a GEOEND card".into());
                        break;
                    };
                    let ok = self.check_geobegin(i, &c);
                    geo = ok.then_some((i, end));
                    i = end + 1;
                    continue;
                }
                k if k.starts_with("ROT-DEFI") => self.rotdefi(i, &c),
                k if k.starts_with("ASSIGNMA") => self.assigns.push((i, c)),
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
        if let Some((begin, end)) = geo {
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

    fn rotdefi(&mut self, i: usize, c: &Card) {
        let mut w = [0.0; 6];
        for (k, f) in c.what.iter().enumerate() {
            if let Some(f) = f {
                match card::number(&f.text) {
                    Some(v) => w[k] = v,
                    None => {
                        let (col, len) = (f.col, f.len());
                        self.err(
                            i,
                            col,
                            len,
                            format!(
                                "expected a number in ROT-DEFI WHAT({}), found `{}`",
                                k + 1,
                                f.text
                            ),
                        );
                        return;
                    }
                }
            }
        }
        let (index, axis) = match rotdefi::index_and_axis(w[0]) {
            Ok(x) => x,
            Err(j) => {
                let (col, len) = c.what[0].as_ref().map_or((1, 8), |f| (f.col, f.len()));
                self.err(
                    i,
                    col,
                    len,
                    format!("ROT-DEFI axis code j = {j} is not 1 (x), 2 (y) or 3 (z)"),
                )
                .hint = Some("WHAT(1) is i + 100 j below 1000 and j + 1000 i above".into());
                return;
            }
        };
        let name = match &c.sdum {
            Some(s) => s.text.clone(),
            None if index > 0 => index.to_string(),
            None => return, // ignored by FLUKA too
        };
        if index > 0 {
            self.rot_index.entry(index).or_insert_with(|| name.clone());
        }
        self.rot.entry(name).or_default().push(RotDefi {
            axis,
            polar: w[1],
            azimuth: w[2],
            offset: DVec3::new(w[3], w[4], w[5]),
        });
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
            let c = card::split(&text, card::is_free(&text, free));
            if c.keyword == "LATTICE" {
                self.lattice(i, &c);
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

    fn lattice(&mut self, i: usize, c: &Card) {
        let Some(cell) = &c.what[0] else {
            self.err(
                i,
                1,
                7,
                "LATTICE needs the name of its container region in WHAT(1)",
            );
            return;
        };
        match self.region_index.get(&cell.text) {
            Some(&r) => {
                // WHAT(2) and WHAT(3) may extend it to a range of regions.
                let last = c.what[1]
                    .as_ref()
                    .and_then(|f| self.region_index.get(&f.text))
                    .copied()
                    .unwrap_or(r);
                let step = c.what[2]
                    .as_ref()
                    .and_then(|f| card::number(&f.text))
                    .filter(|v| *v >= 1.0)
                    .map_or(1, |v| v.min(1e9) as usize);
                for k in (r..=last).step_by(step) {
                    if self.assign_budget == 0 {
                        break;
                    }
                    self.assign_budget -= 1;
                    self.lattices.push((k, i));
                }
            }
            None => {
                let (col, len, name) = (cell.col, cell.len(), cell.text.clone());
                let hint = self.hint_among(&name, self.region_index.keys());
                let d = self.err(
                    i,
                    col,
                    len,
                    format!("LATTICE refers to undefined region `{name}`"),
                );
                d.hint = hint;
            }
        }
        if let Some(t) = &c.sdum {
            let name = t.text.trim_start_matches('-');
            if !self.rot.contains_key(name) {
                let (col, len) = (t.col, t.len());
                self.warn(
                    i,
                    col,
                    len,
                    format!("LATTICE transformation `{name}` has no ROT-DEFI card"),
                );
            }
        }
    }

    /// Read bodies from line `start`; the index after END, or `None` when
    /// END is missing.
    fn bodies_section(&mut self, start: usize, end: usize) -> Option<usize> {
        let mut stack: Vec<Directive> = Vec::new();
        let mut pending: Option<PendingBody> = None;
        let mut result = None;
        for k in start..end {
            let text = clean(&self.lines[k].text).to_string();
            let words: Vec<(usize, String)> = tokens(&text)
                .into_iter()
                .map(|(c, w)| (c, w.to_string()))
                .collect();
            let Some((col0, first)) = words.first().cloned() else {
                continue;
            };
            if first.starts_with('$') {
                if let Some(p) = pending.take() {
                    self.finish_body(&p, &stack);
                }
                self.directive(k, &words, &mut stack);
            } else if first.eq_ignore_ascii_case("END") && words.len() == 1 {
                if let Some(p) = pending.take() {
                    self.finish_body(&p, &stack);
                }
                result = Some(k + 1);
                break;
            } else if starts_numeric(&first) {
                match &mut pending {
                    Some(p) => p.words.extend(words.into_iter().map(|(c, w)| (k, c, w))),
                    None => {
                        self.err(
                            k,
                            col0,
                            first.chars().count(),
                            format!("expected a body type, found `{first}`"),
                        )
                        .hint = Some(
                            "a body starts with its type and name, as in `RPP box 0 1 0 1 0 1`"
                                .into(),
                        );
                    }
                }
            } else {
                if let Some(p) = pending.take() {
                    self.finish_body(&p, &stack);
                }
                pending = Some(PendingBody {
                    words: words.into_iter().map(|(c, w)| (k, c, w)).collect(),
                });
            }
        }
        if let Some(p) = pending.take() {
            // END is missing: the last body still counts.
            self.finish_body(&p, &stack);
        }
        for d in stack {
            let name = format!("$start_{}", d.kind.name());
            self.err(d.line, d.col, d.len, format!("`{name}` is never closed"))
                .hint = Some(format!(
                "add `$end_{}` after the bodies it applies to",
                d.kind.name()
            ));
        }
        result
    }

    fn directive(&mut self, k: usize, words: &[(usize, String)], stack: &mut Vec<Directive>) {
        let (col, word) = (words[0].0, words[0].1.as_str());
        let len = word.chars().count();
        let lower = word.to_ascii_lowercase();
        let args = &words[1..];
        let (start, kind) = match lower.as_str() {
            "$start_translat" => (true, DirKind::Translat),
            "$end_translat" => (false, DirKind::Translat),
            "$start_expansion" => (true, DirKind::Expansion),
            "$end_expansion" => (false, DirKind::Expansion),
            "$start_transform" => (true, DirKind::Transform),
            "$end_transform" => (false, DirKind::Transform),
            _ => {
                let hint = did_you_mean(&lower, DIRECTIVES).map(|s| format!("did you mean `{s}`?"));
                self.err(k, col, len, format!("unknown geometry directive `{word}`"))
                    .hint = hint;
                return;
            }
        };
        let want = if !start {
            0
        } else if kind == DirKind::Translat {
            3
        } else {
            1
        };
        if args.len() > want {
            let (c, w) = (args[want].0, args[want].1.as_str());
            self.err(
                k,
                c,
                w.chars().count(),
                format!("unexpected `{w}` after `{word}`"),
            );
        }
        if !start {
            match stack.iter().rposition(|d| d.kind == kind) {
                Some(p) => {
                    stack.remove(p);
                }
                None => {
                    self.err(
                        k,
                        col,
                        len,
                        format!("`{word}` without a matching `$start_{}`", kind.name()),
                    );
                }
            }
            return;
        }
        let mut d = Directive {
            kind,
            factor: 1.0,
            shift: DVec3::ZERO,
            xf: DAffine3::IDENTITY,
            line: k,
            col,
            len,
        };
        if args.len() < want {
            let what = match kind {
                DirKind::Translat => "three numbers dx dy dz",
                DirKind::Expansion => "a factor",
                DirKind::Transform => "the name of a ROT-DEFI transformation",
            };
            self.err(k, col, len, format!("`{word}` needs {what}"));
            stack.push(d);
            return;
        }
        match kind {
            DirKind::Translat => {
                let mut v = [0.0; 3];
                for (i, (c, w)) in args.iter().take(3).enumerate() {
                    let (c, w) = (*c, w.as_str());
                    match card::number(w) {
                        Some(x) => v[i] = x,
                        None => {
                            self.err(
                                k,
                                c,
                                w.chars().count(),
                                format!("expected a number for `{word}`, found `{w}`"),
                            );
                        }
                    }
                }
                d.shift = DVec3::from(v);
            }
            DirKind::Expansion => {
                let (c, w) = (args[0].0, args[0].1.as_str());
                match card::number(w) {
                    Some(f) if f > 0.0 => d.factor = f,
                    _ => {
                        self.err(
                            k,
                            c,
                            w.chars().count(),
                            format!("`{word}` needs a positive factor, found `{w}`"),
                        );
                    }
                }
            }
            DirKind::Transform => {
                let (c, w) = (args[0].0, args[0].1.as_str());
                let (inverse, name) = match w.strip_prefix('-') {
                    Some(n) => (true, n),
                    None => (false, w),
                };
                let key = if self.rot.contains_key(name) {
                    Some(name.to_string())
                } else {
                    name.parse::<i64>()
                        .ok()
                        .and_then(|i| self.rot_index.get(&i).cloned())
                };
                match key.and_then(|k| self.rot.get(&k)) {
                    Some(cards) => {
                        let xf = rotdefi::compose(cards);
                        d.xf = if inverse { xf.inverse() } else { xf };
                    }
                    None => {
                        let hint = self.hint_among(name, self.rot.keys());
                        let e = self.err(
                            k,
                            c,
                            w.chars().count(),
                            format!(
                                "undefined transformation `{name}`: no ROT-DEFI card has this name"
                            ),
                        );
                        e.hint = hint.or(Some(
                            "define it with a ROT-DEFI card whose SDUM is the name".into(),
                        ));
                    }
                }
            }
        }
        stack.push(d);
    }

    fn finish_body(&mut self, p: &PendingBody, stack: &[Directive]) {
        let (line, col, code) = (p.words[0].0, p.words[0].1, p.words[0].2.as_str());
        let code_len = code.chars().count();
        let Some(kind) = body_code(code) else {
            if UNSUPPORTED_CODES
                .iter()
                .any(|c| c.eq_ignore_ascii_case(code))
            {
                let list = BODY_CODES
                    .iter()
                    .map(|(c, _)| *c)
                    .collect::<Vec<_>>()
                    .join(" ");
                self.err(
                    line,
                    col,
                    code_len,
                    format!("FLUKA body type `{code}` is not supported"),
                )
                .hint = Some(format!("supported body types: {list}"));
            } else {
                let hint = suggest_code(code).map(|s| format!("did you mean `{s}`?"));
                self.err(line, col, code_len, format!("unknown body type `{code}`"))
                    .hint = hint;
            }
            if let Some((_, _, name)) = p.words.get(1) {
                self.bad_bodies.insert(name.clone());
            }
            return;
        };
        let code = code.to_ascii_uppercase();
        let Some((nl, nc, name)) = p.words.get(1).map(|(l, c, n)| (*l, *c, n.as_str())) else {
            self.err(line, col, code_len, format!("`{code}` body has no name"));
            return;
        };
        if starts_numeric(name) {
            self.err(
                nl,
                nc,
                name.chars().count(),
                format!("expected a body name after `{code}`, found `{name}`"),
            );
            return;
        }
        if !is_name(name) {
            self.err(nl, nc, name.chars().count(), format!("body name `{name}` must start with a letter and hold only letters, digits and `_`"));
            self.bad_bodies.insert(name.to_string());
            return;
        }
        if let Some(&first) = self.body_index.get(name) {
            let hint = self.where_is(self.body_lines[first]);
            self.err(
                nl,
                nc,
                name.chars().count(),
                format!("body `{name}` is defined twice"),
            )
            .hint = Some(format!("the first definition is on {hint}"));
            return;
        }
        let values = &p.words[2..];
        let want = kind.info().value_count();
        let mut ok = true;
        if values.len() != want {
            self.err(
                line,
                col,
                code_len,
                format!(
                    "{code} `{name}` needs {want} values, found {}",
                    values.len()
                ),
            )
            .hint = Some(format!("{code} values: {}", layout(kind)));
            ok = false;
        }
        let mut params = Vec::with_capacity(want);
        for (i, (l, c, w)) in values.iter().enumerate().take(want) {
            let (l, c, w) = (*l, *c, w.as_str());
            match card::number(w) {
                Some(v) => params.push(v),
                None => {
                    let what = value_name(kind, i);
                    self.err(
                        l,
                        c,
                        w.chars().count(),
                        format!(
                            "expected a number for {code} `{name}` value {} ({what}), found `{w}`",
                            i + 1
                        ),
                    );
                    ok = false;
                }
            }
        }
        if !ok {
            self.bad_bodies.insert(name.to_string());
            return;
        }
        let mut body = Body::new(name, kind, params);
        if !stack.is_empty() {
            let mut e = 1.0;
            let mut t = DVec3::ZERO;
            let mut r = DAffine3::IDENTITY;
            for d in stack {
                match d.kind {
                    DirKind::Expansion => e *= d.factor,
                    DirKind::Translat => t += d.shift,
                    DirKind::Transform => r *= d.xf,
                }
            }
            let xf = r * DAffine3::from_translation(t) * DAffine3::from_scale(DVec3::splat(e));
            let det = xf.matrix3.determinant();
            if !(xf.is_finite() && det.is_finite() && det > 0.0) {
                self.err(
                    line,
                    col,
                    code_len,
                    format!(
                        "the directives around body `{name}` make a transformation out of range"
                    ),
                );
                self.bad_bodies.insert(name.to_string());
                return;
            }
            match body.transformed(&xf) {
                Ok(b) => body = b,
                Err(err) => {
                    self.err(
                        line,
                        col,
                        code_len,
                        format!("cannot transform body `{name}`: {err}"),
                    );
                    self.bad_bodies.insert(name.to_string());
                    return;
                }
            }
        }
        if body.params.iter().any(|v| !v.is_finite()) {
            self.err(
                line,
                col,
                code_len,
                format!("body `{name}` has a value out of range after its transformation"),
            );
            self.bad_bodies.insert(name.to_string());
            return;
        }
        self.body_index.insert(name.to_string(), self.bodies.len());
        self.bodies.push(body);
        self.body_lines.push(line);
    }

    /// Read regions from line `start`; the index after END, or `None`.
    fn regions_section(&mut self, start: usize, end: usize) -> Option<usize> {
        let mut cur: Option<(usize, usize, String, Vec<Spanned>)> = None; // line, col, name, tokens
        let mut result = None;
        for k in start..end {
            let text = clean(&self.lines[k].text).to_string();
            let words = card::words(&text);
            let Some(&(col0, first)) = words.first() else {
                continue;
            };
            if first.eq_ignore_ascii_case("END") && words.len() == 1 {
                result = Some(k + 1);
                break;
            }
            let opens = first.starts_with(['+', '-', '|', '(']);
            if !opens && words.get(1).is_some_and(|(_, w)| is_integer(w)) {
                if let Some(r) = cur.take() {
                    self.finish_region(r);
                }
                let (ncol, naz) = words[1];
                let after: String = text.chars().skip(ncol - 1 + naz.chars().count()).collect();
                let mut toks = Vec::new();
                region::tokenize(&after, k, &mut toks);
                let shift = ncol - 1 + naz.chars().count();
                for t in &mut toks {
                    t.col += shift;
                }
                if !is_name(first) {
                    self.err(k, col0, first.chars().count(), format!("region name `{first}` must start with a letter and hold only letters, digits and `_`"));
                }
                cur = Some((k, col0, first.to_string(), toks));
            } else if opens && cur.is_some() {
                if let Some((_, _, _, toks)) = &mut cur {
                    region::tokenize(&text, k, toks);
                }
            } else if opens {
                self.err(k, col0, 1, "region expression outside a region: expected a region name and its NAZ number first");
            } else {
                self.err(k, col0, first.chars().count(), format!("expected a region name and its NAZ number, or a line continuing a region with `+`, `-`, `|` or `(`; found `{first}`"));
            }
        }
        if let Some(r) = cur.take() {
            self.finish_region(r);
        }
        result
    }

    fn finish_region(&mut self, (line, col, name, toks): (usize, usize, String, Vec<Spanned>)) {
        let name_len = name.chars().count();
        if toks.is_empty() {
            self.err(
                line,
                col,
                name_len,
                format!("region `{name}` has no expression"),
            );
            return;
        }
        let mut missing: Vec<Spanned> = Vec::new();
        let parsed = {
            let index = &self.body_index;
            let bad = &self.bad_bodies;
            region::Parser::new(&toks, |t| match &t.tok {
                Tok::Name(n) => {
                    let b = index.get(n).copied();
                    if b.is_none() && !bad.contains(n) {
                        missing.push(t.clone());
                    }
                    b
                }
                _ => None,
            })
            .parse()
        };
        let mut ok = true;
        for t in &missing {
            let Tok::Name(b) = &t.tok else { continue };
            let hint = self.hint_among(b, self.body_index.keys());
            self.err(
                t.line,
                t.col,
                t.len,
                format!("region `{name}` refers to undefined body `{b}`"),
            )
            .hint = hint;
            ok = false;
        }
        let parsed = match parsed {
            Ok(p) => p,
            Err(e) => {
                let (l, c, len) = match toks.get(e.at) {
                    Some(t) => (t.line, t.col, t.len),
                    None => {
                        let t = toks.last().expect("not empty");
                        (t.line, t.col + t.len, 0)
                    }
                };
                self.err(l, c, len, format!("in region `{name}`: {}", e.message));
                return;
            }
        };
        if let Some(&first) = self.region_index.get(&name) {
            let hint = self.where_is(self.region_lines[first]);
            self.err(
                line,
                col,
                name_len,
                format!("region `{name}` is defined twice"),
            )
            .hint = Some(format!("the first definition is on {hint}"));
            return;
        }
        self.region_index.insert(name.clone(), self.regions.len());
        self.region_lines.push(line);
        let zones = if ok && missing.is_empty() {
            match self.expander.zones(&parsed) {
                Ok(z) => z,
                Err(region::TooBig::Zones) => {
                    self.err(
                        line,
                        col,
                        name_len,
                        format!("region `{name}` expands to more than {MAX_ZONES} zones"),
                    )
                    .hint = Some("split the region or use fewer nested `-( … )` groups".into());
                    Vec::new()
                }
                Err(region::TooBig::Work) => {
                    self.err(
                        line,
                        col,
                        name_len,
                        format!("region `{name}` is too large to expand into zones"),
                    )
                    .hint = Some("split the region or use fewer parenthesised groups".into());
                    Vec::new()
                }
            }
        } else {
            Vec::new()
        };
        self.regions.push(Region { name, zones });
    }

    fn scene(&mut self) -> Scene {
        let mut props: Vec<RegionProps> = self
            .regions
            .iter()
            .map(|_| RegionProps::default())
            .collect();
        let assigns = std::mem::take(&mut self.assigns);
        for (i, c) in &assigns {
            self.assignma(*i, c, &mut props);
        }
        let mut scene = Scene {
            title: self
                .title
                .clone()
                .filter(|t| !t.is_empty())
                .unwrap_or_else(|| self.geo_title.clone()),
            units: Units::Centimetre,
            geometry: Geometry {
                bodies: std::mem::take(&mut self.bodies),
                regions: std::mem::take(&mut self.regions),
            },
            regions: props,
            ..Scene::default()
        };
        if assigns.is_empty() {
            scene
                .notes
                .push("no ASSIGNMA cards: every region is drawn opaque".to_string());
        }
        if !self.lattices.is_empty() {
            let mut names: Vec<&str> = Vec::new();
            let mut seen = HashSet::new();
            for (r, _) in &self.lattices {
                if seen.insert(*r) {
                    names.push(scene.geometry.regions[*r].name.as_str());
                }
            }
            scene.notes.push(format!(
                "LATTICE replicas are not drawn: {}",
                if names.len() == 1 {
                    format!(
                        "lattice cell {} is drawn as a plain region (its container only)",
                        names[0]
                    )
                } else {
                    format!(
                        "lattice cells {} are drawn as plain regions (their containers only)",
                        names.join(", ")
                    )
                },
            ));
        }
        scene
    }

    fn region_ref(&self, f: &card::Field) -> Option<usize> {
        if let Some(&r) = self.region_index.get(&f.text) {
            return Some(r);
        }
        if f.text == "@LASTREG" {
            return self.regions.len().checked_sub(1);
        }
        card::number(&f.text)
            .filter(|v| *v >= 1.0 && v.fract() == 0.0 && *v <= self.regions.len() as f64)
            .map(|v| v as usize - 1)
    }

    fn assignma(&mut self, i: usize, c: &Card, props: &mut [RegionProps]) {
        let material = match &c.what[0] {
            Some(f) => match card::number(&f.text) {
                Some(v) if v <= 1.0 => "BLCKHOLE".to_string(),
                Some(2.0) => "VACUUM".to_string(),
                Some(v) => format!("material #{v}"),
                None => f.text.clone(),
            },
            None => "BLCKHOLE".to_string(),
        };
        let Some(lo) = &c.what[1] else {
            self.warn(i, 1, 8, "ASSIGNMA names no region");
            return;
        };
        let Some(first) = self.region_ref(lo) else {
            let (col, len) = (lo.col, lo.len());
            self.warn(
                i,
                col,
                len,
                format!("ASSIGNMA refers to undefined region `{}`", lo.text),
            );
            return;
        };
        let last = match &c.what[2] {
            Some(hi) => match self.region_ref(hi) {
                Some(r) => r,
                None => {
                    let (col, len) = (hi.col, hi.len());
                    self.warn(
                        i,
                        col,
                        len,
                        format!("ASSIGNMA refers to undefined region `{}`", hi.text),
                    );
                    first
                }
            },
            None => first,
        };
        let step = c.what[3]
            .as_ref()
            .and_then(|f| card::number(&f.text))
            .filter(|v| *v >= 1.0)
            .map_or(1, |v| v.min(1e9) as usize);
        let mut r = first;
        while r <= last && r < props.len() && self.assign_budget > 0 {
            self.assign_budget -= 1;
            let p = &mut props[r];
            p.description = format!("material: {material}");
            // Vacuum is air: left out of pictures unless `--show-air`, as
            // air-coded regions of COMGEOM decks are.
            p.transparent = material == "BLCKHOLE" || material == "VACUUM";
            p.material = match material.as_str() {
                "BLCKHOLE" => 1,
                "VACUUM" => 2,
                _ => 0,
            };
            p.air = i64::from(material == "VACUUM");
            r += step;
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

    #[test]
    fn value_names_follow_the_table() {
        assert_eq!(value_name(BodyKind::Rcc, 6), "R");
        assert_eq!(value_name(BodyKind::Rcc, 4), "Hy");
        assert_eq!(layout(BodyKind::Rcc), "V(3) H(3) R");
    }
}
