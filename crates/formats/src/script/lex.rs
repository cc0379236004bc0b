//! Splitting a script line into tokens.

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    /// A word or number: anything up to a blank or one of `(),"#`.
    Word(String),
    /// A quoted string (quotes removed).
    Str(String),
    /// `(`.
    Open,
    /// `)`.
    Close,
    /// `,`.
    Comma,
}

/// A token and where it is (1-based line, 1-based column in characters,
/// length in characters).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Token {
    pub tok: Tok,
    pub line: usize,
    pub col: usize,
    pub len: usize,
}

impl Token {
    /// The token as the user wrote it, for messages.
    pub fn shown(&self) -> String {
        match &self.tok {
            Tok::Word(w) => w.clone(),
            Tok::Str(s) => format!("\"{s}\""),
            Tok::Open => "(".into(),
            Tok::Close => ")".into(),
            Tok::Comma => ",".into(),
        }
    }

    /// The word, if the token is one.
    pub fn word(&self) -> Option<&str> {
        match &self.tok {
            Tok::Word(w) => Some(w),
            _ => None,
        }
    }

    /// True when the token is the keyword `kw` (any case).
    pub fn is(&self, kw: &str) -> bool {
        self.word().is_some_and(|w| w.eq_ignore_ascii_case(kw))
    }
}

/// An unterminated string: its column and length in characters.
pub(crate) struct Unterminated {
    pub col: usize,
    pub len: usize,
}

/// Tokens of one line. A line whose first non-blank character is `*` is a
/// comment, and `#` starts a comment anywhere outside a string.
pub(crate) fn tokens(line_no: usize, line: &str) -> Result<Vec<Token>, Unterminated> {
    let chars: Vec<char> = line.chars().collect();
    let mut out = Vec::new();
    if chars.iter().find(|c| !c.is_whitespace()) == Some(&'*') {
        return Ok(out);
    }
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        let tok = match c {
            '#' => break,
            c if c.is_whitespace() => {
                i += 1;
                continue;
            }
            '(' => {
                i += 1;
                Tok::Open
            }
            ')' => {
                i += 1;
                Tok::Close
            }
            ',' => {
                i += 1;
                Tok::Comma
            }
            '"' => {
                let Some(end) = chars[i + 1..].iter().position(|&c| c == '"') else {
                    return Err(Unterminated {
                        col: i + 1,
                        len: chars.len() - i,
                    });
                };
                let s: String = chars[i + 1..i + 1 + end].iter().collect();
                i += end + 2;
                Tok::Str(s)
            }
            _ => {
                while i < chars.len()
                    && !chars[i].is_whitespace()
                    && !matches!(chars[i], '(' | ')' | ',' | '"' | '#')
                {
                    i += 1;
                }
                Tok::Word(chars[start..i].iter().collect())
            }
        };
        out.push(Token {
            tok,
            line: line_no,
            col: start + 1,
            len: i - start,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_command_splits_into_words_and_punctuation() {
        let t = tokens(1, "TURN HELICOPTER (AXIS 1,15)  # comment").unwrap_or_default();
        let shown: Vec<String> = t.iter().map(Token::shown).collect();
        assert_eq!(
            shown,
            ["TURN", "HELICOPTER", "(", "AXIS", "1", ",", "15", ")"]
        );
        assert_eq!((t[2].col, t[6].col, t[6].len), (17, 25, 2));
        assert!(tokens(2, "  * a comment card")
            .unwrap_or_default()
            .is_empty());
        assert!(tokens(3, "SCENE \"a.sv").is_err());
    }
}
