//! The parameters of a cell card that shape the geometry: `IMP`, `U`,
//! `LAT`, `FILL`/`*FILL` (one universe, or a lattice's array, each with an
//! optional transformation in parentheses), `TRCL`/`*TRCL`, and `MAT`/`RHO`
//! of a `LIKE n BUT` card. The other keywords are known and skipped; an
//! unknown one is warned about.

use super::cell::MAX_NUMBER;
use super::input::Word;
use super::number::{self, integer, real, Expander};
use super::{Loc, Log};

/// A transformation as a card gives it: a `TR` number or its values in
/// parentheses.
#[derive(Clone, Debug)]
pub(crate) enum Transform {
    /// `n`: card `TRn`.
    Card(i64, Loc),
    /// The values (`None` for a `J`); angles in degrees when `degrees`.
    Values {
        /// Displacement, matrix and the `M` entry, as far as given.
        values: Vec<Option<f64>>,
        /// `*TRCL`, `*FILL`: the matrix entries are angles in degrees.
        degrees: bool,
        /// The opening parenthesis.
        at: Loc,
    },
}

/// A universe filling an element or a cell, moved or not.
#[derive(Clone, Debug)]
pub(crate) struct Filler {
    /// The universe number.
    pub universe: i64,
    /// How it is moved.
    pub transform: Option<Transform>,
    /// Where the number is.
    pub at: Loc,
}

/// What `FILL` says.
#[derive(Clone, Debug)]
pub(crate) enum FillSpec {
    /// One universe.
    One(Filler),
    /// A lattice's elements: index ranges and one filler per element.
    Array {
        /// Lowest and highest index along each direction.
        ranges: [(i64, i64); 3],
        /// The elements, first index fastest.
        elements: Vec<Filler>,
    },
}

/// A `FILL` parameter and where its keyword is.
#[derive(Clone, Debug)]
pub(crate) struct Fill {
    /// What fills.
    pub spec: FillSpec,
    /// The keyword.
    pub at: Loc,
}

/// The parameters that shape the geometry.
#[derive(Clone, Debug, Default)]
pub(crate) struct Params {
    /// Neutron importance.
    pub imp_neutron: Option<f64>,
    /// Importance of the first other particle given.
    pub imp_other: Option<f64>,
    /// `U=`.
    pub universe: Option<(i64, Loc)>,
    /// `LAT=`.
    pub lattice: Option<(i64, Loc)>,
    /// `FILL=`.
    pub fill: Option<Fill>,
    /// `TRCL=`.
    pub trcl: Option<Transform>,
    /// `MAT=` (LIKE BUT).
    pub material: Option<(i64, Loc)>,
    /// `RHO=` (LIKE BUT).
    pub density: Option<(f64, Loc)>,
}

/// Keywords of cell parameters that do not concern the geometry.
const SKIPPED_PARAMS: [&str; 13] = [
    "vol", "pwt", "ext", "fcl", "wwn", "dxc", "nonu", "pd", "tmp", "elpt", "cosy", "bflcl", "unc",
];

/// A token of a parameter list.
#[derive(Clone, Debug)]
enum ParamTok {
    Key(Word),
    Equals,
    Open(Loc),
    Close(Loc),
    Value(Word),
}

/// Shorthand words a value list may hold that start with a letter.
fn is_letter_value(text: &str) -> bool {
    matches!(
        text.to_ascii_lowercase().as_str(),
        "j" | "r" | "i" | "m" | "log" | "ilog"
    )
}

fn param_tokens(words: &[Word]) -> Vec<ParamTok> {
    let mut out = Vec::new();
    for w in words {
        let chars: Vec<char> = w.text.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            match chars[i] {
                '=' => out.push(ParamTok::Equals),
                '(' => out.push(ParamTok::Open(w.at.part(i, 1))),
                ')' => out.push(ParamTok::Close(w.at.part(i, 1))),
                c => {
                    let from = i;
                    let key = c.is_ascii_alphabetic() || c == '*';
                    while i < chars.len() && !matches!(chars[i], '=' | '(' | ')') {
                        i += 1;
                    }
                    let part = w.part(from, i - from);
                    if key && !is_letter_value(&part.text) {
                        out.push(ParamTok::Key(part));
                    } else {
                        out.push(ParamTok::Value(part));
                    }
                    continue;
                }
            }
            i += 1;
        }
    }
    out
}

/// The parameters of a cell card.
pub(crate) fn params(words: &[Word], log: &mut Log) -> Option<Params> {
    let toks = param_tokens(words);
    let mut p = Params::default();
    let mut i = 0;
    let mut ok = true;
    while i < toks.len() {
        let key = match &toks[i] {
            ParamTok::Key(k) => k.clone(),
            other => {
                let at = match other {
                    ParamTok::Value(w) => w.at,
                    ParamTok::Open(at) | ParamTok::Close(at) => *at,
                    _ => words[0].at,
                };
                log.error(at, "expected a cell parameter such as `IMP:N=1` or `U=2`");
                return None;
            }
        };
        i += 1;
        if let Some(ParamTok::Equals) = toks.get(i) {
            i += 1;
        }
        let from = i;
        while i < toks.len() && !matches!(toks[i], ParamTok::Key(_)) {
            i += 1;
        }
        ok &= one_param(&key, &toks[from..i], &mut p, log);
    }
    ok.then_some(p)
}

/// The values of one keyword: words, and groups in parentheses.
fn values_of(toks: &[ParamTok]) -> Vec<&Word> {
    toks.iter()
        .filter_map(|t| match t {
            ParamTok::Value(w) => Some(w),
            _ => None,
        })
        .collect()
}

fn one_param(key: &Word, toks: &[ParamTok], p: &mut Params, log: &mut Log) -> bool {
    let name = key.text.to_ascii_lowercase();
    let (starred, bare) = match name.strip_prefix('*') {
        Some(b) => (true, b),
        None => (false, name.as_str()),
    };
    let values = values_of(toks);
    let first = |log: &mut Log| -> Option<&Word> {
        let v = values.first().copied();
        if v.is_none() {
            log.error(key.at, format!("`{}` needs a value", key.text));
        }
        v
    };
    if let Some(particles) = bare.strip_prefix("imp:") {
        let Some(w) = first(log) else { return false };
        let Some(v) = real(&w.text) else {
            log.error(w.at, format!("expected an importance, found `{}`", w.text));
            return false;
        };
        if particles.split(',').any(|q| q == "n") {
            p.imp_neutron = Some(v);
        } else {
            p.imp_other = p.imp_other.or(Some(v));
        }
        return true;
    }
    match (bare, starred) {
        ("u", false) | ("lat", false) | ("mat", false) => {
            let Some(w) = first(log) else { return false };
            let Some(v) = integer(&w.text) else {
                log.error(
                    w.at,
                    format!(
                        "expected a whole number for `{}`, found `{}`",
                        key.text, w.text
                    ),
                );
                return false;
            };
            let slot = match bare {
                "u" => &mut p.universe,
                "lat" => &mut p.lattice,
                _ => &mut p.material,
            };
            *slot = Some((v, w.at));
            true
        }
        ("rho", false) => {
            let Some(w) = first(log) else { return false };
            match real(&w.text) {
                Some(v) => {
                    p.density = Some((v, w.at));
                    true
                }
                None => {
                    log.error(w.at, format!("expected a density, found `{}`", w.text));
                    false
                }
            }
        }
        ("trcl", _) => match transform(key, toks, starred, log) {
            Some(t) => {
                p.trcl = Some(t);
                true
            }
            None => false,
        },
        ("fill", _) => match fill(key, toks, starred, log) {
            Some(f) => {
                p.fill = Some(f);
                true
            }
            None => false,
        },
        _ if SKIPPED_PARAMS.iter().any(|s| {
            bare.split([':', '0', '1', '2', '3', '4', '5', '6', '7', '8', '9'])
                .next()
                == Some(s)
        }) =>
        {
            true
        }
        _ => {
            log.warn(
                key.at,
                format!("unknown cell parameter `{}` is skipped", key.text),
            );
            true
        }
    }
}

/// `TRCL=n`, `TRCL=(o1 o2 o3 …)`.
fn transform(key: &Word, toks: &[ParamTok], degrees: bool, log: &mut Log) -> Option<Transform> {
    match toks.first() {
        Some(ParamTok::Open(at)) => {
            let (values, used) = group(*at, &toks[1..], log)?;
            if used + 1 != toks.len() {
                log.error(key.at, format!("`{}` takes one transformation", key.text));
                return None;
            }
            Some(in_parentheses(values, degrees, *at))
        }
        Some(ParamTok::Value(w)) if toks.len() == 1 => match integer(&w.text) {
            Some(n) if (0..=MAX_NUMBER).contains(&n) => Some(Transform::Card(n, w.at)),
            _ => {
                log.error(
                    w.at,
                    format!("expected a transformation number, found `{}`", w.text),
                );
                None
            }
        },
        _ => {
            log.error(
                key.at,
                format!(
                    "`{}` needs a transformation number or values in parentheses",
                    key.text
                ),
            );
            None
        }
    }
}

/// One value in parentheses is a `TR` number; more are the values.
fn in_parentheses(values: Vec<(Option<f64>, Loc)>, degrees: bool, at: Loc) -> Transform {
    if let [(Some(v), loc)] = values.as_slice() {
        if v.fract() == 0.0 && *v >= 0.0 && *v <= MAX_NUMBER as f64 {
            return Transform::Card(*v as i64, *loc);
        }
    }
    Transform::Values {
        values: values.into_iter().map(|e| e.0).collect(),
        degrees,
        at,
    }
}

/// The values up to the `)` closing the group opened at `open`, and how
/// many tokens they took (the `)` included).
fn group(open: Loc, toks: &[ParamTok], log: &mut Log) -> Option<(Vec<number::Entry>, usize)> {
    let mut e = Expander::default();
    for (i, t) in toks.iter().enumerate() {
        match t {
            ParamTok::Value(w) => {
                if let Err(msg) = e.push(w) {
                    log.error(w.at, msg);
                    return None;
                }
            }
            ParamTok::Close(_) => {
                return match e.finish() {
                    Ok(v) => Some((v, i + 1)),
                    Err((at, msg)) => {
                        log.error(at, msg);
                        None
                    }
                };
            }
            _ => break,
        }
    }
    log.error(open, "this `(` is never closed");
    None
}

/// Whether `w` continues the range word before it (a range written with
/// blanks around its colon, `-7 : 7`).
fn glues(before: Option<&Word>, w: &Word) -> bool {
    before.is_some_and(|l| l.text.ends_with(':') || w.text.starts_with(':'))
}

/// Most elements one lattice fill may list.
pub(crate) const MAX_ELEMENTS: usize = 1 << 24;

/// `FILL=u`, `FILL=u (tr)`, `FILL=i1:i2 j1:j2 k1:k2 u u(tr) nR …`.
fn fill(key: &Word, toks: &[ParamTok], degrees: bool, log: &mut Log) -> Option<Fill> {
    let is_range = |t: &ParamTok| matches!(t, ParamTok::Value(w) if w.text.contains(':'));
    if !toks.iter().take(3).any(is_range) {
        let filler = fillers(key, toks, degrees, log)?;
        if filler.len() != 1 {
            log.error(
                key.at,
                format!(
                    "`{}` of a cell that is no lattice takes one universe",
                    key.text
                ),
            )
            .hint = Some(
                "a lattice fill starts with its index ranges, such as `FILL=-1:1 -1:1 0:0`".into(),
            );
            return None;
        }
        return Some(Fill {
            spec: FillSpec::One(filler.into_iter().next()?),
            at: key.at,
        });
    }
    // The ranges: three `low:high` words (blanks around a colon allowed).
    let mut n = 0;
    let mut joined: Vec<Word> = Vec::new();
    while let Some(ParamTok::Value(w)) = toks.get(n) {
        if glues(joined.last(), w) {
            let last = joined.last_mut().expect("glues only after a word");
            last.text.push_str(&w.text);
            last.at.len = (w.at.col + w.at.len).saturating_sub(last.at.col).max(1);
        } else if joined.len() == 3 {
            break;
        } else {
            joined.push(w.clone());
        }
        n += 1;
    }
    let mut ranges = [(0i64, 0i64); 3];
    if joined.len() != 3 {
        log.error(
            key.at,
            format!(
                "`{}` needs three index ranges such as `-1:1 -1:1 0:0`",
                key.text
            ),
        );
        return None;
    }
    for (r, w) in ranges.iter_mut().zip(&joined) {
        let parts = w
            .text
            .split_once(':')
            .and_then(|(a, b)| Some((integer(a)?, integer(b)?)));
        match parts {
            Some((lo, hi)) if lo <= hi && lo.abs() < 1 << 30 && hi.abs() < 1 << 30 => *r = (lo, hi),
            _ => {
                log.error(
                    w.at,
                    format!("`{}` is not an index range `low:high`", w.text),
                );
                return None;
            }
        }
    }
    let elements = fillers(key, &toks[n..], degrees, log)?;
    Some(Fill {
        spec: FillSpec::Array { ranges, elements },
        at: key.at,
    })
}

/// Universe numbers, each with an optional transformation in parentheses,
/// and `nR` repeating the one before.
fn fillers(key: &Word, toks: &[ParamTok], degrees: bool, log: &mut Log) -> Option<Vec<Filler>> {
    let mut out: Vec<Filler> = Vec::new();
    let mut i = 0;
    while i < toks.len() {
        match &toks[i] {
            ParamTok::Value(w) => {
                if let Some(u) = integer(&w.text) {
                    if !(0..=MAX_NUMBER).contains(&u) {
                        log.error(w.at, format!("universe {u} is out of range"));
                        return None;
                    }
                    out.push(Filler {
                        universe: u,
                        transform: None,
                        at: w.at,
                    });
                } else if let Some(count) = repeat_count(&w.text) {
                    let Some(last) = out.last().cloned() else {
                        log.error(w.at, format!("`{}` needs a universe before it", w.text));
                        return None;
                    };
                    if out.len() + count > MAX_ELEMENTS {
                        log.error(
                            w.at,
                            format!("a fill may list at most {MAX_ELEMENTS} elements"),
                        );
                        return None;
                    }
                    out.extend(std::iter::repeat_n(last, count));
                } else {
                    log.error(
                        w.at,
                        format!("expected a universe number, found `{}`", w.text),
                    );
                    return None;
                }
                i += 1;
            }
            ParamTok::Open(at) => {
                let (values, used) = group(*at, &toks[i + 1..], log)?;
                let Some(last) = out.last_mut().filter(|f| f.transform.is_none()) else {
                    log.error(
                        *at,
                        "a transformation in parentheses must follow a universe number",
                    );
                    return None;
                };
                last.transform = Some(in_parentheses(values, degrees, *at));
                i += 1 + used;
            }
            ParamTok::Close(at) => {
                log.error(*at, "unexpected `)`");
                return None;
            }
            ParamTok::Equals | ParamTok::Key(_) => i += 1,
        }
        if out.len() > MAX_ELEMENTS {
            log.error(
                key.at,
                format!("a fill may list at most {MAX_ELEMENTS} elements"),
            );
            return None;
        }
    }
    if out.is_empty() {
        log.error(key.at, format!("`{}` needs a universe number", key.text));
        return None;
    }
    Some(out)
}

/// The count of an `nR` word.
fn repeat_count(text: &str) -> Option<usize> {
    let digits = text.strip_suffix(['r', 'R'])?;
    if digits.is_empty() {
        return Some(1);
    }
    if digits.len() > 9 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}
