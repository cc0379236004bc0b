//! FLUKA command cards outside the geometry body and region lists: the
//! keyword, six WHATs and the SDUM, in fixed columns (A8, 2X, 6E10, A8) or in
//! free format (fields separated by commas, or by blanks after `FREE`).

use crate::text;

/// One field of a card: its text and where it starts on the line.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Field {
    /// The trimmed text.
    pub text: String,
    /// 1-based column (in characters) of the first character.
    pub col: usize,
}

impl Field {
    /// Length in characters.
    pub fn len(&self) -> usize {
        self.text.chars().count()
    }
}

/// A command card split into its fields.
#[derive(Clone, Debug, Default)]
pub(crate) struct Card {
    /// The keyword (`ROT-DEFI`, `ASSIGNMA`, …), upper-cased.
    pub keyword: String,
    /// WHAT(1) … WHAT(6); `None` when blank.
    pub what: [Option<Field>; 6],
    /// SDUM; `None` when blank.
    pub sdum: Option<Field>,
}

/// Whether a card written this way is in free format: it is when free format
/// was requested or when it uses commas, which fixed-format cards never do.
pub(crate) fn is_free(text: &str, free_mode: bool) -> bool {
    free_mode || text.contains(',')
}

/// Split a card. `free` selects free format (see [`is_free`]).
pub(crate) fn split(text: &str, free: bool) -> Card {
    let fields: Vec<Option<Field>> = if free {
        free_fields(text)
    } else {
        fixed_fields(text)
    };
    let mut card = Card::default();
    let mut it = fields.into_iter();
    card.keyword = it
        .next()
        .flatten()
        .map(|f| f.text.to_ascii_uppercase())
        .unwrap_or_default();
    for w in card.what.iter_mut() {
        *w = it.next().flatten();
    }
    card.sdum = it.next().flatten();
    card
}

fn field(chars: &[char], start: usize, end: usize) -> Option<Field> {
    let end = end.min(chars.len());
    if start >= end {
        return None;
    }
    let slice = &chars[start..end];
    let lead = slice.iter().take_while(|c| c.is_whitespace()).count();
    let text: String = slice.iter().collect::<String>().trim().to_string();
    (!text.is_empty()).then(|| Field {
        text,
        col: start + lead + 1,
    })
}

/// Fixed columns: keyword 1–10, WHAT(i) 11+10(i−1) … 20+10(i−1), SDUM 71–80.
fn fixed_fields(text: &str) -> Vec<Option<Field>> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = vec![field(&chars, 0, 10)];
    for i in 0..6 {
        out.push(field(&chars, 10 + 10 * i, 20 + 10 * i));
    }
    out.push(field(&chars, 70, 80));
    out
}

/// Free format: commas separate fields when present (two commas in a row
/// leave a blank field), otherwise runs of blanks do.
fn free_fields(text: &str) -> Vec<Option<Field>> {
    let mut out = Vec::new();
    if text.contains(',') {
        let mut col = 1;
        for part in text.split(',') {
            let lead = part.chars().take_while(|c| c.is_whitespace()).count();
            let t = part.trim();
            out.push((!t.is_empty()).then(|| Field {
                text: t.to_string(),
                col: col + lead,
            }));
            col += part.chars().count() + 1;
        }
    } else {
        for (col, word) in words(text) {
            out.push(Some(Field {
                text: word.to_string(),
                col,
            }));
        }
    }
    out
}

/// The blank-separated words of a line with their 1-based character columns.
pub(crate) fn words(line: &str) -> Vec<(usize, &str)> {
    text::tokens(line, 0, &text::FLUKA_BLANKS)
        .into_iter()
        .map(|t| (t.span.col, t.text))
        .collect()
}

/// Parse a FLUKA number: optional sign, digits with an optional decimal
/// point, and an optional exponent introduced by `E` or `D` (Fortran). Words
/// such as `inf` or `NaN` are refused.
pub(crate) fn number(s: &str) -> Option<f64> {
    let bytes = s.as_bytes();
    let mut i = 0;
    if i < bytes.len() && (bytes[i] == b'+' || bytes[i] == b'-') {
        i += 1;
    }
    let mut digits = 0;
    while i < bytes.len() && bytes[i].is_ascii_digit() {
        i += 1;
        digits += 1;
    }
    if i < bytes.len() && bytes[i] == b'.' {
        i += 1;
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
            digits += 1;
        }
    }
    if digits == 0 {
        return None;
    }
    let mantissa_end = i;
    let mut exponent = String::new();
    if i < bytes.len() && matches!(bytes[i], b'e' | b'E' | b'd' | b'D') {
        i += 1;
        let start = i;
        if i < bytes.len() && (bytes[i] == b'+' || bytes[i] == b'-') {
            i += 1;
        }
        let d0 = i;
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
        }
        if i == d0 {
            return None;
        }
        exponent = format!("e{}", &s[start..i]);
    }
    if i != bytes.len() {
        return None;
    }
    let mut m = s[..mantissa_end].to_string();
    if m.ends_with('.') {
        m.push('0');
    }
    if m.starts_with('.') || m.starts_with("+.") || m.starts_with("-.") {
        m = m.replacen('.', "0.", 1);
    }
    let v: f64 = format!("{m}{exponent}").parse().ok()?;
    v.is_finite().then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_fortran_spellings() {
        assert_eq!(number("50."), Some(50.0));
        assert_eq!(number("-.235482"), Some(-0.235482));
        assert_eq!(number("50.E+00"), Some(50.0));
        assert_eq!(number("1.0D3"), Some(1000.0));
        assert_eq!(number("+5"), Some(5.0));
        assert_eq!(number("1e400"), None);
        assert_eq!(number("inf"), None);
        assert_eq!(number("NaN"), None);
        assert_eq!(number("."), None);
        assert_eq!(number("12.7O"), None);
        assert_eq!(number("1e"), None);
    }

    #[test]
    fn fixed_and_free_cards() {
        let c = split(
            "ROT-DEFI        100.                -45.                              Rotdefi1",
            false,
        );
        assert_eq!(c.keyword, "ROT-DEFI");
        assert_eq!(c.what[0].as_ref().unwrap().text, "100.");
        assert!(c.what[1].is_none());
        assert_eq!(c.what[2].as_ref().unwrap().text, "-45.");
        assert_eq!(c.sdum.as_ref().unwrap().text, "Rotdefi1");
        assert_eq!(c.sdum.as_ref().unwrap().col, 71);
        let f = split("ROT-DEFI  , 1., 45., 45., 10., 0.0, 0.0, rotx", true);
        assert_eq!(f.what[3].as_ref().unwrap().text, "10.");
        assert_eq!(f.sdum.as_ref().unwrap().text, "rotx");
        assert_eq!(f.what[0].as_ref().unwrap().col, 13);
        let g = split("ASSIGNMA  , , cube1", true);
        assert!(g.what[0].is_none());
        assert_eq!(g.what[1].as_ref().unwrap().text, "cube1");
    }
}
