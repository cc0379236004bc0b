//! The region list of a name-based (free-format) FLUKA geometry.

use super::card;
use super::{clean, is_integer, is_name, Reader};
use crate::text::region::{self, Lookup, Spanned, Tok};
use sv_geom::{Region, Zone};

/// A region being read: where its name is, the name and its tokens.
struct Pending {
    line: usize,
    col: usize,
    name: String,
    toks: Vec<Spanned>,
}

impl Reader {
    /// Read regions from line `start`; the index after END, or `None`.
    ///
    /// A line whose first word is a name and whose second is an integer
    /// (the NAZ) starts a region; any other line continues the region
    /// being read, whatever it starts with (`)`, an operator, a body).
    pub(super) fn regions_section(&mut self, start: usize, end: usize) -> Option<usize> {
        let mut cur: Option<Pending> = None;
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
            let starts_region = !first.starts_with(['+', '-', '|', '(', ')'])
                && words.get(1).is_some_and(|(_, w)| is_integer(w));
            if starts_region {
                if let Some(r) = cur.take() {
                    self.finish_region(r);
                }
                let (ncol, naz) = words[1];
                let shift = ncol - 1 + naz.chars().count();
                let after: String = text.chars().skip(shift).collect();
                let mut toks = Vec::new();
                region::tokenize(&after, k, &mut toks);
                for t in &mut toks {
                    t.col += shift;
                }
                if !is_name(first) {
                    let message = format!(
                        "region name `{first}` must start with a letter and hold only letters, \
                         digits and `_`"
                    );
                    self.err(k, col0, first.chars().count(), message);
                }
                cur = Some(Pending {
                    line: k,
                    col: col0,
                    name: first.to_string(),
                    toks,
                });
            } else if let Some(p) = &mut cur {
                region::tokenize(&text, k, &mut p.toks);
            } else if first.starts_with(['+', '-', '|', '(', ')']) {
                let message = "region expression outside a region: expected a region name \
                               and its NAZ number first";
                self.err(k, col0, 1, message);
            } else {
                self.err(
                    k,
                    col0,
                    first.chars().count(),
                    format!("expected a region name and its NAZ number, found `{first}`"),
                )
                .hint = Some(
                    "a region starts with its name and NAZ, as in `target 5 +cyl -hole`".into(),
                );
            }
        }
        if let Some(r) = cur.take() {
            self.finish_region(r);
        }
        result
    }

    /// What a body name in a region stands for; unknown names are
    /// collected in `missing` (reported later, with hints).
    fn lookup_body(&self, t: &Spanned, missing: &mut Vec<Spanned>) -> Lookup {
        let Tok::Name(body_name) = &t.tok else {
            return Lookup::Unknown;
        };
        if let Some(&b) = self.body_index.get(body_name) {
            return Lookup::Body(b);
        }
        if self.empty_bodies.contains(body_name) {
            return Lookup::Empty;
        }
        if !self.bad_bodies.contains(body_name) {
            missing.push(t.clone());
        }
        Lookup::Unknown
    }

    fn finish_region(&mut self, p: Pending) {
        let Pending {
            line,
            col,
            name,
            toks,
        } = p;
        if toks.is_empty() {
            let len = name.chars().count();
            self.err(line, col, len, format!("region `{name}` has no expression"));
            return;
        }
        let mut missing: Vec<Spanned> = Vec::new();
        let parsed = region::Parser::new(&toks, |t| self.lookup_body(t, &mut missing)).parse();
        for t in &missing {
            let Tok::Name(body_name) = &t.tok else {
                continue;
            };
            // A name opening a line may be a region whose NAZ is missing.
            let opens_line = !toks.iter().any(|o| o.line == t.line && o.col < t.col);
            let hint = if opens_line && t.line != line && super::is_name(body_name) {
                Some(format!(
                    "a region starts with its name and NAZ number: if `{body_name}` starts \
                     one, give its NAZ after the name"
                ))
            } else {
                self.hint_among(body_name, self.body_index.keys())
            };
            self.err(
                t.line,
                t.col,
                t.len,
                format!("region `{name}` refers to undefined body `{body_name}`"),
            )
            .hint = hint;
        }
        let zones = match parsed {
            Ok((zones, true)) => zones,
            Ok((_, false)) => Vec::new(),
            Err(error) => {
                let (at_line, at_col, len) = match toks.get(error.at) {
                    Some(t) => (t.line, t.col, t.len),
                    None => {
                        let t = toks.last().expect("not empty");
                        (t.line, t.col + t.len, 0)
                    }
                };
                self.err(
                    at_line,
                    at_col,
                    len,
                    format!("in region `{name}`: {}", error.message),
                );
                return;
            }
        };
        self.add_region(line, col, name, zones);
    }

    /// Add a region read at `line`, `col` (its name there), unless its
    /// name is taken.
    pub(super) fn add_region(&mut self, line: usize, col: usize, name: String, zones: Vec<Zone>) {
        if let Some(&first) = self.region_index.get(&name) {
            let hint = self.where_is(self.region_lines[first]);
            let len = name.chars().count();
            self.err(line, col, len, format!("region `{name}` is defined twice"))
                .hint = Some(format!("the first definition is on {hint}"));
            return;
        }
        self.region_index.insert(name.clone(), self.regions.len());
        self.region_lines.push(line);
        self.regions.push(Region::new(name, zones));
    }
}
