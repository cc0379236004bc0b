//! The deck reader: cards → bodies, regions and ident metadata.

mod bodies;
mod references;
mod regions;

use super::card::{cards, parse_int, Card};
use super::kind_for;
use crate::diag::count;
use crate::{DeckVersion, Diagnostic, Diagnostics, LoadOptions, Loaded, SourceFile};
use sv_geom::{Body, Geometry, Region};
use sv_scene::{RegionProps, Scene, Units};

/// Most terms that copying referenced regions into others may produce in
/// a deck.
const MAX_EXPANSION: usize = 1 << 21;
/// Most diagnostics kept for one deck (the rest are counted).
const MAX_DIAGNOSTICS: usize = 200;
/// Deepest chain of regions referring to regions.
const MAX_REF_DEPTH: usize = 64;

const NUMBER_HINT: &str = "numbers are plain decimals such as 12.5, -3., .75 or 1.5E-3";

/// Where the fields of a card are, per layout version.
#[derive(Clone, Copy)]
struct Layout {
    num_col: usize,
    num_len: usize,
    type_col: usize,
    type_len: usize,
}

fn layout(v: DeckVersion) -> Layout {
    match v {
        DeckVersion::V5 => Layout {
            num_col: 1,
            num_len: 5,
            type_col: 6,
            type_len: 5,
        },
        // comgeom-g reads the v4 type from columns 4-10.
        DeckVersion::V4 => Layout {
            num_col: 1,
            num_len: 3,
            type_col: 4,
            type_len: 7,
        },
        DeckVersion::V1 => Layout {
            num_col: 6,
            num_len: 4,
            type_col: 3,
            type_len: 3,
        },
    }
}

/// `line 37, columns 21–30` (or `column 7` for one column).
fn at(line: usize, col: usize, len: usize) -> String {
    if len <= 1 {
        format!("line {line}, column {col}")
    } else {
        format!("line {line}, columns {col}–{}", col + len - 1)
    }
}

fn is_control_card(card: &Card) -> bool {
    let toks: Vec<&str> = card.text.split_whitespace().collect();
    (1..=2).contains(&toks.len()) && toks.iter().all(|t| parse_int(t).is_some())
}

/// Guess the layout version of a deck from its text.
///
/// v1 has no control card (its second card is a body card with the type in
/// columns 3–5). Otherwise the first body card tells: a type in columns 6–10
/// is v5, in columns 4–10 is v4. Failing that, a blank card after the `-1`
/// card means v4. The default is v5.
pub fn detect_version(text: &str) -> DeckVersion {
    let all = cards(text);
    let mut it = all.iter().filter(|c| !c.is_blank());
    let (_title, Some(second)) = (it.next(), it.next()) else {
        return DeckVersion::V5;
    };
    if !is_control_card(second) {
        let ty = second.field(3, 3).trim();
        if ty.eq_ignore_ascii_case("end") || kind_for(ty, DeckVersion::V1).is_some() {
            return DeckVersion::V1;
        }
        return DeckVersion::V5;
    }
    if let Some(third) = it.next() {
        if kind_for(third.field(6, 5).trim(), DeckVersion::V5).is_some() {
            return DeckVersion::V5;
        }
        if kind_for(third.field(4, 7).trim(), DeckVersion::V4).is_some() {
            return DeckVersion::V4;
        }
    }
    for (i, c) in all.iter().enumerate() {
        if c.field(1, 5).trim() == "-1" && c.field(6, 200).trim().is_empty() {
            if all
                .get(i + 1)
                .is_some_and(|n| n.is_blank() && i + 2 < all.len())
            {
                return DeckVersion::V4;
            }
            break;
        }
    }
    DeckVersion::V5
}

/// One body or region reference on a region card, before resolution.
#[derive(Clone, Copy, Debug)]
struct RawTerm {
    region_ref: bool,
    negate: bool,
    number: usize,
    line: usize,
    col: usize,
}

#[derive(Debug)]
struct RawRegion {
    number: i64,
    line: usize,
    zones: Vec<Vec<RawTerm>>,
    comment: String,
}

struct Reader<'a> {
    src: &'a SourceFile,
    cards: Vec<Card<'a>>,
    pos: usize,
    version: DeckVersion,
    lay: Layout,
    errors: Vec<Diagnostic>,
    warnings: Vec<Diagnostic>,
    /// Bodies in deck order; `None` for a body whose cards had errors.
    bodies: Vec<Option<Body>>,
    numbering_reported: bool,
    /// Errors and warnings not kept beyond [`MAX_DIAGNOSTICS`].
    suppressed: usize,
    /// How many of them are errors.
    suppressed_errors: usize,
    /// Where a diagnostic goes once the limit is reached.
    spare: Option<Diagnostic>,
    /// Terms that region-reference expansion may still produce.
    budget: usize,
    /// `nonblank_from[i]`: non-blank cards from card `i` on.
    nonblank_from: Vec<usize>,
}

/// Read a COMGEOM deck; see the [module documentation](super).
pub fn read(src: &SourceFile, opts: &LoadOptions) -> Result<Loaded, Diagnostics> {
    let version = opts
        .deck_version
        .unwrap_or_else(|| detect_version(&src.text));
    let mut reader = Reader {
        src,
        cards: cards(&src.text),
        pos: 0,
        version,
        lay: layout(version),
        errors: Vec::new(),
        warnings: Vec::new(),
        bodies: Vec::new(),
        numbering_reported: false,
        suppressed: 0,
        suppressed_errors: 0,
        spare: None,
        budget: MAX_EXPANSION,
        nonblank_from: Vec::new(),
    };
    reader.nonblank_from = vec![0; reader.cards.len() + 1];
    for i in (0..reader.cards.len()).rev() {
        reader.nonblank_from[i] =
            reader.nonblank_from[i + 1] + usize::from(!reader.cards[i].is_blank());
    }
    let scene = reader.deck();
    match scene {
        Some(scene) if reader.errors.is_empty() => Ok(Loaded {
            scene,
            warnings: reader.warnings,
            format: crate::Format::Comgeom,
        }),
        _ => {
            if reader.suppressed > 0 {
                let mut note = Diagnostic::error(
                    src,
                    src.text.len(),
                    0,
                    format!(
                        "{} not shown",
                        count(
                            reader.suppressed,
                            "more error or warning is",
                            "more errors and warnings are"
                        )
                    ),
                );
                note.unlisted_errors = reader.suppressed_errors;
                if reader.suppressed_errors == 0 {
                    note = note.warning();
                }
                reader.errors.push(note);
            }
            let mut items = reader.errors;
            items.append(&mut reader.warnings);
            items.sort_by_key(|d| d.offset);
            Err(Diagnostics { items })
        }
    }
}

impl<'a> Reader<'a> {
    /// A diagnostic at columns of a line; the caret is kept on the line even
    /// when the line is shorter than the field.
    fn diag(&self, line: usize, col: usize, len: usize, msg: String) -> Diagnostic {
        let width = self
            .cards
            .get(line.wrapping_sub(1))
            .map_or(0, |c| c.text.chars().count());
        let c = col.min(width + 1).max(1);
        let l = len.min((width + 1).saturating_sub(c));
        match self.cards.get(line.wrapping_sub(1)) {
            // Cards are slices of the source text: find the span from the
            // card alone instead of scanning the whole text.
            Some(card) => {
                let base = card.text.as_ptr() as usize - self.src.text.as_ptr() as usize;
                let start = base + card.field(1, c - 1).len();
                let span = card.field(c, l).len();
                Diagnostic::error(self.src, start, span, msg)
            }
            None => Diagnostic::error(self.src, self.src.text.len(), 0, msg),
        }
    }

    fn full(&mut self) -> bool {
        if self.errors.len() + self.warnings.len() >= MAX_DIAGNOSTICS {
            self.suppressed += 1;
            true
        } else {
            false
        }
    }

    /// Record an error (its hint can be set on the result).
    fn error(&mut self, line: usize, col: usize, len: usize, msg: String) -> &mut Diagnostic {
        if self.full() {
            self.suppressed_errors += 1;
            return self.spare.insert(Diagnostic::error(self.src, 0, 0, msg));
        }
        let d = self.diag(line, col, len, msg);
        self.errors.push(d);
        self.errors.last_mut().expect("just pushed")
    }

    fn warn(&mut self, line: usize, col: usize, len: usize, msg: String) {
        if self.full() {
            return;
        }
        let d = self.diag(line, col, len, msg).warning();
        self.warnings.push(d);
    }

    /// The next non-blank card, without consuming it (blank cards before it
    /// are consumed, as comgeom-g skips blank lines).
    fn peek(&mut self) -> Option<Card<'a>> {
        while self.pos < self.cards.len() && self.cards[self.pos].is_blank() {
            self.pos += 1;
        }
        self.cards.get(self.pos).copied()
    }

    fn next(&mut self) -> Option<Card<'a>> {
        let c = self.peek();
        if c.is_some() {
            self.pos += 1;
        }
        c
    }

    fn last_line(&self) -> usize {
        self.cards
            .iter()
            .rev()
            .find(|c| !c.is_blank())
            .map_or(1, |c| c.line)
    }

    fn type_field(&self, card: &Card<'a>) -> &'a str {
        card.field(self.lay.type_col, self.lay.type_len)
    }

    fn deck(&mut self) -> Option<Scene> {
        let mut scene = Scene::default();
        let Some(title) = self.next() else {
            self.error(1, 1, 0, "the deck is empty: expected a title card".into());
            return None;
        };
        let mut declared = None;
        if self.version == DeckVersion::V1 {
            scene.title = title.text.trim().to_string();
        } else {
            let units_field = title.field(1, 2).trim();
            scene.units = match Units::parse(units_field) {
                Some(units) if units_field.len() <= 2 => units,
                _ => {
                    self.warn(
                        title.line,
                        1,
                        2,
                        format!(
                            "{}: unknown units \"{units_field}\"; inches assumed",
                            at(title.line, 1, 2)
                        ),
                    );
                    Units::Inch
                }
            };
            scene.title = title.rest(4).trim().to_string();
            declared = self.control_card();
        }
        self.body_table(declared.map(|d| d.0));
        let regions = self.region_table();
        let mut props: Vec<RegionProps> = regions
            .iter()
            .map(|r| RegionProps {
                description: r.comment.clone(),
                ..RegionProps::default()
            })
            .collect();
        if self.version != DeckVersion::V1 {
            self.ident_table(&regions, &mut props);
        } else if let Some(c) = self.peek() {
            self.warn(
                c.line,
                1,
                0,
                format!(
                    "line {}: cards after the end of the region table are ignored",
                    c.line
                ),
            );
        }
        let zones = self.resolve_all(&regions);

        if let Some((nb, nr, line)) = declared {
            if nb != self.bodies.len() as i64 {
                self.warn(line, 1, 0, format!("line {line}: the control card declares {nb} bodies, but the deck defines {}", self.bodies.len()));
            }
            if nr != regions.len() as i64 {
                self.warn(line, 1, 0, format!("line {line}: the control card declares {nr} regions, but the deck defines {}", regions.len()));
            }
        }
        if !self.errors.is_empty() {
            return None;
        }
        let bodies: Vec<Body> = std::mem::take(&mut self.bodies)
            .into_iter()
            .flatten()
            .collect();
        scene.geometry = Geometry {
            bodies,
            ..Geometry::default()
        };
        for ((raw, zones), mut p) in regions.iter().zip(zones).zip(props) {
            p.transparent = p.air != 0;
            scene.push_region(Region::new(raw.number.to_string(), zones), p);
        }
        Some(scene)
    }

    /// The control card: body and region counts, and its line.
    fn control_card(&mut self) -> Option<(i64, i64, usize)> {
        let card = self.peek()?;
        let toks: Vec<&str> = card.text.split_whitespace().collect();
        let free = if toks.len() == 2 {
            toks.iter()
                .map(|t| parse_int(t))
                .collect::<Option<Vec<_>>>()
        } else {
            None
        };
        let fixed = || {
            let (a, b) = match self.version {
                DeckVersion::V4 => (card.field(1, 20), card.field(21, 10)),
                _ => (card.field(1, 5), card.field(6, 5)),
            };
            Some(vec![parse_int(a)?, parse_int(b)?])
        };
        match free.or_else(fixed) {
            Some(v) if v[0] >= 0 && v[1] >= 0 => {
                self.pos += 1;
                Some((v[0], v[1], card.line))
            }
            _ => {
                let looks_like_body =
                    kind_for(self.type_field(&card).trim(), self.version).is_some();
                if !looks_like_body {
                    self.pos += 1;
                }
                self.error(
                    card.line,
                    1,
                    card.text.chars().count(),
                    format!("line {}: expected the control card (body count, region count), found \"{}\"", card.line, card.text.trim()),
                )
                .hint = Some("the second card of a v4/v5 deck holds two integers: the number of bodies and of regions".into());
                None
            }
        }
    }
}
