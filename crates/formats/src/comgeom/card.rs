//! Cards (lines) and fixed-column fields.
//!
//! Columns are 1-based and count characters, as on a punched card. A field
//! that lies beyond the end of a short line is blank.

/// One line of the deck.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Card<'a> {
    /// 1-based line number.
    pub line: usize,
    /// The text without the line ending.
    pub text: &'a str,
}

impl<'a> Card<'a> {
    /// The characters in columns `col ..= col + len - 1` (fewer when the line
    /// is shorter).
    pub fn field(&self, col: usize, len: usize) -> &'a str {
        let start = byte_at(self.text, col.saturating_sub(1));
        let end = byte_at(self.text, col.saturating_sub(1).saturating_add(len));
        &self.text[start..end.max(start)]
    }

    /// Everything from column `col` to the end of the line.
    pub fn rest(&self, col: usize) -> &'a str {
        &self.text[byte_at(self.text, col.saturating_sub(1))..]
    }

    /// True when the card holds only spaces.
    pub fn is_blank(&self) -> bool {
        self.text.trim().is_empty()
    }
}

/// Byte offset of the character with 0-based index `chars`, or the length.
fn byte_at(s: &str, chars: usize) -> usize {
    s.char_indices().nth(chars).map_or(s.len(), |(i, _)| i)
}

/// Split text into cards; a trailing `\r` is dropped from each line.
pub(crate) fn cards(text: &str) -> Vec<Card<'_>> {
    text.split('\n')
        .enumerate()
        .map(|(i, l)| Card {
            line: i + 1,
            text: l.strip_suffix('\r').unwrap_or(l),
        })
        .collect()
}

/// Read a number the way C `atof` reads a well-formed field: optional sign,
/// digits with an optional decimal point (`3.`, `.5`, `.` alone is 0) and an
/// optional `E` exponent. Surrounding blanks are ignored and a blank field is
/// 0. Anything else (`12.7O`, `1D3`, `inf`, embedded blanks) is `None`: unlike
/// `atof`, trailing junk is not silently dropped.
pub(crate) fn parse_real(field: &str) -> Option<f64> {
    let s = field.trim();
    if s.is_empty() {
        return Some(0.0);
    }
    let bytes = s.as_bytes();
    let mut i = 0;
    if matches!(bytes.first(), Some(b'+' | b'-')) {
        i += 1;
    }
    let int_start = i;
    while i < bytes.len() && bytes[i].is_ascii_digit() {
        i += 1;
    }
    let mut digits = i - int_start;
    let mut point = false;
    if i < bytes.len() && bytes[i] == b'.' {
        point = true;
        i += 1;
        let frac_start = i;
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
        }
        digits += i - frac_start;
    }
    if digits == 0 {
        // `.`, `-.` and `+.` are zero on the old decks; a lone sign is not.
        return if point && i == bytes.len() {
            Some(0.0)
        } else {
            None
        };
    }
    if i < bytes.len() && matches!(bytes[i], b'e' | b'E') {
        i += 1;
        if i < bytes.len() && matches!(bytes[i], b'+' | b'-') {
            i += 1;
        }
        let exp_start = i;
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
        }
        if i == exp_start {
            return None;
        }
    }
    if i != bytes.len() {
        return None;
    }
    s.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// Read an integer field: optional sign and digits, blanks around it
/// ignored, blank is 0.
pub(crate) fn parse_int(field: &str) -> Option<i64> {
    let s = field.trim();
    if s.is_empty() {
        return Some(0);
    }
    let digits = s.strip_prefix(['+', '-']).unwrap_or(s);
    if digits.is_empty() || !digits.bytes().all(|c| c.is_ascii_digit()) {
        return None;
    }
    s.parse::<i64>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reals_read_like_atof_on_clean_fields() {
        assert_eq!(parse_real("   21.5   "), Some(21.5));
        assert_eq!(parse_real("    0.    "), Some(0.0));
        assert_eq!(parse_real("     .0000"), Some(0.0));
        assert_eq!(parse_real("    -.5000"), Some(-0.5));
        assert_eq!(parse_real("."), Some(0.0));
        assert_eq!(parse_real(""), Some(0.0));
        assert_eq!(parse_real("1.5E-3"), Some(1.5e-3));
        assert_eq!(parse_real("+2e2"), Some(200.0));
        assert_eq!(parse_real("12.7O"), None);
        assert_eq!(parse_real("1D3"), None);
        assert_eq!(parse_real("1 0"), None);
        assert_eq!(parse_real("-"), None);
        assert_eq!(parse_real("1e"), None);
        assert_eq!(parse_real("inf"), None);
        assert_eq!(parse_real("1e999"), None);
    }

    #[test]
    fn fields_are_character_columns_and_short_lines_are_blank() {
        let c = Card {
            line: 1,
            text: "ab\u{e9}def",
        };
        assert_eq!(c.field(3, 2), "\u{e9}d");
        assert_eq!(c.field(6, 10), "f");
        assert_eq!(c.field(20, 10), "");
        assert_eq!(c.rest(4), "def");
        assert_eq!(parse_int(" -12 "), Some(-12));
        assert_eq!(parse_int("1-2"), None);
    }
}
