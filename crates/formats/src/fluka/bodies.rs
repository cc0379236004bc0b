//! The body list of a FLUKA geometry: bodies, which may continue over
//! several lines, and the `$start_…`/`$end_…` directives that move them.

use super::{card, clean, is_name, rotdefi, tokens, Reader, BODY_CODES};
use crate::did_you_mean;
use sv_geom::{Body, BodyKind};
use sv_math::{DAffine3, DVec3};

/// FLUKA body types this reader knows of but does not read.
const UNSUPPORTED_CODES: [&str; 4] = ["PYX", "PYY", "PYZ", "TET"];

const DIRECTIVES: [&str; 6] = [
    "$start_translat",
    "$end_translat",
    "$start_expansion",
    "$end_expansion",
    "$start_transform",
    "$end_transform",
];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DirKind {
    Translat,
    Expansion,
    Transform,
}

impl DirKind {
    fn name(self) -> &'static str {
        match self {
            DirKind::Translat => "translat",
            DirKind::Expansion => "expansion",
            DirKind::Transform => "transform",
        }
    }
}

#[derive(Clone, Debug)]
struct Directive {
    kind: DirKind,
    factor: f64,
    shift: DVec3,
    xf: DAffine3,
    line: usize,
    col: usize,
    len: usize,
}

struct PendingBody {
    /// (line index, column, text) of each word.
    words: Vec<(usize, usize, String)>,
}

fn starts_numeric(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_digit() || c == '+' || c == '-' || c == '.')
}

fn body_code(s: &str) -> Option<BodyKind> {
    BODY_CODES
        .iter()
        .find(|(c, _)| c.eq_ignore_ascii_case(s))
        .map(|(_, k)| *k)
}

/// The body code a mistyped one was meant to be: one with the same letters
/// in another order (`SHP` → `SPH`), else the closest by edit distance.
fn suggest_code(code: &str) -> Option<&'static str> {
    let mut letters: Vec<char> = code.to_ascii_uppercase().chars().collect();
    letters.sort_unstable();
    let anagram = BODY_CODES.iter().map(|(c, _)| *c).find(|c| {
        let mut l: Vec<char> = c.chars().collect();
        l.sort_unstable();
        l == letters
    });
    anagram.or_else(|| did_you_mean(code, BODY_CODES.iter().map(|(c, _)| *c)))
}

/// The name of value `i` of a body type (`V` components become `Vx`, `Vy`, `Vz`).
fn value_name(kind: BodyKind, i: usize) -> String {
    let mut at = 0;
    for p in kind.info().params {
        let w = p.kind.width();
        if i < at + w {
            return if w == 3 {
                format!("{}{}", p.name, ["x", "y", "z"][i - at])
            } else {
                p.name.to_string()
            };
        }
        at += w;
    }
    format!("#{}", i + 1)
}

/// `V(3) H(3) R` for a body type.
fn layout(kind: BodyKind) -> String {
    kind.info()
        .params
        .iter()
        .map(|p| {
            if p.kind.width() == 3 {
                format!("{}(3)", p.name)
            } else {
                p.name.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

impl Reader {
    /// Read bodies from line `start`; the index after END, or `None` when
    /// END is missing.
    pub(super) fn bodies_section(&mut self, start: usize, end: usize) -> Option<usize> {
        let mut stack: Vec<Directive> = Vec::new();
        let mut pending: Option<PendingBody> = None;
        let mut result = None;
        for k in start..end {
            let text = clean(&self.lines[k].text).to_string();
            let words: Vec<(usize, String)> = tokens(&text)
                .into_iter()
                .map(|(c, w)| (c, w.to_string()))
                .collect();
            let Some((col0, first)) = words.first().cloned() else {
                continue;
            };
            if first.starts_with('$') {
                if let Some(p) = pending.take() {
                    self.finish_body(&p, &stack);
                }
                self.directive(k, &words, &mut stack);
            } else if first.eq_ignore_ascii_case("END") && words.len() == 1 {
                if let Some(p) = pending.take() {
                    self.finish_body(&p, &stack);
                }
                result = Some(k + 1);
                break;
            } else if starts_numeric(&first) {
                match &mut pending {
                    Some(p) => p.words.extend(words.into_iter().map(|(c, w)| (k, c, w))),
                    None => {
                        self.err(
                            k,
                            col0,
                            first.chars().count(),
                            format!("expected a body type, found `{first}`"),
                        )
                        .hint = Some(
                            "a body starts with its type and name, as in `RPP box 0 1 0 1 0 1`"
                                .into(),
                        );
                    }
                }
            } else {
                if let Some(p) = pending.take() {
                    self.finish_body(&p, &stack);
                }
                pending = Some(PendingBody {
                    words: words.into_iter().map(|(c, w)| (k, c, w)).collect(),
                });
            }
        }
        if let Some(p) = pending.take() {
            // END is missing: the last body still counts.
            self.finish_body(&p, &stack);
        }
        for d in stack {
            let name = format!("$start_{}", d.kind.name());
            self.err(d.line, d.col, d.len, format!("`{name}` is never closed"))
                .hint = Some(format!(
                "add `$end_{}` after the bodies it applies to",
                d.kind.name()
            ));
        }
        result
    }

    fn directive(&mut self, k: usize, words: &[(usize, String)], stack: &mut Vec<Directive>) {
        let (col, word) = (words[0].0, words[0].1.as_str());
        let len = word.chars().count();
        let lower = word.to_ascii_lowercase();
        let args = &words[1..];
        let (start, kind) = match lower.as_str() {
            "$start_translat" => (true, DirKind::Translat),
            "$end_translat" => (false, DirKind::Translat),
            "$start_expansion" => (true, DirKind::Expansion),
            "$end_expansion" => (false, DirKind::Expansion),
            "$start_transform" => (true, DirKind::Transform),
            "$end_transform" => (false, DirKind::Transform),
            _ => {
                let hint = did_you_mean(&lower, DIRECTIVES).map(|s| format!("did you mean `{s}`?"));
                self.err(k, col, len, format!("unknown geometry directive `{word}`"))
                    .hint = hint;
                return;
            }
        };
        let want = if !start {
            0
        } else if kind == DirKind::Translat {
            3
        } else {
            1
        };
        if args.len() > want {
            let (c, w) = (args[want].0, args[want].1.as_str());
            self.err(
                k,
                c,
                w.chars().count(),
                format!("unexpected `{w}` after `{word}`"),
            );
        }
        if !start {
            match stack.iter().rposition(|d| d.kind == kind) {
                Some(p) => {
                    stack.remove(p);
                }
                None => {
                    self.err(
                        k,
                        col,
                        len,
                        format!("`{word}` without a matching `$start_{}`", kind.name()),
                    );
                }
            }
            return;
        }
        let mut d = Directive {
            kind,
            factor: 1.0,
            shift: DVec3::ZERO,
            xf: DAffine3::IDENTITY,
            line: k,
            col,
            len,
        };
        if args.len() < want {
            let what = match kind {
                DirKind::Translat => "three numbers dx dy dz",
                DirKind::Expansion => "a factor",
                DirKind::Transform => "the name of a ROT-DEFI transformation",
            };
            self.err(k, col, len, format!("`{word}` needs {what}"));
            stack.push(d);
            return;
        }
        match kind {
            DirKind::Translat => {
                let mut v = [0.0; 3];
                for (i, (c, w)) in args.iter().take(3).enumerate() {
                    let (c, w) = (*c, w.as_str());
                    match card::number(w) {
                        Some(x) => v[i] = x,
                        None => {
                            self.err(
                                k,
                                c,
                                w.chars().count(),
                                format!("expected a number for `{word}`, found `{w}`"),
                            );
                        }
                    }
                }
                d.shift = DVec3::from(v);
            }
            DirKind::Expansion => {
                let (c, w) = (args[0].0, args[0].1.as_str());
                match card::number(w) {
                    Some(f) if f > 0.0 => d.factor = f,
                    _ => {
                        self.err(
                            k,
                            c,
                            w.chars().count(),
                            format!("`{word}` needs a positive factor, found `{w}`"),
                        );
                    }
                }
            }
            DirKind::Transform => {
                let (c, w) = (args[0].0, args[0].1.as_str());
                let (inverse, name) = match w.strip_prefix('-') {
                    Some(n) => (true, n),
                    None => (false, w),
                };
                let key = if self.rot.contains_key(name) {
                    Some(name.to_string())
                } else {
                    name.parse::<i64>()
                        .ok()
                        .and_then(|i| self.rot_index.get(&i).cloned())
                };
                match key.and_then(|k| self.rot.get(&k)) {
                    Some(cards) => {
                        let xf = rotdefi::compose(cards);
                        d.xf = if inverse { xf.inverse() } else { xf };
                    }
                    None => {
                        let hint = self.hint_among(name, self.rot.keys());
                        let e = self.err(
                            k,
                            c,
                            w.chars().count(),
                            format!(
                                "undefined transformation `{name}`: no ROT-DEFI card has this name"
                            ),
                        );
                        e.hint = hint.or(Some(
                            "define it with a ROT-DEFI card whose SDUM is the name".into(),
                        ));
                    }
                }
            }
        }
        stack.push(d);
    }

    fn finish_body(&mut self, p: &PendingBody, stack: &[Directive]) {
        let (line, col, code) = (p.words[0].0, p.words[0].1, p.words[0].2.as_str());
        let code_len = code.chars().count();
        let Some(kind) = body_code(code) else {
            if UNSUPPORTED_CODES
                .iter()
                .any(|c| c.eq_ignore_ascii_case(code))
            {
                let list = BODY_CODES
                    .iter()
                    .map(|(c, _)| *c)
                    .collect::<Vec<_>>()
                    .join(" ");
                self.err(
                    line,
                    col,
                    code_len,
                    format!("FLUKA body type `{code}` is not supported"),
                )
                .hint = Some(format!("supported body types: {list}"));
            } else {
                let hint = suggest_code(code).map(|s| format!("did you mean `{s}`?"));
                self.err(line, col, code_len, format!("unknown body type `{code}`"))
                    .hint = hint;
            }
            if let Some((_, _, name)) = p.words.get(1) {
                self.bad_bodies.insert(name.clone());
            }
            return;
        };
        let code = code.to_ascii_uppercase();
        let Some((nl, nc, name)) = p.words.get(1).map(|(l, c, n)| (*l, *c, n.as_str())) else {
            self.err(line, col, code_len, format!("`{code}` body has no name"));
            return;
        };
        if starts_numeric(name) {
            self.err(
                nl,
                nc,
                name.chars().count(),
                format!("expected a body name after `{code}`, found `{name}`"),
            );
            return;
        }
        if !is_name(name) {
            self.err(nl, nc, name.chars().count(), format!("body name `{name}` must start with a letter and hold only letters, digits and `_`"));
            self.bad_bodies.insert(name.to_string());
            return;
        }
        if let Some(&first) = self.body_index.get(name) {
            let hint = self.where_is(self.body_lines[first]);
            self.err(
                nl,
                nc,
                name.chars().count(),
                format!("body `{name}` is defined twice"),
            )
            .hint = Some(format!("the first definition is on {hint}"));
            return;
        }
        let values = &p.words[2..];
        let want = kind.info().value_count();
        let mut ok = true;
        if values.len() != want {
            self.err(
                line,
                col,
                code_len,
                format!(
                    "{code} `{name}` needs {want} values, found {}",
                    values.len()
                ),
            )
            .hint = Some(format!("{code} values: {}", layout(kind)));
            ok = false;
        }
        let mut params = Vec::with_capacity(want);
        for (i, (l, c, w)) in values.iter().enumerate().take(want) {
            let (l, c, w) = (*l, *c, w.as_str());
            match card::number(w) {
                Some(v) => params.push(v),
                None => {
                    let what = value_name(kind, i);
                    self.err(
                        l,
                        c,
                        w.chars().count(),
                        format!(
                            "expected a number for {code} `{name}` value {} ({what}), found `{w}`",
                            i + 1
                        ),
                    );
                    ok = false;
                }
            }
        }
        if !ok {
            self.bad_bodies.insert(name.to_string());
            return;
        }
        let mut body = Body::new(name, kind, params);
        if !stack.is_empty() {
            let mut e = 1.0;
            let mut t = DVec3::ZERO;
            let mut r = DAffine3::IDENTITY;
            for d in stack {
                match d.kind {
                    DirKind::Expansion => e *= d.factor,
                    DirKind::Translat => t += d.shift,
                    DirKind::Transform => r *= d.xf,
                }
            }
            let xf = r * DAffine3::from_translation(t) * DAffine3::from_scale(DVec3::splat(e));
            let det = xf.matrix3.determinant();
            if !(xf.is_finite() && det.is_finite() && det > 0.0) {
                self.err(
                    line,
                    col,
                    code_len,
                    format!(
                        "the directives around body `{name}` make a transformation out of range"
                    ),
                );
                self.bad_bodies.insert(name.to_string());
                return;
            }
            match body.transformed(&xf) {
                Ok(b) => body = b,
                Err(err) => {
                    self.err(
                        line,
                        col,
                        code_len,
                        format!("cannot transform body `{name}`: {err}"),
                    );
                    self.bad_bodies.insert(name.to_string());
                    return;
                }
            }
        }
        if body.params.iter().any(|v| !v.is_finite()) {
            self.err(
                line,
                col,
                code_len,
                format!("body `{name}` has a value out of range after its transformation"),
            );
            self.bad_bodies.insert(name.to_string());
            return;
        }
        self.body_index.insert(name.to_string(), self.bodies.len());
        self.bodies.push(body);
        self.body_lines.push(line);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_names_follow_the_table() {
        assert_eq!(value_name(BodyKind::Rcc, 6), "R");
        assert_eq!(value_name(BodyKind::Rcc, 4), "Hy");
        assert_eq!(layout(BodyKind::Rcc), "V(3) H(3) R");
    }
}
