//! The native scene language (`.sv`).
//!
//! Line oriented, keywords case-insensitive, `#` starts a comment. Values
//! are separated by spaces; commas and parentheses may be used to group
//! vectors for readability: `(0, 0, 1)` is the same as `0 0 1`.
//!
//! ```text
//! TITLE  Figure 1 of the paper
//! UNITS  in
//! BODY 1 SPH  (0,0,0) 1.0                  # sphere: centre, radius
//! BODY 2 RCC  (0.45,-0.2,-1.4) (0,0,2.8) 0.6
//! REGION D = +1 -2   COLOR 0.9 0.5 0.2  K 0.9
//! REGION E = +2 -1 OR +3                    # OR unions zones
//! REGION C TRANSPARENT                      # change a region defined earlier
//! INCLUDE "deck.cg"                         # .sv, COMGEOM or FLUKA
//! CAMERA EYE (9,-13,6.5) AT (-1.6,0,2) UP (0,0,1) FOV 46
//! CAMERA ORTHO EYE (10,10,10) AT (0,0,0) HEIGHT 12
//! CAMERA EYE (0,-20,0) DIR (0,1,0) FOCAL 50 FILM 24
//! LIGHT SUN  PARALLEL DIR (0.6,1,-1.5) INTENSITY 0.85
//! LIGHT LAMP POINT AT (0,0,10) INTENSITY 100 DECAY 2 COLOR 1 0.9 0.8
//! AMBIENT 0.15
//! BACKGROUND 0.1            # or three values for a colour
//! SHADOWS OFF
//! SIZE 960 720
//! ```

use crate::diag::{did_you_mean, Diagnostic, Diagnostics, SourceFile};
use crate::{LoadError, LoadOptions, Loaded};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use sv_geom::{Body, BodyKind, Op, Region, Term, Zone, BODY_TYPES};
use sv_math::DVec3;
use sv_scene::{Background, Camera, Lens, Light, LightKind, RegionProps, Scene, Units};

/// The statement keywords, for suggestions.
pub const KEYWORDS: &[&str] = &[
    "TITLE",
    "UNITS",
    "BODY",
    "REGION",
    "INCLUDE",
    "CAMERA",
    "LIGHT",
    "AMBIENT",
    "BACKGROUND",
    "SHADOWS",
    "SIZE",
];

const MAX_INCLUDE_DEPTH: usize = 16;

/// A token of a line.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    /// Text (without quotes for strings).
    pub text: String,
    /// 1-based column (characters).
    pub col: usize,
    /// Length in characters as written.
    pub len: usize,
    /// True for a quoted string.
    pub quoted: bool,
}

/// Split a line into tokens: words, numbers and quoted strings; commas and
/// parentheses separate; `#` ends the line; `=` is a token of its own.
pub fn tokenize(line: &str) -> Vec<Token> {
    let chars: Vec<char> = line.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '#' {
            break;
        }
        if c.is_whitespace() || c == ',' || c == '(' || c == ')' {
            i += 1;
            continue;
        }
        if c == '=' {
            out.push(Token {
                text: "=".into(),
                col: i + 1,
                len: 1,
                quoted: false,
            });
            i += 1;
            continue;
        }
        if c == '"' {
            let start = i;
            i += 1;
            let mut s = String::new();
            while i < chars.len() && chars[i] != '"' {
                s.push(chars[i]);
                i += 1;
            }
            i = (i + 1).min(chars.len());
            out.push(Token {
                text: s,
                col: start + 1,
                len: i - start,
                quoted: true,
            });
            continue;
        }
        let start = i;
        let mut s = String::new();
        while i < chars.len()
            && !chars[i].is_whitespace()
            && !matches!(chars[i], ',' | '(' | ')' | '#' | '=' | '"')
        {
            s.push(chars[i]);
            i += 1;
        }
        out.push(Token {
            text: s,
            col: start + 1,
            len: i - start,
            quoted: false,
        });
    }
    out
}

struct Ctx<'a> {
    src: &'a SourceFile,
    line: usize,
    diags: &'a mut Diagnostics,
}

impl Ctx<'_> {
    fn err(&mut self, t: &Token, msg: impl Into<String>) -> Diagnostic {
        Diagnostic::error_at(self.src, self.line, t.col, t.len, msg)
    }

    fn report(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }
}

/// Cursor over one line's tokens.
struct Line<'t> {
    toks: &'t [Token],
    pos: usize,
    end_col: usize,
}

impl<'t> Line<'t> {
    fn peek(&self) -> Option<&'t Token> {
        self.toks.get(self.pos)
    }
    fn next(&mut self) -> Option<&'t Token> {
        let t = self.toks.get(self.pos);
        self.pos += 1;
        t
    }
    fn end_token(&self) -> Token {
        Token {
            text: String::new(),
            col: self.end_col,
            len: 0,
            quoted: false,
        }
    }
    fn number(&mut self, cx: &mut Ctx, what: &str) -> Result<f64, Diagnostic> {
        match self.next() {
            Some(t) => t
                .text
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    cx.err(
                        t,
                        format!("expected a number for {what}, found `{}`", t.text),
                    )
                }),
            None => {
                let e = self.end_token();
                Err(cx.err(
                    &e,
                    format!("expected a number for {what}, found the end of the line"),
                ))
            }
        }
    }
    fn vec3(&mut self, cx: &mut Ctx, what: &str) -> Result<DVec3, Diagnostic> {
        Ok(DVec3::new(
            self.number(cx, what)?,
            self.number(cx, what)?,
            self.number(cx, what)?,
        ))
    }
    fn word(&mut self, cx: &mut Ctx, what: &str) -> Result<&'t Token, Diagnostic> {
        self.next().ok_or_else(|| {
            let e = self.end_token();
            cx.err(&e, format!("expected {what}, found the end of the line"))
        })
    }
}

/// Read a scene file.
pub fn read(src: &SourceFile, opts: &LoadOptions) -> Result<Loaded, Diagnostics> {
    let mut scene = Scene::default();
    let mut diags = Diagnostics::default();
    let mut warnings = Vec::new();
    let mut stack = vec![PathBuf::from(&src.name)];
    let mut units_set = false;
    read_into(
        src,
        opts,
        &mut scene,
        &mut diags,
        &mut warnings,
        &mut stack,
        &mut units_set,
    );
    if diags.has_errors() {
        return Err(diags);
    }
    warnings.extend(diags.items);
    Ok(Loaded {
        scene,
        warnings,
        format: crate::Format::Native,
    })
}

/// Name → index maps of the scene being read, kept in step with it, so a
/// look-up costs O(1): a linear search per reference made reading a
/// 100,000-body scene quadratic.
#[derive(Default)]
struct Names {
    bodies: HashMap<String, usize>,
    regions: HashMap<String, usize>,
}

impl Names {
    /// Take in bodies and regions added since the last call.
    fn sync(&mut self, scene: &Scene) {
        let g = &scene.geometry;
        for (i, b) in g.bodies.iter().enumerate().skip(self.bodies.len()) {
            self.bodies.entry(b.name.clone()).or_insert(i);
        }
        for (i, r) in g.regions.iter().enumerate().skip(self.regions.len()) {
            self.regions.entry(r.name.clone()).or_insert(i);
        }
    }
}

fn read_into(
    src: &SourceFile,
    opts: &LoadOptions,
    scene: &mut Scene,
    diags: &mut Diagnostics,
    warnings: &mut Vec<Diagnostic>,
    stack: &mut Vec<PathBuf>,
    units_set: &mut bool,
) {
    let mut names = Names::default();
    for (i, text) in src.text.lines().enumerate() {
        let toks = tokenize(text);
        if toks.is_empty() {
            continue;
        }
        names.sync(scene);
        let mut cx = Ctx {
            src,
            line: i + 1,
            diags,
        };
        let mut ln = Line {
            toks: &toks,
            pos: 1,
            end_col: text.chars().count() + 1,
        };
        let kw = &toks[0];
        let r = match kw.text.to_ascii_uppercase().as_str() {
            "TITLE" => {
                scene.title = text[text.to_ascii_uppercase().find("TITLE").unwrap_or(0) + 5..]
                    .trim()
                    .to_string();
                ln.pos = toks.len();
                Ok(())
            }
            "UNITS" => ln
                .word(&mut cx, "a unit (in, ft, mm, cm, m)")
                .and_then(|t| match Units::parse(&t.text) {
                    Some(u) => {
                        if !scene.geometry.bodies.is_empty() && u != scene.units {
                            return Err(
                                cx.err(t, "UNITS must come before the first body or INCLUDE")
                            );
                        }
                        scene.units = u;
                        *units_set = true;
                        Ok(())
                    }
                    None => Err(cx
                        .err(t, format!("unknown unit `{}`", t.text))
                        .with_hint("use one of in, ft, mm, cm, m")),
                }),
            "BODY" => body(&mut ln, &mut cx, scene, &names),
            "REGION" => region(&mut ln, &mut cx, scene, &names),
            "INCLUDE" => match ln.word(&mut cx, "a file name in quotes") {
                Ok(t) => {
                    include(t, &mut cx, opts, scene, warnings, stack, units_set);
                    Ok(())
                }
                Err(e) => Err(e),
            },
            "CAMERA" => camera(&mut ln, &mut cx).map(|c| scene.camera = Some(c)),
            "LIGHT" => light(&mut ln, &mut cx).map(|l| {
                scene
                    .lights
                    .retain(|o| !o.name.eq_ignore_ascii_case(&l.name));
                scene.lights.push(l)
            }),
            "AMBIENT" => ln
                .number(&mut cx, "the ambient intensity")
                .map(|a| scene.ambient = a),
            "BACKGROUND" => (|| {
                let g = ln.number(&mut cx, "the background intensity")?;
                let c = if ln.peek().is_some() {
                    [g, ln.number(&mut cx, "green")?, ln.number(&mut cx, "blue")?]
                } else {
                    [g; 3]
                };
                scene.background = Background::Colour(c);
                Ok(())
            })(),
            "SHADOWS" => ln.word(&mut cx, "ON or OFF").and_then(|t| {
                match t.text.to_ascii_uppercase().as_str() {
                    "ON" => {
                        scene.shadows = true;
                        Ok(())
                    }
                    "OFF" => {
                        scene.shadows = false;
                        Ok(())
                    }
                    _ => Err(cx.err(t, format!("expected ON or OFF, found `{}`", t.text))),
                }
            }),
            "SIZE" => (|| {
                let w = ln.number(&mut cx, "the width")?;
                let h = ln.number(&mut cx, "the height")?;
                if !(1.0..=65536.0).contains(&w)
                    || !(1.0..=65536.0).contains(&h)
                    || w.fract() != 0.0
                    || h.fract() != 0.0
                {
                    let t = &toks[1];
                    return Err(cx.err(t, "picture size must be whole numbers from 1 to 65536"));
                }
                scene.size = Some((w as u32, h as u32));
                Ok(())
            })(),
            other => {
                let mut d = cx.err(kw, format!("unknown statement `{}`", kw.text));
                if let Some(s) = did_you_mean(other, KEYWORDS.iter().copied()) {
                    d = d.with_hint(format!("did you mean `{s}`?"));
                } else if BodyKind::from_name(other).is_some() {
                    d = d.with_hint(format!(
                        "bodies are written `BODY name {} values…`",
                        other.to_ascii_uppercase()
                    ));
                }
                ln.pos = toks.len();
                Err(d)
            }
        };
        match r {
            Err(d) => cx.report(d),
            Ok(()) => {
                if let Some(t) = ln.peek() {
                    let d = cx.err(
                        t,
                        format!("unexpected `{}` at the end of the statement", t.text),
                    );
                    cx.report(d);
                }
            }
        }
    }
}

fn body(ln: &mut Line, cx: &mut Ctx, scene: &mut Scene, names: &Names) -> Result<(), Diagnostic> {
    let name = ln.word(cx, "a body name or number")?;
    let ty = ln.word(cx, "a body type (SPH, RCC, …)")?;
    let Some(kind) = BodyKind::from_name(&ty.text) else {
        let mut d = cx.err(ty, format!("unknown body type `{}`", ty.text));
        let names = BODY_TYPES
            .iter()
            .flat_map(|t| std::iter::once(t.name).chain(t.aliases.iter().copied()));
        if let Some(s) = did_you_mean(&ty.text, names) {
            d = d.with_hint(format!("did you mean `{s}`?"));
        }
        ln.pos = ln.toks.len();
        return Err(d);
    };
    let start = ln.pos;
    let mut params = Vec::new();
    while ln.peek().is_some() {
        params.push(ln.number(cx, &format!("{kind} parameters"))?);
    }
    let info = kind.info();
    let want = info.value_count();
    let ok = if kind == BodyKind::Ars {
        params.len() >= 2
            && params[0] >= 0.0
            && params[1] >= 0.0
            && params.len() as f64 == 2.0 + 3.0 * params[0] * params[1]
    } else {
        params.len() == want
    };
    if !ok {
        let t = ln
            .toks
            .get(start)
            .cloned()
            .unwrap_or_else(|| ln.end_token());
        let layout: Vec<&str> = info.params.iter().map(|p| p.name).collect();
        let want_s = if kind == BodyKind::Ars {
            "curves, points per curve, then 3 values per point".to_string()
        } else {
            format!("{want} values")
        };
        return Err(cx
            .err(&t, format!("{kind} takes {want_s}, found {}", params.len()))
            .with_hint(if kind == BodyKind::Ars {
                "ARS: curves points x y z …".into()
            } else {
                format!("{kind}: {}", layout.join(" "))
            }));
    }
    if names.bodies.contains_key(&name.text) {
        return Err(cx.err(name, format!("body `{}` is defined twice", name.text)));
    }
    scene
        .geometry
        .bodies
        .push(Body::new(name.text.clone(), kind, params));
    Ok(())
}

fn colour(ln: &mut Line, cx: &mut Ctx) -> Result<[f64; 3], Diagnostic> {
    Ok([
        ln.number(cx, "red")?,
        ln.number(cx, "green")?,
        ln.number(cx, "blue")?,
    ])
}

const REGION_PROPS: &[&str] = &["COLOR", "COLOUR", "K", "TRANSPARENT", "OPAQUE", "DENSITY"];

fn region(ln: &mut Line, cx: &mut Ctx, scene: &mut Scene, names: &Names) -> Result<(), Diagnostic> {
    let name = ln.word(cx, "a region name or number")?;
    let existing = names.regions.get(&name.text).copied();
    let mut props = existing
        .map(|i| scene.regions[i].clone())
        .unwrap_or_default();
    let idx = if ln.peek().is_some_and(|t| t.text == "=") {
        ln.next();
        if existing.is_some() {
            return Err(cx.err(name, format!("region `{}` is defined twice", name.text)));
        }
        let mut zones = vec![Zone::default()];
        let mut errors = Vec::new();
        while let Some(t) = ln.peek() {
            if REGION_PROPS.iter().any(|p| p.eq_ignore_ascii_case(&t.text)) {
                break;
            }
            ln.next();
            if t.text.eq_ignore_ascii_case("OR") {
                zones.push(Zone::default());
                continue;
            }
            let (op, body) = match t.text.chars().next() {
                Some('+') => (Op::Inside, &t.text[1..]),
                Some('-') => (Op::Outside, &t.text[1..]),
                _ => {
                    let d = match did_you_mean(&t.text, REGION_PROPS.iter().copied()) {
                        Some(p) => cx
                            .err(t, format!("unknown region property `{}`", t.text))
                            .with_hint(format!("did you mean `{p}`?")),
                        None => cx
                            .err(
                                t,
                                format!("expected `+body`, `-body` or OR, found `{}`", t.text),
                            )
                            .with_hint(
                                "write `+1` to intersect with body 1 and `-2` to subtract body 2",
                            ),
                    };
                    errors.push(d);
                    continue;
                }
            };
            match names.bodies.get(body).copied() {
                Some(b) => zones.last_mut().unwrap().terms.push(Term { op, body: b }),
                None => {
                    let mut d = cx.err(
                        t,
                        format!(
                            "region `{}` refers to body `{body}`, which is not defined",
                            name.text
                        ),
                    );
                    if let Some(s) =
                        did_you_mean(body, scene.geometry.bodies.iter().map(|b| b.name.as_str()))
                    {
                        d = d.with_hint(format!("did you mean `{s}`?"));
                    } else {
                        d = d.with_hint("define bodies before the regions that use them");
                    }
                    errors.push(d);
                }
            }
        }
        if let Some(e) = errors.into_iter().next() {
            // Report the first; the rest of the line is likely the same mistake.
            return Err(e);
        }
        if zones.iter().any(|z| z.terms.is_empty()) {
            return Err(cx
                .err(name, format!("region `{}` has an empty zone", name.text))
                .with_hint("every OR must be followed by at least one body"));
        }
        scene.push_region(
            Region {
                name: name.text.clone(),
                zones,
            },
            RegionProps::default(),
        )
    } else {
        match existing {
            Some(i) => i,
            None => {
                let mut d = cx.err(name, format!("region `{}` is not defined", name.text));
                if let Some(s) = did_you_mean(
                    &name.text,
                    scene.geometry.regions.iter().map(|r| r.name.as_str()),
                ) {
                    d = d.with_hint(format!(
                        "did you mean `{s}`? (a new region needs `= +body …`)"
                    ));
                } else {
                    d = d.with_hint("a new region is written `REGION name = +body -body …`");
                }
                return Err(d);
            }
        }
    };
    while let Some(t) = ln.next() {
        match t.text.to_ascii_uppercase().as_str() {
            "COLOR" | "COLOUR" => props.colour = Some(colour(ln, cx)?),
            "K" => {
                let k = ln.number(cx, "the reflectivity k")?;
                if !(0.0..=1.0).contains(&k) {
                    return Err(cx.err(
                        t,
                        format!("reflectivity k must lie between 0 and 1 (is {k})"),
                    ));
                }
                props.k = k;
            }
            "TRANSPARENT" => props.transparent = true,
            "OPAQUE" => props.transparent = false,
            "DENSITY" => props.density = Some(ln.number(cx, "the density (g/cm³)")?),
            other => {
                let mut d = cx.err(t, format!("unknown region property `{}`", t.text));
                if let Some(s) = did_you_mean(other, REGION_PROPS.iter().copied()) {
                    d = d.with_hint(format!("did you mean `{s}`?"));
                }
                return Err(d);
            }
        }
    }
    scene.regions[idx] = props;
    Ok(())
}

fn camera(ln: &mut Line, cx: &mut Ctx) -> Result<Camera, Diagnostic> {
    let mut cam = Camera::default();
    let mut ortho = false;
    let (mut eye, mut at, mut dir) = (None, None, None);
    let mut lens = None;
    const WORDS: &[&str] = &[
        "PERSPECTIVE",
        "ORTHO",
        "EYE",
        "AT",
        "DIR",
        "UP",
        "FOV",
        "FOCAL",
        "FILM",
        "HEIGHT",
    ];
    let mut focal = None;
    let mut film = None;
    while let Some(t) = ln.next() {
        match t.text.to_ascii_uppercase().as_str() {
            "PERSPECTIVE" => ortho = false,
            "ORTHO" | "ORTHOGRAPHIC" => ortho = true,
            "EYE" => eye = Some(ln.vec3(cx, "the eye point")?),
            "AT" => at = Some(ln.vec3(cx, "the aim point")?),
            "DIR" => dir = Some(ln.vec3(cx, "the view direction")?),
            "UP" => cam.up = ln.vec3(cx, "the up vector")?,
            "FOV" => {
                let f = ln.number(cx, "the field of view (degrees)")?;
                if !(f > 0.0 && f < 180.0) {
                    return Err(cx.err(
                        t,
                        format!("field of view must lie between 0 and 180 degrees (is {f})"),
                    ));
                }
                lens = Some(Lens::Fov { vertical_deg: f });
            }
            "FOCAL" => focal = Some(ln.number(cx, "the focal distance")?),
            "FILM" => film = Some(ln.number(cx, "the film height")?),
            "HEIGHT" => {
                lens = Some(Lens::Ortho {
                    height: ln.number(cx, "the view height")?,
                })
            }
            other => {
                let mut d = cx.err(t, format!("unknown camera setting `{}`", t.text));
                if let Some(s) = did_you_mean(other, WORDS.iter().copied()) {
                    d = d.with_hint(format!("did you mean `{s}`?"));
                }
                return Err(d);
            }
        }
    }
    let e0 = ln.end_token();
    cam.eye = eye.ok_or_else(|| {
        cx.err(&e0, "the camera needs an EYE point")
            .with_hint("CAMERA EYE (x,y,z) AT (x,y,z)")
    })?;
    cam.dir = match (at, dir) {
        (Some(a), None) => a - cam.eye,
        (None, Some(d)) => d,
        _ => {
            return Err(cx.err(
                &e0,
                "the camera needs exactly one of AT (aim point) or DIR (direction)",
            ))
        }
    };
    if cam.dir.length_squared() == 0.0 {
        return Err(cx.err(&e0, "the aim point coincides with the eye"));
    }
    if let (Some(f), Some(h)) = (focal, film) {
        if f <= 0.0 || h <= 0.0 {
            return Err(cx.err(&e0, "FOCAL and FILM must be positive"));
        }
        lens = Some(Lens::Focal {
            focal: f,
            film_height: h,
        });
    } else if focal.is_some() != film.is_some() {
        return Err(cx.err(
            &e0,
            "FOCAL needs FILM (the film height) and FILM needs FOCAL",
        ));
    }
    cam.lens = match (ortho, lens) {
        (true, Some(l @ Lens::Ortho { .. })) => l,
        (true, _) => {
            return Err(cx.err(
                &e0,
                "an ORTHO camera needs HEIGHT (the visible height in model units)",
            ))
        }
        (false, Some(Lens::Ortho { .. })) => {
            return Err(cx.err(
                &e0,
                "HEIGHT belongs to ORTHO cameras; use FOV or FOCAL/FILM",
            ))
        }
        (false, Some(l)) => l,
        (false, None) => Lens::Fov { vertical_deg: 40.0 },
    };
    Ok(cam)
}

fn light(ln: &mut Line, cx: &mut Ctx) -> Result<Light, Diagnostic> {
    let name = ln.word(cx, "a light name")?.text.clone();
    let kt = ln.word(cx, "PARALLEL or POINT")?;
    let parallel = match kt.text.to_ascii_uppercase().as_str() {
        "PARALLEL" | "SUN" => true,
        "POINT" => false,
        _ => {
            return Err(cx.err(
                kt,
                format!("expected PARALLEL or POINT, found `{}`", kt.text),
            ))
        }
    };
    let (mut dir, mut pos, mut decay) = (None, None, 0.0);
    let mut l = Light {
        name,
        kind: LightKind::Parallel { dir: -DVec3::Z },
        intensity: 1.0,
        colour: [1.0; 3],
    };
    while let Some(t) = ln.next() {
        match t.text.to_ascii_uppercase().as_str() {
            "DIR" if parallel => dir = Some(ln.vec3(cx, "the light direction")?),
            "AT" if !parallel => pos = Some(ln.vec3(cx, "the light position")?),
            "DECAY" if !parallel => decay = ln.number(cx, "the decay exponent n")?,
            "INTENSITY" => l.intensity = ln.number(cx, "the intensity")?,
            "COLOR" | "COLOUR" => l.colour = colour(ln, cx)?,
            _ => {
                let hint = if parallel {
                    "a PARALLEL light takes DIR, INTENSITY, COLOR"
                } else {
                    "a POINT light takes AT, INTENSITY, DECAY, COLOR"
                };
                return Err(cx
                    .err(t, format!("unexpected `{}` in a light", t.text))
                    .with_hint(hint));
            }
        }
    }
    let e0 = ln.end_token();
    l.kind = if parallel {
        let d = dir.ok_or_else(|| {
            cx.err(
                &e0,
                "a PARALLEL light needs DIR (the direction the light travels)",
            )
        })?;
        if d.length_squared() == 0.0 {
            return Err(cx.err(&e0, "the light direction is zero"));
        }
        LightKind::Parallel { dir: d }
    } else {
        LightKind::Point {
            pos: pos.ok_or_else(|| cx.err(&e0, "a POINT light needs AT (its position)"))?,
            decay,
        }
    };
    Ok(l)
}

fn include(
    t: &Token,
    cx: &mut Ctx,
    opts: &LoadOptions,
    scene: &mut Scene,
    warnings: &mut Vec<Diagnostic>,
    stack: &mut Vec<PathBuf>,
    units_set: &mut bool,
) {
    let base = Path::new(&cx.src.name).parent().unwrap_or(Path::new(""));
    let path = base.join(&t.text);
    if stack.len() > MAX_INCLUDE_DEPTH || stack.iter().any(|p| same_file(p, &path)) {
        let d = cx
            .err(t, format!("`{}` includes itself", t.text))
            .with_hint("remove the circular INCLUDE");
        cx.report(d);
        return;
    }
    let text = match std::fs::read(&path) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) => {
            let d = cx.err(t, format!("cannot read `{}`: {e}", path.display()));
            cx.report(d);
            return;
        }
    };
    let src = SourceFile::new(path.display().to_string(), text);
    let format = crate::Format::detect(&path, &src.text);
    let loaded = if format == crate::Format::Native {
        // An included scene is read on its own, then merged (and scaled
        // into this scene's units) like any deck; without UNITS of its own
        // it is in the including scene's units.
        let mut inner = Scene::default();
        let mut inner_units_set = false;
        let before = cx.diags.errors().count();
        stack.push(path);
        read_into(
            &src,
            opts,
            &mut inner,
            cx.diags,
            warnings,
            stack,
            &mut inner_units_set,
        );
        stack.pop();
        if !inner_units_set {
            inner.units = scene.units;
        }
        if cx.diags.errors().count() > before {
            return;
        }
        Ok(Loaded {
            scene: inner,
            warnings: Vec::new(),
            format: crate::Format::Native,
        })
    } else {
        crate::load_source(&src, format, opts)
    };
    match loaded {
        Ok(loaded) => {
            warnings.extend(loaded.warnings);
            // A scene that has not said its units takes those of the first
            // model it includes.
            if !*units_set && scene.geometry.bodies.is_empty() {
                scene.units = loaded.scene.units;
                *units_set = true;
            }
            let tag = Path::new(&t.text)
                .file_stem()
                .map_or(t.text.clone(), |s| s.to_string_lossy().into_owned());
            if let Err(MergeError::Region(r)) = merge(scene, loaded.scene, &tag, Clash::Rename) {
                let d = cx.err(
                    t,
                    format!("region `{r}` is defined both here and in the included file"),
                );
                cx.report(d);
            }
        }
        Err(LoadError::Invalid(ds)) => cx.diags.items.extend(ds.items),
        Err(e) => {
            let d = cx.err(t, e.to_string());
            cx.report(d);
        }
    }
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

/// Why a scene cannot be merged into another.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MergeError {
    /// A region of this name is in both scenes.
    Region(String),
}

/// What [`merge`] does with a region whose name is taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clash {
    /// Refuse the merge (names matter to the caller, as in a film script).
    Refuse,
    /// Rename the incoming region `tag/name`.
    Rename,
}

/// Add `other` to `scene`: its bodies (a body whose name is taken becomes
/// `tag/name`; regions as `regions` says), its regions (body references shifted), its lights whose
/// names are new, and its notes; camera, picture size and title are taken
/// only where `scene` has none. `other` is scaled from its units into the
/// scene's. A region name in both scenes is an error, and `scene` is then
/// left unchanged.
pub fn merge(
    scene: &mut Scene,
    mut other: Scene,
    tag: &str,
    regions: Clash,
) -> Result<(), MergeError> {
    for r in &mut other.geometry.regions {
        if scene.geometry.region_index(&r.name).is_some() {
            match regions {
                Clash::Refuse => return Err(MergeError::Region(r.name.clone())),
                Clash::Rename => r.name = format!("{tag}/{}", r.name),
            }
        }
    }
    let offset = scene.geometry.bodies.len();
    if other.units != scene.units {
        let f = other.units.mm() / scene.units.mm();
        let xf = sv_math::DAffine3::from_scale(DVec3::splat(f));
        for b in &mut other.geometry.bodies {
            // A uniform positive scale is a similarity: it cannot fail.
            if let Ok(scaled) = b.transformed(&xf) {
                *b = scaled;
            }
        }
    }
    for mut b in other.geometry.bodies {
        if scene.geometry.body_index(&b.name).is_some() {
            b.name = format!("{tag}/{}", b.name);
        }
        scene.geometry.bodies.push(b);
    }
    for (mut r, p) in other.geometry.regions.into_iter().zip(other.regions) {
        for z in &mut r.zones {
            for t in &mut z.terms {
                t.body += offset;
            }
        }
        scene.push_region(r, p);
    }
    if scene.title.is_empty() {
        scene.title = other.title;
    }
    scene.notes.extend(other.notes);
    for l in other.lights {
        if !scene
            .lights
            .iter()
            .any(|m| m.name.eq_ignore_ascii_case(&l.name))
        {
            scene.lights.push(l);
        }
    }
    scene.camera = scene.camera.or(other.camera);
    scene.size = scene.size.or(other.size);
    Ok(())
}

fn fmt_num(v: f64) -> String {
    // Shortest text that reads back to the same f64.
    let s = format!("{v}");
    if s.parse::<f64>().ok() == Some(v) {
        s
    } else {
        format!("{v:e}")
    }
}

/// Write a scene in the native language; reading it back gives the same
/// scene (bodies, regions, properties, camera, lights).
pub fn write(scene: &Scene) -> String {
    let mut s = String::new();
    if !scene.title.is_empty() {
        s.push_str(&format!("TITLE {}\n", scene.title));
    }
    s.push_str(&format!("UNITS {}\n\n", scene.units.abbrev()));
    let names: Vec<String> = scene
        .geometry
        .bodies
        .iter()
        .map(|b| quote_name(&b.name))
        .collect();
    for (b, n) in scene.geometry.bodies.iter().zip(&names) {
        let vals: Vec<String> = b.params.iter().map(|v| fmt_num(*v)).collect();
        s.push_str(&format!("BODY {n} {} {}\n", b.kind, vals.join(" ")));
    }
    s.push('\n');
    for (r, p) in scene.geometry.regions.iter().zip(&scene.regions) {
        let zones: Vec<String> = r
            .zones
            .iter()
            .map(|z| z.expression(|b| &names[b]))
            .collect();
        s.push_str(&format!(
            "REGION {} = {}",
            quote_name(&r.name),
            zones.join(" OR ")
        ));
        if let Some(c) = p.colour {
            s.push_str(&format!(
                " COLOR {} {} {}",
                fmt_num(c[0]),
                fmt_num(c[1]),
                fmt_num(c[2])
            ));
        }
        s.push_str(&format!(" K {}", fmt_num(p.k)));
        if p.transparent {
            s.push_str(" TRANSPARENT");
        }
        if let Some(d) = p.density {
            s.push_str(&format!(" DENSITY {}", fmt_num(d)));
        }
        s.push('\n');
    }
    s.push('\n');
    let v = |d: DVec3| format!("({}, {}, {})", fmt_num(d.x), fmt_num(d.y), fmt_num(d.z));
    if let Some(c) = &scene.camera {
        let lens = match c.lens {
            Lens::Fov { vertical_deg } => format!("FOV {}", fmt_num(vertical_deg)),
            Lens::Focal { focal, film_height } => {
                format!("FOCAL {} FILM {}", fmt_num(focal), fmt_num(film_height))
            }
            Lens::Ortho { height } => format!("HEIGHT {}", fmt_num(height)),
        };
        let ortho = if matches!(c.lens, Lens::Ortho { .. }) {
            "ORTHO "
        } else {
            ""
        };
        s.push_str(&format!(
            "CAMERA {ortho}EYE {} DIR {} UP {} {lens}\n",
            v(c.eye),
            v(c.dir),
            v(c.up)
        ));
    }
    for l in &scene.lights {
        let kind = match l.kind {
            LightKind::Parallel { dir } => format!("PARALLEL DIR {}", v(dir)),
            LightKind::Point { pos, decay } => {
                format!("POINT AT {} DECAY {}", v(pos), fmt_num(decay))
            }
        };
        s.push_str(&format!(
            "LIGHT {} {kind} INTENSITY {} COLOR {} {} {}\n",
            l.name,
            fmt_num(l.intensity),
            fmt_num(l.colour[0]),
            fmt_num(l.colour[1]),
            fmt_num(l.colour[2])
        ));
    }
    s.push_str(&format!("AMBIENT {}\n", fmt_num(scene.ambient)));
    let Background::Colour(bg) = scene.background;
    s.push_str(&format!(
        "BACKGROUND {} {} {}\n",
        fmt_num(bg[0]),
        fmt_num(bg[1]),
        fmt_num(bg[2])
    ));
    s.push_str(&format!(
        "SHADOWS {}\n",
        if scene.shadows { "ON" } else { "OFF" }
    ));
    if let Some((w, h)) = scene.size {
        s.push_str(&format!("SIZE {w} {h}\n"));
    }
    s
}

fn quote_name(n: &str) -> String {
    // Names are single tokens; anything else is replaced so the file reads back.
    let ok = !n.is_empty()
        && n.chars().all(|c| {
            !c.is_whitespace() && !matches!(c, ',' | '(' | ')' | '#' | '=' | '"' | '+' | '-')
        });
    if ok {
        n.to_string()
    } else {
        n.chars()
            .map(|c| {
                if c.is_whitespace() || matches!(c, ',' | '(' | ')' | '#' | '=' | '"' | '+' | '-') {
                    '_'
                } else {
                    c
                }
            })
            .collect()
    }
}
