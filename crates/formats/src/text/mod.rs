//! The text front end shared by the scene language, the director's scripts
//! and FLUKA's free format: one tokenizer, configured per language by a
//! [`Syntax`], and one line [`Cursor`] for the languages read statement by
//! statement.
//!
//! A line becomes [`Token`]s: words (anything up to a blank, a separator,
//! a punctuation character, a comment or a quote), quoted strings and
//! punctuation characters that are tokens of their own. Each token knows its
//! [`Span`]: line, 1-based column and length, both in characters, as the
//! diagnostics show them.

mod cursor;
pub(crate) mod region;

pub(crate) use cursor::Cursor;

use crate::diag::Span;

/// How a language splits its lines.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Syntax {
    /// Characters that are tokens of their own.
    pub punctuation: &'static str,
    /// Characters that only separate words, as blanks do.
    pub separators: &'static str,
    /// The character that starts a comment running to the end of the line.
    pub comment: char,
    /// A line that starts with this is a comment card.
    pub comment_card: Option<CommentCard>,
    /// Whether `"` opens a quoted string.
    pub strings: bool,
}

/// Where a comment card's mark must stand.
#[derive(Clone, Copy, Debug)]
pub(crate) enum CommentCard {
    /// In column 1 (FLUKA's `*`).
    FirstColumn(char),
    /// As the first character that is not blank (a script's `*`).
    FirstNonBlank(char),
}

/// The scene language: `=` is a token, commas and parentheses only group
/// numbers for the eye (`(0, 0, 1)` reads as `0 0 1`), `#` comments.
pub(crate) const SCENE: Syntax = Syntax {
    punctuation: "=",
    separators: ",()",
    comment: '#',
    comment_card: None,
    strings: true,
};

/// The director's scripts: parentheses and commas are tokens, `#` comments
/// and a line starting with `*` is a comment card.
pub(crate) const SCRIPT: Syntax = Syntax {
    punctuation: "(),",
    separators: "",
    comment: '#',
    comment_card: Some(CommentCard::FirstNonBlank('*')),
    strings: true,
};

/// FLUKA free format: words between blanks or the separators of its free
/// geometry format (`,` `;` `:` `%` `\`), `!` comments, `*` in column 1 a
/// comment card.
pub(crate) const FLUKA: Syntax = Syntax {
    punctuation: "",
    separators: ",;:%\\",
    comment: '!',
    comment_card: Some(CommentCard::FirstColumn('*')),
    strings: false,
};

/// FLUKA words between blanks only (region names and their NAZ number).
pub(crate) const FLUKA_BLANKS: Syntax = Syntax {
    separators: "",
    ..FLUKA
};

/// FLUKA region expressions: `+ - | ( )` are tokens of their own.
pub(crate) const FLUKA_REGION: Syntax = Syntax {
    punctuation: "+-|()",
    ..FLUKA
};

/// What a token is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// A word or a number.
    Word,
    /// A quoted string; `closed` is false when the line ends inside it.
    Quoted {
        /// Whether the closing quote is there.
        closed: bool,
    },
    /// A punctuation character of the [`Syntax`].
    Punct(char),
}

/// A token of a line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Token<'a> {
    /// What it is.
    pub kind: Kind,
    /// The word, the string without its quotes, or the punctuation character.
    pub text: &'a str,
    /// Where it is, quotes included.
    pub span: Span,
}

impl Token<'_> {
    /// True when the token is the word `keyword`, ignoring case.
    pub fn is(&self, keyword: &str) -> bool {
        self.kind == Kind::Word && self.text.eq_ignore_ascii_case(keyword)
    }

    /// True when the token is the punctuation character `c`.
    pub fn is_punct(&self, c: char) -> bool {
        self.kind == Kind::Punct(c)
    }

    /// The word, if the token is one.
    pub fn word(&self) -> Option<&str> {
        (self.kind == Kind::Word).then_some(self.text)
    }

    /// The token as written, for messages (strings with their quotes).
    pub fn shown(&self) -> String {
        match self.kind {
            Kind::Quoted { .. } => format!("\"{}\"", self.text),
            _ => self.text.to_string(),
        }
    }

    /// The number the token spells (Rust's decimal syntax), if it is a word
    /// spelling a finite one.
    pub fn number(&self) -> Option<f64> {
        self.word()?.parse::<f64>().ok().filter(|v| v.is_finite())
    }
}

/// True when `text` is a comment card in `syntax`.
fn is_comment_card(text: &str, syntax: &Syntax) -> bool {
    match syntax.comment_card {
        Some(CommentCard::FirstColumn(c)) => text.starts_with(c),
        Some(CommentCard::FirstNonBlank(c)) => text.trim_start().starts_with(c),
        None => false,
    }
}

/// The tokens of one line (`line` is the number given to their spans).
pub(crate) fn tokens<'a>(text: &'a str, line: usize, syntax: &Syntax) -> Vec<Token<'a>> {
    let mut out = Vec::new();
    scan(text, line, syntax, |t| out.push(t));
    out
}

/// The part of a line before its comment (empty for a comment card).
pub(crate) fn code<'a>(text: &'a str, syntax: &Syntax) -> &'a str {
    let mut end = text.len();
    let cut = scan(text, 0, syntax, |_| {});
    if let Some(comment) = cut {
        end = comment;
    }
    &text[..end]
}

/// Split `text` into tokens, handing each to `emit`; the byte offset of the
/// comment that ends the line, if any.
fn scan<'a>(
    text: &'a str,
    line: usize,
    syntax: &Syntax,
    mut emit: impl FnMut(Token<'a>),
) -> Option<usize> {
    if is_comment_card(text, syntax) {
        return Some(0);
    }
    let separates = |c: char| c.is_whitespace() || syntax.separators.contains(c);
    let ends_word = |c: char| {
        separates(c)
            || syntax.punctuation.contains(c)
            || c == syntax.comment
            || (syntax.strings && c == '"')
    };
    let mut chars = text.char_indices().peekable();
    // Column (1-based, in characters) of the character `chars` yields next.
    let mut col = 1;
    while let Some((start, c)) = chars.next() {
        let start_col = col;
        col += 1;
        if c == syntax.comment {
            return Some(start);
        }
        if separates(c) {
            continue;
        }
        let (kind, body) = if syntax.punctuation.contains(c) {
            (Kind::Punct(c), &text[start..start + c.len_utf8()])
        } else if syntax.strings && c == '"' {
            let inner = start + 1;
            let mut closed = false;
            let mut end = text.len();
            for (at, q) in chars.by_ref() {
                col += 1;
                if q == '"' {
                    closed = true;
                    end = at;
                    break;
                }
            }
            (Kind::Quoted { closed }, &text[inner..end])
        } else {
            let mut end = text.len();
            while let Some(&(at, w)) = chars.peek() {
                if ends_word(w) {
                    end = at;
                    break;
                }
                chars.next();
                col += 1;
            }
            (Kind::Word, &text[start..end])
        };
        emit(Token {
            kind,
            text: body,
            span: Span {
                line,
                col: start_col,
                len: col - start_col,
            },
        });
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shown(text: &str, syntax: &Syntax) -> Vec<String> {
        tokens(text, 1, syntax).iter().map(Token::shown).collect()
    }

    #[test]
    fn a_script_line_splits_into_words_and_punctuation() {
        let t = tokens("TURN HELICOPTER (AXIS 1,15)  # comment", 4, &SCRIPT);
        let words: Vec<String> = t.iter().map(Token::shown).collect();
        assert_eq!(
            words,
            ["TURN", "HELICOPTER", "(", "AXIS", "1", ",", "15", ")"]
        );
        assert_eq!((t[2].span.col, t[6].span.col, t[6].span.len), (17, 25, 2));
        assert_eq!(t[0].span.line, 4);
        assert!(tokens("  * a comment card", 1, &SCRIPT).is_empty());
        let open = tokens("SCENE \"a.sv", 1, &SCRIPT);
        assert_eq!(open[1].kind, Kind::Quoted { closed: false });
        assert_eq!((open[1].text, open[1].span.len), ("a.sv", 5));
    }

    #[test]
    fn scene_lines_group_vectors_with_separators() {
        assert_eq!(
            shown("REGION D = +1 -2 # note", &SCENE),
            ["REGION", "D", "=", "+1", "-2"]
        );
        assert_eq!(
            shown("EYE (9,-13, 6.5)", &SCENE),
            ["EYE", "9", "-13", "6.5"]
        );
        let t = tokens("INCLUDE \"a b#.cg\" x", 1, &SCENE);
        assert_eq!((t[1].text, t[1].span.col, t[1].span.len), ("a b#.cg", 9, 9));
        assert_eq!(t[2].span.col, 19);
        // A star is no comment in a scene.
        assert_eq!(shown("* x", &SCENE), ["*", "x"]);
    }

    #[test]
    fn fluka_comments_and_region_punctuation() {
        assert!(tokens("* a comment", 1, &FLUKA).is_empty());
        assert_eq!(shown(" * not one", &FLUKA), ["*", "not", "one"]);
        assert_eq!(shown("RPP a,1 2 ! c", &FLUKA), ["RPP", "a", "1", "2"]);
        assert_eq!(
            shown("SPH b;0:0 % 0\\1", &FLUKA),
            ["SPH", "b", "0", "0", "0", "1"]
        );
        assert_eq!(shown("a,b c", &FLUKA_BLANKS), ["a,b", "c"]);
        assert_eq!(
            shown("+a -(b|c2)", &FLUKA_REGION),
            ["+", "a", "-", "(", "b", "|", "c2", ")"]
        );
        assert_eq!(code("r 5 +a ! -b", &FLUKA), "r 5 +a ");
        assert_eq!(code("*r 5", &FLUKA), "");
        assert_eq!(code("SCENE \"#1\" # x", &SCRIPT), "SCENE \"#1\" ");
    }

    #[test]
    fn columns_count_characters() {
        let t = tokens("é (1, 2)", 1, &SCRIPT);
        assert_eq!(t[1].span.col, 3);
        assert_eq!(t[2].number(), Some(1.0));
        assert_eq!(t[1].number(), None);
        assert!(tokens("inf", 1, &SCENE)[0].number().is_none());
    }
}
