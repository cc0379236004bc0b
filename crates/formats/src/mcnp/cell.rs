//! Cell cards: `j m d geometry parameters` and `j LIKE n BUT parameters`.
//!
//! The geometry is read as written into a tree of unions of intersections:
//! a surface number with its sense (a facet as `n.k`), `:` for union,
//! juxtaposition for intersection, parentheses, `#n` (the space cell n
//! leaves) and `#( … )`. The parameters that shape the geometry are kept
//! (`IMP`, `U`, `FILL`/`*FILL`, `LAT`, `TRCL`/`*TRCL`, and `MAT`/`RHO` of a
//! `LIKE n BUT` card); the others are known and skipped.

use super::input::{Card, Word};
use super::number::{integer, real};
use super::params::{params, Params};
use super::{Loc, Log};

/// Highest cell, surface, universe or transformation number MCNP takes.
pub(crate) const MAX_NUMBER: i64 = 99_999_999;

/// A surface named in a cell's geometry.
#[derive(Clone, Debug)]
pub(crate) struct SurfaceRef {
    /// `-n`: the negative side.
    pub negative: bool,
    /// The surface number.
    pub number: i64,
    /// The facet of a macrobody (`n.k`).
    pub facet: Option<u8>,
    /// Where it is written.
    pub at: Loc,
}

/// One operand of an intersection.
#[derive(Clone, Debug)]
pub(crate) enum Factor {
    /// A surface's side.
    Surface(SurfaceRef),
    /// `#n`: everything but cell n.
    NotCell(i64, Loc),
    /// `#( … )`.
    Not(Union),
    /// `( … )`.
    Group(Union),
}

/// A union of intersections.
pub(crate) type Union = Vec<Vec<Factor>>;

/// A cell card.
#[derive(Clone, Debug)]
pub(crate) struct CellCard {
    /// Cell number.
    pub number: i64,
    /// Where the number is.
    pub at: Loc,
    /// `LIKE n BUT`: the cell copied.
    pub like: Option<(i64, Loc)>,
    /// Material number (0: void).
    pub material: i64,
    /// Where the material number is.
    pub material_at: Loc,
    /// Density: negative g/cm³, positive atoms/b-cm.
    pub density: Option<f64>,
    /// The geometry.
    pub geometry: Union,
    /// Parameters.
    pub params: Params,
    /// The card's `$` comment.
    pub description: Option<String>,
}

/// A whole number within MCNP's range for identifiers.
pub(crate) fn identifier(w: &Word, what: &str, log: &mut Log) -> Option<i64> {
    match integer(&w.text) {
        Some(n) if (1..=MAX_NUMBER).contains(&n) => Some(n),
        Some(_) => {
            log.error(
                w.at,
                format!("{what} must be 1 to {MAX_NUMBER}, not {}", w.text),
            );
            None
        }
        None => {
            log.error(w.at, format!("expected {what}, found `{}`", w.text));
            None
        }
    }
}

/// Read a cell card; `None` (reported) when it cannot be used.
pub(crate) fn read(card: &Card, log: &mut Log) -> Option<CellCard> {
    let words = &card.words;
    let number = identifier(&words[0], "a cell number", log)?;
    let mut cell = CellCard {
        number,
        at: words[0].at,
        like: None,
        material: 0,
        material_at: words[0].at,
        density: None,
        geometry: Vec::new(),
        params: Params::default(),
        description: card.comment.clone(),
    };
    let Some(second) = words.get(1) else {
        log.error(words[0].at, format!("cell {number} has no material"));
        return None;
    };
    let rest: Vec<Word>;
    if second.is("like") {
        let Some(other) = words.get(2) else {
            log.error(second.at, "LIKE needs a cell number");
            return None;
        };
        cell.like = Some((identifier(other, "a cell number", log)?, other.at));
        match words.get(3) {
            Some(w) if w.is("but") => rest = words[4..].to_vec(),
            Some(w) => {
                log.error(w.at, format!("expected `BUT`, found `{}`", w.text));
                return None;
            }
            None => {
                log.error(other.at, "expected `BUT` after the cell number");
                return None;
            }
        }
        cell.params = params(&rest, log)?;
        return Some(cell);
    }
    cell.material_at = second.at;
    cell.material = match integer(&second.text) {
        Some(m) if (0..=MAX_NUMBER).contains(&m) => m,
        _ => {
            log.error(
                second.at,
                format!("expected a material number, found `{}`", second.text),
            );
            return None;
        }
    };
    let mut geometry: Vec<Word> = Vec::new();
    let mut next = 2;
    if cell.material != 0 {
        let Some(d) = words.get(2) else {
            log.error(
                second.at,
                format!("cell {number} has a material but no density"),
            );
            return None;
        };
        // A density may run into the geometry's first parenthesis.
        let cut = d.text.find('(').unwrap_or(d.text.len());
        let (value, tail) = d.text.split_at(cut);
        match real(value) {
            Some(v) => cell.density = Some(v),
            None => {
                log.error(
                    d.at,
                    format!("expected the density of cell {number}, found `{}`", d.text),
                );
                return None;
            }
        }
        if !tail.is_empty() {
            let n = value.chars().count();
            geometry.push(d.part(n, tail.chars().count()));
        }
        next = 3;
    }
    let start = words[next..]
        .iter()
        .position(|w| {
            w.text
                .starts_with(|c: char| c.is_ascii_alphabetic() || c == '*')
        })
        .map_or(words.len(), |i| next + i);
    geometry.extend_from_slice(&words[next..start]);
    if geometry.is_empty() {
        log.error(
            words[next.min(words.len() - 1)].at,
            format!("cell {number} has no geometry"),
        );
        return None;
    }
    cell.geometry = Parser::new(&geometry).parse(log)?;
    cell.params = params(&words[start..], log)?;
    Some(cell)
}

/// A token of a geometry.
#[derive(Clone, Debug)]
enum Tok {
    Number(Word),
    Colon(Loc),
    Open(Loc),
    Close(Loc),
    Hash(Loc),
}

/// Split geometry words into tokens.
fn tokens(words: &[Word], log: &mut Log) -> Option<Vec<Tok>> {
    let mut out = Vec::new();
    for w in words {
        let chars: Vec<char> = w.text.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            let at = w.at.part(i, 1);
            match chars[i] {
                ':' => out.push(Tok::Colon(at)),
                '(' => out.push(Tok::Open(at)),
                ')' => out.push(Tok::Close(at)),
                '#' => out.push(Tok::Hash(at)),
                c if c.is_ascii_digit() || c == '+' || c == '-' || c == '.' => {
                    let from = i;
                    i += 1;
                    while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                        i += 1;
                    }
                    out.push(Tok::Number(w.part(from, i - from)));
                    continue;
                }
                c => {
                    log.error(at, format!("unexpected `{c}` in the geometry of a cell"))
                        .hint =
                        Some("a geometry holds surface numbers, `:`, `#` and parentheses".into());
                    return None;
                }
            }
            i += 1;
        }
    }
    Some(out)
}

/// Recursive descent over geometry tokens.
struct Parser {
    toks: Vec<Tok>,
    pos: usize,
    words: Vec<Word>,
}

/// How deep parentheses may nest (deeper is an error, not a stack overflow).
const MAX_NESTING: usize = 200;

impl Parser {
    fn new(words: &[Word]) -> Parser {
        Parser {
            toks: Vec::new(),
            pos: 0,
            words: words.to_vec(),
        }
    }

    fn parse(mut self, log: &mut Log) -> Option<Union> {
        self.toks = tokens(&self.words, log)?;
        let u = self.union(log, 0)?;
        if let Some(t) = self.toks.get(self.pos) {
            let at = tok_at(t);
            log.error(at, "unexpected `)`: no parenthesis is open");
            return None;
        }
        Some(u)
    }

    fn union(&mut self, log: &mut Log, depth: usize) -> Option<Union> {
        let mut out = vec![self.intersection(log, depth)?];
        while let Some(Tok::Colon(_)) = self.toks.get(self.pos) {
            self.pos += 1;
            out.push(self.intersection(log, depth)?);
        }
        Some(out)
    }

    fn intersection(&mut self, log: &mut Log, depth: usize) -> Option<Vec<Factor>> {
        let mut out = Vec::new();
        loop {
            match self.toks.get(self.pos) {
                None | Some(Tok::Colon(_)) | Some(Tok::Close(_)) => break,
                Some(_) => out.push(self.factor(log, depth)?),
            }
        }
        if out.is_empty() {
            let at = match self.toks.get(self.pos).or(self.toks.last()) {
                Some(t) => tok_at(t),
                None => self.words[0].at,
            };
            log.error(at, "expected a surface, `#` or `(` here");
            return None;
        }
        Some(out)
    }

    fn factor(&mut self, log: &mut Log, depth: usize) -> Option<Factor> {
        if depth > MAX_NESTING {
            let at = tok_at(&self.toks[self.pos]);
            log.error(at, format!("parentheses nest more than {MAX_NESTING} deep"));
            return None;
        }
        let tok = self.toks[self.pos].clone();
        self.pos += 1;
        match tok {
            Tok::Number(w) => surface_ref(&w, log).map(Factor::Surface),
            Tok::Open(at) => {
                let inner = self.union(log, depth + 1)?;
                self.close(at, log)?;
                Some(Factor::Group(inner))
            }
            Tok::Hash(at) => match self.toks.get(self.pos).cloned() {
                Some(Tok::Open(open)) => {
                    self.pos += 1;
                    let inner = self.union(log, depth + 1)?;
                    self.close(open, log)?;
                    Some(Factor::Not(inner))
                }
                Some(Tok::Number(w)) => {
                    self.pos += 1;
                    let n = identifier(&w, "a cell number after `#`", log)?;
                    // `#n` as one place when written on one line.
                    let both = if w.at.line == at.line && w.at.file == at.file {
                        Loc {
                            len: w.at.col + w.at.len - at.col,
                            ..at
                        }
                    } else {
                        w.at
                    };
                    Some(Factor::NotCell(n, both))
                }
                _ => {
                    log.error(at, "`#` needs a cell number or `(` after it");
                    None
                }
            },
            Tok::Colon(at) | Tok::Close(at) => {
                log.error(at, "expected a surface, `#` or `(` here");
                None
            }
        }
    }

    fn close(&mut self, open: Loc, log: &mut Log) -> Option<()> {
        match self.toks.get(self.pos) {
            Some(Tok::Close(_)) => {
                self.pos += 1;
                Some(())
            }
            _ => {
                log.error(open, "this `(` is never closed");
                None
            }
        }
    }
}

fn tok_at(t: &Tok) -> Loc {
    match t {
        Tok::Number(w) => w.at,
        Tok::Colon(at) | Tok::Open(at) | Tok::Close(at) | Tok::Hash(at) => *at,
    }
}

/// `-12`, `12`, `+12`, `-12.3`.
fn surface_ref(w: &Word, log: &mut Log) -> Option<SurfaceRef> {
    let (negative, body) = match w.text.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, w.text.strip_prefix('+').unwrap_or(&w.text)),
    };
    let (num, facet) = match body.split_once('.') {
        Some((n, f)) => (n, Some(f)),
        None => (body, None),
    };
    let number = match integer(num) {
        Some(n) if (1..=MAX_NUMBER).contains(&n) && !num.starts_with(['+', '-']) => n,
        _ => {
            log.error(w.at, format!("`{}` is not a surface number", w.text));
            return None;
        }
    };
    let facet = match facet {
        None => None,
        Some(f) => match f.parse::<u8>() {
            Ok(k) if (1..=8).contains(&k) && f.len() == 1 => Some(k),
            _ => {
                log.error(
                    w.at,
                    format!("`{}` names no facet: facets are `.1` to `.8`", w.text),
                );
                return None;
            }
        },
    };
    Some(SurfaceRef {
        negative,
        number,
        facet,
        at: w.at,
    })
}
