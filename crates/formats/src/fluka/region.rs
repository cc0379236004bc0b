//! Region expressions: parsing and conversion to a union of zones.
//!
//! Grammar (juxtaposition intersects, `|` unites, parentheses nest):
//!
//! ```text
//! union  := ['|'] inter ('|' inter)*
//! inter  := factor+
//! factor := ('+' | '-') (NAME | '(' union ')') | '(' union ')' | NAME
//! ```
//!
//! A bare `NAME` counts as `+NAME`. The result is put in disjunctive normal
//! form: intersection distributes over union and `-( … )` uses De Morgan's
//! laws. Zones that hold a body both with `+` and `-` are empty and dropped.

use crate::text;
use sv_geom::{Op, Term, Zone};

/// Most zones a region may expand to.
pub const MAX_ZONES: usize = 100_000;
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
    for t in text::tokens(line_text, line, &text::FLUKA_REGION) {
        let tok = match t.kind {
            text::Kind::Punct('+') => Tok::Plus,
            text::Kind::Punct('-') => Tok::Minus,
            text::Kind::Punct('|') => Tok::Bar,
            text::Kind::Punct('(') => Tok::Open,
            text::Kind::Punct(')') => Tok::Close,
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

/// A parsed expression: zones of factors.
#[derive(Clone, Debug)]
pub(crate) enum Factor {
    /// A body reference (`None` when the body is unknown; already reported).
    Body { outside: bool, body: Option<usize> },
    /// A parenthesised union.
    Group {
        outside: bool,
        inner: Vec<Vec<Factor>>,
    },
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
pub(crate) struct Parser<'a, F: FnMut(&Spanned) -> Option<usize>> {
    toks: &'a [Spanned],
    pos: usize,
    lookup: F,
}

impl<'a, F: FnMut(&Spanned) -> Option<usize>> Parser<'a, F> {
    /// A parser over `toks`.
    pub fn new(toks: &'a [Spanned], lookup: F) -> Self {
        Parser {
            toks,
            pos: 0,
            lookup,
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

    /// Parse the whole expression.
    pub fn parse(mut self) -> Result<Vec<Vec<Factor>>, ParseError> {
        let u = self.union(0)?;
        match self.peek() {
            None => Ok(u),
            Some(Tok::Close) => self.fail("unexpected `)` with no `(` open"),
            Some(_) => self.fail("unexpected token in region expression"),
        }
    }

    fn union(&mut self, depth: usize) -> Result<Vec<Vec<Factor>>, ParseError> {
        let mut zones = Vec::new();
        if self.peek() == Some(&Tok::Bar) {
            self.pos += 1;
        }
        loop {
            zones.push(self.inter(depth)?);
            if self.peek() == Some(&Tok::Bar) {
                self.pos += 1;
            } else {
                return Ok(zones);
            }
        }
    }

    fn inter(&mut self, depth: usize) -> Result<Vec<Factor>, ParseError> {
        let mut factors = Vec::new();
        while let Some(t) = self.peek() {
            match t {
                Tok::Bar | Tok::Close => break,
                _ => factors.push(self.factor(depth)?),
            }
        }
        if factors.is_empty() {
            return match self.peek() {
                None => self.fail("expected a body after this point, found the end of the region"),
                Some(Tok::Bar) => self.fail("empty zone: expected `+body` or `-body` before `|`"),
                _ if depth == 0 => self.fail("unexpected `)` with no `(` open"),
                _ => self.fail("empty parentheses: expected `+body` or `-body` before `)`"),
            };
        }
        Ok(factors)
    }

    fn factor(&mut self, depth: usize) -> Result<Factor, ParseError> {
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
                let body = (self.lookup)(&self.toks[self.pos]);
                self.pos += 1;
                Ok(Factor::Body { outside, body })
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
                Ok(Factor::Group { outside, inner })
            }
            None => self.fail("expected a body name, found the end of the region"),
            Some(_) => self.fail("expected a body name or `(`"),
        }
    }
}

/// The expansion was too large.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TooBig {
    /// More than [`MAX_ZONES`] zones.
    Zones,
    /// More than the work budget (terms copied while expanding).
    Work,
}

type Dnf = Vec<Vec<Term>>;

/// Expansion state: the work left (terms written, summed over every
/// product), so no input can keep the expansion busy for long.
pub(crate) struct Expander {
    budget: usize,
}

impl Default for Expander {
    fn default() -> Self {
        Expander { budget: MAX_WORK }
    }
}

/// Terms the expansion of all regions of one input may write.
pub(crate) const MAX_WORK: usize = 20_000_000;

fn term(outside: bool, body: usize) -> Term {
    Term {
        op: if outside { Op::Outside } else { Op::Inside },
        body,
    }
}

/// Append `b` to zone `a`, skipping repeated terms; `None` if the result
/// holds a body both with `+` and `-` (an empty zone).
fn join(a: &[Term], b: &[Term]) -> Option<Vec<Term>> {
    let mut z = a.to_vec();
    if a.len() + b.len() <= 32 {
        for t in b {
            if z.iter().any(|u| u.body == t.body && u.op != t.op) {
                return None;
            }
            if !z.contains(t) {
                z.push(*t);
            }
        }
        return Some(z);
    }
    let mut seen: std::collections::HashMap<usize, Op> = a.iter().map(|t| (t.body, t.op)).collect();
    for t in b {
        match seen.get(&t.body) {
            Some(op) if *op != t.op => return None,
            Some(_) => {}
            None => {
                seen.insert(t.body, t.op);
                z.push(*t);
            }
        }
    }
    Some(z)
}

impl Expander {
    fn spend(&mut self, n: usize) -> Result<(), TooBig> {
        self.budget = self.budget.checked_sub(n).ok_or(TooBig::Work)?;
        Ok(())
    }

    fn product(&mut self, a: &Dnf, b: &Dnf) -> Result<Dnf, TooBig> {
        if a.len().saturating_mul(b.len()) > MAX_ZONES {
            return Err(TooBig::Zones);
        }
        let mut out = Vec::with_capacity(a.len() * b.len());
        for x in a {
            for y in b {
                self.spend(x.len() + y.len() + 1)?;
                if let Some(z) = join(x, y) {
                    out.push(z);
                }
            }
        }
        Ok(out)
    }

    fn negate(&mut self, d: &Dnf) -> Result<Dnf, TooBig> {
        // not (Z1 or Z2 …) = (not Z1) and (not Z2) …, and not Zi is the
        // union of its negated terms.
        let mut acc: Dnf = vec![Vec::new()];
        for zone in d {
            let alt: Dnf = zone
                .iter()
                .map(|t| {
                    vec![Term {
                        op: if t.op == Op::Inside {
                            Op::Outside
                        } else {
                            Op::Inside
                        },
                        body: t.body,
                    }]
                })
                .collect();
            acc = self.product(&acc, &alt)?;
        }
        Ok(acc)
    }

    fn union(&mut self, u: &[Vec<Factor>]) -> Result<Dnf, TooBig> {
        let mut out = Vec::new();
        for zone in u {
            let mut acc: Dnf = vec![Vec::new()];
            // Runs of plain body terms are joined in one step.
            let mut run: Vec<Term> = Vec::new();
            for f in zone {
                match f {
                    Factor::Body {
                        outside,
                        body: Some(b),
                    } => run.push(term(*outside, *b)),
                    Factor::Body { body: None, .. } => {}
                    Factor::Group { outside, inner } => {
                        if !run.is_empty() {
                            acc = self.product(&acc, &vec![std::mem::take(&mut run)])?;
                        }
                        let d = self.union(inner)?;
                        let d = if *outside { self.negate(&d)? } else { d };
                        acc = self.product(&acc, &d)?;
                    }
                }
            }
            if !run.is_empty() {
                acc = self.product(&acc, &vec![run])?;
            }
            out.extend(acc);
            if out.len() > MAX_ZONES {
                return Err(TooBig::Zones);
            }
        }
        Ok(out)
    }

    /// The union of zones equivalent to a parsed expression.
    pub(crate) fn zones(&mut self, u: &[Vec<Factor>]) -> Result<Vec<Zone>, TooBig> {
        Ok(self.union(u)?.into_iter().map(Zone::new).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn zones(expr: &str) -> Result<Vec<String>, String> {
        let mut toks = Vec::new();
        tokenize(expr, 0, &mut toks);
        let names = ["a", "b", "c", "d"];
        let u = Parser::new(&toks, |t| match &t.tok {
            Tok::Name(n) => names.iter().position(|x| x == n),
            _ => None,
        })
        .parse()
        .map_err(|e| e.message)?;
        Ok(Expander::default()
            .zones(&u)
            .map_err(|_| "too big".to_string())?
            .iter()
            .map(|z| z.expression(&|b| names[b]))
            .collect())
    }

    #[test]
    fn distributes_and_uses_de_morgan() {
        assert_eq!(zones("+a -b").unwrap(), ["+a -b"]);
        assert_eq!(zones("| +a | +b").unwrap(), ["+a", "+b"]);
        assert_eq!(zones("+a -(+b -c)").unwrap(), ["+a -b", "+a +c"]);
        assert_eq!(zones("+a +(+b | +c) -d").unwrap(), ["+a +b -d", "+a +c -d"]);
        assert_eq!(zones("-(+a | +b)").unwrap(), ["-a -b"]);
        assert_eq!(zones("+a -a | +b").unwrap(), ["+b"]);
        assert_eq!(
            zones("(+a | +b) (+c | +d)").unwrap(),
            ["+a +c", "+a +d", "+b +c", "+b +d"]
        );
        assert_eq!(zones("a b").unwrap(), ["+a +b"]);
    }

    #[test]
    fn syntax_errors() {
        assert_eq!(zones("+a -(+b").unwrap_err(), "`(` is never closed");
        assert_eq!(
            zones("+a )").unwrap_err(),
            "unexpected `)` with no `(` open"
        );
        assert_eq!(
            zones("+a | | +b").unwrap_err(),
            "empty zone: expected `+body` or `-body` before `|`"
        );
        assert_eq!(
            zones("+a +").unwrap_err(),
            "expected a body name, found the end of the region"
        );
        assert_eq!(
            zones("+a -()").unwrap_err(),
            "empty parentheses: expected `+body` or `-body` before `)`"
        );
        let deep = format!("{}+a{}", "+(".repeat(100), ")".repeat(100));
        assert!(zones(&deep).unwrap_err().contains("nested more than 64"));
    }

    #[test]
    fn long_zones_join_in_linear_time() {
        let n = 200_000;
        let u = vec![(0..n)
            .map(|b| Factor::Body {
                outside: b % 2 == 1,
                body: Some(b),
            })
            .collect::<Vec<_>>()];
        let z = Expander::default().zones(&u).unwrap();
        assert_eq!(z.len(), 1);
        assert_eq!(z[0].terms.len(), n);
        // A contradiction far apart still empties the zone.
        let mut f = u[0].clone();
        f.push(Factor::Group {
            outside: false,
            inner: vec![vec![Factor::Body {
                outside: false,
                body: Some(n - 1),
            }]],
        });
        assert!(Expander::default().zones(&[f]).unwrap().is_empty());
    }

    #[test]
    fn work_is_bounded() {
        // Many one-term groups after a long run: each product copies the run.
        let mut f: Vec<Factor> = (0..10_000)
            .map(|b| Factor::Body {
                outside: false,
                body: Some(b),
            })
            .collect();
        for b in 0..10_000 {
            f.push(Factor::Group {
                outside: false,
                inner: vec![vec![Factor::Body {
                    outside: false,
                    body: Some(20_000 + b),
                }]],
            });
        }
        assert_eq!(Expander::default().zones(&[f]).unwrap_err(), TooBig::Work);
    }

    #[test]
    fn blow_up_is_capped() {
        // (a|b)^20 would be a million zones.
        let e = "(+a | +b) ".repeat(20).replace('b', "c");
        let mut toks = Vec::new();
        tokenize(&e, 0, &mut toks);
        let mut n = 0;
        let u = Parser::new(&toks, |_| {
            n += 1;
            Some(n)
        })
        .parse()
        .unwrap();
        assert_eq!(Expander::default().zones(&u).unwrap_err(), TooBig::Zones);
    }
}
