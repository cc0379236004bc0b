//! The geometry between GEOBEGIN and GEOEND: where it is read from (the
//! input or a separate file), its layout (names or numbers), the VOXELS
//! card, the title line, and the sections that follow one another.

use super::card::{self, Card};
use super::{clean, is_name, tokens, Reader};

/// The geometry title line: IVLFLG, IDBG and the title.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct TitleLine {
    /// Region volumes follow the regions when 3.
    pub ivlflg: i64,
    /// The fixed-format layout (0, ±10, ±100).
    pub idbg: i64,
    pub title: String,
}

/// The geometry title from the line after GEOBEGIN: two integers (IVLFLG,
/// IDBG), then the title (column 21 on in fixed format).
pub(super) fn geometry_title(text: &str) -> TitleLine {
    let mut rest = text;
    let mut numbers = [0i64; 2];
    for number in &mut numbers {
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
        *number = t[..n].parse().unwrap_or(0);
        rest = &t[n..];
        rest = rest.trim_start_matches([' ', '\t']);
        rest = rest.strip_prefix(',').unwrap_or(rest);
    }
    TitleLine {
        ivlflg: numbers[0],
        idbg: numbers[1],
        title: rest.trim().to_string(),
    }
}

/// What the GEOBEGIN card asks for.
struct Begin {
    /// `Some(true)` for COMBNAME (names), `Some(false)` for COMBINAT or a
    /// blank SDUM (numbers, unless the bodies are plainly written with
    /// names), `None` when the geometry cannot be read.
    named: Option<bool>,
    /// Whether the geometry is in a separate file (WHAT(3) a logical unit
    /// other than 5), and whether an output file is named after it
    /// (WHAT(4) a logical unit other than 11).
    separate: bool,
    output_named: bool,
}

impl Reader {
    /// What GEOBEGIN asks for (an SDUM that names no geometry this reader
    /// knows is reported).
    fn check_geobegin(&mut self, i: usize, c: &Card) -> Begin {
        let unit = |k: usize| c.what[k].as_ref().and_then(|f| card::number(&f.text));
        let separate = unit(2).is_some_and(|v| v > 0.0 && v != 5.0);
        let output_named = unit(3).is_some_and(|v| v > 0.0 && v != 11.0);
        let mut begin = Begin {
            named: None,
            separate,
            output_named,
        };
        // COMBNAME belongs in SDUM; a free-format card that leaves out the
        // blank WHATs puts it in an earlier field, which is accepted too.
        let says = |word: &str| {
            c.sdum
                .iter()
                .chain(c.what.iter().flatten())
                .any(|f| f.text.eq_ignore_ascii_case(word))
        };
        if says("COMBNAME") {
            begin.named = Some(true);
        } else if c.sdum.is_none() || says("COMBINAT") {
            begin.named = Some(false);
        } else if let Some(f) = &c.sdum {
            let (col, len, text) = (f.col, f.len(), f.text.clone());
            let hint = "FLUKA reads COMBNAME (names, free format) or COMBINAT \
                        (numbers, fixed format; the default)";
            let message = format!("GEOBEGIN SDUM `{text}` names no combinatorial geometry");
            self.err(i, col, len, message).hint = Some(hint.into());
        }
        begin
    }

    /// The geometry of the GEOBEGIN card at line `begin`, whose GEOEND is
    /// at line `end`.
    pub(super) fn geometry(&mut self, begin: usize, end: usize, c: &Card, free: bool) {
        let start = self.check_geobegin(begin, c);
        let Some(named) = start.named else {
            return;
        };
        if !start.separate {
            self.geometry_lines(begin + 1, end, named, free);
            return;
        }
        let mut cards = (begin + 1..end).filter(|&k| !clean(&self.lines[k].text).trim().is_empty());
        let Some(name_line) = cards.next() else {
            let what3 = c.what[2].as_ref().map_or((1, 8), |f| (f.col, f.len()));
            self.err(
                begin,
                what3.0,
                what3.1,
                "GEOBEGIN WHAT(3) names a logical unit, but no card names the geometry file",
            )
            .hint = Some("put the geometry file's name on the card after GEOBEGIN".into());
            return;
        };
        let skip = usize::from(start.output_named);
        if let Some(extra) = cards.nth(skip) {
            self.warn(
                extra,
                1,
                self.lines[extra].text.trim_end().chars().count(),
                "ignored: the geometry is read from the file named after GEOBEGIN",
            );
        }
        let text = clean(&self.lines[name_line].text).to_string();
        let name = text.trim();
        let col = text.chars().take_while(|c| c.is_whitespace()).count() + 1;
        let file = self.lines[name_line].file;
        let at = (self.lines[name_line].line, col, name.chars().count());
        let range = self.out.read_file(file, at, name);
        self.take_reading_errors();
        if let Some(range) = range {
            // The reader took the input's lines; the file's are appended.
            let offset = self.lines.len() - range.start;
            self.lines.append(&mut self.out.lines);
            self.geometry_lines(offset + range.start, offset + range.end, named, free);
        }
    }

    /// Move the errors of a file read late into the reader's.
    fn take_reading_errors(&mut self) {
        for d in std::mem::take(&mut self.out.errors) {
            if self.errors.len() >= super::MAX_ERRORS {
                self.suppressed += 1;
            } else {
                self.errors.push(d);
            }
        }
    }

    /// The geometry on lines `start..end`: the VOXELS card, the title line,
    /// bodies, regions, then LATTICE cards (and region volumes).
    fn geometry_lines(&mut self, start: usize, end: usize, named: bool, free: bool) {
        let is_card = |r: &Reader, k: usize| {
            !r.lines[k].text.starts_with('*') && !r.lines[k].text.trim().is_empty()
        };
        let mut first = (start..end).find(|&k| is_card(self, k));
        if let Some(k) = first {
            let text = clean(&self.lines[k].text).to_string();
            let card = card::split(&text, card::is_free(&text, free));
            if card.keyword == "VOXELS" {
                self.voxels_card(k, &card);
                first = (k + 1..end).find(|&j| is_card(self, j));
            }
        }
        let title = first.map_or_else(
            || geometry_title(""),
            |k| geometry_title(&self.lines[k].text),
        );
        self.geo_title = title.title.clone();
        let body_start = first.map_or(end, |k| k + 1);
        let numbered = !named && !self.written_with_names(body_start, end);
        let regions_start = if numbered {
            self.fixed_bodies(body_start, end, title.idbg)
        } else {
            self.bodies_section(body_start, end)
        };
        let Some(regions_start) = regions_start else {
            let at = self.last_line(start, end);
            self.err(at, 1, 6, "missing END after the bodies").hint =
                Some("the body list ends with a line holding END".into());
            return;
        };
        self.place_voxel_cage();
        let after_regions = if numbered {
            self.fixed_regions(regions_start, end, title.idbg)
        } else {
            self.regions_section(regions_start, end)
        };
        let Some(after_regions) = after_regions else {
            let at = self.last_line(start, end);
            self.err(at, 1, 6, "missing END after the regions").hint =
                Some("the region list ends with a line holding END".into());
            return;
        };
        self.add_voxel_regions();
        if self.regions.is_empty() && self.errors.is_empty() {
            let at = self.last_line(start, end);
            self.err(at, 1, 6, "the geometry has no regions");
        }
        self.after_regions(after_regions, end, title.ivlflg, free);
    }

    /// Where a missing part of the geometry is reported: on GEOEND, or on
    /// the last line of a separate geometry file.
    fn last_line(&self, start: usize, end: usize) -> usize {
        if end < self.lines.len() {
            end
        } else {
            end.saturating_sub(1).max(start.min(end.saturating_sub(1)))
        }
    }

    /// Whether a geometry whose GEOBEGIN asks for numbers is in fact
    /// written with names (`RPP box …`): the first body's second word is a
    /// name, never the case in fixed columns.
    fn written_with_names(&self, start: usize, end: usize) -> bool {
        (start..end)
            .map(|k| clean(&self.lines[k].text))
            .map(tokens)
            .find(|w| w.first().is_some_and(|(_, t)| !t.starts_with('$')))
            .and_then(|w| w.get(1).map(|(_, t)| is_name(t)))
            .unwrap_or(false)
    }

    /// LATTICE cards (and, after IVLFLG 3, region volumes) up to GEOEND.
    fn after_regions(&mut self, start: usize, end: usize, ivlflg: i64, free: bool) {
        for i in start..end {
            let text = clean(&self.lines[i].text).to_string();
            if text.trim().is_empty() {
                continue;
            }
            let card = card::split(&text, card::is_free(&text, free));
            if card.keyword == "LATTICE" {
                self.lattice(i, &card);
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometry_title_forms() {
        let t = |s: &str| {
            let l = geometry_title(s);
            (l.ivlflg, l.idbg, l.title)
        };
        assert_eq!(
            t("    0    0          a beam line"),
            (0, 0, "a beam line".into())
        );
        assert_eq!(t("0,0,et inside vacuum"), (0, 0, "et inside vacuum".into()));
        assert_eq!(
            t("\t\t\t A simple Be target"),
            (0, 0, "A simple Be target".into())
        );
        assert_eq!(t("    1    0"), (1, 0, String::new()));
        assert_eq!(t("    0  -10          precise"), (0, -10, "precise".into()));
    }
}
