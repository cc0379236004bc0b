//! A cursor over one line's tokens, with the readers of values every
//! statement needs and the errors they give.

use super::{code, tokens, Kind, Syntax, Token};
use crate::diag::{Diagnostic, SourceFile, Span};
use sv_math::DVec3;

/// One line of a file being read, token by token.
pub(crate) struct Cursor<'a> {
    src: &'a SourceFile,
    tokens: Vec<Token<'a>>,
    pos: usize,
    /// Where the line's code ends (before a comment and trailing blanks).
    end: Span,
}

impl<'a> Cursor<'a> {
    /// The tokens of line `line` (1-based) of `src`, whose text is `text`.
    pub fn new(src: &'a SourceFile, line: usize, text: &'a str, syntax: &Syntax) -> Cursor<'a> {
        let end_col = code(text, syntax).trim_end().chars().count() + 1;
        Cursor {
            src,
            tokens: tokens(text, line, syntax),
            pos: 0,
            end: Span {
                line,
                col: end_col,
                len: 0,
            },
        }
    }

    /// The line's tokens, all of them.
    pub fn tokens(&self) -> &[Token<'a>] {
        &self.tokens
    }

    /// The line's text from the start of `from` to the start of `until`
    /// (to the end of the line's code when `None`): what the tokens
    /// between them were read from, separators and all.
    pub fn text_between(&self, from: Span, until: Option<Span>) -> &'a str {
        let until = until.unwrap_or(self.end);
        let start = self.src.offset(from.line, from.col);
        let stop = self.src.offset(until.line, until.col).max(start);
        &self.src.text[start..stop]
    }

    /// The tokens not yet taken.
    pub fn rest(&self) -> &[Token<'a>] {
        &self.tokens[self.pos..]
    }

    /// True when the line holds no token.
    pub fn is_blank(&self) -> bool {
        self.tokens.is_empty()
    }

    /// The next token, not taken.
    pub fn peek(&self) -> Option<Token<'a>> {
        self.tokens.get(self.pos).copied()
    }

    /// The token after the next one, not taken.
    pub fn peek_second(&self) -> Option<Token<'a>> {
        self.tokens.get(self.pos + 1).copied()
    }

    /// Take the next token.
    pub fn advance(&mut self) -> Option<Token<'a>> {
        let t = self.peek();
        if t.is_some() {
            self.pos += 1;
        }
        t
    }

    /// Take every token left.
    pub fn skip_rest(&mut self) {
        self.pos = self.tokens.len();
    }

    /// An error at `span`.
    pub fn error_at(&self, span: Span, msg: impl Into<String>) -> Diagnostic {
        Diagnostic::error_in(self.src, span, msg)
    }

    /// An error at a token.
    pub fn error(&self, t: &Token, msg: impl Into<String>) -> Diagnostic {
        self.error_at(t.span, msg)
    }

    /// Where the line's code ends: errors about something missing point
    /// there.
    pub fn end(&self) -> Span {
        self.end
    }

    /// `expected {what}, found `…``, at `t`.
    pub fn expected(&self, t: &Token, what: &str) -> Diagnostic {
        self.error(t, format!("expected {what}, found `{}`", t.shown()))
    }

    /// `expected {what}, found the end of the line`, at the end.
    pub fn missing(&self, what: &str) -> Diagnostic {
        self.error_at(
            self.end,
            format!("expected {what}, found the end of the line"),
        )
    }

    /// Take the next token, whatever it is; `what` names what was expected
    /// when the line has ended.
    pub fn any(&mut self, what: &str) -> Result<Token<'a>, Diagnostic> {
        self.advance().ok_or_else(|| self.missing(what))
    }

    /// Take the next token when it is a word.
    pub fn word(&mut self, what: &str) -> Result<Token<'a>, Diagnostic> {
        let t = self.any(what)?;
        match t.kind {
            Kind::Word => Ok(t),
            _ => Err(self.expected(&t, what)),
        }
    }

    /// Take the next token when `wanted` says it is the one.
    fn eat_if(&mut self, wanted: impl Fn(&Token) -> bool) -> bool {
        let found = self.peek().is_some_and(|t| wanted(&t));
        if found {
            self.pos += 1;
        }
        found
    }

    /// Take the next token when it is the keyword `keyword` (any case).
    pub fn eat(&mut self, keyword: &str) -> bool {
        self.eat_if(|t| t.is(keyword))
    }

    /// Take the next token when it is the punctuation character `c`.
    pub fn eat_punct(&mut self, c: char) -> bool {
        self.eat_if(|t| t.is_punct(c))
    }

    /// The next token must be `what` (as `wanted` tells).
    fn expect_if(
        &mut self,
        what: &str,
        wanted: impl Fn(&Token) -> bool,
    ) -> Result<Token<'a>, Diagnostic> {
        let t = self.any(what)?;
        if wanted(&t) {
            Ok(t)
        } else {
            Err(self.expected(&t, what))
        }
    }

    /// The keyword `keyword` (any case) must come next.
    pub fn expect(&mut self, keyword: &str) -> Result<Token<'a>, Diagnostic> {
        self.expect_if(&format!("`{keyword}`"), |t| t.is(keyword))
    }

    /// The punctuation character `c` must come next.
    pub fn expect_punct(&mut self, c: char) -> Result<Token<'a>, Diagnostic> {
        self.expect_if(&format!("`{c}`"), |t| t.is_punct(c))
    }

    /// A number; `purpose` says what it is for in the messages
    /// (`expected a number for the eye point, found …`).
    pub fn number(&mut self, purpose: Option<&str>) -> Result<f64, Diagnostic> {
        self.number_token(purpose).map(|(v, _)| v)
    }

    /// A number and its token.
    pub fn number_token(&mut self, purpose: Option<&str>) -> Result<(f64, Token<'a>), Diagnostic> {
        let what = || match purpose {
            Some(p) => format!("a number for {p}"),
            None => "a number".to_string(),
        };
        let t = self.advance().ok_or_else(|| self.missing(&what()))?;
        match t.number() {
            Some(v) => Ok((v, t)),
            None => Err(self.expected(&t, &what())),
        }
    }

    /// Three numbers: `(x, y, z)`, `x, y, z` or `x y z` (commas and the
    /// parentheses are optional; a `(` needs its `)`).
    pub fn vector(&mut self, purpose: Option<&str>) -> Result<DVec3, Diagnostic> {
        let open = self.eat_punct('(');
        let x = self.number(purpose)?;
        self.eat_punct(',');
        let y = self.number(purpose)?;
        self.eat_punct(',');
        let z = self.number(purpose)?;
        if open {
            self.expect_punct(')')?;
        }
        Ok(DVec3::new(x, y, z))
    }

    /// The statement must end here.
    pub fn finish(&self) -> Result<(), Diagnostic> {
        match self.peek() {
            Some(t) => Err(self.error(
                &t,
                format!("unexpected `{}` at the end of the statement", t.shown()),
            )),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::text::{SCENE, SCRIPT};

    #[test]
    fn vectors_with_and_without_parentheses() {
        let src = SourceFile::new("t", "");
        for text in ["(1, 2, 3)", "(1 2 3)", "1,2,3", "1 2 3"] {
            let mut c = Cursor::new(&src, 1, text, &SCRIPT);
            assert_eq!(c.vector(None).unwrap(), DVec3::new(1.0, 2.0, 3.0), "{text}");
            assert!(c.finish().is_ok());
        }
        let mut c = Cursor::new(&src, 1, "(1, 2, 3 # no close", &SCRIPT);
        assert_eq!(
            c.vector(None).unwrap_err().message,
            "expected `)`, found the end of the line"
        );
        assert_eq!(c.end().col, 9);
        let mut c = Cursor::new(&src, 1, "(1, x, 3)", &SCENE);
        assert_eq!(
            c.vector(Some("the eye point")).unwrap_err().message,
            "expected a number for the eye point, found `x`"
        );
    }

    #[test]
    fn keywords_ignore_case() {
        let src = SourceFile::new("t", "");
        let mut c = Cursor::new(&src, 1, "over 3 Frames extra", &SCRIPT);
        assert!(c.eat("OVER"));
        assert_eq!(c.number(None).unwrap(), 3.0);
        assert!(c.expect("FRAMES").is_ok());
        assert_eq!(
            c.finish().unwrap_err().message,
            "unexpected `extra` at the end of the statement"
        );
    }
}
