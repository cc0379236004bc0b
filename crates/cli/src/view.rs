//! What the picture-making commands share: the raster size, the renderer
//! with the view options applied, the worker threads and the progress bar.

use crate::args::ViewArgs;
use crate::error::{bad_input, runtime, CliError};
use crate::parse::{parse_numbers, parse_size, parse_vec3};
use sv_math::DVec3;
use sv_render::{default_camera, rt_camera, Frame, Renderer, Settings, Shading, UpAxis, ViewSpec};
use sv_scene::{Lens, Light, LightKind, Scene};

/// Raster size from `--size`, the scene, or 960×720.
pub fn size(view: &ViewArgs, scene: &Scene) -> Result<(u32, u32), CliError> {
    match &view.size {
        Some(text) => parse_size(text, 65536),
        None => Ok(scene.size.unwrap_or((960, 720))),
    }
}

/// Prepare the renderer and apply the view options.
pub fn renderer(
    scene: &Scene,
    view: &ViewArgs,
    width: u32,
    height: u32,
) -> Result<Renderer, CliError> {
    let aspect = width as f64 / height as f64;
    let cut_scene;
    let scene = if view.cut.is_empty() {
        scene
    } else {
        let mut cut = scene.clone();
        for plane in &view.cut {
            let (normal, point) = parse_cut(plane)?;
            cut.cut_away(normal, point);
        }
        cut_scene = cut;
        &cut_scene
    };
    let spec = view_spec(view)?;
    // Warnings about bodies were reported, located, by the reader.
    let (mut renderer, _) =
        Renderer::new(scene, aspect).map_err(|e| CliError::Input(format!("error: {e}")))?;
    let reframe = view.ortho || view.az.is_some() || view.el.is_some() || view.up.is_some();
    if reframe || view.eye.is_some() || view.at.is_some() {
        let mut camera = if reframe || scene.camera.is_none() {
            default_camera(renderer.prepared(), aspect, &spec)
        } else {
            renderer.camera
        };
        match (&view.eye, &view.at) {
            (Some(eye), Some(at)) => {
                let (eye, at) = (parse_vec3(eye, "--eye")?, parse_vec3(at, "--at")?);
                if eye == at {
                    return Err(bad_input("--eye and --at are the same point"));
                }
                camera.eye = eye;
                camera.dir = at - eye;
            }
            (None, None) => {}
            _ => return Err(bad_input("--eye and --at go together")),
        }
        renderer.camera = camera;
    }
    if let Some(fov) = view.fov {
        if !(fov > 0.0 && fov < 180.0) {
            return Err(bad_input(format!(
                "--fov must lie between 0 and 180 degrees, found {fov}"
            )));
        }
        renderer.camera.lens = Lens::Fov { vertical_deg: fov };
    }
    if view.rt {
        renderer.camera = rt_camera(scene, renderer.prepared(), width, height, &spec);
    }
    if view.eye_light || view.rt {
        // The light is the eye's; none of the scene's lights is used.
        renderer.lights.clear();
        renderer.shading = Shading::RtEyeLight;
    } else if scene.lights.is_empty() && !view.cut.is_empty() {
        // A cutaway view: the light comes with the eye, so that the cut
        // faces, which face the viewer, are lit whatever their angle.
        renderer.lights = vec![Light {
            name: "HEADLIGHT".into(),
            kind: LightKind::Parallel {
                dir: renderer.camera.dir,
            },
            intensity: 0.85,
            colour: [1.0; 3],
        }];
    } else if scene.lights.is_empty() && (reframe || view.eye.is_some()) {
        renderer.lights = sv_render::default_lights(&renderer.camera);
    }
    Ok(renderer)
}

/// The default view the options ask for: --az, --el, --up, --ortho and
/// --view-size, each checked.
pub fn view_spec(view: &ViewArgs) -> Result<ViewSpec, CliError> {
    let angle = |value: Option<f64>, name: &str, default: f64| match value {
        None => Ok(default),
        Some(v) if v.is_finite() => Ok(v),
        Some(v) => Err(bad_input(format!(
            "--{name} must be a number of degrees, found {v}"
        ))),
    };
    let up = match view.up.as_deref().map(str::to_ascii_lowercase).as_deref() {
        None | Some("z") => UpAxis::Z,
        Some("y") => UpAxis::Y,
        Some("x") => UpAxis::X,
        Some(other) => {
            return Err(bad_input(format!(
                "--up: expected x, y or z, found `{other}`"
            )))
        }
    };
    if let Some(size) = view.view_size {
        if !(size > 0.0 && size.is_finite()) {
            return Err(bad_input(format!(
                "--view-size must be positive, found {size}"
            )));
        }
        if !view.ortho && !view.rt {
            return Err(bad_input(
                "--view-size sizes an orthographic view: add --ortho (or --rt)",
            ));
        }
    }
    Ok(ViewSpec {
        az: angle(view.az, "az", 35.0)?,
        el: angle(view.el, "el", 25.0)?,
        up,
        ortho: view.ortho,
        view_size: view.view_size,
    })
}

/// `--cut`: `x=V`, `-x=V` (and y, z), or `NX,NY,NZ,PX,PY,PZ`; the normal
/// points into the part taken away.
fn parse_cut(text: &str) -> Result<(DVec3, DVec3), CliError> {
    let bad = || {
        bad_input(format!(
            "--cut: expected AXIS=VALUE (x=0, -y=2.5) or NX,NY,NZ,PX,PY,PZ, found `{text}`"
        ))
    };
    if let Some((axis, value)) = text.split_once('=') {
        let (sign, axis) = match axis.trim().strip_prefix('-') {
            Some(rest) => (-1.0, rest),
            None => (1.0, axis.trim().trim_start_matches('+')),
        };
        let index = match axis.to_ascii_lowercase().as_str() {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return Err(bad()),
        };
        let value: f64 = value.trim().parse().map_err(|_| bad())?;
        if !value.is_finite() {
            return Err(bad());
        }
        let (mut normal, mut point) = (DVec3::ZERO, DVec3::ZERO);
        normal[index] = sign;
        point[index] = value;
        return Ok((normal, point));
    }
    match parse_numbers(text).as_deref() {
        Some(&[nx, ny, nz, px, py, pz]) => {
            let (normal, point) = (DVec3::new(nx, ny, nz), DVec3::new(px, py, pz));
            if normal.length_squared() > 0.0 && normal.is_finite() && point.is_finite() {
                Ok((normal, point))
            } else {
                Err(bad_input(format!(
                    "--cut: the normal must be finite and not zero, found `{text}`"
                )))
            }
        }
        _ => Err(bad()),
    }
}

/// The worker threads. The calling thread is one of them, so a picture
/// begins at once on the thread that asks for it instead of waiting for a
/// sleeping worker to be woken (BENCHMARKS.md).
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool, CliError> {
    let mut builder = rayon::ThreadPoolBuilder::new().use_current_thread();
    if let Some(count) = threads {
        if count == 0 {
            return Err(bad_input("--threads must be at least 1"));
        }
        builder = builder.num_threads(count);
    }
    builder
        .build()
        .map_err(|e| runtime(format!("cannot start threads: {e}")))
}

/// A progress bar of `len` steps drawn with `template`, when stderr is a
/// terminal and `--quiet` was not given.
pub fn progress_bar(len: u64, template: &str) -> Option<indicatif::ProgressBar> {
    if crate::term::quiet() || !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        return None;
    }
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template(template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    Some(bar)
}

/// Render into `frame` (its memory reused when it fits), with a progress
/// bar of rows when asked and stderr is a terminal.
pub fn render_frame(
    renderer: &Renderer,
    settings: &Settings,
    pool: &rayon::ThreadPool,
    show_progress: bool,
    frame: &mut Frame,
) {
    let bar = show_progress
        .then(|| {
            progress_bar(
                settings.height as u64,
                "{spinner} rendering [{bar:40}] {pos}/{len} rows {elapsed_precise} ETA {eta}",
            )
        })
        .flatten();
    let progress = |rows: usize| {
        if let Some(bar) = &bar {
            bar.set_position(rows as u64);
        }
    };
    pool.install(|| renderer.render_into(settings, frame, &progress));
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
}
