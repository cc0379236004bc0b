//! The BODY and REGION statements.

use super::Names;
use crate::camera_light::colour;
use crate::diag::{did_you_mean, Diagnostic, Span};
use crate::text::region::{self, Lookup, Spanned, Tok};
use crate::text::{Cursor, Token};
use sv_geom::{Body, BodyKind, Op, Region, Term, Zone, BODY_TYPES};
use sv_scene::{RegionProps, Scene};

/// `BODY name TYPE values…`, after the keyword; warnings about the body
/// (rendered, though something is off) go to `warnings`.
pub(super) fn body(
    line: &mut Cursor,
    scene: &mut Scene,
    names: &Names,
    warnings: &mut Vec<Diagnostic>,
) -> Result<(), Diagnostic> {
    let name = line.any("a body name or number")?;
    let type_token = line.any("a body type (SPH, RCC, …)")?;
    let Some(kind) = BodyKind::from_name(type_token.text) else {
        let mut d = line.error(
            &type_token,
            format!("unknown body type `{}`", type_token.text),
        );
        let type_names = BODY_TYPES
            .iter()
            .flat_map(|t| std::iter::once(t.name).chain(t.aliases.iter().copied()));
        if let Some(s) = did_you_mean(type_token.text, type_names) {
            d = d.with_hint(format!("did you mean `{s}`?"));
        }
        line.skip_rest();
        return Err(d);
    };
    let first_value = line.peek();
    let purpose = format!("{kind} parameters");
    let mut params = Vec::new();
    while line.peek().is_some() {
        params.push(line.number(Some(&purpose))?);
    }
    let info = kind.info();
    let want = info.value_count();
    let count_ok = if kind == BodyKind::Ars {
        params.len() >= 2
            && params[0] >= 0.0
            && params[1] >= 0.0
            && params.len() as f64 == 2.0 + 3.0 * params[0] * params[1]
    } else {
        params.len() == want
    };
    if !count_ok {
        let span = first_value.map_or(line.end(), |t| t.span);
        let (want_text, hint) = if kind == BodyKind::Ars {
            (
                "curves, points per curve, then 3 values per point".to_string(),
                "ARS: curves points x y z …".to_string(),
            )
        } else {
            let layout: Vec<&str> = info.params.iter().map(|p| p.name).collect();
            (
                format!("{want} values"),
                format!("{kind}: {}", layout.join(" ")),
            )
        };
        return Err(line
            .error_at(
                span,
                format!("{kind} takes {want_text}, found {}", params.len()),
            )
            .with_hint(hint));
    }
    if names.bodies.contains_key(name.text) {
        return Err(line.error(&name, format!("body `{}` is defined twice", name.text)));
    }
    let body = Body::new(name.text.to_string(), kind, params);
    // The engine's own rules for the body (positive radii, min below max,
    // …), reported at its type.
    let mut body_warnings = Vec::new();
    let checked = sv_geom::prepare(&body, &mut body_warnings);
    for warning in body_warnings {
        let message = format!("{kind} `{}`: {}", name.text, warning.message);
        warnings.push(line.error(&type_token, message).warning());
    }
    // Kept even when wrong, so that the regions using it are not reported
    // as well.
    scene.geometry.bodies.push(body);
    match checked {
        Ok(_) => Ok(()),
        Err(msg) => Err(line.error(&type_token, format!("{kind} `{}`: {msg}", name.text))),
    }
}

const REGION_PROPS: &[&str] = &["COLOR", "COLOUR", "K", "TRANSPARENT", "OPAQUE", "DENSITY"];

/// `REGION name = zones [properties]` defines a region,
/// `REGION name properties` changes one defined earlier.
pub(super) fn region(
    line: &mut Cursor,
    scene: &mut Scene,
    names: &Names,
) -> Result<(), Diagnostic> {
    let name = line.any("a region name or number")?;
    let existing = names.regions.get(name.text).copied();
    let mut props = existing
        .map(|i| scene.regions[i].clone())
        .unwrap_or_default();
    let index = if line.peek().is_some_and(|t| t.text == "=") {
        line.advance();
        if existing.is_some() {
            return Err(line.error(&name, format!("region `{}` is defined twice", name.text)));
        }
        let zones = zones(line, &name, scene, names)?;
        scene.push_region(Region::new(name.text, zones), RegionProps::default())
    } else {
        match existing {
            Some(i) => i,
            None => return Err(undefined_region(line, &name, scene)),
        }
    };
    properties(line, &mut props)?;
    scene.regions[index] = props;
    Ok(())
}

/// The zones after `=`: `+body` and `-body` terms, `OR` between zones, up
/// to the first property.
fn zones(
    line: &mut Cursor,
    name: &Token,
    scene: &Scene,
    names: &Names,
) -> Result<Vec<Zone>, Diagnostic> {
    let is_property = |t: &Token| REGION_PROPS.iter().any(|p| p.eq_ignore_ascii_case(t.text));
    let expression: Vec<Token> = line
        .rest()
        .iter()
        .take_while(|t| !is_property(t))
        .copied()
        .collect();
    if let Some(first) = expression.first() {
        let stop = line.rest().get(expression.len()).map(|t| t.span);
        let text = line.text_between(first.span, stop);
        if text.contains(['(', ')', '|']) {
            for _ in &expression {
                line.advance();
            }
            return nested_zones(line, name, (text, first.span), scene, names);
        }
    }
    let mut zones = vec![Zone::default()];
    let mut errors = Vec::new();
    while let Some(t) = line.peek() {
        if REGION_PROPS.iter().any(|p| p.eq_ignore_ascii_case(t.text)) {
            break;
        }
        line.advance();
        if t.text.eq_ignore_ascii_case("OR") {
            zones.push(Zone::default());
            continue;
        }
        let (op, body) = match t.text.chars().next() {
            Some('+') => (Op::Inside, &t.text[1..]),
            Some('-') => (Op::Outside, &t.text[1..]),
            _ => {
                errors.push(bad_term(line, &t));
                continue;
            }
        };
        match names.bodies.get(body).copied() {
            Some(b) => zones
                .last_mut()
                .expect("zones start with one")
                .terms
                .push(Term { op, body: b }),
            None => errors.push(undefined_body(line, name, body, t.span, scene)),
        }
    }
    if let Some(e) = errors.into_iter().next() {
        // Report the first; the rest of the line is likely the same mistake.
        return Err(e);
    }
    if zones.iter().any(|z| z.terms.is_empty()) {
        return Err(line
            .error(name, format!("region `{}` has an empty zone", name.text))
            .with_hint("every OR must be followed by at least one body"));
    }
    Ok(zones)
}

/// A region's use of a body that is not defined (yet).
fn undefined_body(
    line: &Cursor,
    region: &Token,
    body: &str,
    at: Span,
    scene: &Scene,
) -> Diagnostic {
    let d = line.error_at(
        at,
        format!(
            "region `{}` refers to body `{body}`, which is not defined",
            region.text
        ),
    );
    let body_names = scene.geometry.bodies.iter().map(|b| b.name.as_str());
    match did_you_mean(body, body_names) {
        Some(s) => d.with_hint(format!("did you mean `{s}`?")),
        None => d.with_hint("define bodies before the regions that use them"),
    }
}

/// The zones of an expression that nests, such as `+a -(+b | +c)` (`OR`
/// is `|`), read by the grammar of parenthesised regions that FLUKA's
/// reader uses too: groups are kept as written, never expanded.
fn nested_zones(
    line: &Cursor,
    name: &Token,
    (text, at): (&str, Span),
    scene: &Scene,
    names: &Names,
) -> Result<Vec<Zone>, Diagnostic> {
    let mut toks = Vec::new();
    region::tokenize(text, at.line, &mut toks);
    for piece in &mut toks {
        // Columns on the line, and OR as `|`.
        piece.col += at.col - 1;
        if matches!(&piece.tok, Tok::Name(w) if w.eq_ignore_ascii_case("OR")) {
            piece.tok = Tok::Bar;
        }
    }
    let span_of = |s: &Spanned| Span {
        line: s.line,
        col: s.col,
        len: s.len,
    };
    let mut missing = None;
    let parsed = region::Parser::new(&toks, |s| match &s.tok {
        Tok::Name(body) => match names.bodies.get(body.as_str()) {
            Some(&b) => Lookup::Body(b),
            None => {
                missing.get_or_insert_with(|| (body.clone(), span_of(s)));
                Lookup::Unknown
            }
        },
        _ => Lookup::Unknown,
    })
    .parse();
    if let Some((body, at)) = missing {
        return Err(undefined_body(line, name, &body, at, scene));
    }
    match parsed {
        Ok((zones, _)) if zones.iter().all(|z| !z.is_empty()) && !zones.is_empty() => Ok(zones),
        Ok(_) => Err(line
            .error(name, format!("region `{}` has an empty zone", name.text))
            .with_hint("every `|` or OR must be followed by at least one body")),
        Err(e) => {
            let at = toks.get(e.at).map_or(line.end(), span_of);
            Err(line
                .error_at(at, format!("region `{}`: {}", name.text, e.message))
                .with_hint("write `+a -(+b | +c)`: `|` (or OR) unites, parentheses group, `+` and `-` intersect and subtract"))
        }
    }
}

/// A word among the zones that is neither a term nor OR.
fn bad_term(line: &Cursor, t: &Token) -> Diagnostic {
    match did_you_mean(t.text, REGION_PROPS.iter().copied()) {
        Some(p) => line
            .error(t, format!("unknown region property `{}`", t.text))
            .with_hint(format!("did you mean `{p}`?")),
        None => line
            .error(
                t,
                format!("expected `+body`, `-body` or OR, found `{}`", t.text),
            )
            .with_hint("write `+1` to intersect with body 1 and `-2` to subtract body 2"),
    }
}

fn undefined_region(line: &Cursor, name: &Token, scene: &Scene) -> Diagnostic {
    let d = line.error(name, format!("region `{}` is not defined", name.text));
    let region_names = scene.geometry.regions.iter().map(|r| r.name.as_str());
    match did_you_mean(name.text, region_names) {
        Some(s) => d.with_hint(format!(
            "did you mean `{s}`? (a new region needs `= +body …`)"
        )),
        None => d.with_hint("a new region is written `REGION name = +body -body …`"),
    }
}

/// COLOR, K, TRANSPARENT, OPAQUE and DENSITY, to the end of the line.
fn properties(line: &mut Cursor, props: &mut RegionProps) -> Result<(), Diagnostic> {
    while let Some(t) = line.advance() {
        match t.text.to_ascii_uppercase().as_str() {
            "COLOR" | "COLOUR" => props.colour = Some(colour(line)?),
            "K" => {
                let k = line.number(Some("the reflectivity k"))?;
                if !(0.0..=1.0).contains(&k) {
                    return Err(line.error(
                        &t,
                        format!("reflectivity k must lie between 0 and 1 (is {k})"),
                    ));
                }
                props.k = k;
            }
            "TRANSPARENT" => props.transparent = true,
            "OPAQUE" => props.transparent = false,
            "DENSITY" => props.density = Some(line.number(Some("the density (g/cm³)"))?),
            other => {
                let mut d = line.error(&t, format!("unknown region property `{}`", t.text));
                if let Some(s) = did_you_mean(other, REGION_PROPS.iter().copied()) {
                    d = d.with_hint(format!("did you mean `{s}`?"));
                }
                return Err(d);
            }
        }
    }
    Ok(())
}
