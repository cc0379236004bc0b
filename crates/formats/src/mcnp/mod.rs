//! MCNP inputs: the cell, surface and data blocks read as MCNP reads them,
//! the geometry lowered to bodies and regions.
//!
//! [`read`] takes an MCNP input (title card, cell cards, surface cards,
//! data cards; comments, continuations, shorthand and `READ` cards as in
//! [`input`](self) and [`number`](self)) and makes a [`Scene`] in
//! centimetres:
//!
//! * every surface becomes one body whose inside is its negative side, or a
//!   few bodies intersected (a one-sheet cone, a hexagonal prism); a
//!   macrobody's facet `n.k` becomes the plane, cylinder or cone it lies
//!   on. Surfaces may be moved by `TRn` cards (`*TRn` in degrees).
//!   Reflecting (`*`), white (`+`) and periodic surfaces are read as
//!   ordinary ones, which a note says.
//! * every cell becomes a region named by its number: its geometry lowered
//!   as written to zones and groups (a surface's `-` sense is its body's
//!   inside, `+` its outside; `#n` is `-(` cell n `)`, cell n as it is
//!   placed), in the universe its `U` gives, filled by `FILL` (a universe,
//!   moved by the fill's transformation, or for a lattice cell the
//!   elements of its `FILL` array). `TRCL` (`*TRCL` in degrees) moves the
//!   cell's surfaces, and its fill with them. `LIKE n BUT` copies cell n
//!   and changes what it names.
//! * a lattice cell (`LAT=1` hexahedra, `LAT=2` hexagonal prisms) covers
//!   all of its universe (its region is the inside and the outside of its
//!   first surface, together); its surfaces, in the order MCNP reads them, give
//!   element (0,0,0) and the steps to the next elements: across the first
//!   surface is element (1,0,0), across the third (0,1,0), across the fifth
//!   (0,0,1) (the seventh for `LAT=2`, whose fifth and sixth lead to
//!   (−1,1,0) and (1,−1,0)). The universe of element (i,j,k) is moved by
//!   i a + j b + k c. A lattice given by four (six for `LAT=2`) surfaces
//!   is unbounded along its axis: its one layer is [`UNBOUNDED`] thick. An
//!   element's own transformation (`u(tr)` in a fill array) makes a
//!   universe of one region holding universe u moved, named after the
//!   lattice cell and the element's fill (`10:2(TR3)`).
//! * a cell of zero neutron importance is the outside of the model
//!   ([`RegionProps::outside`](sv_scene::RegionProps::outside)); a void
//!   cell that nothing fills is air (air code 1, transparent).
//! * `M` cards become [`Scene::materials`](sv_scene::Scene::materials):
//!   each component's ZAID as (Z, A, m), atom (positive) or weight
//!   (negative) fraction. A cell's material is `m<N>`; a negative density
//!   is g/cm³, a positive one atoms per barn-centimetre.
//! * data cards that do not concern the geometry are skipped, and a note
//!   lists them.
//!
//! Every problem is reported at once with file, line and column: an
//! undefined surface, cell, universe or transformation, a cell complementing
//! itself through `#`, universes filling each other, a lattice fill of the
//! wrong size. No input makes the reader panic, hang or allocate without
//! bound: shorthand, fill arrays, `#` complements copied in and nesting
//! ([`MAX_DEPTH`]) all have limits.
//!
//! ```
//! use sv_formats::{mcnp, LoadOptions, SourceFile};
//! let text = "a ball in a box\n\
//!     1 1 -7.9 -1 imp:n=1 $ steel\n\
//!     2 0 1 -2 imp:n=1\n\
//!     3 0 2 imp:n=0\n\
//!     \n\
//!     1 so 5\n\
//!     2 rpp -10 10 -10 10 -10 10\n\
//!     \n\
//!     m1 26056.80c 1\n";
//! let loaded = mcnp::read(&SourceFile::new("ball.i", text), &LoadOptions::default()).unwrap();
//! let scene = loaded.scene;
//! assert_eq!(scene.geometry.regions.len(), 3);
//! assert_eq!(scene.regions[0].density, Some(7.9));
//! assert_eq!(scene.regions[0].material_name.as_deref(), Some("m1"));
//! assert!(scene.regions[2].outside);
//! ```

mod cell;
mod data;
mod input;
mod lattice;
mod lower;
mod macrobody;
mod number;
mod params;
mod region;
mod surface;
mod transform;

pub use input::MAX_READ_DEPTH;
pub use lower::MAX_DEPTH;

use crate::diag::count;
use crate::{Diagnostic, Diagnostics, LoadOptions, Loaded, SourceFile};
use cell::CellCard;
use std::collections::{HashMap, HashSet};
use surface::SurfaceCard;
use sv_geom::{Body, Term};
use sv_math::DAffine3;
use sv_scene::{Material, Scene};

/// Most errors listed for one input; the rest are counted.
pub const MAX_ERRORS: usize = 100;
/// Most warnings listed for one input.
const MAX_WARNINGS: usize = 100;
/// Most body terms all regions may hold together once `#n` complements
/// are copied in (a bound on the work, far above real models).
pub const MAX_TERMS: usize = 1 << 22;
/// The thickness given to the one layer of a lattice whose surfaces do not
/// bound it along its axis (cm).
pub const UNBOUNDED: f64 = 1.0e10;

/// Where a word or character stands: file (index into the files read),
/// 1-based line and column (characters of the line as written) and length.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Loc {
    pub file: u32,
    pub line: u32,
    /// Byte offset of the line's start in its file.
    pub line_start: u32,
    pub col: u32,
    pub len: u32,
}

impl Loc {
    /// Characters `from..from + len` of the word at `self` (a word holds no
    /// tab, so its characters are its columns).
    pub fn part(self, from: usize, len: usize) -> Loc {
        Loc {
            col: self.col + from as u32,
            len: len.max(1) as u32,
            ..self
        }
    }
}

/// The files read and what was found wrong in them.
pub(crate) struct Log {
    pub files: Vec<SourceFile>,
    pub errors: Vec<Diagnostic>,
    pub warnings: Vec<Diagnostic>,
    /// Errors past [`MAX_ERRORS`], counted only.
    pub suppressed: usize,
    /// Where diagnostics past the limits go.
    sink: Diagnostic,
}

impl Log {
    fn new(src: &SourceFile) -> Log {
        Log {
            files: vec![src.clone()],
            errors: Vec::new(),
            warnings: Vec::new(),
            suppressed: 0,
            sink: Diagnostic::error(src, 0, 0, ""),
        }
    }

    fn diagnostic(&self, at: Loc, msg: String) -> Diagnostic {
        let src = &self.files[at.file as usize];
        let start = (at.line_start as usize).min(src.text.len());
        let line = &src.text[start..];
        let line = &line[..line.find('\n').unwrap_or(line.len())];
        let byte = |c: u32| {
            line.char_indices()
                .nth(c.saturating_sub(1) as usize)
                .map_or(line.len(), |(b, _)| b)
        };
        let (a, b) = (byte(at.col), byte(at.col + at.len));
        Diagnostic::error(src, start + a, b.max(a) - a, msg)
    }

    /// An error at `at`; the hint may be set on what is returned.
    pub fn error(&mut self, at: Loc, msg: impl Into<String>) -> &mut Diagnostic {
        if self.errors.len() >= MAX_ERRORS {
            self.suppressed += 1;
            return &mut self.sink;
        }
        let d = self.diagnostic(at, msg.into());
        self.errors.push(d);
        self.errors.last_mut().expect("just pushed")
    }

    /// A warning at `at`.
    pub fn warn(&mut self, at: Loc, msg: impl Into<String>) -> &mut Diagnostic {
        if self.warnings.len() >= MAX_WARNINGS {
            return &mut self.sink;
        }
        let d = self.diagnostic(at, msg.into()).warning();
        self.warnings.push(d);
        self.warnings.last_mut().expect("just pushed")
    }

    /// The errors, sorted by file and place, the unlisted ones counted.
    fn into_errors(mut self) -> Diagnostics {
        self.errors.sort_by_key(|d| {
            let file = self.files.iter().position(|f| f.name == d.source.name);
            (file, d.offset)
        });
        if self.suppressed > 0 {
            let last = self.errors.last().unwrap_or(&self.sink);
            self.errors.push(last.unlisted(self.suppressed));
        }
        Diagnostics { items: self.errors }
    }
}

/// A cell's own frame: the transformation its `TRCL` gives.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    /// The cell number (it names the moved surfaces).
    pub cell: i64,
    /// Cell coordinates to those of its universe.
    pub xf: DAffine3,
}

/// The reader's state, from cards to scene.
pub(crate) struct Reader {
    log: Log,
    notes: Vec<String>,
    title: String,
    bodies: Vec<Body>,
    surfaces: Vec<SurfaceCard>,
    surface_index: HashMap<i64, usize>,
    /// Each surface's negative side as body terms to intersect; `None` for
    /// a surface in error (references to it are not reported again).
    sides: Vec<Option<Vec<Term>>>,
    /// The body each surface part became, by surface and name suffix.
    part_bodies: HashMap<(usize, String), usize>,
    /// Macrobody facets, by surface and facet number.
    facets: HashMap<(usize, u8), Option<Vec<Term>>>,
    /// Bodies moved into a cell's frame, by body and cell number.
    moved: HashMap<(usize, i64), usize>,
    /// `TRn` cards: the transformation and where the card is.
    transforms: HashMap<i64, (DAffine3, Loc)>,
    cells: Vec<CellCard>,
    cell_index: HashMap<i64, usize>,
    materials: Vec<Material>,
    material_index: HashMap<i64, usize>,
    /// Data cards skipped, by name, in the order met.
    skipped: Vec<String>,
    /// Body terms written into regions so far (bounded by [`MAX_TERMS`]).
    terms: usize,
    /// Each cell's frame, for cells with a `TRCL` (`None` when it is in
    /// error).
    frames: HashMap<i64, Option<Frame>>,
    /// Where each cell's zones stand while cells are lowered.
    states: Vec<lower::State>,
    /// Cells left out for their errors (references to them stay quiet).
    bad_cells: HashSet<i64>,
    /// Surfaces left out for their errors.
    bad_surfaces: HashSet<i64>,
    /// Materials already reported as having no M card.
    missing_materials: HashSet<i64>,
    /// Whether a geometry nesting too deep was reported.
    too_deep: bool,
}

/// Read an MCNP input. `READ` cards name files relative to the folder of
/// the file that reads them.
pub fn read(src: &SourceFile, _opts: &LoadOptions) -> Result<Loaded, Diagnostics> {
    let mut log = Log::new(src);
    let deck = input::read(&mut log);
    let mut r = Reader {
        log,
        notes: Vec::new(),
        title: deck.title.clone(),
        bodies: Vec::new(),
        surfaces: Vec::new(),
        surface_index: HashMap::new(),
        sides: Vec::new(),
        part_bodies: HashMap::new(),
        facets: HashMap::new(),
        moved: HashMap::new(),
        transforms: HashMap::new(),
        cells: Vec::new(),
        cell_index: HashMap::new(),
        materials: Vec::new(),
        material_index: HashMap::new(),
        skipped: Vec::new(),
        terms: 0,
        frames: HashMap::new(),
        states: Vec::new(),
        bad_cells: HashSet::new(),
        bad_surfaces: HashSet::new(),
        missing_materials: HashSet::new(),
        too_deep: false,
    };
    if deck.past_old_columns > 0 {
        r.notes.push(format!(
            "{} data past column 80, read as MCNP6.2 and later read it (MCNP5 and MCNP6.1 stop at column 80)",
            count(deck.past_old_columns, "line holds", "lines hold")
        ));
    }
    let scene = r.run(&deck);
    if !r.log.errors.is_empty() || r.log.suppressed > 0 {
        return Err(r.log.into_errors());
    }
    Ok(Loaded {
        scene: scene.unwrap_or_default(),
        warnings: r.log.warnings,
        format: crate::Format::Mcnp,
    })
}

/// The number a card starts with (a cell's or a surface's), if any.
fn leading_number(card: &input::Card) -> Option<i64> {
    number::integer(card.words.first()?.text.trim_start_matches(['*', '+']))
}

/// Whether `text` reads as an MCNP input: after an optional message
/// block and the title card, a cell card (a cell number, then a material
/// number or `LIKE`) and, after the cell block's blank line, a surface card
/// (a number, perhaps a transformation, and a surface type).
pub fn looks_like(text: &str) -> bool {
    let mut lines = text.lines().map(|l| l.replace('\t', "        "));
    let blank = |l: &str| l.trim().is_empty();
    let comment = |l: &str| {
        let t = l.trim_start();
        l.len() - t.len() < 5
            && t.starts_with(['c', 'C'])
            && t[1..].chars().next().is_none_or(|c| c == ' ')
    };
    let Some(first) = lines.next() else {
        return false;
    };
    let message = first
        .trim_start()
        .to_ascii_lowercase()
        .starts_with("message:");
    if message && (!lines.by_ref().any(|l| blank(&l)) || lines.next().is_none()) {
        return false;
    }
    let mut cells = 0;
    for l in lines.by_ref() {
        if blank(&l) {
            break;
        }
        if comment(&l) || l.starts_with("     ") {
            continue;
        }
        let w: Vec<&str> = l
            .split('$')
            .next()
            .unwrap_or("")
            .split_whitespace()
            .collect();
        let material = w.get(1).is_some_and(|m| {
            m.eq_ignore_ascii_case("like") || m.bytes().all(|b| b.is_ascii_digit())
        });
        if w.len() < 2 || number::integer(w[0]).is_none() || !material {
            return false;
        }
        cells += 1;
    }
    if cells == 0 {
        return false;
    }
    for l in lines {
        if blank(&l) {
            return false;
        }
        if comment(&l) {
            continue;
        }
        let w: Vec<&str> = l.split_whitespace().collect();
        let number = w.first().map(|n| n.trim_start_matches(['*', '+']));
        if number.and_then(number::integer).is_none() {
            return false;
        }
        let at = if w.get(1).and_then(|t| number::integer(t)).is_some() {
            2
        } else {
            1
        };
        return w.get(at).is_some_and(|m| surface::is_mnemonic(m));
    }
    false
}

impl Reader {
    fn run(&mut self, deck: &input::Deck) -> Option<Scene> {
        let [cells, surfaces, data] = &deck.blocks;
        if cells.is_empty() {
            let at = Loc {
                line: 1,
                col: 1,
                len: 1,
                ..Loc::default()
            };
            self.log.error(at, "the input has no cell cards").hint =
                Some("an MCNP input is a title card, cell cards, a blank line, surface cards, a blank line and data cards".into());
            return None;
        }
        for card in cells {
            let Some(c) = cell::read(card, &mut self.log) else {
                self.bad_cells.extend(leading_number(card));
                continue;
            };
            {
                if let Some(&first) = self.cell_index.get(&c.number) {
                    let line = self.cells[first].at.line;
                    self.log
                        .warn(c.at, format!("cell {} is defined again (first on line {line}); MCNP refuses this", c.number))
                        .hint = Some("it is read as a region of its own; `#` and `LIKE` find the first".into());
                } else {
                    self.cell_index.insert(c.number, self.cells.len());
                }
                self.cells.push(c);
            }
        }
        for card in surfaces {
            let Some(s) = surface::read(card, &mut self.log) else {
                self.bad_surfaces.extend(leading_number(card));
                continue;
            };
            {
                if let Some(&first) = self.surface_index.get(&s.number) {
                    let line = self.surfaces[first].at.line;
                    self.log
                        .warn(s.at, format!("surface {} is defined again (first on line {line}); MCNP refuses this", s.number))
                        .hint = Some("cells use the first definition".into());
                } else {
                    self.surface_index.insert(s.number, self.surfaces.len());
                }
                self.surfaces.push(s);
            }
        }
        self.data_block(data);
        self.lower_surfaces();
        self.resolve_likes();
        self.lower_cells()
    }
}
