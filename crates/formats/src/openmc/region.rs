//! Cell region expressions, lowered as written to zones and groups.
//!
//! OpenMC's grammar: a half-space is a surface id with `-` (its negative
//! side) or `+`/nothing (its positive side); intersection is juxtaposition,
//! union `|`, complement `~` of a half-space or a parenthesised expression;
//! complement binds tightest, then intersection, then union. Tokens need no
//! blanks between them (`5-3` is `5 -3`), as OpenMC's tokenizer reads them.
//!
//! A body's inside is its surface's negative side, so `-5` is the term
//! `+5` of a zone and `5` the term `-5`. A parenthesised union becomes a
//! group (its single zone is merged into the enclosing zone when it has only
//! one), `~( … )` a `-` group: the tree keeps the expression's size.

use super::xml::{Sink, Value, Xml};
use std::collections::HashMap;
use sv_geom::{Group, Op, Term, Zone};

/// The deepest nesting of parentheses and complements read.
pub const MAX_DEPTH: usize = 100;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Open,
    Close,
    Union,
    Not,
    /// A half-space: the body's inside (`-id`) or outside (`+id`).
    Half {
        op: Op,
        id: i64,
    },
}

#[derive(Clone, Copy, Debug)]
struct Token<'a> {
    kind: Kind,
    text: &'a str,
}

/// A factor of an intersection: one term, or a signed group of zones.
enum Factor {
    Term(Term),
    Group(Op, Vec<Zone>),
}

impl Factor {
    fn complement(self) -> Factor {
        match self {
            Factor::Term(t) => Factor::Term(Term {
                op: flip(t.op),
                ..t
            }),
            Factor::Group(Op::Inside, zones) => match single_term(&zones) {
                Some(t) => Factor::Term(Term {
                    op: flip(t.op),
                    ..t
                }),
                None => Factor::Group(Op::Outside, zones),
            },
            Factor::Group(Op::Outside, zones) => Factor::Group(Op::Inside, zones),
        }
    }

    /// Intersect `zone` with the factor.
    fn add_to(self, zone: &mut Zone) {
        match self {
            Factor::Term(t) => zone.terms.push(t),
            Factor::Group(Op::Inside, mut zones) if zones.len() == 1 => {
                let only = zones.pop().unwrap_or_default();
                zone.terms.extend(only.terms);
                zone.groups.extend(only.groups);
            }
            Factor::Group(op, zones) => zone.groups.push(Group { op, zones }),
        }
    }
}

/// `( … )`: a group, or the one group it holds (`(~( … ))`).
fn parenthesised(mut zones: Vec<Zone>) -> Factor {
    match &mut zones[..] {
        [z] if z.terms.is_empty() && z.groups.len() == 1 => {
            let g = z.groups.pop().expect("one group");
            Factor::Group(g.op, g.zones)
        }
        _ => Factor::Group(Op::Inside, zones),
    }
}

fn flip(op: Op) -> Op {
    match op {
        Op::Inside => Op::Outside,
        Op::Outside => Op::Inside,
    }
}

fn single_term(zones: &[Zone]) -> Option<Term> {
    match zones {
        [z] if z.groups.is_empty() && z.terms.len() == 1 => Some(z.terms[0]),
        _ => None,
    }
}

/// All space, as a cell without a region fills it: the one zone that
/// subtracts nothing (an empty zone would be no zone at all to the tracer).
pub(super) fn all_space() -> Vec<Zone> {
    vec![Zone {
        terms: Vec::new(),
        groups: vec![Group {
            op: Op::Outside,
            zones: Vec::new(),
        }],
    }]
}

/// The zones of a cell's region expression; an empty expression is all
/// space. Surfaces are found by id in `surfaces` (id → body index, `None`
/// for a surface whose errors were reported where it is defined). `None`
/// after reporting the errors (every undefined surface is reported).
pub(super) fn parse(
    xml: &Xml,
    sink: &mut Sink,
    value: &Value,
    surfaces: &HashMap<i64, Option<usize>>,
) -> Option<Vec<Zone>> {
    let tokens = tokens(xml, sink, value)?;
    let mut undefined = false;
    for t in &tokens {
        if let Kind::Half { id, .. } = t.kind {
            let known = surfaces.get(&id);
            undefined |= !matches!(known, Some(Some(_)));
            if known.is_none() {
                sink.error(
                    xml.error_at(value, t.text, format!("surface {id} is not defined"))
                        .with_hint(format!(
                            "define it with <surface id=\"{id}\" type=… coeffs=…/>"
                        )),
                );
            }
        }
    }
    if tokens.is_empty() {
        return (!undefined).then(all_space);
    }
    let mut parser = Parser {
        xml,
        value,
        tokens: &tokens,
        pos: 0,
        depth: 0,
        surfaces,
    };
    let parsed = parser.union().and_then(|zones| match parser.peek() {
        None => Ok(zones),
        Some(t) => Err(parser.error(t, format!("unexpected `{}`", t.text))),
    });
    match parsed {
        Ok(zones) if !undefined => Some(zones),
        Ok(_) => None,
        Err(d) => {
            sink.error(d);
            None
        }
    }
}

/// OpenMC's tokens of a region expression.
fn tokens<'a>(xml: &Xml, sink: &mut Sink, value: &Value<'a>) -> Option<Vec<Token<'a>>> {
    let text = value.text;
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        let kind = match c {
            b'(' => Kind::Open,
            b')' => Kind::Close,
            b'|' => Kind::Union,
            b'~' => Kind::Not,
            b'-' | b'+' | b'0'..=b'9' => {
                let digits_from = i + usize::from(!c.is_ascii_digit());
                let end = digits_from
                    + bytes[digits_from..]
                        .iter()
                        .take_while(|b| b.is_ascii_digit())
                        .count();
                let word = &text[i..end];
                let id = match text[digits_from..end].parse::<i64>() {
                    Ok(id) if id <= i64::from(i32::MAX) => id,
                    _ => {
                        let msg = if end == digits_from {
                            format!("`{}` must be followed by a surface id", c as char)
                        } else {
                            format!("surface id `{word}` is too large")
                        };
                        sink.error(xml.error_at(value, word, msg));
                        return None;
                    }
                };
                let op = if c == b'-' { Op::Inside } else { Op::Outside };
                out.push(Token {
                    kind: Kind::Half { op, id },
                    text: word,
                });
                i = end;
                continue;
            }
            c if c.is_ascii_whitespace() => {
                i += 1;
                continue;
            }
            _ => {
                let ch = text[i..].chars().next().unwrap_or(' ');
                let bad = &text[i..i + ch.len_utf8()];
                sink.error(
                    xml.error_at(value, bad, format!("`{ch}` has no meaning in a region"))
                        .with_hint(
                            "a region is made of surface ids with `-` or `+`, blanks \
                             (intersection), `|` (union), `~` (complement) and parentheses",
                        ),
                );
                return None;
            }
        };
        out.push(Token {
            kind,
            text: &text[i..i + 1],
        });
        i += 1;
    }
    Some(out)
}

struct Parser<'p, 'a> {
    xml: &'p Xml<'p>,
    value: &'p Value<'a>,
    tokens: &'p [Token<'a>],
    pos: usize,
    depth: usize,
    surfaces: &'p HashMap<i64, Option<usize>>,
}

impl<'a> Parser<'_, 'a> {
    fn peek(&self) -> Option<Token<'a>> {
        self.tokens.get(self.pos).copied()
    }

    fn error(&self, t: Token, msg: String) -> crate::Diagnostic {
        self.xml.error_at(self.value, t.text, msg)
    }

    /// After the last token: the end of the value.
    fn end_error(&self, msg: &str) -> crate::Diagnostic {
        let last = self.tokens.last().map_or("", |t| t.text);
        self.xml.error_at(self.value, last, msg.to_string())
    }

    fn union(&mut self) -> Result<Vec<Zone>, crate::Diagnostic> {
        let mut zones = vec![self.intersection()?];
        while self.peek().is_some_and(|t| t.kind == Kind::Union) {
            self.pos += 1;
            zones.push(self.intersection()?);
        }
        Ok(zones)
    }

    fn intersection(&mut self) -> Result<Zone, crate::Diagnostic> {
        let mut zone = Zone::default();
        self.factor()?.add_to(&mut zone);
        while self
            .peek()
            .is_some_and(|t| !matches!(t.kind, Kind::Union | Kind::Close))
        {
            self.factor()?.add_to(&mut zone);
        }
        Ok(zone)
    }

    fn factor(&mut self) -> Result<Factor, crate::Diagnostic> {
        let Some(t) = self.peek() else {
            return Err(self.end_error("the region ends where a half-space is expected"));
        };
        self.pos += 1;
        match t.kind {
            Kind::Half { op, id } => Ok(Factor::Term(Term {
                op,
                body: self.surfaces.get(&id).copied().flatten().unwrap_or(0),
            })),
            Kind::Not => self.nested(t, |p| Ok(p.factor()?.complement())),
            Kind::Open => {
                let zones = self.nested(t, Self::union)?;
                match self.peek() {
                    Some(c) if c.kind == Kind::Close => {
                        self.pos += 1;
                        Ok(parenthesised(zones))
                    }
                    _ => Err(self.error(t, "this `(` is not closed".into())),
                }
            }
            Kind::Close | Kind::Union => {
                Err(self.error(t, format!("`{}` where a half-space is expected", t.text)))
            }
        }
    }

    /// Run `inner` one level deeper, within [`MAX_DEPTH`].
    fn nested<T>(
        &mut self,
        at: Token,
        inner: impl FnOnce(&mut Self) -> Result<T, crate::Diagnostic>,
    ) -> Result<T, crate::Diagnostic> {
        if self.depth >= MAX_DEPTH {
            return Err(self.error(
                at,
                format!("the region nests more than {MAX_DEPTH} parentheses and complements deep"),
            ));
        }
        self.depth += 1;
        let out = inner(self);
        self.depth -= 1;
        out
    }
}
