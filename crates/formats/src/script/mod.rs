//! Director scripts (`.svs`): the director's language as text.
//!
//! A script names the scene it animates, declares objects and axes, and
//! then lists the film's commands top to bottom. It is line oriented;
//! keywords and object, axis and light names ignore case (region names are
//! matched exactly first, then ignoring case); `#` starts a comment anywhere
//! and a line starting with `*` is a comment card.
//!
//! ```text
//! SCENE "helicopter.sv"          # path relative to the script; repeatable
//! FPS 24
//! SIZE 960 720
//! CAMERA EYE (60,-80,25) AT (0,0,5) UP (0,0,1) FOV 35   # optional
//! OBJECT ROTOR REGIONS hub blade_a blade_b
//! OBJECT HELICOPTER REGIONS fuselage tailboom CONTAINS ROTOR
//! AXIS 1 POINT (0,0,0) DIR (0,0,1) ON HELICOPTER
//!
//! MOVE HELICOPTER (3,0,-1)                  # the paper's examples
//! TURN HELICOPTER (AXIS 1,15)
//! SPIN ROTOR (AXIS 1, 30) PER FRAME         # keeps turning on every frame
//! MOVE HELICOPTER (30,0,0) OVER 48 FRAMES   # shoots 48 frames
//! TOGETHER                                  # changes over the same frames
//!   MOVE HELICOPTER (0,0,10) OVER 2 SECONDS SMOOTH
//!   TURN CAMERA (AXIS 1, 20) OVER 24
//!   AIM CAMERA AT HELICOPTER
//! END
//! REPEAT 4
//!   TURN HELICOPTER (AXIS 1, 90) OVER 12
//!   HOLD 6
//! END
//! SHOOT
//! ```
//!
//! Commands:
//!
//! | command | effect |
//! |---|---|
//! | `MOVE target (dx,dy,dz)` | translate an object (and what it carries), `CAMERA`, or a point light (`LIGHT name` or just the name) |
//! | `TURN target (AXIS a, degrees)` | rotate about an axis (`AXIS` and the comma are optional) |
//! | `SPIN object (AXIS a, degrees) [PER FRAME]` | turn an object by that much on every frame shot from then on |
//! | `STOP object` / `STOP CAMERA` | end a SPIN / end TRACK |
//! | `AIM [CAMERA] AT (x,y,z)` / `AT object` | point the camera |
//! | `TRACK [CAMERA] object` | re-aim the camera at the object on every frame |
//! | `ZOOM [CAMERA] FOV deg` / `FOCAL f [FILM h]` / `HEIGHT h` | change the lens |
//! | `INTENSITY [LIGHT] name value` | change a light's intensity |
//! | `SHOOT [n]`, `FRAME [n]` | shoot n frames (1) with the current set-up |
//! | `HOLD n` | shoot n frames (spinning objects keep spinning) |
//! | `REPEAT n … END` | repeat the commands n times |
//! | `TOGETHER … END` | run the changes inside over the same frames |
//!
//! MOVE, TURN, AIM, ZOOM and INTENSITY take `OVER n [FRAMES]` or
//! `OVER x SECONDS`, optionally followed by `SMOOTH` (slow in and out): the
//! change is spread over that many frames, which are shot. Without OVER a
//! change applies at once and shoots nothing. See [`sv_director`] for the
//! exact timing rules.
//!
//! The whole script is checked before any frame is made: every unknown
//! command, object, axis, region or light is reported with its line, column
//! and a suggestion.
//!
//! ```
//! use sv_formats::{script::build_timeline, SourceFile};
//! use sv_geom::{Body, BodyKind, Op, Region, Term, Zone};
//! use sv_scene::{RegionProps, Scene};
//! let mut scene = Scene::default();
//! scene.geometry.bodies.push(Body::new("1", BodyKind::Sph, vec![0.0, 0.0, 5.0, 1.0]));
//! let zone = Zone { terms: vec![Term { op: Op::Inside, body: 0 }] };
//! scene.push_region(Region { name: "fuselage".into(), zones: vec![zone] }, RegionProps::default());
//!
//! let text = "SCENE \"helicopter.sv\"\nOBJECT HELICOPTER REGIONS fuselage\n\
//!             AXIS 1 POINT (2,0,0) DIR (0,0,1)\nMOVE HELICOPTER (3,0,-1)\n\
//!             TURN HELICOPTER (AXIS 1,15) OVER 3 FRAMES\n";
//! let timeline = build_timeline(&SourceFile::new("film.svs", text), &scene).unwrap();
//! assert_eq!(timeline.frame_count(), 3);
//! let last = timeline.scene_at(&scene, 2);
//! assert!((last.geometry.bodies[0].vec3(0).z - 4.0).abs() < 1e-12);
//!
//! let bad = SourceFile::new("film.svs", "SCENE \"h.sv\"\nTURN HELICOPTR (AXIS 1,15)\n");
//! let errors = build_timeline(&bad, &scene).unwrap_err();
//! assert_eq!(errors.items[0].to_string(), "film.svs:2:6: unknown object or light `HELICOPTR`");
//! ```

mod lex;
mod parse;

pub use parse::{
    parse, AimAst, AxisAst, Block, CameraAst, Cmd, CmdKind, Duration, Name, ObjectAst, ScriptAst,
    Span, TargetAst, KEYWORDS,
};

use crate::diag::{did_you_mean, Diagnostic, Diagnostics, SourceFile};
use crate::{load_file, LoadError, LoadOptions};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use sv_director::{
    AimPoint, Axis, Change, DirectorError, Object, Owner, Spec, Step, Target, Timed, Timeline, Zoom,
};
use sv_scene::{Camera, Lens, LightKind, Scene};

/// A script read, its scene loaded and its timeline built.
#[derive(Debug)]
pub struct Film {
    /// The script text.
    pub source: SourceFile,
    /// The scene files it names, as resolved against the script's folder.
    pub scene_paths: Vec<PathBuf>,
    /// The scene at the start of the film (all `SCENE` files together).
    pub scene: Scene,
    /// The film.
    pub timeline: Timeline,
    /// Warnings from reading the scenes.
    pub warnings: Vec<Diagnostic>,
}

impl Film {
    /// The scene at `frame` (see [`Timeline::scene_at`]).
    pub fn scene_at(&self, frame: usize) -> Scene {
        self.timeline.scene_at(&self.scene, frame)
    }

    /// Digest of the film's timeline and scene (see
    /// [`Timeline::fingerprint`]); add render settings to it to key frames
    /// on disk.
    pub fn fingerprint(&self) -> String {
        self.timeline.fingerprint(&self.scene)
    }
}

/// Why a script could not be used: the script file could not be read, or
/// it (or a scene it names) has errors, all of them listed.
pub type ScriptError = LoadError;

/// Read a script file, load the scenes it names and build its timeline.
/// Every error of the script and of its scenes is reported at once.
pub fn load_script(path: &Path, opts: &LoadOptions) -> Result<Film, ScriptError> {
    let bytes = std::fs::read(path).map_err(|source| ScriptError::Io {
        path: path.to_owned(),
        source,
    })?;
    let src = SourceFile::new(
        path.display().to_string(),
        String::from_utf8_lossy(&bytes).into_owned(),
    );
    let dir = path.parent().unwrap_or(Path::new(""));
    load_source(&src, dir, opts)
}

/// [`load_script`] for text already read; scene paths are relative to `dir`.
pub fn load_source(src: &SourceFile, dir: &Path, opts: &LoadOptions) -> Result<Film, ScriptError> {
    let (ast, mut diags) = parse(src);
    let mut scene: Option<Scene> = None;
    let mut first_name = String::new();
    let mut warnings = Vec::new();
    let mut scene_paths = Vec::new();
    let mut scene_ok = true;
    for (name, span) in &ast.scenes {
        let path = dir.join(name);
        scene_paths.push(path.clone());
        match load_file(&path, opts) {
            Ok(loaded) => {
                warnings.extend(loaded.warnings);
                match scene.as_mut() {
                    None => {
                        first_name = name.clone();
                        scene = Some(loaded.scene);
                    }
                    Some(s) => {
                        if let Err(crate::native::MergeError::Region(region)) = crate::native::merge(
                            s,
                            loaded.scene,
                            &scene_tag(name),
                            crate::native::Clash::Refuse,
                        ) {
                            diags.push(at(src, *span, format!("region `{region}` of `{name}` has the same name as a region of `{first_name}`")));
                            scene_ok = false;
                        }
                    }
                }
            }
            Err(LoadError::Io { source, .. }) => {
                scene_ok = false;
                diags.push(at(
                    src,
                    *span,
                    format!("cannot read scene `{name}`: {source}"),
                ));
            }
            Err(LoadError::Invalid(d)) => {
                scene_ok = false;
                let n = d.errors().count();
                diags.push(at(
                    src,
                    *span,
                    format!(
                        "scene `{name}` has {n} error{}",
                        if n == 1 { "" } else { "s" }
                    ),
                ));
                diags.items.extend(d.items);
            }
        }
    }
    let fail = |mut diags: Diagnostics| {
        diags.items.sort_by_key(|d| {
            if d.source.name == src.name {
                (0, d.offset)
            } else {
                (1, 0)
            }
        });
        ScriptError::Invalid(diags)
    };
    let Some(scene) = scene.filter(|_| scene_ok) else {
        return Err(fail(diags));
    };
    match resolve(src, &ast, &scene) {
        Ok(timeline) if !diags.has_errors() => Ok(Film {
            source: src.clone(),
            scene_paths,
            scene,
            timeline,
            warnings,
        }),
        Ok(_) => Err(fail(diags)),
        Err(more) => {
            diags.items.extend(more.items);
            Err(fail(diags))
        }
    }
}

/// Parse a script and build its timeline for an already loaded scene (its
/// `SCENE` lines are checked for syntax only). Syntax and name errors are
/// reported together, in file order.
pub fn build_timeline(src: &SourceFile, scene: &Scene) -> Result<Timeline, Diagnostics> {
    let (ast, mut diags) = parse(src);
    match resolve(src, &ast, scene) {
        Ok(t) if !diags.has_errors() => return Ok(t),
        Ok(_) => {}
        Err(more) => diags.items.extend(more.items),
    }
    diags.items.sort_by_key(|d| d.offset);
    Err(diags)
}

/// The tag that tells apart bodies of the same name from two scenes.
fn scene_tag(name: &str) -> String {
    Path::new(name)
        .file_stem()
        .map_or_else(|| name.to_string(), |s| s.to_string_lossy().into_owned())
}

fn at(src: &SourceFile, s: Span, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::error_at(src, s.line.max(1), s.col.max(1), s.len, msg)
}

fn suggest(d: Diagnostic, word: &str, candidates: &[String]) -> Diagnostic {
    match did_you_mean(word, candidates.iter().map(String::as_str)) {
        Some(s) => d.with_hint(format!("did you mean `{s}`?")),
        None => d,
    }
}

struct Resolver<'a> {
    src: &'a SourceFile,
    scene: &'a Scene,
    objects: HashMap<String, usize>,
    object_names: Vec<String>,
    axes: HashMap<String, usize>,
    axis_names: Vec<String>,
    light_names: Vec<String>,
    has_camera: bool,
    ortho: bool,
    camera_reported: bool,
    diags: Diagnostics,
    fps: f64,
    broken: &'a [String],
}

impl Resolver<'_> {
    fn object(&mut self, n: &Name) -> Option<usize> {
        let i = self.objects.get(&n.text.to_ascii_uppercase()).copied();
        if i.is_none() && !self.broken.contains(&n.text.to_ascii_uppercase()) {
            let d = at(self.src, n.span, format!("unknown object `{}`", n.text));
            self.diags.push(suggest(d, &n.text, &self.object_names));
        }
        i
    }

    fn axis(&mut self, n: &Name) -> Option<usize> {
        let i = self.axes.get(&n.text.to_ascii_uppercase()).copied();
        if i.is_none() && !self.broken.contains(&n.text.to_ascii_uppercase()) {
            let d = at(self.src, n.span, format!("unknown axis `{}`", n.text));
            self.diags.push(suggest(d, &n.text, &self.axis_names));
        }
        i
    }

    fn find_light(&self, n: &str) -> Option<usize> {
        self.light_names
            .iter()
            .position(|l| l.eq_ignore_ascii_case(n))
    }

    fn light(&mut self, n: &Name) -> Option<usize> {
        let i = self.find_light(&n.text);
        if i.is_none() {
            let d = at(self.src, n.span, format!("unknown light `{}`", n.text));
            self.diags.push(suggest(d, &n.text, &self.light_names));
        }
        i
    }

    fn camera(&mut self, span: Span) -> bool {
        if !self.has_camera && !self.camera_reported {
            self.camera_reported = true;
            self.diags.push(
                at(
                    self.src,
                    span,
                    "the camera is not set: the scene has no CAMERA and the script none",
                )
                .with_hint("add `CAMERA EYE (x,y,z) AT (x,y,z)` to the script"),
            );
        }
        self.has_camera
    }

    fn target(&mut self, t: &TargetAst, moving: bool) -> Option<Target> {
        let target = match t {
            TargetAst::Camera(s) => {
                return self.camera(*s).then_some(Target::Camera);
            }
            TargetAst::Light(n) => Target::Light(self.light(n)?),
            TargetAst::Named(n) => {
                if let Some(&o) = self.objects.get(&n.text.to_ascii_uppercase()) {
                    return Some(Target::Object(o));
                }
                match self.find_light(&n.text) {
                    Some(l) => Target::Light(l),
                    None if self.broken.contains(&n.text.to_ascii_uppercase()) => return None,
                    None => {
                        let d = at(
                            self.src,
                            n.span,
                            format!("unknown object or light `{}`", n.text),
                        );
                        let mut all = self.object_names.clone();
                        all.extend(self.light_names.iter().cloned());
                        all.push("CAMERA".into());
                        self.diags.push(suggest(d, &n.text, &all));
                        return None;
                    }
                }
            }
        };
        if let (Target::Light(l), true) = (target, moving) {
            if matches!(self.scene.lights[l].kind, LightKind::Parallel { .. }) {
                let span = match t {
                    TargetAst::Light(n) | TargetAst::Named(n) => n.span,
                    TargetAst::Camera(s) => *s,
                };
                self.diags.push(
                    at(
                        self.src,
                        span,
                        format!(
                            "light `{}` is parallel and cannot be moved",
                            self.scene.lights[l].name
                        ),
                    )
                    .with_hint("TURN it about an axis to change its direction"),
                );
                return None;
            }
        }
        Some(target)
    }

    fn timed(&mut self, cmd: &Cmd) -> Option<Timed> {
        let change = match &cmd.kind {
            CmdKind::Move(t, by) => Change::Move {
                target: self.target(t, true)?,
                by: *by,
            },
            CmdKind::Turn(t, a, deg) => {
                let target = self.target(t, false);
                let axis = self.axis(a);
                Change::Turn {
                    target: target?,
                    axis: axis?,
                    degrees: *deg,
                }
            }
            CmdKind::Spin(o, a, deg) => {
                let object = self.object(o);
                let axis = self.axis(a);
                Change::Spin {
                    object: object?,
                    axis: axis?,
                    degrees_per_frame: *deg,
                }
            }
            CmdKind::Stop(o) => Change::Stop {
                object: self.object(o)?,
            },
            CmdKind::StopTrack => Change::Track(None),
            CmdKind::Aim(a) => {
                let point = match a {
                    AimAst::Point(p) => AimPoint::Point(*p),
                    AimAst::Object(n) => AimPoint::Object(self.object(n)?),
                };
                if !self.camera(cmd.span) {
                    return None;
                }
                Change::Aim(point)
            }
            CmdKind::Track(n) => {
                let o = self.object(n)?;
                if !self.camera(cmd.span) {
                    return None;
                }
                Change::Track(Some(o))
            }
            CmdKind::Zoom(z, _) => {
                if !self.camera(cmd.span) {
                    return None;
                }
                let wants_ortho = matches!(z, Zoom::Height(_));
                if wants_ortho != self.ortho {
                    let (what, needs) = match z {
                        Zoom::Fov(_) => ("FOV", "a perspective"),
                        Zoom::Focal { .. } => ("FOCAL", "a perspective"),
                        Zoom::Height(_) => ("HEIGHT", "an orthographic"),
                    };
                    self.diags.push(at(
                        self.src,
                        cmd.span,
                        format!("ZOOM {what} needs {needs} camera"),
                    ));
                    return None;
                }
                Change::Zoom(*z)
            }
            CmdKind::Intensity(n, v) => Change::Intensity {
                light: self.light(n)?,
                value: *v,
            },
        };
        let (frames, easing) = match cmd.over {
            None => (0, Default::default()),
            Some((Duration::Frames(n), e)) => (n, e),
            Some((Duration::Seconds(s), e)) => {
                let n = (s * self.fps).round();
                (
                    if n.is_finite() && n >= 1.0 {
                        (n as usize).min(sv_director::MAX_FRAMES)
                    } else {
                        1
                    },
                    e,
                )
            }
        };
        Some(Timed {
            change,
            frames,
            easing,
        })
    }

    fn blocks(&mut self, blocks: &[Block]) -> Vec<Step> {
        let mut out = Vec::new();
        for b in blocks {
            match b {
                Block::Cmd(c) => {
                    if let Some(t) = self.timed(c) {
                        out.push(Step::Change(t));
                    }
                }
                Block::Together(cmds, _) => {
                    let ts: Vec<Timed> = cmds.iter().filter_map(|c| self.timed(c)).collect();
                    out.push(Step::Together(ts));
                }
                Block::Shoot(n, _) => out.push(Step::Shoot(*n)),
                Block::Repeat(n, body, _) => {
                    let body = self.blocks(body);
                    out.push(Step::Repeat(*n, body));
                }
            }
        }
        out
    }
}

/// Look every name of a parsed script up in its scene and build the
/// timeline. All problems are reported together.
pub fn resolve(src: &SourceFile, ast: &ScriptAst, scene: &Scene) -> Result<Timeline, Diagnostics> {
    let camera = ast
        .camera
        .as_ref()
        .map(|c| Camera::looking_at(c.eye, c.at, c.up, c.lens));
    let start_camera = camera.or(scene.camera);
    let mut r = Resolver {
        src,
        scene,
        objects: HashMap::new(),
        object_names: Vec::new(),
        axes: HashMap::new(),
        axis_names: Vec::new(),
        light_names: scene.lights.iter().map(|l| l.name.clone()).collect(),
        has_camera: start_camera.is_some(),
        ortho: matches!(
            start_camera,
            Some(Camera {
                lens: Lens::Ortho { .. },
                ..
            })
        ),
        camera_reported: false,
        diags: Diagnostics::default(),
        fps: ast.fps.map_or(24.0, |f| f.0),
        broken: &ast.broken,
    };
    // Declarations first, so that they may come in any order.
    let mut first_line: HashMap<String, usize> = HashMap::new();
    for o in &ast.objects {
        let key = o.name.text.to_ascii_uppercase();
        if let Some(line) = first_line.get(&key) {
            r.diags.push(at(
                src,
                o.name.span,
                format!(
                    "object `{}` is already declared on line {line}",
                    o.name.text
                ),
            ));
            continue;
        }
        first_line.insert(key.clone(), o.name.span.line);
        r.objects.insert(key, r.object_names.len());
        r.object_names.push(o.name.text.clone());
    }
    let region_names: Vec<String> = scene
        .geometry
        .regions
        .iter()
        .map(|g| g.name.clone())
        .collect();
    let mut objects: Vec<Object> = Vec::new();
    let mut object_ast: Vec<&ObjectAst> = Vec::new();
    for o in &ast.objects {
        if r.objects.get(&o.name.text.to_ascii_uppercase()) != Some(&objects.len()) {
            continue;
        }
        let mut regions = Vec::new();
        for n in &o.regions {
            let found = scene.geometry.region_index(&n.text).or_else(|| {
                let mut it = region_names
                    .iter()
                    .enumerate()
                    .filter(|(_, g)| g.eq_ignore_ascii_case(&n.text));
                match (it.next(), it.next()) {
                    (Some((i, _)), None) => Some(i),
                    _ => None,
                }
            });
            match found {
                Some(i) => regions.push(i),
                None => {
                    let d = at(src, n.span, format!("unknown region `{}`", n.text));
                    r.diags.push(suggest(d, &n.text, &region_names));
                }
            }
        }
        let children = o.contains.iter().filter_map(|c| r.object(c)).collect();
        objects.push(Object {
            name: o.name.text.clone(),
            regions,
            children,
        });
        object_ast.push(o);
    }
    let mut axis_line: HashMap<String, usize> = HashMap::new();
    let mut axes = Vec::new();
    for a in &ast.axes {
        let key = a.name.text.to_ascii_uppercase();
        if let Some(line) = axis_line.get(&key) {
            r.diags.push(at(
                src,
                a.name.span,
                format!("axis `{}` is already declared on line {line}", a.name.text),
            ));
            continue;
        }
        let on = match &a.on {
            Some(n) => match r.object(n) {
                Some(o) => Some(o),
                None => continue,
            },
            None => None,
        };
        axis_line.insert(key.clone(), a.name.span.line);
        r.axes.insert(key, axes.len());
        r.axis_names.push(a.name.text.clone());
        axes.push(Axis {
            name: a.name.text.clone(),
            point: a.point,
            dir: a.dir,
            on,
        });
    }
    let steps = r.blocks(&ast.blocks);
    let mut diags = r.diags;
    let spec = Spec {
        objects,
        axes,
        steps,
        fps: ast.fps.map_or(24.0, |f| f.0),
        size: ast.size.map(|s| s.0),
        camera,
    };
    if diags.has_errors() {
        diags.items.sort_by_key(|d| d.offset);
        return Err(diags);
    }
    match Timeline::new(spec, scene) {
        Ok(t) => Ok(t),
        Err(errors) => {
            for e in errors {
                diags.push(director_error(src, ast, &object_ast, e));
            }
            diags.items.sort_by_key(|d| d.offset);
            Err(diags)
        }
    }
}

fn director_error(
    src: &SourceFile,
    ast: &ScriptAst,
    objects: &[&ObjectAst],
    e: DirectorError,
) -> Diagnostic {
    let object_span = |name: &str| {
        objects
            .iter()
            .find(|o| o.name.text == name)
            .map(|o| o.name.span)
            .unwrap_or(Span {
                line: 1,
                col: 1,
                len: 0,
            })
    };
    match &e {
        DirectorError::Cycle { name, .. } => at(src, object_span(name), e.to_string()),
        DirectorError::TwoParents { name, second, .. } => {
            let span = objects
                .iter()
                .find(|o| &o.name.text == second)
                .and_then(|o| {
                    o.contains
                        .iter()
                        .find(|c| c.text.eq_ignore_ascii_case(name))
                })
                .map_or(object_span(second), |c| c.span);
            at(src, span, e.to_string())
        }
        DirectorError::SharedBody { first, second, .. } => {
            let span = match (second, first) {
                (Owner::Object(o), _) | (Owner::Region(_), Owner::Object(o)) => object_span(o),
                _ => Span {
                    line: 1,
                    col: 1,
                    len: 0,
                },
            };
            at(src, span, e.to_string()).with_hint("give each object its own copy of the body")
        }
        _ => {
            let span = ast.blocks.first().map_or(
                Span {
                    line: 1,
                    col: 1,
                    len: 0,
                },
                |b| match b {
                    Block::Cmd(c) => c.span,
                    Block::Together(_, s) | Block::Shoot(_, s) | Block::Repeat(_, _, s) => *s,
                },
            );
            at(src, span, e.to_string())
        }
    }
}
