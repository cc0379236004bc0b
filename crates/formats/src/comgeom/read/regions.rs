//! The region table: region cards, their operator and number fields,
//! and the ident table that describes the regions.

use super::{at, RawRegion, RawTerm, Reader};
use crate::comgeom::card::{parse_int, Card};
use crate::DeckVersion;
use std::collections::HashMap;
use sv_scene::RegionProps;

const FIELD_HINT: &str =
    "each region field is a 2-character operator and a signed 5-digit body number";

impl<'a> Reader<'a> {
    pub(super) fn region_table(&mut self) -> Vec<RawRegion> {
        let mut regions: Vec<RawRegion> = Vec::new();
        let mut by_number: HashMap<i64, usize> = HashMap::new();
        let body_count = self.bodies.len();
        if self.peek().is_none() {
            let last = self.last_line();
            let end = self
                .cards
                .get(last - 1)
                .map_or(0, |c| c.text.chars().count());
            self.error(
                last,
                end + 1,
                0,
                format!("line {last}: the deck ends before the region table"),
            );
            return regions;
        }
        let field_start = self.region_field_start();
        let number_len = (field_start - 1).min(5);
        loop {
            let Some(card) = self.next() else {
                let last = self.last_line();
                let msg = match self.version {
                    DeckVersion::V1 => format!("line {last}: the region table has no end card"),
                    _ => format!("line {last}: the region table has no -1 end card"),
                };
                self.warn(last, 1, 0, msg);
                break;
            };
            if self.version == DeckVersion::V1 && card.text.trim().eq_ignore_ascii_case("end") {
                break;
            }
            let number_field = card.field(1, number_len);
            let Some(num) = parse_int(number_field) else {
                self.error(card.line, 1, number_len, format!("{}: expected a region number, found \"{}\"", at(card.line, 1, number_len), number_field.trim()))
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
                    comment: card.rest(field_start + 63).trim().to_string(),
                });
            }
            let region = regions.last_mut().expect("a region exists");
            for i in 0..9 {
                self.region_field(card, field_start + 7 * i, region, body_count);
            }
        }
        for region in &mut regions {
            region.zones.retain(|z| !z.is_empty());
        }
        regions
    }

    /// One operator and number field of a region card at column `col`: a
    /// term added to `region` (a new zone first after OR), or an error.
    fn region_field(
        &mut self,
        card: Card<'a>,
        col: usize,
        region: &mut RawRegion,
        body_count: usize,
    ) {
        let rnum = region.number;
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
                .hint = Some(FIELD_HINT.into());
            }
            return;
        }
        let Some(n) = parse_int(&digits) else {
            self.error(
                card.line,
                col + 2,
                5,
                format!(
                    "{}: expected a body number in region {rnum}, found \"{}\"",
                    at(card.line, col + 2, 5),
                    raw.trim()
                ),
            )
            .hint = Some(FIELD_HINT.into());
            return;
        };
        if n == 0 {
            return;
        }
        let Some((region_ref, new_zone, op_minus)) = parse_op(op) else {
            self.error(
                card.line,
                col,
                2,
                format!(
                    "{}: expected an operator (blank, OR, G or OG), found \"{op}\"",
                    at(card.line, col, 2)
                ),
            )
            .hint = Some("OR starts a new zone; G marks the number as a region, not a body".into());
            return;
        };
        let number = n.unsigned_abs() as usize;
        if !region_ref && number > body_count {
            self.error(
                card.line,
                col + 2,
                5,
                format!(
                    "{}: region {rnum} refers to body {number}, which is not defined (the deck has {body_count} bodies)",
                    at(card.line, col + 2, 5)
                ),
            );
            return;
        }
        if new_zone && region.zones.last().is_some_and(|z| !z.is_empty()) {
            region.zones.push(Vec::new());
        }
        let term = RawTerm {
            region_ref,
            negate: n < 0 || op_minus,
            number,
            line: card.line,
            col: col + 2,
        };
        region.zones.last_mut().expect("a zone exists").push(term);
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

    pub(super) fn ident_table(&mut self, regions: &[RawRegion], props: &mut [RegionProps]) {
        let by_number: HashMap<i64, usize> = regions
            .iter()
            .enumerate()
            .map(|(i, region)| (region.number, i))
            .collect();
        let mut seen: HashMap<usize, usize> = HashMap::new();
        let mut textual: Option<(usize, usize)> = None;
        while let Some(card) = self.next() {
            let v5 = self.version == DeckVersion::V5;
            let (number_at, fields) = if v5 {
                ((1, 5), [(6, 5), (11, 5), (16, 5), (21, 5)])
            } else {
                ((1, 10), [(11, 10), (21, 10), (75, 3), (78, 3)])
            };
            let number_field = card.field(number_at.0, number_at.1);
            let Some(number) = parse_int(number_field) else {
                self.error(
                    card.line,
                    number_at.0,
                    number_at.1,
                    format!(
                        "{}: expected a region number on an ident card, found \"{}\"",
                        at(card.line, number_at.0, number_at.1),
                        number_field.trim()
                    ),
                );
                continue;
            };
            if number <= 0 {
                if let Some(next) = self.peek() {
                    self.warn(next.line, 1, 0, format!("line {}: cards after the ident table's end (region {number} on line {}) are ignored", next.line, card.line));
                }
                self.pos = self.cards.len();
                return;
            }
            let Some(&index) = by_number.get(&number) else {
                self.error(
                    card.line,
                    number_at.0,
                    number_at.1,
                    format!(
                        "{}: ident card for region {number}, which the region table does not define",
                        at(card.line, number_at.0, number_at.1)
                    ),
                );
                continue;
            };
            if let Some(first) = seen.insert(index, card.line) {
                self.warn(card.line, number_at.0, number_at.1, format!("{}: second ident card for region {number} (first on line {first}); this one is used", at(card.line, number_at.0, number_at.1)));
            }
            let names = [
                "ident code",
                "air code",
                "material code",
                "line-of-sight percent",
            ];
            let mut values: [Option<i64>; 4] = [None; 4];
            let mut has_text = false;
            for (k, &(col, len)) in fields.iter().enumerate() {
                let text = card.field(col, len);
                if text.trim().is_empty() {
                    continue;
                }
                match parse_int(text) {
                    Some(v) => values[k] = Some(v),
                    // The GIFT sample target writes the body type in columns
                    // 75-80 of its v4 ident cards: a comment, not numbers.
                    None if !v5 && k >= 2 => has_text = true,
                    None => {
                        self.error(
                            card.line,
                            col,
                            len,
                            format!(
                                "{}: expected the {} of region {number} (an integer), found \"{}\"",
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
            let region_props = &mut props[index];
            region_props.ident = values[0].unwrap_or(0);
            region_props.air = values[1].unwrap_or(0);
            region_props.material = values[2].unwrap_or(0);
            region_props.los = values[3].unwrap_or(100);
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
                region_props.description = desc.to_string();
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
pub(super) fn region_card_fits(card: &Card, start: usize) -> bool {
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
pub(super) fn starts_with_operator(card: &Card) -> bool {
    let op = card.field(7, 2).to_ascii_uppercase();
    matches!(op.as_str(), "OR" | "OG" | " G" | "+G" | "-G")
        && parse_int(card.field(1, 5)).is_some_and(|n| n > 0)
        && parse_int(&card.field(9, 5).replace(' ', "")).is_some_and(|n| n != 0)
}
