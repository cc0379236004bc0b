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
//! CAMERA EYE (60,-80,25) AT (0,0,5) UP (0,0,1) FOV 35   # optional, as in scenes
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
//! CAMERA is the scene language's statement, read by the same grammar (any
//! order of settings; FOCAL needs FILM; a field of view lies between 0 and
//! 180 degrees). ZOOM reads its lens values as CAMERA does; `FOCAL f`
//! without FILM keeps the camera's film height, so it needs a camera that
//! has one (a focal lens) when it comes.
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
//! let zone = Zone::new(vec![Term { op: Op::Inside, body: 0 }]);
//! scene.push_region(Region::new("fuselage", vec![zone]), RegionProps::default());
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

mod ast;
mod command;
mod parse;
mod resolve;

pub use ast::{
    AimAst, AxisAst, Block, CameraAst, Cmd, CmdKind, Duration, Name, ObjectAst, ScriptAst, Span,
    TargetAst, KEYWORDS,
};
pub use parse::parse;
pub use resolve::resolve;

use crate::diag::{Diagnostic, Diagnostics, SourceFile};
use crate::{load_file, LoadError, LoadOptions};
use std::path::{Path, PathBuf};
use sv_director::Timeline;
use sv_scene::Scene;

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
                            diags.push(Diagnostic::error_in(src, *span, format!("region `{region}` of `{name}` has the same name as a region of `{first_name}`")));
                            scene_ok = false;
                        }
                    }
                }
            }
            Err(LoadError::Io { source, .. }) => {
                scene_ok = false;
                diags.push(Diagnostic::error_in(
                    src,
                    *span,
                    format!("cannot read scene `{name}`: {source}"),
                ));
            }
            Err(LoadError::Invalid(d)) => {
                scene_ok = false;
                diags.push(Diagnostic::error_in(
                    src,
                    *span,
                    format!("scene `{name}` has {d}"),
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
