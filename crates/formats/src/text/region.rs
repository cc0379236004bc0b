//! Region expressions with parentheses, parsed into zones and groups as
//! written: FLUKA's, and the scene language's when they nest.
//!
//! Grammar (juxtaposition intersects, `|` unites, parentheses nest):
//!
//! ```text
//! union  := ['|'] inter ('|' inter)*
//! inter  := factor+
//! factor := ('+' | '-') (NAME | '(' union ')') | '(' union ')' | NAME
//! ```
//!
//! A bare `NAME` counts as `+NAME`. The result keeps the expression's
//! shape: a `+( … )` or `-( … )` becomes a [`Group`] of its zones, so the
//! cost is linear in the length of the expression however the groups nest
//! (no expansion into sums of products). Only groups that change nothing
//! are opened: `+( one zone )` joins its zone, and `-( one body )` is the
//! body's own term.

use sv_geom::{Group, Op, Term, Zone};

/// Deepest parenthesis nesting accepted.
pub const MAX_DEPTH: usize = 64;

/// A token of a region expression.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    Plus,
    Minus,
    Bar,
    Open,
    Close,
    Name(String),
}

/// A token and where it is: index into the preprocessed lines, 1-based
/// column and length in characters.
#[derive(Clone, Debug)]
pub(crate) struct Spanned {
    pub tok: Tok,
    pub line: usize,
    pub col: usize,
    pub len: usize,
}

/// Split one line of a region expression into tokens.
pub(crate) fn tokenize(line_text: &str, line: usize, out: &mut Vec<Spanned>) {
    for t in super::tokens(line_text, line, &super::FLUKA_REGION) {
        let tok = match t.kind {
            super::Kind::Punct('+') => Tok::Plus,
            super::Kind::Punct('-') => Tok::Minus,
            super::Kind::Punct('|') => Tok::Bar,
            super::Kind::Punct('(') => Tok::Open,
            super::Kind::Punct(')') => Tok::Close,
            _ => Tok::Name(t.text.to_string()),
        };
        out.push(Spanned {
            tok,
            line,
            col: t.span.col,
            len: t.span.len,
        });
    }
}

/// What a body name in an expression stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Lookup {
    /// The body of this index.
    Body(usize),
    /// A body known to be empty (a voxel cage whose file is missing):
    /// `+` it empties its zone, `-` it takes nothing away.
    Empty,
    /// No such body (already reported by the lookup).
    Unknown,
}

/// A parse problem at a token (index into the token list) or at the end.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ParseError {
    /// Token index (`tokens.len()` for the end of the expression).
    pub at: usize,
    pub message: String,
}

/// Parser over one region's tokens. `lookup` resolves a body name and
/// reports unknown ones itself.
pub(crate) struct Parser<'a, F: FnMut(&Spanned) -> Lookup> {
    toks: &'a [Spanned],
    pos: usize,
    lookup: F,
    /// Whether some name was unknown (the zones are then incomplete).
    unknown: bool,
}

/// A zone being built, and whether it is already known to be empty.
struct ZoneBuild {
    zone: Zone,
    empty: bool,
}

impl ZoneBuild {
    fn term(&mut self, outside: bool, found: Lookup) {
        match (found, outside) {
            (Lookup::Body(body), _) => self.zone.terms.push(Term {
                op: if outside { Op::Outside } else { Op::Inside },
                body,
            }),
            (Lookup::Empty, false) => self.empty = true,
            (Lookup::Empty, true) | (Lookup::Unknown, _) => {}
        }
    }

    /// Intersect with (`outside` false) or subtract the union `zones`.
    fn group(&mut self, outside: bool, mut zones: Vec<Zone>) {
        if zones.is_empty() {
            // The group is empty: intersecting empties the zone,
            // subtracting takes nothing away.
            self.empty |= !outside;
            return;
        }
        if zones.len() == 1 {
            let only = zones.pop().expect("one zone");
            if !outside {
                self.zone.terms.extend(only.terms);
                self.zone.groups.extend(only.groups);
                return;
            }
            if only.is_empty() {
                // All space taken away.
                self.empty = true;
                return;
            }
            if only.groups.is_empty() && only.terms.len() == 1 {
                let t = only.terms[0];
                let op = match t.op {
                    Op::Inside => Op::Outside,
                    Op::Outside => Op::Inside,
                };
                self.zone.terms.push(Term { op, body: t.body });
                return;
            }
            zones.push(only);
        }
        self.zone.groups.push(Group {
            op: if outside { Op::Outside } else { Op::Inside },
            zones,
        });
    }
}

impl<'a, F: FnMut(&Spanned) -> Lookup> Parser<'a, F> {
    /// A parser over `toks`.
    pub fn new(toks: &'a [Spanned], lookup: F) -> Self {
        Parser {
            toks,
            pos: 0,
            lookup,
            unknown: false,
        }
    }

    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos).map(|t| &t.tok)
    }

    fn fail<T>(&self, message: impl Into<String>) -> Result<T, ParseError> {
        Err(ParseError {
            at: self.pos,
            message: message.into(),
        })
    }

    /// Parse the whole expression: its zones, and whether every body name
    /// was found.
    pub fn parse(mut self) -> Result<(Vec<Zone>, bool), ParseError> {
        let zones = self.union(0)?;
        match self.peek() {
            None => Ok((zones, !self.unknown)),
            Some(Tok::Close) => self.fail("unexpected `)` with no `(` open"),
            Some(_) => self.fail("unexpected token in region expression"),
        }
    }

    fn union(&mut self, depth: usize) -> Result<Vec<Zone>, ParseError> {
        let mut zones = Vec::new();
        if self.peek() == Some(&Tok::Bar) {
            self.pos += 1;
        }
        loop {
            if let Some(zone) = self.inter(depth)? {
                zones.push(zone);
            }
            if self.peek() == Some(&Tok::Bar) {
                self.pos += 1;
            } else {
                return Ok(zones);
            }
        }
    }

    /// One zone; `None` when it is known to be empty.
    fn inter(&mut self, depth: usize) -> Result<Option<Zone>, ParseError> {
        let mut build = ZoneBuild {
            zone: Zone::default(),
            empty: false,
        };
        let mut factors = 0;
        while let Some(t) = self.peek() {
            match t {
                Tok::Bar | Tok::Close => break,
                _ => {
                    self.factor(depth, &mut build)?;
                    factors += 1;
                }
            }
        }
        if factors == 0 {
            return match self.peek() {
                None => self.fail("expected a body after this point, found the end of the region"),
                Some(Tok::Bar) => self.fail("empty zone: expected `+body` or `-body` before `|`"),
                _ if depth == 0 => self.fail("unexpected `)` with no `(` open"),
                _ => self.fail("empty parentheses: expected `+body` or `-body` before `)`"),
            };
        }
        Ok((!build.empty).then_some(build.zone))
    }

    fn factor(&mut self, depth: usize, build: &mut ZoneBuild) -> Result<(), ParseError> {
        let outside = match self.peek() {
            Some(Tok::Plus) => {
                self.pos += 1;
                false
            }
            Some(Tok::Minus) => {
                self.pos += 1;
                true
            }
            _ => false,
        };
        match self.peek() {
            Some(Tok::Name(_)) => {
                let found = (self.lookup)(&self.toks[self.pos]);
                self.unknown |= found == Lookup::Unknown;
                self.pos += 1;
                build.term(outside, found);
                Ok(())
            }
            Some(Tok::Open) => {
                if depth >= MAX_DEPTH {
                    return self.fail(format!(
                        "parentheses nested more than {MAX_DEPTH} levels deep"
                    ));
                }
                let open = self.pos;
                self.pos += 1;
                let inner = self.union(depth + 1)?;
                if self.peek() != Some(&Tok::Close) {
                    return Err(ParseError {
                        at: open,
                        message: "`(` is never closed".into(),
                    });
                }
                self.pos += 1;
                build.group(outside, inner);
                Ok(())
            }
            None => self.fail("expected a body name, found the end of the region"),
            Some(_) => self.fail("expected a body name or `(`"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NAMES: [&str; 5] = ["a", "b", "c", "d", "cage"];

    fn parse(expr: &str) -> Result<(Vec<Zone>, bool), String> {
        let mut toks = Vec::new();
        tokenize(expr, 0, &mut toks);
        Parser::new(&toks, |t| match &t.tok {
            Tok::Name(n) if n == "cage" => Lookup::Empty,
            Tok::Name(n) => NAMES
                .iter()
                .position(|x| x == n)
                .map_or(Lookup::Unknown, Lookup::Body),
            _ => Lookup::Unknown,
        })
        .parse()
        .map_err(|e| e.message)
    }

    fn shown(expr: &str) -> String {
        let (zones, _) = parse(expr).unwrap();
        let name = |b: usize| NAMES[b];
        zones
            .iter()
            .map(|z| z.expression(&name))
            .collect::<Vec<_>>()
            .join(" | ")
    }

    #[test]
    fn groups_are_kept_as_written() {
        assert_eq!(shown("+a -b"), "+a -b");
        assert_eq!(shown("| +a | +b"), "+a | +b");
        assert_eq!(shown("+a -(+b -c)"), "+a -(+b -c)");
        assert_eq!(shown("+a +(+b | +c) -d"), "+a -d +(+b | +c)");
        assert_eq!(shown("-(+a | +b)"), "-(+a | +b)");
        assert_eq!(shown("a b"), "+a +b");
        assert_eq!(shown("(a + b - c) - (d)"), "+a +b -c -d");
        assert_eq!(shown("-(-a)"), "+a");
        assert_eq!(shown("+a -((+b | +c) -d)"), "+a -(-d +(+b | +c))");
    }

    #[test]
    fn an_empty_body_empties_zones_or_takes_nothing_away() {
        assert_eq!(shown("+a -cage"), "+a");
        assert_eq!(shown("+cage | +b"), "+b");
        assert_eq!(shown("+a -(+cage | +cage -b)"), "+a");
        assert_eq!(shown("+a +(+cage)"), "");
        assert!(parse("+a -z").map(|(_, complete)| complete) == Ok(false));
    }

    #[test]
    fn syntax_errors() {
        assert_eq!(parse("+a -(+b").unwrap_err(), "`(` is never closed");
        assert_eq!(
            parse("+a )").unwrap_err(),
            "unexpected `)` with no `(` open"
        );
        assert_eq!(
            parse("+a | | +b").unwrap_err(),
            "empty zone: expected `+body` or `-body` before `|`"
        );
        assert_eq!(
            parse("+a +").unwrap_err(),
            "expected a body name, found the end of the region"
        );
        assert_eq!(
            parse("+a -()").unwrap_err(),
            "empty parentheses: expected `+body` or `-body` before `)`"
        );
        let deep = format!("{}+a{}", "+(".repeat(100), ")".repeat(100));
        assert!(parse(&deep).unwrap_err().contains("nested more than 64"));
    }

    #[test]
    fn a_union_of_many_groups_stays_the_size_of_its_text() {
        // +a -( +(+b -c) | +(+b -c) | … ) with 5 000 groups: as written,
        // one group of 5 000 zones (sums of products would need 2^5000).
        let expr = format!("+a -( {} )", vec!["+(+b -c)"; 5000].join(" | "));
        let (zones, complete) = parse(&expr).unwrap();
        assert!(complete);
        assert_eq!(zones.len(), 1);
        assert_eq!(zones[0].groups.len(), 1);
        assert_eq!(zones[0].groups[0].zones.len(), 5000);
    }
}
