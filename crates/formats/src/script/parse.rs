//! Script text to syntax tree, with syntax errors.

use super::lex::{tokens, Tok, Token};
use crate::diag::{did_you_mean, Diagnostic, Diagnostics, SourceFile};
use sv_director::{Easing, Zoom};
use sv_math::DVec3;

/// A place in the script: 1-based line and column, length in characters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Span {
    /// Line.
    pub line: usize,
    /// Column (characters).
    pub col: usize,
    /// Length (characters).
    pub len: usize,
}

impl Span {
    fn of(t: &Token) -> Span {
        Span {
            line: t.line,
            col: t.col,
            len: t.len,
        }
    }
}

/// A name as written and where.
#[derive(Clone, Debug, PartialEq)]
pub struct Name {
    /// The text.
    pub text: String,
    /// Where it is.
    pub span: Span,
}

impl Name {
    fn of(t: &Token) -> Name {
        Name {
            text: t.shown(),
            span: Span::of(t),
        }
    }
}

/// How long a change lasts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Duration {
    /// A number of frames.
    Frames(usize),
    /// Seconds, turned into frames with the script's frame rate.
    Seconds(f64),
}

/// What MOVE and TURN act on, before names are looked up.
#[derive(Clone, Debug, PartialEq)]
pub enum TargetAst {
    /// `CAMERA`.
    Camera(Span),
    /// `LIGHT name`.
    Light(Name),
    /// A name: an object, else a light.
    Named(Name),
}

/// Where AIM points.
#[derive(Clone, Debug, PartialEq)]
pub enum AimAst {
    /// A point.
    Point(DVec3),
    /// An object.
    Object(Name),
}

/// A change command.
#[derive(Clone, Debug, PartialEq)]
pub enum CmdKind {
    /// `MOVE target (dx,dy,dz)`.
    Move(TargetAst, DVec3),
    /// `TURN target (AXIS a, degrees)`.
    Turn(TargetAst, Name, f64),
    /// `SPIN object (AXIS a, degrees) [PER FRAME]`.
    Spin(Name, Name, f64),
    /// `STOP object`.
    Stop(Name),
    /// `STOP CAMERA` (ends TRACK).
    StopTrack,
    /// `AIM [CAMERA] AT …`.
    Aim(AimAst),
    /// `TRACK [CAMERA] object`.
    Track(Name),
    /// `ZOOM [CAMERA] FOV|FOCAL|HEIGHT v`; the film height of FOCAL is
    /// `None` when not given.
    Zoom(Zoom, Option<f64>),
    /// `INTENSITY [LIGHT] name value`.
    Intensity(Name, f64),
}

/// A change command with its timing.
#[derive(Clone, Debug, PartialEq)]
pub struct Cmd {
    /// What it does.
    pub kind: CmdKind,
    /// `OVER …`, if given.
    pub over: Option<(Duration, Easing)>,
    /// The command keyword.
    pub span: Span,
}

/// One statement of the film part of a script.
#[derive(Clone, Debug, PartialEq)]
pub enum Block {
    /// A change.
    Cmd(Cmd),
    /// `TOGETHER … END`.
    Together(Vec<Cmd>, Span),
    /// `SHOOT [n]`, `FRAME [n]`, `HOLD n`.
    Shoot(usize, Span),
    /// `REPEAT n … END`.
    Repeat(usize, Vec<Block>, Span),
}

/// `CAMERA` line of the header.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraAst {
    /// Eye point.
    pub eye: DVec3,
    /// Point looked at.
    pub at: DVec3,
    /// Up vector.
    pub up: DVec3,
    /// Lens.
    pub lens: sv_scene::Lens,
    /// The keyword.
    pub span: Span,
}

/// `OBJECT` line.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectAst {
    /// Its name.
    pub name: Name,
    /// Region names.
    pub regions: Vec<Name>,
    /// Carried objects.
    pub contains: Vec<Name>,
}

/// `AXIS` line.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisAst {
    /// Its name.
    pub name: Name,
    /// Point.
    pub point: DVec3,
    /// Direction.
    pub dir: DVec3,
    /// Carrying object.
    pub on: Option<Name>,
}

/// A whole script as written.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct ScriptAst {
    /// `SCENE` file names as written, with the span of each.
    pub scenes: Vec<(String, Span)>,
    /// `FPS`.
    pub fps: Option<(f64, Span)>,
    /// `SIZE`.
    pub size: Option<((u32, u32), Span)>,
    /// `CAMERA`.
    pub camera: Option<CameraAst>,
    /// Objects.
    pub objects: Vec<ObjectAst>,
    /// Axes.
    pub axes: Vec<AxisAst>,
    /// The film.
    pub blocks: Vec<Block>,
    /// Names (upper case) of objects and axes whose declaration has a
    /// syntax error: uses of them are not reported again as unknown.
    pub broken: Vec<String>,
}

/// Every statement keyword, for suggestions.
pub const KEYWORDS: &[&str] = &[
    "SCENE",
    "FPS",
    "SIZE",
    "CAMERA",
    "OBJECT",
    "AXIS",
    "MOVE",
    "TURN",
    "SPIN",
    "STOP",
    "AIM",
    "TRACK",
    "ZOOM",
    "INTENSITY",
    "SHOOT",
    "FRAME",
    "HOLD",
    "REPEAT",
    "TOGETHER",
    "END",
];

type PResult<T> = Result<T, Diagnostic>;

struct Line<'a> {
    src: &'a SourceFile,
    toks: Vec<Token>,
    pos: usize,
    line: usize,
    end_col: usize,
}

impl<'a> Line<'a> {
    fn err_at(&self, t: &Token, msg: impl Into<String>) -> Diagnostic {
        Diagnostic::error_at(self.src, t.line, t.col, t.len, msg)
    }

    fn peek(&self) -> Option<&Token> {
        self.toks.get(self.pos)
    }

    fn next(&mut self, what: &str) -> PResult<Token> {
        match self.toks.get(self.pos) {
            Some(t) => {
                self.pos += 1;
                Ok(t.clone())
            }
            None => Err(self.missing(what)),
        }
    }

    fn missing(&self, what: &str) -> Diagnostic {
        Diagnostic::error_at(
            self.src,
            self.line,
            self.end_col,
            0,
            format!("expected {what} at the end of the line"),
        )
    }

    fn expected(&self, t: &Token, what: &str) -> Diagnostic {
        self.err_at(t, format!("expected {what}, found `{}`", t.shown()))
    }

    fn eat(&mut self, kw: &str) -> bool {
        if self.peek().is_some_and(|t| t.is(kw)) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn eat_tok(&mut self, tok: &Tok) -> bool {
        if self.peek().is_some_and(|t| &t.tok == tok) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn expect_kw(&mut self, kw: &str) -> PResult<Token> {
        let what = format!("`{kw}`");
        let t = self.next(&what)?;
        if t.is(kw) {
            Ok(t)
        } else {
            Err(self.expected(&t, &what))
        }
    }

    fn expect_tok(&mut self, tok: Tok, what: &str) -> PResult<Token> {
        let t = self.next(what)?;
        if t.tok == tok {
            Ok(t)
        } else {
            Err(self.expected(&t, what))
        }
    }

    fn number(&mut self) -> PResult<f64> {
        let t = self.next("a number")?;
        parse_number(&t).ok_or_else(|| self.expected(&t, "a number"))
    }

    fn positive(&mut self, what: &str) -> PResult<f64> {
        let t = self.next(what)?;
        match parse_number(&t) {
            Some(v) if v > 0.0 => Ok(v),
            _ => Err(self.expected(&t, what)),
        }
    }

    fn count(&mut self, what: &str, max: usize) -> PResult<usize> {
        let t = self.next(what)?;
        match t.word().and_then(|w| w.parse::<usize>().ok()) {
            Some(n) if n >= 1 && n <= max => Ok(n),
            _ => Err(self.expected(&t, what)),
        }
    }

    fn name(&mut self, what: &str) -> PResult<Name> {
        let t = self.next(what)?;
        match t.tok {
            Tok::Word(_) => Ok(Name::of(&t)),
            _ => Err(self.expected(&t, what)),
        }
    }

    /// `(x, y, z)`, commas optional.
    fn triple(&mut self) -> PResult<DVec3> {
        self.expect_tok(Tok::Open, "`(`")?;
        let x = self.number()?;
        self.eat_tok(&Tok::Comma);
        let y = self.number()?;
        self.eat_tok(&Tok::Comma);
        let z = self.number()?;
        self.expect_tok(Tok::Close, "`)`")?;
        Ok(DVec3::new(x, y, z))
    }

    /// `(AXIS a, degrees)`, `AXIS` and the comma optional.
    fn axis_angle(&mut self) -> PResult<(Name, f64)> {
        self.expect_tok(Tok::Open, "`(`")?;
        self.eat("AXIS");
        let axis = self.name("an axis name")?;
        self.eat_tok(&Tok::Comma);
        let deg = self.number()?;
        self.expect_tok(Tok::Close, "`)`")?;
        Ok((axis, deg))
    }

    fn target(&mut self) -> PResult<TargetAst> {
        let t = self.next("an object, `CAMERA` or `LIGHT name`")?;
        if t.is("CAMERA") {
            Ok(TargetAst::Camera(Span::of(&t)))
        } else if t.is("LIGHT") {
            Ok(TargetAst::Light(self.name("a light name")?))
        } else if t.word().is_some() {
            Ok(TargetAst::Named(Name::of(&t)))
        } else {
            Err(self.expected(&t, "an object, `CAMERA` or `LIGHT name`"))
        }
    }

    fn timing(&mut self) -> PResult<Option<(Duration, Easing)>> {
        if !self.eat("OVER") {
            return Ok(None);
        }
        let t = self.next("a number of frames or seconds")?;
        let v = parse_number(&t).filter(|v| *v > 0.0);
        let d = if self.eat("SECONDS") || self.eat("SECOND") || self.eat("S") {
            Duration::Seconds(v.ok_or_else(|| self.expected(&t, "a number of seconds above 0"))?)
        } else {
            let _ = self.eat("FRAMES") || self.eat("FRAME");
            match t.word().and_then(|w| w.parse::<usize>().ok()) {
                Some(n) if (1..=sv_director::MAX_FRAMES).contains(&n) => Duration::Frames(n),
                _ => return Err(self.expected(&t, "a whole number of frames (at least 1)")),
            }
        };
        let easing = if self.eat("SMOOTH") {
            Easing::Smooth
        } else {
            self.eat("LINEAR");
            Easing::Linear
        };
        Ok(Some((d, easing)))
    }

    fn finish(&self) -> PResult<()> {
        match self.peek() {
            Some(t) => Err(self.err_at(t, format!("unexpected `{}` after the command", t.shown()))),
            None => Ok(()),
        }
    }
}

fn parse_number(t: &Token) -> Option<f64> {
    t.word()
        .and_then(|w| w.parse::<f64>().ok())
        .filter(|v| v.is_finite())
}

struct Open {
    kind: &'static str,
    span: Span,
    count: usize,
    blocks: Vec<Block>,
    cmds: Vec<Cmd>,
}

/// Parse a script; statements with errors are left out and every error is
/// reported.
pub fn parse(src: &SourceFile) -> (ScriptAst, Diagnostics) {
    let mut ast = ScriptAst::default();
    let mut diags = Diagnostics::default();
    let mut stack: Vec<Open> = Vec::new();
    let mut top: Vec<Block> = Vec::new();
    for (i, text) in src.text.lines().enumerate() {
        let line_no = i + 1;
        let toks = match tokens(line_no, text) {
            Ok(t) => t,
            Err(u) => {
                diags.push(
                    Diagnostic::error_at(src, line_no, u.col, u.len, "unterminated string")
                        .with_hint("close it with `\"`"),
                );
                continue;
            }
        };
        if toks.is_empty() {
            continue;
        }
        let end_col = text
            .split('#')
            .next()
            .unwrap_or("")
            .trim_end()
            .chars()
            .count()
            + 1;
        let mut l = Line {
            src,
            toks,
            pos: 0,
            line: line_no,
            end_col,
        };
        if let Err(d) = statement(&mut l, &mut ast, &mut stack, &mut top) {
            diags.push(d);
        }
    }
    while let Some(open) = stack.pop() {
        diags.push(
            Diagnostic::error_at(
                src,
                open.span.line,
                open.span.col,
                open.span.len,
                format!("{} without END", open.kind),
            )
            .with_hint("close the block with `END`"),
        );
        // Keep what the block held so that its names are still checked.
        let block = match open.kind {
            "TOGETHER" => Block::Together(open.cmds, open.span),
            _ => Block::Repeat(open.count, open.blocks, open.span),
        };
        match stack.last_mut() {
            Some(outer) => outer.blocks.push(block),
            None => top.push(block),
        }
    }
    if ast.scenes.is_empty() {
        diags.push(
            Diagnostic::error_at(src, 1, 1, 0, "the script names no scene")
                .with_hint("start the script with `SCENE \"file.sv\"`"),
        );
    }
    ast.blocks = top;
    diags.items.sort_by_key(|d| d.offset);
    (ast, diags)
}

fn statement(
    l: &mut Line,
    ast: &mut ScriptAst,
    stack: &mut Vec<Open>,
    top: &mut Vec<Block>,
) -> PResult<()> {
    let kw = l.next("a command")?;
    let Some(word) = kw.word().map(|w| w.to_ascii_uppercase()) else {
        return Err(l.expected(&kw, "a command"));
    };
    let span = Span::of(&kw);
    let in_together = stack.last().is_some_and(|o| o.kind == "TOGETHER");
    let header_or_block = matches!(
        word.as_str(),
        "SCENE"
            | "FPS"
            | "SIZE"
            | "CAMERA"
            | "OBJECT"
            | "AXIS"
            | "SHOOT"
            | "FRAME"
            | "HOLD"
            | "REPEAT"
            | "TOGETHER"
    );
    if in_together && header_or_block {
        return Err(l
            .err_at(&kw, format!("{word} cannot be used inside TOGETHER"))
            .with_hint("TOGETHER holds changes that run over the same frames; put this before or after the block"));
    }
    let mut push = |b: Block, stack: &mut Vec<Open>| match stack.last_mut() {
        Some(o) => o.blocks.push(b),
        None => top.push(b),
    };
    match word.as_str() {
        "SCENE" => {
            let t = l.next("a quoted file name")?;
            let Tok::Str(s) = &t.tok else {
                return Err(l.expected(&t, "a quoted file name"));
            };
            ast.scenes.push((s.clone(), Span::of(&t)));
        }
        "FPS" => {
            let v = l.positive("a frame rate above 0")?;
            if let Some((_, at)) = ast.fps {
                return Err(l.err_at(&kw, format!("FPS is already set on line {}", at.line)));
            }
            ast.fps = Some((v, span));
        }
        "SIZE" => {
            let w = l.count("a width in pixels", 1 << 16)?;
            let h = l.count("a height in pixels", 1 << 16)?;
            if let Some((_, at)) = ast.size {
                return Err(l.err_at(&kw, format!("SIZE is already set on line {}", at.line)));
            }
            ast.size = Some(((w as u32, h as u32), span));
        }
        "CAMERA" => {
            l.expect_kw("EYE")?;
            let eye = l.triple()?;
            l.expect_kw("AT")?;
            let at = l.triple()?;
            let up = if l.eat("UP") { l.triple()? } else { DVec3::Z };
            let lens = if l.eat("FOV") {
                sv_scene::Lens::Fov {
                    vertical_deg: l.positive("an angle above 0")?,
                }
            } else if l.eat("FOCAL") {
                let focal = l.positive("a focal length above 0")?;
                let film_height = if l.eat("FILM") {
                    l.positive("a film height above 0")?
                } else {
                    24.0
                };
                sv_scene::Lens::Focal { focal, film_height }
            } else if l.eat("ORTHO") {
                sv_scene::Lens::Ortho {
                    height: l.positive("a height above 0")?,
                }
            } else {
                sv_scene::Lens::Fov { vertical_deg: 40.0 }
            };
            if let Some(c) = &ast.camera {
                return Err(l.err_at(
                    &kw,
                    format!("CAMERA is already set on line {}", c.span.line),
                ));
            }
            l.finish()?;
            ast.camera = Some(CameraAst {
                eye,
                at,
                up,
                lens,
                span,
            });
            return Ok(());
        }
        "OBJECT" => {
            let name = l.name("an object name")?;
            ast.broken.push(name.text.to_ascii_uppercase());
            if !l.eat("REGIONS") {
                l.eat("REGION");
            }
            let mut regions = Vec::new();
            let mut contains = Vec::new();
            let mut in_contains = false;
            while let Some(t) = l.peek().cloned() {
                l.pos += 1;
                if t.is("CONTAINS") && !in_contains {
                    in_contains = true;
                    continue;
                }
                l.eat_tok(&Tok::Comma);
                let n = match t.tok {
                    Tok::Word(_) => Name::of(&t),
                    Tok::Comma => continue,
                    _ => {
                        return Err(l.expected(
                            &t,
                            if in_contains {
                                "an object name"
                            } else {
                                "a region name"
                            },
                        ))
                    }
                };
                if in_contains {
                    contains.push(n);
                } else {
                    regions.push(n);
                }
            }
            if in_contains && contains.is_empty() {
                return Err(l.missing("an object name"));
            }
            ast.broken.pop();
            ast.objects.push(ObjectAst {
                name,
                regions,
                contains,
            });
            return Ok(());
        }
        "AXIS" => {
            let name = l.name("an axis name")?;
            ast.broken.push(name.text.to_ascii_uppercase());
            l.expect_kw("POINT")?;
            let point = l.triple()?;
            let dir_kw = l.expect_kw("DIR")?;
            let dir = l.triple()?;
            if dir.length_squared() == 0.0 {
                return Err(l.err_at(&dir_kw, "the axis direction must not be zero"));
            }
            let on = if l.eat("ON") {
                Some(l.name("an object name")?)
            } else {
                None
            };
            l.finish()?;
            ast.broken.pop();
            ast.axes.push(AxisAst {
                name,
                point,
                dir,
                on,
            });
            return Ok(());
        }
        "SHOOT" | "FRAME" | "HOLD" => {
            let n = if word == "HOLD" || l.peek().is_some() {
                l.count(
                    "a whole number of frames (at least 1)",
                    sv_director::MAX_FRAMES,
                )?
            } else {
                1
            };
            l.finish()?;
            push(Block::Shoot(n, span), stack);
            return Ok(());
        }
        "REPEAT" => {
            // The block is opened even when the count is wrong, so that its
            // END is not reported as well.
            let n = l.count("a repeat count (at least 1)", sv_director::MAX_FRAMES);
            let _ = l.eat("TIMES");
            let rest = l.finish();
            stack.push(Open {
                kind: "REPEAT",
                span,
                count: *n.as_ref().unwrap_or(&0),
                blocks: Vec::new(),
                cmds: Vec::new(),
            });
            n?;
            return rest;
        }
        "TOGETHER" => {
            stack.push(Open {
                kind: "TOGETHER",
                span,
                count: 1,
                blocks: Vec::new(),
                cmds: Vec::new(),
            });
            return l.finish();
        }
        "END" => {
            let _ = l.eat("REPEAT") || l.eat("TOGETHER");
            l.finish()?;
            let Some(open) = stack.pop() else {
                return Err(l.err_at(&kw, "END without REPEAT or TOGETHER"));
            };
            let b = match open.kind {
                "TOGETHER" => Block::Together(open.cmds, open.span),
                _ => Block::Repeat(open.count, open.blocks, open.span),
            };
            push(b, stack);
            return Ok(());
        }
        "MOVE" | "TURN" | "SPIN" | "STOP" | "AIM" | "TRACK" | "ZOOM" | "INTENSITY" => {
            let kind = command(l, &word)?;
            let over = if matches!(
                kind,
                CmdKind::Spin(..) | CmdKind::Stop(_) | CmdKind::StopTrack | CmdKind::Track(_)
            ) {
                None
            } else {
                l.timing()?
            };
            l.finish()?;
            let cmd = Cmd { kind, over, span };
            match stack.last_mut() {
                Some(o) if o.kind == "TOGETHER" => o.cmds.push(cmd),
                _ => push(Block::Cmd(cmd), stack),
            }
            return Ok(());
        }
        _ => {
            let mut d = l.err_at(&kw, format!("unknown command `{}`", kw.shown()));
            if let Some(s) = did_you_mean(&word, KEYWORDS.iter().copied()) {
                d = d.with_hint(format!("did you mean `{s}`?"));
            }
            return Err(d);
        }
    }
    l.finish()
}

fn command(l: &mut Line, word: &str) -> PResult<CmdKind> {
    Ok(match word {
        "MOVE" => {
            let t = l.target()?;
            CmdKind::Move(t, l.triple()?)
        }
        "TURN" => {
            let t = l.target()?;
            let (a, d) = l.axis_angle()?;
            CmdKind::Turn(t, a, d)
        }
        "SPIN" => {
            let o = l.name("an object name")?;
            let (a, d) = l.axis_angle()?;
            if l.eat("PER") {
                l.expect_kw("FRAME")?;
            }
            CmdKind::Spin(o, a, d)
        }
        "STOP" => {
            let t = l.name("an object name or `CAMERA`")?;
            if t.text.eq_ignore_ascii_case("CAMERA") || t.text.eq_ignore_ascii_case("TRACK") {
                CmdKind::StopTrack
            } else {
                CmdKind::Stop(t)
            }
        }
        "AIM" => {
            l.eat("CAMERA");
            l.expect_kw("AT")?;
            if l.peek().is_some_and(|t| t.tok == Tok::Open) {
                CmdKind::Aim(AimAst::Point(l.triple()?))
            } else {
                CmdKind::Aim(AimAst::Object(l.name("a point or an object name")?))
            }
        }
        "TRACK" => {
            if l.toks.len() > l.pos + 1 {
                l.eat("CAMERA");
            }
            CmdKind::Track(l.name("an object name")?)
        }
        "ZOOM" => {
            l.eat("CAMERA");
            let t = l.next("`FOV`, `FOCAL` or `HEIGHT`")?;
            if t.is("FOV") {
                CmdKind::Zoom(Zoom::Fov(l.positive("an angle above 0")?), None)
            } else if t.is("FOCAL") {
                let focal = l.positive("a focal length above 0")?;
                let film = if l.eat("FILM") {
                    Some(l.positive("a film height above 0")?)
                } else {
                    None
                };
                CmdKind::Zoom(
                    Zoom::Focal {
                        focal,
                        film_height: film.unwrap_or(24.0),
                    },
                    film,
                )
            } else if t.is("HEIGHT") {
                CmdKind::Zoom(Zoom::Height(l.positive("a height above 0")?), None)
            } else {
                return Err(l.expected(&t, "`FOV`, `FOCAL` or `HEIGHT`"));
            }
        }
        _ => {
            // INTENSITY
            l.eat("LIGHT");
            let n = l.name("a light name")?;
            let v = l.number()?;
            if v < 0.0 {
                return Err(Diagnostic::error_at(
                    l.src,
                    l.line,
                    l.toks[l.pos - 1].col,
                    l.toks[l.pos - 1].len,
                    "an intensity cannot be negative",
                ));
            }
            CmdKind::Intensity(n, v)
        }
    })
}
