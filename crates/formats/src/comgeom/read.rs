//! The deck reader: cards → bodies, regions and ident metadata.

use super::card::{cards, parse_int, parse_real, Card};
use super::{kind_for, TYPE_NAMES};
use crate::{did_you_mean, DeckVersion, Diagnostic, Diagnostics, LoadOptions, Loaded, SourceFile};
use std::collections::HashMap;
use sv_geom::{Body, BodyKind, Geometry, Op, Region, Term, Zone};
use sv_scene::{RegionProps, Scene, Units};

/// Most zones a region may expand to when it refers to other regions.
pub const MAX_ZONES: usize = 4096;
/// Most terms in one zone after expanding region references.
const MAX_TERMS: usize = 4096;
/// Most terms that expanding all region references of a deck may produce.
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
    has_refs: bool,
}

enum Resolve {
    Todo,
    Visiting,
    Done(Option<Vec<Vec<Term>>>),
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
    let mut r = Reader {
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
        spare: None,
        budget: MAX_EXPANSION,
        nonblank_from: Vec::new(),
    };
    r.nonblank_from = vec![0; r.cards.len() + 1];
    for i in (0..r.cards.len()).rev() {
        r.nonblank_from[i] = r.nonblank_from[i + 1] + usize::from(!r.cards[i].is_blank());
    }
    let scene = r.deck();
    match scene {
        Some(scene) if r.errors.is_empty() => Ok(Loaded {
            scene,
            warnings: r.warnings,
            format: crate::Format::Comgeom,
        }),
        _ => {
            if r.suppressed > 0 {
                let n = r.suppressed;
                let d = Diagnostic::error(
                    src,
                    src.text.len(),
                    0,
                    format!("{n} more errors and warnings are not shown"),
                );
                r.errors.push(d);
            }
            let mut items = r.errors;
            items.append(&mut r.warnings);
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
            let u = title.field(1, 2).trim();
            scene.units = match Units::parse(u) {
                Some(units) if u.len() <= 2 => units,
                _ => {
                    self.warn(
                        title.line,
                        1,
                        2,
                        format!(
                            "{}: unknown units \"{u}\"; inches assumed",
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
            regions: Vec::new(),
        };
        for ((raw, zones), mut p) in regions.iter().zip(zones).zip(props) {
            p.transparent = p.air != 0;
            let zones = zones.into_iter().map(|terms| Zone { terms }).collect();
            scene.push_region(
                Region {
                    name: raw.number.to_string(),
                    zones,
                },
                p,
            );
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

    fn body_table(&mut self, declared: Option<i64>) {
        loop {
            let Some(card) = self.peek() else {
                if self.version == DeckVersion::V1 {
                    let l = self.last_line();
                    self.error(
                        l,
                        1,
                        0,
                        format!(
                            "line {l}: the deck ends inside the body table: expected an END card"
                        ),
                    );
                }
                return;
            };
            let ty = self.type_field(&card).trim();
            if self.version == DeckVersion::V1 {
                if ty.eq_ignore_ascii_case("end") {
                    self.pos += 1;
                    return;
                }
            } else {
                let starts_alpha = ty.chars().next().is_some_and(|c| c.is_alphabetic());
                let more_declared = declared.is_some_and(|d| (self.bodies.len() as i64) < d);
                // A first region card that starts with an operator (`OR`,
                // `G`) has letters in the type columns too.
                let region_like =
                    kind_for(ty, self.version).is_none() && starts_with_operator(&card);
                // More declared bodies do not make a region card a body:
                // a wrong count is only a warning.
                let region_card = [7, 6, 5, 8, 9].iter().any(|&s| region_card_fits(&card, s));
                let is_body = !ty.is_empty()
                    && (kind_for(ty, self.version).is_some()
                        || starts_alpha && !region_like
                        || more_declared && !region_card);
                if !is_body {
                    return;
                }
            }
            self.pos += 1;
            let body = self.body(card);
            self.bodies.push(body);
        }
    }

    /// Skip the continuation cards of a body that cannot be read: cards with
    /// a blank type field, no other body number and six readable values (a
    /// v5 region card also has a blank type field, but rarely such values).
    fn skip_continuations(&mut self) {
        let number = (self.bodies.len() + 1) as i64;
        while let Some(c) = self.peek() {
            let num = parse_int(c.field(self.lay.num_col, self.lay.num_len));
            let values = (0..6).all(|f| parse_real(c.field(11 + 10 * f, 10)).is_some());
            if self.version == DeckVersion::V1
                || !self.type_field(&c).trim().is_empty()
                || !matches!(num, Some(0)) && num != Some(number)
                || !values
            {
                break;
            }
            self.pos += 1;
        }
    }

    fn body(&mut self, header: Card<'a>) -> Option<Body> {
        let number = self.bodies.len() + 1;
        let lay = self.lay;
        if self.version == DeckVersion::V5 && !self.numbering_reported {
            let f = header.field(lay.num_col, lay.num_len);
            if parse_int(f) != Some(number as i64) {
                self.numbering_reported = true;
                self.error(
                    header.line,
                    lay.num_col,
                    lay.num_len,
                    format!(
                        "{}: expected body number {number}, found \"{}\"",
                        at(header.line, lay.num_col, lay.num_len),
                        f.trim()
                    ),
                )
                .hint = Some("v5 body cards are numbered 1, 2, 3, … in deck order".into());
            }
        }
        let ty = header.field(lay.type_col, lay.type_len).trim();
        let Some(kind) = kind_for(ty, self.version) else {
            let hint = match suggest_type(ty) {
                Some(s) => format!("did you mean \"{s}\"?"),
                None => format!("COMGEOM body types are {}", TYPE_NAMES.join(", ")),
            };
            self.error(
                header.line,
                lay.type_col,
                lay.type_len,
                format!(
                    "{}: unknown body type \"{ty}\" (body {number})",
                    at(header.line, lay.type_col, lay.type_len)
                ),
            )
            .hint = Some(hint);
            self.skip_continuations();
            return None;
        };
        let params = if kind == BodyKind::Ars {
            self.ars(header, number)?
        } else {
            let n = kind.info().value_count();
            let mut vals = Vec::with_capacity(n);
            let mut ok = self.values(header, kind, n, &mut vals, &|i| param_label(kind, i));
            let mut card = header;
            let total = n.div_ceil(6);
            for k in 2..=total {
                card = self.continuation(card, number, kind, k, total)?;
                ok &= self.values(card, kind, n, &mut vals, &|i| param_label(kind, i));
            }
            if !ok {
                return None;
            }
            vals
        };
        Some(Body::new(number.to_string(), kind, params))
    }

    /// Read up to six values of a card into `vals` (until it holds `n`).
    fn values(
        &mut self,
        card: Card<'a>,
        kind: BodyKind,
        n: usize,
        vals: &mut Vec<f64>,
        label: &dyn Fn(usize) -> String,
    ) -> bool {
        let mut ok = true;
        for f in 0..6 {
            if vals.len() >= n {
                break;
            }
            let col = 11 + 10 * f;
            let text = card.field(col, 10);
            match parse_real(text) {
                Some(v) => vals.push(v),
                None => {
                    let what = label(vals.len());
                    self.error(
                        card.line,
                        col,
                        10,
                        format!(
                            "{}: expected a number for {} {what}, found \"{}\"",
                            at(card.line, col, 10),
                            kind.name(),
                            text.trim()
                        ),
                    )
                    .hint = Some(NUMBER_HINT.into());
                    vals.push(0.0);
                    ok = false;
                }
            }
        }
        ok
    }

    /// The next card, which must continue body `number`.
    fn continuation(
        &mut self,
        prev: Card<'a>,
        number: usize,
        kind: BodyKind,
        k: usize,
        total: usize,
    ) -> Option<Card<'a>> {
        let lay = self.lay;
        match self.peek() {
            Some(c) if self.type_field(&c).trim().is_empty() => {
                self.pos += 1;
                Some(c)
            }
            Some(c) => {
                let found = self.type_field(&c).trim();
                self.error(
                    c.line,
                    lay.type_col,
                    lay.type_len,
                    format!(
                        "{}: expected continuation card {k} of {total} for body {number} ({}), a card with a blank type field, found \"{found}\"",
                        at(c.line, lay.type_col, lay.type_len),
                        kind.name()
                    ),
                )
                .hint = Some(format!("a {} body takes {total} cards", kind.name()));
                None
            }
            None => {
                let len = prev.text.chars().count();
                self.error(
                    prev.line,
                    len + 1,
                    0,
                    format!("line {}: the deck ends inside body {number} ({}): expected continuation card {k} of {total}", prev.line, kind.name()),
                );
                None
            }
        }
    }

    fn ars(&mut self, header: Card<'a>, number: usize) -> Option<Vec<f64>> {
        let mut counts = [0usize; 2];
        let mut ok = true;
        for (i, what) in ["curve count", "number of points per curve"]
            .iter()
            .enumerate()
        {
            let col = 11 + 10 * i;
            let text = header.field(col, 10);
            match parse_int(text) {
                Some(v) if v > 0 => counts[i] = v as usize,
                _ => {
                    self.error(
                        header.line,
                        col,
                        10,
                        format!(
                            "{}: expected the ARS {what} (a positive integer), found \"{}\"",
                            at(header.line, col, 10),
                            text.trim()
                        ),
                    );
                    ok = false;
                }
            }
        }
        if !ok {
            self.skip_continuations();
            return None;
        }
        let [curves, ppc] = counts;
        let per_curve = (ppc as u128 * 3).div_ceil(6);
        let needed = curves as u128 * per_curve;
        let remaining = self.nonblank_from[self.pos.min(self.cards.len())];
        if needed > remaining as u128 {
            self.error(
                header.line,
                11,
                20,
                format!(
                    "{}: ARS body {number} claims {curves} curves of {ppc} points ({needed} cards), but only {remaining} cards follow",
                    at(header.line, 11, 20)
                ),
            );
            self.skip_continuations();
            return None;
        }
        let per_curve = per_curve as usize;
        let mut vals = Vec::with_capacity(2 + curves * ppc * 3);
        vals.push(curves as f64);
        vals.push(ppc as f64);
        let mut card = header;
        for c in 0..curves {
            let mut curve = Vec::with_capacity(ppc * 3);
            for k in 0..per_curve {
                let idx = 2 + c * per_curve + k;
                card =
                    self.continuation(card, number, BodyKind::Ars, idx, 1 + curves * per_curve)?;
                ok &= self.values(card, BodyKind::Ars, ppc * 3, &mut curve, &|i| {
                    format!(
                        "curve {} point {} ({})",
                        c + 1,
                        i / 3 + 1,
                        ["x", "y", "z"][i % 3]
                    )
                });
            }
            vals.extend(curve);
        }
        ok.then_some(vals)
    }

    fn region_table(&mut self) -> Vec<RawRegion> {
        let mut regions: Vec<RawRegion> = Vec::new();
        let mut by_number: HashMap<i64, usize> = HashMap::new();
        let nbodies = self.bodies.len();
        if self.peek().is_none() {
            let l = self.last_line();
            let end = self.cards.get(l - 1).map_or(0, |c| c.text.chars().count());
            self.error(
                l,
                end + 1,
                0,
                format!("line {l}: the deck ends before the region table"),
            );
            return regions;
        }
        let fc = self.region_field_start();
        let nlen = (fc - 1).min(5);
        loop {
            let Some(card) = self.next() else {
                let l = self.last_line();
                let msg = match self.version {
                    DeckVersion::V1 => format!("line {l}: the region table has no end card"),
                    _ => format!("line {l}: the region table has no -1 end card"),
                };
                self.warn(l, 1, 0, msg);
                break;
            };
            if self.version == DeckVersion::V1 && card.text.trim().eq_ignore_ascii_case("end") {
                break;
            }
            let nf = card.field(1, nlen);
            let Some(num) = parse_int(nf) else {
                self.error(card.line, 1, nlen, format!("{}: expected a region number, found \"{}\"", at(card.line, 1, nlen), nf.trim()))
                    .hint = Some("a region card starts with the region number in columns 1–5 (blank continues the region, -1 ends the table)".into());
                continue;
            };
            if num < 0 {
                break;
            }
            if num == 0 {
                if regions.is_empty() {
                    self.error(card.line, 1, 5, format!("{}: a continuation card (blank region number) comes before the first region", at(card.line, 1, 5)));
                    continue;
                }
            } else if let Some(&i) = by_number.get(&num) {
                let first = regions[i].line;
                self.error(
                    card.line,
                    1,
                    5,
                    format!(
                        "{}: region {num} is defined twice (first on line {first})",
                        at(card.line, 1, 5)
                    ),
                );
                continue;
            } else {
                by_number.insert(num, regions.len());
                regions.push(RawRegion {
                    number: num,
                    line: card.line,
                    zones: vec![Vec::new()],
                    comment: card.rest(fc + 63).trim().to_string(),
                    has_refs: false,
                });
            }
            let region = regions.last_mut().expect("a region exists");
            let rnum = region.number;
            for i in 0..9 {
                let col = fc + 7 * i;
                let op = card.field(col, 2);
                let raw = card.field(col + 2, 5);
                let digits: String = raw.chars().filter(|c| !c.is_whitespace()).collect();
                if digits.is_empty() {
                    if !op.trim().is_empty() {
                        self.error(
                            card.line,
                            col,
                            7,
                            format!(
                                "{}: expected an operator and a body number in region {rnum}, found \"{}\" with no number",
                                at(card.line, col, 7),
                                op.trim()
                            ),
                        )
                        .hint = Some("each region field is a 2-character operator and a signed 5-digit body number".into());
                    }
                    continue;
                }
                let Some(n) = parse_int(&digits) else {
                    self.error(card.line, col + 2, 5, format!("{}: expected a body number in region {rnum}, found \"{}\"", at(card.line, col + 2, 5), raw.trim()))
                        .hint = Some("each region field is a 2-character operator and a signed 5-digit body number".into());
                    continue;
                };
                if n == 0 {
                    continue;
                }
                let (region_ref, new_zone, op_minus) = match parse_op(op) {
                    Some(o) => o,
                    None => {
                        self.error(
                            card.line,
                            col,
                            2,
                            format!(
                                "{}: expected an operator (blank, OR, G or OG), found \"{op}\"",
                                at(card.line, col, 2)
                            ),
                        )
                        .hint = Some(
                            "OR starts a new zone; G marks the number as a region, not a body"
                                .into(),
                        );
                        continue;
                    }
                };
                let number = n.unsigned_abs() as usize;
                if !region_ref && number > nbodies {
                    self.error(
                        card.line,
                        col + 2,
                        5,
                        format!(
                            "{}: region {rnum} refers to body {number}, which is not defined (the deck has {nbodies} bodies)",
                            at(card.line, col + 2, 5)
                        ),
                    );
                    continue;
                }
                let region = regions.last_mut().expect("a region exists");
                if new_zone && region.zones.last().is_some_and(|z| !z.is_empty()) {
                    region.zones.push(Vec::new());
                }
                region.has_refs |= region_ref;
                let term = RawTerm {
                    region_ref,
                    negate: n < 0 || op_minus,
                    number,
                    line: card.line,
                    col: col + 2,
                };
                region.zones.last_mut().expect("a zone exists").push(term);
            }
        }
        for r in &mut regions {
            r.zones.retain(|z| !z.is_empty());
        }
        regions
    }

    /// The column where the nine region fields start. comgeom-g reads them
    /// from column 7 (11 in v1), but decks with left-aligned (MEP-021A) or
    /// GIFT-style numbers can put a 4- or 5-digit number across a field
    /// boundary there. When column 7 does not read every region card and
    /// another start (6, 5, 8 or 9) reads them all, that one is used, with a
    /// warning.
    fn region_field_start(&mut self) -> usize {
        if self.version == DeckVersion::V1 {
            return 11;
        }
        let table: Vec<Card<'a>> = self.cards[self.pos..]
            .iter()
            .filter(|c| !c.is_blank())
            .take_while(|c| parse_int(c.field(1, 5)).is_none_or(|n| n >= 0))
            .copied()
            .collect();
        let Some(bad) = table.iter().find(|c| !region_card_fits(c, 7)) else {
            return 7;
        };
        for start in [6, 5, 8, 9] {
            if table.iter().all(|c| region_card_fits(c, start)) {
                let line = bad.line;
                self.warn(
                    line,
                    7,
                    63,
                    format!("{}: the region fields do not fit the columns from 7 (first on this card); every region card reads with fields from column {start}, so that is used", at(line, 7, 63)),
                );
                return start;
            }
        }
        7
    }

    fn ident_table(&mut self, regions: &[RawRegion], props: &mut [RegionProps]) {
        let by_number: HashMap<i64, usize> = regions
            .iter()
            .enumerate()
            .map(|(i, r)| (r.number, i))
            .collect();
        let mut seen: HashMap<usize, usize> = HashMap::new();
        let mut textual: Option<(usize, usize)> = None;
        while let Some(card) = self.next() {
            let v5 = self.version == DeckVersion::V5;
            let (reg_f, fields) = if v5 {
                ((1, 5), [(6, 5), (11, 5), (16, 5), (21, 5)])
            } else {
                ((1, 10), [(11, 10), (21, 10), (75, 3), (78, 3)])
            };
            let rf = card.field(reg_f.0, reg_f.1);
            let Some(reg) = parse_int(rf) else {
                self.error(
                    card.line,
                    reg_f.0,
                    reg_f.1,
                    format!(
                        "{}: expected a region number on an ident card, found \"{}\"",
                        at(card.line, reg_f.0, reg_f.1),
                        rf.trim()
                    ),
                );
                continue;
            };
            if reg <= 0 {
                if let Some(c) = self.peek() {
                    self.warn(c.line, 1, 0, format!("line {}: cards after the ident table's end (region {reg} on line {}) are ignored", c.line, card.line));
                }
                self.pos = self.cards.len();
                return;
            }
            let Some(&ri) = by_number.get(&reg) else {
                self.error(
                    card.line,
                    reg_f.0,
                    reg_f.1,
                    format!(
                        "{}: ident card for region {reg}, which the region table does not define",
                        at(card.line, reg_f.0, reg_f.1)
                    ),
                );
                continue;
            };
            if let Some(first) = seen.insert(ri, card.line) {
                self.warn(card.line, reg_f.0, reg_f.1, format!("{}: second ident card for region {reg} (first on line {first}); this one is used", at(card.line, reg_f.0, reg_f.1)));
            }
            let names = [
                "ident code",
                "air code",
                "material code",
                "line-of-sight percent",
            ];
            let mut vals: [Option<i64>; 4] = [None; 4];
            let mut has_text = false;
            for (k, &(col, len)) in fields.iter().enumerate() {
                let text = card.field(col, len);
                if text.trim().is_empty() {
                    continue;
                }
                match parse_int(text) {
                    Some(v) => vals[k] = Some(v),
                    // The GIFT sample target writes the body type in columns
                    // 75-80 of its v4 ident cards: a comment, not numbers.
                    None if !v5 && k >= 2 => has_text = true,
                    None => {
                        self.error(
                            card.line,
                            col,
                            len,
                            format!(
                                "{}: expected the {} of region {reg} (an integer), found \"{}\"",
                                at(card.line, col, len),
                                names[k],
                                text.trim()
                            ),
                        );
                    }
                }
            }
            if has_text {
                textual.get_or_insert((card.line, 0)).1 += 1;
            }
            let p = &mut props[ri];
            p.ident = vals[0].unwrap_or(0);
            p.air = vals[1].unwrap_or(0);
            p.material = vals[2].unwrap_or(0);
            p.los = vals[3].unwrap_or(100);
            // When columns 75-80 are text they are part of the comment.
            let desc = if v5 {
                card.rest(26)
            } else if has_text {
                card.rest(31)
            } else {
                card.field(31, 44)
            };
            let desc = desc.trim();
            if !desc.is_empty() {
                p.description = desc.to_string();
            }
        }
        if let Some((line, n)) = textual {
            self.warn(
                line,
                75,
                6,
                format!("{}: {n} v4 ident cards hold text, not material and line-of-sight numbers, in columns 75–80; they are kept in the description, and material 0 and line of sight 100 are used", at(line, 75, 6)),
            );
        }
    }

    fn resolve_all(&mut self, regions: &[RawRegion]) -> Vec<Vec<Vec<Term>>> {
        let by_number: HashMap<usize, usize> = regions
            .iter()
            .enumerate()
            .map(|(i, r)| (r.number as usize, i))
            .collect();
        let mut memo: Vec<Resolve> = regions.iter().map(|_| Resolve::Todo).collect();
        (0..regions.len())
            .map(|i| {
                self.resolve(i, regions, &by_number, &mut memo, 0)
                    .unwrap_or_default()
            })
            .collect()
    }

    /// Take `n` terms from the expansion budget; false when it is spent.
    fn charge(&mut self, n: usize) -> bool {
        match self.budget.checked_sub(n) {
            Some(b) => {
                self.budget = b;
                true
            }
            None => {
                self.budget = 0;
                false
            }
        }
    }

    /// The zones of region `i` with its region references expanded.
    fn resolve(
        &mut self,
        i: usize,
        regions: &[RawRegion],
        by_number: &HashMap<usize, usize>,
        memo: &mut Vec<Resolve>,
        depth: usize,
    ) -> Option<Vec<Vec<Term>>> {
        match &memo[i] {
            Resolve::Done(z) => {
                let z = z.clone();
                let size = z.as_ref().map_or(0, |z| z.iter().map(Vec::len).sum());
                return if self.charge(size) { z } else { None };
            }
            Resolve::Visiting => return None,
            Resolve::Todo => {}
        }
        memo[i] = Resolve::Visiting;
        let r = &regions[i];
        let mut out: Option<Vec<Vec<Term>>> = Some(Vec::new());
        for raw_zone in &r.zones {
            let mut set: Vec<Vec<Term>> = vec![Vec::new()];
            for t in raw_zone {
                let fail = |me: &mut Self, msg: String| {
                    me.error(t.line, t.col, 5, format!("{}: {msg}", at(t.line, t.col, 5)));
                };
                if !t.region_ref {
                    if !self.charge(set.len()) {
                        fail(self, format!("region {}: region references expand to more than {MAX_EXPANSION} terms in all", r.number));
                        out = None;
                        break;
                    }
                    let op = if t.negate { Op::Outside } else { Op::Inside };
                    for z in &mut set {
                        z.push(Term {
                            op,
                            body: t.number - 1,
                        });
                    }
                    continue;
                }
                let Some(&target) = by_number.get(&t.number) else {
                    fail(
                        self,
                        format!(
                            "region {} refers to region {}, which is not defined",
                            r.number, t.number
                        ),
                    );
                    out = None;
                    continue;
                };
                if matches!(memo[target], Resolve::Visiting) {
                    fail(
                        self,
                        format!("region {} refers to region {}, which leads back to region {} (a cycle)", r.number, t.number, r.number),
                    );
                    out = None;
                    continue;
                }
                if depth >= MAX_REF_DEPTH {
                    fail(
                        self,
                        format!("region references nest more than {MAX_REF_DEPTH} deep"),
                    );
                    out = None;
                    continue;
                }
                let Some(tz) = self.resolve(target, regions, by_number, memo, depth + 1) else {
                    out = None;
                    continue;
                };
                let expanded = if t.negate {
                    subtract(&set, &tz)
                } else {
                    intersect(&set, &tz)
                };
                let size = expanded
                    .as_ref()
                    .map_or(0, |e| e.iter().map(Vec::len).sum());
                match expanded {
                    Some(e) if self.charge(size) => set = e,
                    Some(_) => {
                        fail(self, format!("region {}: region references expand to more than {MAX_EXPANSION} terms in all", r.number));
                        out = None;
                        break;
                    }
                    None => {
                        let verb = if t.negate {
                            "subtracting"
                        } else {
                            "intersecting with"
                        };
                        fail(self, format!("region {}: {verb} region {} expands to more than {MAX_ZONES} zones", r.number, t.number))
                            ;
                        if let Some(last) = self.errors.last_mut() {
                            last.hint =
                                Some("write the region with body references instead".into());
                        }
                        out = None;
                        set = vec![Vec::new()];
                    }
                }
            }
            if let Some(o) = &mut out {
                o.extend(set);
                if o.len() > MAX_ZONES {
                    self.error(
                        r.line,
                        1,
                        5,
                        format!(
                            "line {}: region {} expands to more than {MAX_ZONES} zones",
                            r.line, r.number
                        ),
                    );
                    out = None;
                }
            }
        }
        if r.has_refs {
            if let Some(o) = &mut out {
                simplify(o);
            }
        }
        memo[i] = Resolve::Done(out.clone());
        out
    }
}

/// Each zone of `set` joined with each zone of `region`.
fn intersect(set: &[Vec<Term>], region: &[Vec<Term>]) -> Option<Vec<Vec<Term>>> {
    if set.len().checked_mul(region.len())? > MAX_ZONES {
        return None;
    }
    let mut out = Vec::with_capacity(set.len() * region.len());
    for z in set {
        for rz in region {
            if z.len() + rz.len() > MAX_TERMS {
                return None;
            }
            out.push(z.iter().chain(rz).copied().collect());
        }
    }
    Some(prune(out))
}

/// `set` minus every zone of `region`: by De Morgan, minus a zone
/// `t1 ∩ t2 ∩ …` is the union of the complements `¬t1 ∪ ¬t2 ∪ …`, so each
/// zone splits into one zone per term of the subtracted zone.
fn subtract(set: &[Vec<Term>], region: &[Vec<Term>]) -> Option<Vec<Vec<Term>>> {
    let mut cur = set.to_vec();
    for rz in region {
        if cur.len().checked_mul(rz.len())? > MAX_ZONES {
            return None;
        }
        let mut next = Vec::with_capacity(cur.len() * rz.len());
        for z in &cur {
            if z.len() >= MAX_TERMS {
                return None;
            }
            for t in rz {
                let op = if t.op == Op::Inside {
                    Op::Outside
                } else {
                    Op::Inside
                };
                let mut nz = z.clone();
                nz.push(Term { op, body: t.body });
                next.push(nz);
            }
        }
        cur = prune(next);
    }
    Some(cur)
}

/// Drop repeated terms, and zones that hold a body both inside and outside
/// (they are empty).
fn prune(zones: Vec<Vec<Term>>) -> Vec<Vec<Term>> {
    zones
        .into_iter()
        .filter_map(|z| {
            let mut seen: HashMap<usize, Op> = HashMap::with_capacity(z.len());
            let mut out: Vec<Term> = Vec::with_capacity(z.len());
            for t in z {
                match seen.insert(t.body, t.op) {
                    Some(op) if op != t.op => return None,
                    Some(_) => {}
                    None => out.push(t),
                }
            }
            Some(out)
        })
        .collect()
}

/// Prune, then drop repeated zones.
fn simplify(zones: &mut Vec<Vec<Term>>) {
    let mut seen = std::collections::HashSet::new();
    let z = prune(std::mem::take(zones));
    zones.extend(z.into_iter().filter(|zone| seen.insert(zone.clone())));
}

/// The meaning of a region-field operator: (region reference, starts a new
/// zone, subtracts). Blank, `OR`, `G`/`OG` for a region; `+` and `-` signs
/// in the operator columns are accepted too.
fn parse_op(op: &str) -> Option<(bool, bool, bool)> {
    let up: Vec<char> = op
        .chars()
        .map(|c| c.to_ascii_uppercase())
        .chain([' ', ' '])
        .take(2)
        .collect();
    Some(match (up[0], up[1]) {
        ('O', 'R') => (false, true, false),
        ('O', 'G') => (true, true, false),
        (c0, 'G') if matches!(c0, ' ' | '+' | '-') => (true, false, c0 == '-'),
        (c0, c1) if matches!(c0, ' ' | '+' | '-') && matches!(c1, ' ' | '+' | '-') => {
            (false, false, c0 == '-' || c1 == '-')
        }
        _ => return None,
    })
}

/// True when a region card reads without errors with its fields starting
/// at column `start` (and its region number in the columns before, at most
/// 5 of them).
fn region_card_fits(card: &Card, start: usize) -> bool {
    if parse_int(card.field(1, (start - 1).min(5))).is_none()
        || start > 6 && !card.field(6, start - 6).trim().is_empty()
    {
        return false;
    }
    (0..9).all(|i| {
        let col = start + 7 * i;
        let digits: String = card
            .field(col + 2, 5)
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect();
        match parse_int(&digits) {
            _ if digits.is_empty() => card.field(col, 2).trim().is_empty(),
            Some(_) => parse_op(card.field(col, 2)).is_some(),
            None => false,
        }
    })
}

/// True when a card reads as a region card whose first field has an `OR` or
/// `G` operator: a positive region number and an operator in columns 7–8
/// followed by a non-zero number.
fn starts_with_operator(card: &Card) -> bool {
    let op = card.field(7, 2).to_ascii_uppercase();
    matches!(op.as_str(), "OR" | "OG" | " G" | "+G" | "-G")
        && parse_int(card.field(1, 5)).is_some_and(|n| n > 0)
        && parse_int(&card.field(9, 5).replace(' ', "")).is_some_and(|n| n != 0)
}

/// The type name `ty` was probably meant to be: a swap of two neighbouring
/// letters first (`SHP` → `SPH`), else the closest by edit distance.
fn suggest_type(ty: &str) -> Option<&'static str> {
    let up: Vec<char> = ty.to_ascii_uppercase().chars().collect();
    for i in 1..up.len() {
        let mut s = up.clone();
        s.swap(i - 1, i);
        let s: String = s.into_iter().collect();
        if let Some(t) = TYPE_NAMES.iter().find(|t| **t == s) {
            return Some(t);
        }
    }
    did_you_mean(ty, TYPE_NAMES.iter().copied())
}

/// `radius (R)`, `height vector (H.y)`, `vertex (P3.z)` for value `i` of a
/// body type.
fn param_label(kind: BodyKind, i: usize) -> String {
    let mut start = 0;
    for p in kind.info().params {
        let w = p.kind.width();
        if i < start + w {
            let doc = if p.doc.is_empty() { "vertex" } else { p.doc };
            return if w == 1 {
                format!("{doc} ({})", p.name)
            } else {
                format!("{doc} ({}.{})", p.name, ["x", "y", "z"][i - start])
            };
        }
        start += w;
    }
    format!("value {}", i + 1)
}
