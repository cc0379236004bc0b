//! The body table: body cards, their continuation cards and ARS bodies.

use super::regions::{region_card_fits, starts_with_operator};
use super::{at, Reader, NUMBER_HINT};
use crate::comgeom::card::{parse_int, parse_real, Card};
use crate::comgeom::{kind_for, TYPE_NAMES};
use crate::{did_you_mean, DeckVersion};
use sv_geom::{Body, BodyKind};

impl<'a> Reader<'a> {
    pub(super) fn body_table(&mut self, declared: Option<i64>) {
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
            let number_field = header.field(lay.num_col, lay.num_len);
            if parse_int(number_field) != Some(number as i64) {
                self.numbering_reported = true;
                self.error(
                    header.line,
                    lay.num_col,
                    lay.num_len,
                    format!(
                        "{}: expected body number {number}, found \"{}\"",
                        at(header.line, lay.num_col, lay.num_len),
                        number_field.trim()
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
            let count = kind.info().value_count();
            let mut values = Vec::with_capacity(count);
            let mut ok = self.values(header, kind, count, &mut values, &|i| param_label(kind, i));
            let mut card = header;
            let total = count.div_ceil(6);
            for k in 2..=total {
                card = self.continuation(card, number, kind, k, total)?;
                ok &= self.values(card, kind, count, &mut values, &|i| param_label(kind, i));
            }
            if !ok {
                return None;
            }
            values
        };
        let body = Body::new(
            number.to_string(),
            kind,
            crate::comgeom::card_to_body_params(kind, params),
        );
        // The engine's own rules for the body (positive radii, ARB faces
        // that close, …), reported at its type field.
        let (col, len) = (lay.type_col, lay.type_len);
        let mut warnings = Vec::new();
        if let Err(msg) = sv_geom::prepare(&body, &mut warnings) {
            let place = at(header.line, col, len);
            self.error(
                header.line,
                col,
                len,
                format!("{place}: {kind} body {number}: {msg}"),
            );
            return None;
        }
        for warning in warnings {
            let place = at(header.line, col, len);
            let msg = format!("{place}: {kind} body {number}: {}", warning.message);
            self.warn(header.line, col, len, msg);
        }
        Some(body)
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
        let [curves, points] = counts;
        let per_curve = (points as u128 * 3).div_ceil(6);
        let needed = curves as u128 * per_curve;
        let remaining = self.nonblank_from[self.pos.min(self.cards.len())];
        if needed > remaining as u128 {
            self.error(
                header.line,
                11,
                20,
                format!(
                    "{}: ARS body {number} claims {curves} curves of {points} points ({needed} cards), but only {remaining} cards follow",
                    at(header.line, 11, 20)
                ),
            );
            self.skip_continuations();
            return None;
        }
        let per_curve = per_curve as usize;
        let mut values = Vec::with_capacity(2 + curves * points * 3);
        values.push(curves as f64);
        values.push(points as f64);
        let mut card = header;
        for curve_index in 0..curves {
            let mut curve = Vec::with_capacity(points * 3);
            for k in 0..per_curve {
                let card_index = 2 + curve_index * per_curve + k;
                card = self.continuation(
                    card,
                    number,
                    BodyKind::Ars,
                    card_index,
                    1 + curves * per_curve,
                )?;
                ok &= self.values(card, BodyKind::Ars, points * 3, &mut curve, &|i| {
                    format!(
                        "curve {} point {} ({})",
                        curve_index + 1,
                        i / 3 + 1,
                        ["x", "y", "z"][i % 3]
                    )
                });
            }
            values.extend(curve);
        }
        ok.then_some(values)
    }
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
