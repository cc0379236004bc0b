//! Looking a parsed script's names up in its scene and building the
//! timeline, with every unknown name reported.

use super::ast::{
    AimAst, Block, Cmd, CmdKind, Duration, Name, ObjectAst, ScriptAst, Span, TargetAst,
};
use crate::diag::{did_you_mean, Diagnostic, Diagnostics, SourceFile};
use std::collections::HashMap;
use sv_director::{
    AimPoint, Axis, Change, DirectorError, Object, Owner, Spec, Step, Target, Timed, Timeline, Zoom,
};
use sv_scene::{Camera, Lens, LightKind, Scene};

fn at(src: &SourceFile, span: Span, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::error_in(src, span, msg)
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
    let camera = ast.camera.as_ref().map(|c| c.camera);
    let start_camera = camera.or(scene.camera);
    let mut resolver = Resolver {
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
    resolver.declare_objects(&ast.objects);
    let (objects, object_ast) = resolver.objects_of(&ast.objects);
    let axes = resolver.axes_of(ast);
    let steps = resolver.blocks(&ast.blocks);
    if let Some(Camera {
        lens: Lens::Fov { .. } | Lens::Focal { .. },
        ..
    }) = start_camera
    {
        let has_film = matches!(start_camera.map(|c| c.lens), Some(Lens::Focal { .. }));
        resolver.check_films(&ast.blocks, has_film, &mut Vec::new());
    }
    let mut diags = resolver.diags;
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
            for error in errors {
                diags.push(director_error(src, ast, &object_ast, error));
            }
            diags.items.sort_by_key(|d| d.offset);
            Err(diags)
        }
    }
}

impl<'a> Resolver<'a> {
    /// Give every object a number, refusing a name declared twice.
    fn declare_objects(&mut self, objects: &[ObjectAst]) {
        let mut first_line: HashMap<String, usize> = HashMap::new();
        for o in objects {
            let key = o.name.text.to_ascii_uppercase();
            if let Some(line) = first_line.get(&key) {
                self.diags.push(at(
                    self.src,
                    o.name.span,
                    format!(
                        "object `{}` is already declared on line {line}",
                        o.name.text
                    ),
                ));
                continue;
            }
            first_line.insert(key.clone(), o.name.span.line);
            self.objects.insert(key, self.object_names.len());
            self.object_names.push(o.name.text.clone());
        }
    }

    /// The declared objects with their regions and children looked up, and
    /// the declaration each comes from.
    fn objects_of<'o>(&mut self, declared: &'o [ObjectAst]) -> (Vec<Object>, Vec<&'o ObjectAst>) {
        let mut objects: Vec<Object> = Vec::new();
        let mut object_ast: Vec<&ObjectAst> = Vec::new();
        for o in declared {
            if self.objects.get(&o.name.text.to_ascii_uppercase()) != Some(&objects.len()) {
                continue;
            }
            let regions = o.regions.iter().filter_map(|n| self.region(n)).collect();
            let children = o.contains.iter().filter_map(|c| self.object(c)).collect();
            objects.push(Object {
                name: o.name.text.clone(),
                regions,
                children,
            });
            object_ast.push(o);
        }
        (objects, object_ast)
    }

    /// A region by name: exactly, else ignoring case when that finds one.
    fn region(&mut self, n: &Name) -> Option<usize> {
        let geometry = &self.scene.geometry;
        let found = geometry.region_index(&n.text).or_else(|| {
            let mut same = geometry
                .regions
                .iter()
                .enumerate()
                .filter(|(_, g)| g.name.eq_ignore_ascii_case(&n.text));
            match (same.next(), same.next()) {
                (Some((i, _)), None) => Some(i),
                _ => None,
            }
        });
        if found.is_none() {
            let region_names: Vec<String> =
                geometry.regions.iter().map(|g| g.name.clone()).collect();
            let d = at(self.src, n.span, format!("unknown region `{}`", n.text));
            self.diags.push(suggest(d, &n.text, &region_names));
        }
        found
    }

    /// The declared axes, each given a number.
    fn axes_of(&mut self, ast: &ScriptAst) -> Vec<Axis> {
        let mut first_line: HashMap<String, usize> = HashMap::new();
        let mut axes = Vec::new();
        for a in &ast.axes {
            let key = a.name.text.to_ascii_uppercase();
            if let Some(line) = first_line.get(&key) {
                self.diags.push(at(
                    self.src,
                    a.name.span,
                    format!("axis `{}` is already declared on line {line}", a.name.text),
                ));
                continue;
            }
            let on = match &a.on {
                Some(n) => match self.object(n) {
                    Some(o) => Some(o),
                    None => continue,
                },
                None => None,
            };
            first_line.insert(key.clone(), a.name.span.line);
            self.axes.insert(key, axes.len());
            self.axis_names.push(a.name.text.clone());
            axes.push(Axis {
                name: a.name.text.clone(),
                point: a.point,
                dir: a.dir,
                on,
            });
        }
        axes
    }

    /// ZOOM FOCAL without FILM keeps the camera's film height, so the
    /// camera must have one when it comes: follow the lens through the film
    /// in script order (a REPEAT's body twice, as its second round starts
    /// where the first ended) and report a FOCAL without FILM met while the
    /// lens is a field of view. `has_film` is true while it is a focal lens.
    fn check_films(
        &mut self,
        blocks: &[Block],
        mut has_film: bool,
        reported: &mut Vec<Span>,
    ) -> bool {
        for block in blocks {
            has_film = match block {
                Block::Cmd(cmd) => self.check_film(cmd, has_film, reported),
                Block::Together(cmds, _) => cmds
                    .iter()
                    .fold(has_film, |film, cmd| self.check_film(cmd, film, reported)),
                Block::Shoot(..) => has_film,
                Block::Repeat(times, body, _) => {
                    let after_one = self.check_films(body, has_film, reported);
                    if *times > 1 && after_one != has_film {
                        self.check_films(body, after_one, reported)
                    } else {
                        after_one
                    }
                }
            };
        }
        has_film
    }

    /// [`Resolver::check_films`] for one command.
    fn check_film(&mut self, cmd: &Cmd, has_film: bool, reported: &mut Vec<Span>) -> bool {
        match cmd.kind {
            CmdKind::Zoom(Zoom::Fov(_), _) => false,
            CmdKind::Zoom(
                Zoom::Focal {
                    film_height: Some(_),
                    ..
                },
                _,
            ) => true,
            CmdKind::Zoom(
                Zoom::Focal {
                    film_height: None, ..
                },
                span,
            ) => {
                if !has_film && !reported.contains(&span) {
                    reported.push(span);
                    self.diags.push(
                        at(
                            self.src,
                            span,
                            "FOCAL needs FILM here: the camera has a field of view, not a film",
                        )
                        .with_hint(crate::camera_light::FILM_HINT),
                    );
                }
                true
            }
            _ => has_film,
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
