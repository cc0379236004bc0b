//! The numbered fixed-format geometry (GEOBEGIN SDUM blank or `COMBINAT`,
//! FLUKA's default), read by columns as FLUKA's Fortran formats do.
//!
//! Bodies: `(2X,A3,I5,6D10.3)`, or `(2X,A3,I5,3D22.15)` when the title line
//! gives IDBG −10 or −100: the code in columns 3–5, the body number in 6–10
//! (blank: the next number), values from column 11, continued on lines
//! whose columns 3–10 are blank. A blank value field is 0; a value without
//! a decimal point is read as Fortran's `D10.3` reads it (`100` is 0.1),
//! with a warning, since FLUKA requires the point.
//!
//! Regions: `(2X,A3,I5,9(A2,I5))`, or `(2X,A3,I5,7(A2,I7))` for IDBG ±100:
//! a label in columns 3–5 (blank on continuation lines), the NAZ in 6–10,
//! then pairs of an operator field (`OR` or blank) and a signed body
//! number. `OR` starts a new zone. Regions are named by their number in
//! input order, as FLUKA numbers them; the label is kept in the
//! description.
//!
//! Within a field, blanks are ignored (Fortran's `BN` editing).

use super::bodies::{Directive, PendingBody};
use super::{clean, tokens, Reader};
use sv_geom::{Op, Term, Zone};

/// A fixed-format region being read.
struct FixedRegion {
    /// Line of its first card.
    line: usize,
    /// Columns 3–5 of the first card.
    label: String,
    zones: Vec<Zone>,
    /// The zone being read (an `OR` closes it).
    zone: Zone,
    /// False once a body or field was wrong (already reported).
    complete: bool,
}

/// The characters of `chars` in columns `from..to` (0-based, clipped),
/// without blanks.
fn field(chars: &[char], from: usize, to: usize) -> String {
    chars
        .get(from.min(chars.len())..to.min(chars.len()))
        .unwrap_or(&[])
        .iter()
        .filter(|c| !c.is_whitespace())
        .collect()
}

/// A Fortran `Dw.d` value: with a decimal point as written, without one
/// the last `decimals` digits of the mantissa are the fraction. The value
/// and whether the decimal point was implied; `None` for a non-number.
fn fortran_real(text: &str, decimals: i32) -> Option<(f64, bool)> {
    if text.contains('.') {
        return super::card::number(text).map(|v| (v, false));
    }
    let split = text.find(['e', 'E', 'd', 'D']).unwrap_or(text.len());
    let (mantissa, rest) = text.split_at(split);
    let exponent: i32 = match rest.get(1..) {
        None => 0,
        Some(e) => {
            let e = e.strip_prefix('+').unwrap_or(e);
            if e.is_empty() || e.len() > 4 {
                return None;
            }
            e.parse().ok()?
        }
    };
    let digits = mantissa.strip_prefix(['+', '-']).unwrap_or(mantissa);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let m: f64 = mantissa.parse().ok()?;
    let v = m * 10f64.powi(exponent.checked_sub(decimals)?);
    v.is_finite().then_some((v, true))
}

/// A Fortran `Iw` value (blanks already removed; blank is 0).
fn fortran_int(text: &str) -> Option<i64> {
    if text.is_empty() {
        return Some(0);
    }
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if digits.is_empty() || digits.len() > 9 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    text.parse().ok()
}

impl Reader {
    /// Read fixed-format bodies from line `start`; the index after END.
    pub(super) fn fixed_bodies(&mut self, start: usize, end: usize, idbg: i64) -> Option<usize> {
        let (width, per_line, decimals) = if idbg == -10 || idbg == -100 {
            (22, 3, 15)
        } else {
            (10, 6, 3)
        };
        let mut stack: Vec<Directive> = Vec::new();
        let mut pending: Option<PendingBody> = None;
        let mut numbered = 0i64;
        let mut result = None;
        for k in start..end {
            let Some((text, chars, code)) = self.fixed_line(k) else {
                continue;
            };
            let trimmed = text.trim();
            if trimmed.starts_with('$') {
                if let Some(p) = pending.take() {
                    self.finish_fixed_body(p, &stack, decimals);
                }
                let words: Vec<(usize, String)> = tokens(&text)
                    .into_iter()
                    .map(|(c, w)| (c, w.to_string()))
                    .collect();
                self.directive(k, &words, &mut stack);
                continue;
            }
            if code.eq_ignore_ascii_case("END") || trimmed.eq_ignore_ascii_case("END") {
                if let Some(p) = pending.take() {
                    self.finish_fixed_body(p, &stack, decimals);
                }
                result = Some(k + 1);
                break;
            }
            if !code.is_empty() {
                if let Some(p) = pending.take() {
                    self.finish_fixed_body(p, &stack, decimals);
                }
                let Some(number) = self.body_number(k, &chars, numbered) else {
                    continue;
                };
                numbered = number;
                pending = Some(PendingBody {
                    words: vec![(k, 3, code), (k, 6, number.to_string())],
                    numbered: true,
                });
            } else if pending.is_none() {
                self.orphan_line(k, &text, "body", "its code in columns 3-5 and its number");
                continue;
            }
            let p = pending.as_mut().expect("a body is being read");
            for f in 0..per_line {
                let from = 10 + f * width;
                let text = field(&chars, from, from + width);
                let lead = chars.get(from.min(chars.len())..).map_or(0, |rest| {
                    rest.iter()
                        .take(width)
                        .take_while(|c| c.is_whitespace())
                        .count()
                });
                p.words.push((k, from + 1 + lead, text));
            }
        }
        if let Some(p) = pending.take() {
            self.finish_fixed_body(p, &stack, decimals);
        }
        self.unclosed(stack);
        result
    }

    /// The body number in columns 6–10 (blank: the one after `previous`).
    fn body_number(&mut self, k: usize, chars: &[char], previous: i64) -> Option<i64> {
        let text = field(chars, 5, 10);
        match fortran_int(&text) {
            Some(0) if text.is_empty() => Some(previous + 1),
            Some(n) if n > 0 => Some(n),
            _ => {
                let len = chars.len().clamp(6, 10) - 5;
                self.err(
                    k,
                    6,
                    len,
                    format!("expected a body number in columns 6-10, found `{text}`"),
                );
                None
            }
        }
    }

    /// Read fixed-format regions from line `start`; the index after END.
    pub(super) fn fixed_regions(&mut self, start: usize, end: usize, idbg: i64) -> Option<usize> {
        // Pairs per line, their width and the width of the body field.
        let (pairs, stride, body_width) = if idbg.abs() == 100 {
            (7, 9, 7)
        } else {
            (9, 7, 5)
        };
        let mut cur: Option<FixedRegion> = None;
        for k in start..end {
            let Some((text, chars, label)) = self.fixed_line(k) else {
                continue;
            };
            let trimmed = text.trim();
            if label.eq_ignore_ascii_case("END") || trimmed.eq_ignore_ascii_case("END") {
                if let Some(r) = cur.take() {
                    self.finish_fixed_region(r);
                }
                return Some(k + 1);
            }
            if !label.is_empty() {
                if let Some(r) = cur.take() {
                    self.finish_fixed_region(r);
                }
                cur = Some(FixedRegion {
                    line: k,
                    label,
                    zones: Vec::new(),
                    zone: Zone::default(),
                    complete: true,
                });
            }
            let Some(r) = cur.as_mut() else {
                self.orphan_line(k, &text, "region", "a label in columns 3-5 and its NAZ");
                continue;
            };
            let number = self.regions.len() + 1;
            for pair in 0..pairs {
                let at = 10 + pair * stride;
                let mut op = field(&chars, at, at + 2);
                let mut body = field(&chars, at + 2, at + 2 + body_width);
                if (op == "+" || op == "-") && !body.is_empty() && !body.starts_with(['+', '-']) {
                    // The sign slipped into the operator field: the number
                    // is meant, as it would be in free format.
                    let (from, to) = (at + 1, at + 2);
                    let message = format!(
                        "the sign `{op}` stands in the operator field (columns {from}-{to}), \
                         not with the body number"
                    );
                    self.warn(k, from, 2, message);
                    body = format!("{op}{body}");
                    op.clear();
                }
                if !op.is_empty() && !op.eq_ignore_ascii_case("OR") {
                    self.err(
                        k,
                        at + 1,
                        2,
                        format!(
                            "expected `OR` or blanks in columns {}-{}, found `{op}`",
                            at + 1,
                            at + 2
                        ),
                    );
                    r.complete = false;
                    continue;
                }
                if !op.is_empty() && !r.zone.is_empty() {
                    r.zones.push(std::mem::take(&mut r.zone));
                }
                let col = at + 3;
                match fortran_int(&body) {
                    Some(0) => {}
                    Some(n) => match self.body_index.get(&n.unsigned_abs().to_string()) {
                        Some(&b) => r.zone.terms.push(Term {
                            op: if n > 0 { Op::Inside } else { Op::Outside },
                            body: b,
                        }),
                        None => {
                            r.complete = false;
                            if !self.bad_bodies.contains(&n.unsigned_abs().to_string()) {
                                self.err(
                                    k,
                                    col,
                                    body_width,
                                    format!(
                                        "region {number} refers to undefined body {}",
                                        n.unsigned_abs()
                                    ),
                                );
                            }
                        }
                    },
                    None => {
                        r.complete = false;
                        self.err(
                            k,
                            col,
                            body_width,
                            format!(
                                "expected a signed body number in columns {}-{}, found `{body}`",
                                col,
                                col + body_width - 1
                            ),
                        );
                    }
                }
            }
        }
        None
    }

    /// Line `k` without its comment, as characters, and its columns 3–5;
    /// `None` when it is blank.
    fn fixed_line(&self, k: usize) -> Option<(String, Vec<char>, String)> {
        let text = clean(&self.lines[k].text).to_string();
        if text.trim().is_empty() {
            return None;
        }
        let chars: Vec<char> = text.chars().collect();
        let code = field(&chars, 2, 5);
        Some((text, chars, code))
    }

    /// A continuation line (columns 3–5 blank) with no body or region
    /// (`what`) before it, which starts with `start` and a number in 6–10.
    fn orphan_line(&mut self, k: usize, text: &str, what: &str, start: &str) {
        let col = text.chars().take_while(|c| c.is_whitespace()).count() + 1;
        let len = text.trim().chars().count().min(10);
        let message = format!("a {what} continuation line with no {what} before it");
        self.err(k, col, len, message).hint = Some(format!(
            "in fixed format a {what} starts with {start} in 6-10"
        ));
    }

    /// Add a fixed-format region, named by its number.
    fn finish_fixed_region(&mut self, mut r: FixedRegion) {
        if !r.zone.is_empty() {
            r.zones.push(std::mem::take(&mut r.zone));
        }
        let number = (self.regions.len() + 1).to_string();
        if r.zones.is_empty() && r.complete {
            self.err(
                r.line,
                3,
                3,
                format!("region {number} ({}) has no bodies", r.label),
            );
            return;
        }
        let zones = if r.complete { r.zones } else { Vec::new() };
        self.region_labels.insert(self.regions.len(), r.label);
        self.add_region(r.line, 3, number, zones);
    }

    /// A fixed-format body whose lines are read: its fields become the
    /// values its type takes (blank fields are 0, trailing ones beyond the
    /// count are dropped), then it is checked and added as a free-format
    /// body is.
    fn finish_fixed_body(&mut self, mut p: PendingBody, stack: &[Directive], decimals: i32) {
        if let Some(count) = super::bodies::value_count(&p.words[0].2) {
            let want = 2 + count;
            if p.words.len() > want {
                let extra: Vec<_> = p.words.drain(want..).filter(|w| !w.2.is_empty()).collect();
                if let Some((line, col, text)) = extra.first() {
                    let code = p.words[0].2.to_ascii_uppercase();
                    let message = format!(
                        "{code} body {} takes {} values: `{text}` and what follows are ignored",
                        p.words[1].2,
                        want - 2
                    );
                    self.warn(*line, *col, text.chars().count(), message);
                }
            }
        }
        for (line, col, text) in p.words.iter_mut().skip(2) {
            if text.is_empty() {
                *text = "0".to_string();
            } else if let Some((v, implied)) = fortran_real(text, decimals) {
                if implied {
                    let written = std::mem::replace(text, format!("{v:e}"));
                    let message = format!(
                        "`{written}` has no decimal point: FLUKA's fixed format reads it as {v}"
                    );
                    let hint = "write the decimal point: FLUKA requires it in body values";
                    let len = written.chars().count();
                    self.warn_hinted(*line, *col, len, message, Some(hint.into()));
                }
            }
        }
        self.finish_body(&p, stack);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fortran_fields() {
        assert_eq!(fortran_real("-5000000.0", 3), Some((-5000000.0, false)));
        assert_eq!(fortran_real("100", 3), Some((0.1, true)));
        assert_eq!(fortran_real("25E2", 3), Some((25.0 * 10f64.powi(-1), true)));
        assert_eq!(fortran_real("1.5D2", 3), Some((150.0, false)));
        assert_eq!(fortran_real("x", 3), None);
        assert_eq!(fortran_int("+12"), Some(12));
        assert_eq!(fortran_int(""), Some(0));
        assert_eq!(fortran_int("1.0"), None);
        let chars: Vec<char> = "  RPP    1 -1 0. 2.".chars().collect();
        assert_eq!(field(&chars, 5, 10), "1");
        assert_eq!(field(&chars, 10, 20), "-10.2.");
        assert_eq!(field(&chars, 30, 40), "");
    }
}
