//! The syntax tree of a script: what the parser makes and the resolver
//! looks up.

pub use crate::diag::Span;
use crate::text::Token;
use sv_director::{Easing, Zoom};
use sv_math::DVec3;

/// A name as written and where.
#[derive(Clone, Debug, PartialEq)]
pub struct Name {
    /// The text.
    pub text: String,
    /// Where it is.
    pub span: Span,
}

impl Name {
    /// The name a token spells.
    pub(crate) fn of(t: &Token) -> Name {
        Name {
            text: t.shown(),
            span: t.span,
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
    /// `ZOOM [CAMERA] FOV|FOCAL|HEIGHT v`, with the span of the lens word.
    Zoom(Zoom, Span),
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
    /// The camera it sets.
    pub camera: sv_scene::Camera,
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
