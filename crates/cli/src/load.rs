//! Loading scenes for the commands, and the errors commands report.

use crate::args::{InputArgs, ViewArgs};
use std::path::Path;
use std::process::ExitCode;
use sv_formats::{DeckVersion, LoadError, LoadOptions, Loaded};
use sv_math::DVec3;
use sv_render::{default_camera, Renderer};
use sv_scene::{Lens, Light, LightKind, Scene};

/// The bundled default scene: the paper's helicopter.
pub const HELICOPTER: &str = include_str!("../../../examples/helicopter/helicopter.sv");

/// A command's failure.
pub enum CliError {
    /// Bad input: diagnostics already formatted. Exit 2.
    Input(String),
    /// Could not write output or another run-time failure. Exit 3.
    Runtime(String),
}

impl CliError {
    pub fn print(&self) {
        match self {
            CliError::Input(s) | CliError::Runtime(s) => eprintln!("{}", s.trim_end()),
        }
    }

    pub fn exit_code(&self) -> ExitCode {
        match self {
            CliError::Input(_) => ExitCode::from(2),
            CliError::Runtime(_) => ExitCode::from(3),
        }
    }
}

pub fn input(msg: impl Into<String>) -> CliError {
    CliError::Input(format!("error: {}", msg.into()))
}

fn render_diagnostics(ds: &sv_formats::Diagnostics) -> String {
    let handler = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        miette::GraphicalReportHandler::new()
    } else {
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
    };
    let mut out = String::new();
    for d in &ds.items {
        let _ = handler.render_report(&mut out, d);
    }
    let n = ds.errors().count();
    if n > 0 {
        out.push_str(&format!(
            "{n} error{} found; nothing was written\n",
            if n == 1 { "" } else { "s" }
        ));
    }
    out
}

/// Load a scene (or the bundled helicopter) and apply the input options.
pub fn load(path: Option<&Path>, a: &InputArgs) -> Result<Scene, CliError> {
    let deck_version = match a
        .deck_version
        .as_deref()
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        None => None,
        Some("v1" | "1") => Some(DeckVersion::V1),
        Some("v4" | "4") => Some(DeckVersion::V4),
        Some("v5" | "5") => Some(DeckVersion::V5),
        Some(o) => {
            return Err(input(format!(
                "unknown deck version `{o}`; use v1, v4 or v5"
            )))
        }
    };
    let opts = LoadOptions { deck_version };
    let loaded = match path {
        Some(p) => sv_formats::load_file(p, &opts),
        None => {
            let src = sv_formats::SourceFile::new("helicopter.sv (bundled)", HELICOPTER);
            sv_formats::load_source(&src, sv_formats::Format::Native, &opts)
        }
    };
    let Loaded {
        mut scene,
        warnings,
    } = match loaded {
        Ok(l) => l,
        Err(LoadError::Invalid(ds)) => return Err(CliError::Input(render_diagnostics(&ds))),
        Err(e @ LoadError::Io { .. }) => return Err(input(e.to_string())),
    };
    if !warnings.is_empty() {
        eprint!(
            "{}",
            render_diagnostics(&sv_formats::Diagnostics { items: warnings })
        );
    }
    for n in &scene.notes {
        eprintln!("note: {n}");
    }
    if a.show_air {
        for p in scene.regions.iter_mut().filter(|p| p.air != 0) {
            p.transparent = false;
        }
    }
    if scene.show_air_if_nothing_else() {
        eprintln!(
            "note: every region that is not air is transparent, so the air regions are shown"
        );
    }
    for name in &a.transparent {
        match scene.geometry.region_index(name) {
            Some(i) => scene.regions[i].transparent = true,
            None => {
                let hint = sv_formats::did_you_mean(
                    name,
                    scene.geometry.regions.iter().map(|r| r.name.as_str()),
                )
                .map(|s| format!("; did you mean `{s}`?"))
                .unwrap_or_default();
                return Err(input(format!("--transparent: no region `{name}`{hint}")));
            }
        }
    }
    for text in &a.transparent_matching {
        let t = text.to_ascii_lowercase();
        let mut any = false;
        for p in scene.regions.iter_mut() {
            if p.description.to_ascii_lowercase().contains(&t) {
                p.transparent = true;
                any = true;
            }
        }
        if !any {
            return Err(input(format!(
                "--transparent-matching: no region description contains `{text}`"
            )));
        }
    }
    Ok(scene)
}

/// Three comma-separated numbers, for the option named `what`.
pub fn parse_vec3(s: &str, what: &str) -> Result<DVec3, CliError> {
    let v =
        parse_numbers(s).ok_or_else(|| input(format!("{what}: expected X,Y,Z, found `{s}`")))?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err(input(format!(
            "{what}: expected three numbers X,Y,Z, found `{s}`"
        )));
    }
    Ok(DVec3::new(v[0], v[1], v[2]))
}

/// Comma-separated numbers (`None` if any is not a number).
pub fn parse_numbers(s: &str) -> Option<Vec<f64>> {
    s.split(',').map(|x| x.trim().parse::<f64>().ok()).collect()
}

/// A raster size `WxH` given to `--size`, each side from 1 to `max`.
pub fn parse_size(s: &str, max: u32) -> Result<(u32, u32), CliError> {
    let bad = || input(format!("--size: expected WxH such as 960x720, found `{s}`"));
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if w == 0 || h == 0 || w > max || h > max {
        return Err(input(format!(
            "--size: {w}x{h} is out of range (1 to {max} each way)"
        )));
    }
    Ok((w, h))
}

/// Raster size from `--size`, the scene, or 960×720.
pub fn size(view: &ViewArgs, scene: &Scene) -> Result<(u32, u32), CliError> {
    match &view.size {
        Some(s) => parse_size(s, 65536),
        None => Ok(scene.size.unwrap_or((960, 720))),
    }
}

/// Prepare the renderer and apply the view options.
pub fn renderer(scene: &Scene, view: &ViewArgs, w: u32, h: u32) -> Result<Renderer, CliError> {
    let aspect = w as f64 / h as f64;
    let (mut r, warnings) =
        Renderer::new(scene, aspect).map_err(|e| CliError::Input(format!("error: {e}")))?;
    for wn in warnings {
        eprintln!("warning: {wn}");
    }
    let reframe = view.ortho || view.az.is_some() || view.el.is_some();
    if reframe || (view.eye.is_some() || view.at.is_some()) {
        let mut cam = if reframe || scene.camera.is_none() {
            default_camera(
                r.prepared(),
                aspect,
                view.az.unwrap_or(35.0),
                view.el.unwrap_or(25.0),
                view.ortho,
            )
        } else {
            r.camera
        };
        match (&view.eye, &view.at) {
            (Some(e), Some(a)) => {
                let (e, a) = (parse_vec3(e, "--eye")?, parse_vec3(a, "--at")?);
                if e == a {
                    return Err(input("--eye and --at are the same point"));
                }
                cam.eye = e;
                cam.dir = a - e;
            }
            (None, None) => {}
            _ => return Err(input("--eye and --at go together")),
        }
        r.camera = cam;
    }
    if let Some(f) = view.fov {
        if !(f > 0.0 && f < 180.0) {
            return Err(input(format!(
                "--fov must lie between 0 and 180 degrees, found {f}"
            )));
        }
        r.camera.lens = Lens::Fov { vertical_deg: f };
    }
    if view.eye_light {
        r.lights = vec![Light {
            name: "EYE".into(),
            kind: LightKind::Parallel { dir: r.camera.dir },
            intensity: 1.0,
            colour: [1.0; 3],
        }];
        r.set_ambient(0.0);
    } else if scene.lights.is_empty() && (reframe || view.eye.is_some()) {
        r.lights = sv_render::default_lights(&r.camera);
    }
    Ok(r)
}
