//! The region list of a FLUKA geometry and its LATTICE cards.

use super::card::{self, Card};
use super::region::{self, Spanned, Tok};
use super::{clean, is_integer, is_name, Reader, MAX_ZONES};
use sv_geom::Region;

impl Reader {
    /// Read regions from line `start`; the index after END, or `None`.
    pub(super) fn regions_section(&mut self, start: usize, end: usize) -> Option<usize> {
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
                Tok::Name(body_name) => {
                    let body = index.get(body_name).copied();
                    if body.is_none() && !bad.contains(body_name) {
                        missing.push(t.clone());
                    }
                    body
                }
                _ => None,
            })
            .parse()
        };
        let mut ok = true;
        for t in &missing {
            let Tok::Name(body_name) = &t.tok else {
                continue;
            };
            let hint = self.hint_among(body_name, self.body_index.keys());
            self.err(
                t.line,
                t.col,
                t.len,
                format!("region `{name}` refers to undefined body `{body_name}`"),
            )
            .hint = hint;
            ok = false;
        }
        let parsed = match parsed {
            Ok(p) => p,
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
                Ok(zones) => zones,
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
        self.regions.push(Region::new(name, zones));
    }

    pub(super) fn lattice(&mut self, i: usize, c: &Card) {
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
}
