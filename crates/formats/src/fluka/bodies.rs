//! The body list of a FLUKA geometry: bodies, which may continue over
//! several lines, and the `$start_…`/`$end_…` directives that move them.

use super::{card, clean, is_name, tokens, Reader, BODY_CODES};
use crate::did_you_mean;
use sv_geom::{Body, BodyKind};
use sv_math::{DAffine3, DVec3};

/// FLUKA body types this reader knows of but does not read.
const UNSUPPORTED_CODES: [&str; 1] = ["TET"];

/// FLUKA's pyramids along x, y and z, and the names of their 7 values:
/// the centre of the major base, the half-sides of the major base (along
/// the next two axes in x, y, z order), the height (its sign points from
/// the major base to the minor one) and the ratio of the minor base's
/// sides to the major base's (0: not truncated).
const PYRAMIDS: [&str; 3] = ["PYX", "PYY", "PYZ"];
const PYRAMID_VALUES: [&str; 7] = ["Vx", "Vy", "Vz", "L1", "L2", "H", "R"];

/// What a body's values are: those of a body type, or a pyramid's.
#[derive(Clone, Copy, Debug)]
enum ValuesOf {
    Kind(BodyKind),
    /// A PYX, PYY or PYZ: the axis (0, 1, 2).
    Pyramid(usize),
}

impl ValuesOf {
    fn count(self) -> usize {
        match self {
            ValuesOf::Kind(k) => k.info().value_count(),
            ValuesOf::Pyramid(_) => PYRAMID_VALUES.len(),
        }
    }

    fn name(self, i: usize) -> String {
        match self {
            ValuesOf::Kind(k) => value_name(k, i),
            ValuesOf::Pyramid(_) => PYRAMID_VALUES[i].to_string(),
        }
    }

    fn layout(self) -> String {
        match self {
            ValuesOf::Kind(k) => layout(k),
            ValuesOf::Pyramid(_) => PYRAMID_VALUES.join(" "),
        }
    }
}

/// A pyramid along axis `axis` as the polyhedron of its corners: an ARB8
/// (truncated) or an ARB5 (full, with its apex).
fn pyramid(axis: usize, v: &[f64]) -> Result<(BodyKind, Vec<f64>), String> {
    let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
    let (half_u, half_w, height, ratio) = (v[3], v[4], v[5], v[6]);
    if !(half_u > 0.0 && half_w > 0.0) {
        return Err("the half-sides of its major base must be positive".into());
    }
    if height == 0.0 {
        return Err("its height is zero".into());
    }
    if !(0.0..1.0).contains(&ratio) {
        return Err(format!(
            "its ratio R = {ratio} must be at least 0 and below 1"
        ));
    }
    let corner = |su: f64, sw: f64, scale: f64, up: f64| {
        let mut p = [v[0], v[1], v[2]];
        p[u] += su * half_u * scale;
        p[w] += sw * half_w * scale;
        p[axis] += up;
        p
    };
    let square = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut points: Vec<[f64; 3]> = square
        .iter()
        .map(|&(a, b)| corner(a, b, 1.0, 0.0))
        .collect();
    let kind = if ratio == 0.0 {
        points.push(corner(0.0, 0.0, 0.0, height));
        BodyKind::Arb5
    } else {
        points.extend(square.iter().map(|&(a, b)| corner(a, b, ratio, height)));
        BodyKind::Arb8
    };
    Ok((kind, points.concat()))
}

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

/// An open `$start_…` directive.
#[derive(Clone, Debug)]
pub(super) struct Directive {
    kind: DirKind,
    factor: f64,
    shift: DVec3,
    xf: DAffine3,
    line: usize,
    col: usize,
    len: usize,
}

/// A body whose words are being collected.
pub(super) struct PendingBody {
    /// (line index, column, text) of each word: code, name, values.
    pub words: Vec<(usize, usize, String)>,
    /// Whether the name is a fixed-format body number.
    pub numbered: bool,
}

fn starts_numeric(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_digit() || c == '+' || c == '-' || c == '.')
}

/// How many values a body of code `s` takes, when the code is known.
pub(super) fn value_count(s: &str) -> Option<usize> {
    if PYRAMIDS.iter().any(|p| p.eq_ignore_ascii_case(s)) {
        return Some(PYRAMID_VALUES.len());
    }
    body_code(s).map(|k| k.info().value_count())
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

/// Where the directives around a body put it: all expansions act first
/// (they multiply), then all translations (they add up), then the
/// transforms, the innermost first.
fn placement(stack: &[Directive]) -> DAffine3 {
    let mut factor = 1.0;
    let mut shift = DVec3::ZERO;
    let mut turn = DAffine3::IDENTITY;
    for d in stack {
        match d.kind {
            DirKind::Expansion => factor *= d.factor,
            DirKind::Translat => shift += d.shift,
            DirKind::Transform => turn *= d.xf,
        }
    }
    turn * DAffine3::from_translation(shift) * DAffine3::from_scale(DVec3::splat(factor))
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
                    numbered: false,
                });
            }
        }
        if let Some(p) = pending.take() {
            // END is missing: the last body still counts.
            self.finish_body(&p, &stack);
        }
        self.unclosed(stack);
        result
    }

    /// Report the directives left open at the end of the bodies.
    pub(super) fn unclosed(&mut self, stack: Vec<Directive>) {
        for d in stack {
            let name = format!("$start_{}", d.kind.name());
            self.err(d.line, d.col, d.len, format!("`{name}` is never closed"))
                .hint = Some(format!(
                "add `$end_{}` after the bodies it applies to",
                d.kind.name()
            ));
        }
    }

    /// A `$start_…` or `$end_…` line: opens a directive on `stack` (even a
    /// faulty one, so that its `$end_…` matches) or closes the innermost of
    /// its kind.
    pub(super) fn directive(
        &mut self,
        line: usize,
        words: &[(usize, String)],
        stack: &mut Vec<Directive>,
    ) {
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
                self.err(
                    line,
                    col,
                    len,
                    format!("unknown geometry directive `{word}`"),
                )
                .hint = hint;
                return;
            }
        };
        let want = match (start, kind) {
            (false, _) => 0,
            (true, DirKind::Translat) => 3,
            (true, _) => 1,
        };
        if let Some((extra_col, extra)) = args.get(want) {
            let len = extra.chars().count();
            let message = format!("unexpected `{extra}` after `{word}`");
            if start {
                self.err(line, *extra_col, len, message);
            } else {
                // FLUKA reads no argument after an `$end_…` and goes on.
                self.warn(line, *extra_col, len, format!("{message}: ignored"));
            }
        }
        if !start {
            match stack.iter().rposition(|d| d.kind == kind) {
                Some(open) => {
                    stack.remove(open);
                }
                None => {
                    self.err(
                        line,
                        col,
                        len,
                        format!("`{word}` without a matching `$start_{}`", kind.name()),
                    );
                }
            }
            return;
        }
        let mut opened = Directive {
            kind,
            factor: 1.0,
            shift: DVec3::ZERO,
            xf: DAffine3::IDENTITY,
            line,
            col,
            len,
        };
        if args.len() < want {
            let what = match kind {
                DirKind::Translat => "three numbers dx dy dz",
                DirKind::Expansion => "a factor",
                DirKind::Transform => "the name of a ROT-DEFI transformation",
            };
            self.err(line, col, len, format!("`{word}` needs {what}"));
        } else {
            match kind {
                DirKind::Translat => opened.shift = self.translation(line, word, args),
                DirKind::Expansion => opened.factor = self.expansion(line, word, &args[0]),
                DirKind::Transform => opened.xf = self.transform(line, &args[0]),
            }
        }
        stack.push(opened);
    }

    /// The shift of `$start_translat dx dy dz` (a bad number counts as 0).
    fn translation(&mut self, line: usize, word: &str, args: &[(usize, String)]) -> DVec3 {
        let mut shift = [0.0; 3];
        for (axis, (col, text)) in args.iter().take(3).enumerate() {
            match card::number(text) {
                Some(v) => shift[axis] = v,
                None => {
                    self.err(
                        line,
                        *col,
                        text.chars().count(),
                        format!("expected a number for `{word}`, found `{text}`"),
                    );
                }
            }
        }
        DVec3::from(shift)
    }

    /// The factor of `$start_expansion f` (1 when it is not a positive
    /// number).
    fn expansion(&mut self, line: usize, word: &str, (col, text): &(usize, String)) -> f64 {
        match card::number(text) {
            Some(f) if f > 0.0 => f,
            _ => {
                self.err(
                    line,
                    *col,
                    text.chars().count(),
                    format!("`{word}` needs a positive factor, found `{text}`"),
                );
                1.0
            }
        }
    }

    /// The transformation `$start_transform [-]name` names (by ROT-DEFI
    /// name or index; `-` for its inverse), or the identity when there is
    /// none.
    fn transform(&mut self, line: usize, (col, text): &(usize, String)) -> DAffine3 {
        if let Some(xf) = self.find_transform(text) {
            return xf;
        }
        let name = text.trim_start_matches('-');
        let hint = self.hint_among(name, self.rot.keys());
        let e = self.err(
            line,
            *col,
            text.chars().count(),
            format!("undefined transformation `{name}`: no ROT-DEFI card has this name"),
        );
        e.hint = hint.or(Some(
            "define it with a ROT-DEFI card whose SDUM is the name".into(),
        ));
        DAffine3::IDENTITY
    }

    /// A body whose words are all read: checked, moved by the directives
    /// around it and added, or reported.
    pub(super) fn finish_body(&mut self, pending: &PendingBody, stack: &[Directive]) {
        let (line, col, code) = &pending.words[0];
        let code_len = code.chars().count();
        let values_of = match PYRAMIDS.iter().position(|p| p.eq_ignore_ascii_case(code)) {
            Some(axis) => ValuesOf::Pyramid(axis),
            None => match self.body_kind(pending) {
                Some(kind) => ValuesOf::Kind(kind),
                None => return,
            },
        };
        let code = code.to_ascii_uppercase();
        let Some(name) = self.body_name(pending, &code) else {
            return;
        };
        let at = |reader: &mut Reader, msg: String| {
            reader.err(*line, *col, code_len, msg);
            reader.bad_bodies.insert(name.to_string());
        };
        let Some(params) = self.body_values(pending, values_of, &code, name) else {
            self.bad_bodies.insert(name.to_string());
            return;
        };
        let (kind, params) = match values_of {
            ValuesOf::Kind(kind) => (kind, params),
            ValuesOf::Pyramid(axis) => match pyramid(axis, &params) {
                Ok(made) => made,
                Err(e) => return at(self, format!("{code} `{name}`: {e}")),
            },
        };
        let mut body = Body::new(name, kind, params);
        if !stack.is_empty() {
            let xf = placement(stack);
            let det = xf.matrix3.determinant();
            if !(xf.is_finite() && det.is_finite() && det > 0.0) {
                let msg = format!(
                    "the directives around body `{name}` make a transformation out of range"
                );
                return at(self, msg);
            }
            match body.transformed(&xf) {
                Ok(moved) => body = moved,
                Err(err) => return at(self, format!("cannot transform body `{name}`: {err}")),
            }
        }
        if body.params.iter().any(|v| !v.is_finite()) {
            let msg = format!("body `{name}` has a value out of range after its transformation");
            return at(self, msg);
        }
        // The engine's own rules for the body (positive radii, a plane's
        // normal not zero, …), reported at its card.
        let mut warnings = Vec::new();
        if let Err(msg) = sv_geom::prepare(&body, &mut warnings) {
            return at(self, format!("{code} `{name}`: {msg}"));
        }
        for warning in warnings {
            let msg = format!("{code} `{name}`: {}", warning.message);
            self.warn(*line, *col, code_len, msg);
        }
        self.body_index.insert(name.to_string(), self.bodies.len());
        self.bodies.push(body);
        self.body_lines.push(*line);
    }

    /// The kind of a body's code, or `None` (reported) for an unknown or
    /// unsupported one.
    fn body_kind(&mut self, pending: &PendingBody) -> Option<BodyKind> {
        let (line, col, code) = &pending.words[0];
        let (line, col, code_len) = (*line, *col, code.chars().count());
        if let Some(kind) = body_code(code) {
            return Some(kind);
        }
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
        if let Some((_, _, name)) = pending.words.get(1) {
            self.bad_bodies.insert(name.clone());
        }
        None
    }

    /// The body's name, when it is a new, well-formed one (else reported).
    fn body_name<'p>(&mut self, pending: &'p PendingBody, code: &str) -> Option<&'p str> {
        let (line, col, code_len) = (pending.words[0].0, pending.words[0].1, code.chars().count());
        let Some((name_line, name_col, name)) =
            pending.words.get(1).map(|(l, c, n)| (*l, *c, n.as_str()))
        else {
            self.err(line, col, code_len, format!("`{code}` body has no name"));
            return None;
        };
        let name_len = name.chars().count();
        // A fixed-format body number was checked where it was read.
        if !pending.numbered && starts_numeric(name) {
            self.err(
                name_line,
                name_col,
                name_len,
                format!("expected a body name after `{code}`, found `{name}`"),
            );
            return None;
        }
        if !pending.numbered && !is_name(name) {
            self.err(name_line, name_col, name_len, format!("body name `{name}` must start with a letter and hold only letters, digits and `_`"));
            self.bad_bodies.insert(name.to_string());
            return None;
        }
        if let Some(&first) = self.body_index.get(name) {
            let hint = self.where_is(self.body_lines[first]);
            self.err(
                name_line,
                name_col,
                name_len,
                format!("body `{name}` is defined twice"),
            )
            .hint = Some(format!("the first definition is on {hint}"));
            return None;
        }
        Some(name)
    }

    /// The body's values: as many as its kind takes, all numbers (else
    /// every problem is reported and `None` returned).
    fn body_values(
        &mut self,
        pending: &PendingBody,
        values_of: ValuesOf,
        code: &str,
        name: &str,
    ) -> Option<Vec<f64>> {
        let (line, col) = (pending.words[0].0, pending.words[0].1);
        let values = &pending.words[2..];
        let want = values_of.count();
        let mut ok = true;
        if values.len() != want {
            self.err(
                line,
                col,
                code.chars().count(),
                format!(
                    "{code} `{name}` needs {want} values, found {}",
                    values.len()
                ),
            )
            .hint = Some(format!("{code} values: {}", values_of.layout()));
            ok = false;
        }
        let mut params = Vec::with_capacity(want);
        for (i, (value_line, value_col, text)) in values.iter().enumerate().take(want) {
            match card::number(text) {
                Some(v) => params.push(v),
                None => {
                    let what = values_of.name(i);
                    self.err(
                        *value_line,
                        *value_col,
                        text.chars().count(),
                        format!(
                            "expected a number for {code} `{name}` value {} ({what}), found `{text}`",
                            i + 1
                        ),
                    );
                    ok = false;
                }
            }
        }
        ok.then_some(params)
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
