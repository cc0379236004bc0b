//! The geometry-checking commands: `check`, `slice`, `volume`, and the
//! overlap painting of `render --overlaps`.

use crate::args::InputArgs;
use crate::load::{input, load, parse_numbers, parse_size, parse_vec3, CliError};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use sv_check::{
    CheckError, CheckOptions, Model, Plane, SliceOptions, UniverseChoice, VolumeOptions,
};
use sv_output::{write_atomic, write_image, ImageFormat, Pixels, WriteOptions};
use sv_render::{Frame, Renderer};
use sv_scene::Scene;

#[derive(Args, Debug, Clone)]
pub struct UniverseArgs {
    /// The region (or body) that the other regions must fill; voids are
    /// looked for inside it. Default: a black-hole region if the deck marks
    /// one (see docs/checking.md).
    #[arg(long, value_name = "REGION|BODY")]
    pub universe: Option<String>,
    /// Do not look for voids, even if a black-hole region is found.
    #[arg(long, conflicts_with = "universe")]
    pub no_universe: bool,
    /// Overlaps and voids no longer than this along a ray are ignored
    /// (model units; default 1e-5 of the bounding-box diagonal).
    #[arg(long, value_name = "T")]
    pub tolerance: Option<f64>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// Scene, deck or FLUKA input.
    pub scene: PathBuf,
    /// Distance between grid rays (model units; default: about 120 000
    /// rays in all, as a cube with 200 rays per side).
    #[arg(long, value_name = "D")]
    pub spacing: Option<f64>,
    /// Extra rays in random directions.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub random: u64,
    /// Fire the rays through this box instead of the model's bounds (look
    /// closely at a part; needed when no region is finite).
    #[arg(
        long = "box",
        value_name = "X0,Y0,Z0,X1,Y1,Z1",
        allow_hyphen_values = true
    )]
    pub bounds: Option<String>,
    /// Seed of the random rays.
    #[arg(long, default_value_t = 1971)]
    pub seed: u64,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Count overlaps with air regions (non-zero air code) as problems too
    /// (always so for FLUKA inputs).
    #[arg(long)]
    pub strict_air: bool,
    #[command(flatten)]
    pub check: UniverseArgs,
    #[command(flatten)]
    pub input: InputArgs,
}

#[derive(Args, Debug)]
pub struct SliceArgs {
    /// Scene, deck or FLUKA input.
    pub scene: PathBuf,
    /// Axis-aligned plane: x=VALUE, y=VALUE or z=VALUE.
    #[arg(long, value_name = "AXIS=VALUE", allow_hyphen_values = true)]
    pub plane: Option<String>,
    /// A point of an arbitrary plane (with --normal).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub origin: Option<String>,
    /// Normal of an arbitrary plane (with --origin).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub normal: Option<String>,
    /// Width (and height) of the view in model units: W or W,H. Default:
    /// the model's bounds.
    #[arg(long, value_name = "W[,H]")]
    pub extent: Option<String>,
    /// Raster size, e.g. 800x600 (default: 800 on the long side).
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Output picture (.png or .ppm); default: the scene's name with
    /// .slice.png. The section is drawn above a legend strip; the legend
    /// also goes beside it as .legend.json.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Print the legend as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Leave the legend strip (names and swatches) off the picture.
    #[arg(long)]
    pub no_legend: bool,
    /// Draw overlaps with air regions as overlaps (default: the solid
    /// region is drawn there).
    #[arg(long)]
    pub strict_air: bool,
    #[command(flatten)]
    pub check: UniverseArgs,
    #[command(flatten)]
    pub input: InputArgs,
}

#[derive(Args, Debug)]
pub struct VolumeArgs {
    /// Scene, deck or FLUKA input.
    pub scene: PathBuf,
    /// Target relative (one sigma) error of every region's volume.
    #[arg(long, default_value_t = 0.001)]
    pub rel_error: f64,
    /// Stop after about this many rays.
    #[arg(long, default_value_t = 20_000_000)]
    pub max_rays: u64,
    /// Seed of the sampling.
    #[arg(long, default_value_t = 1971)]
    pub seed: u64,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    #[command(flatten)]
    pub input: InputArgs,
}

/// FLUKA has no rule that air gives way (its `VACUUM` regions get air code
/// 1 from the reader): for FLUKA inputs every overlap counts.
fn is_fluka(path: &Path) -> bool {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    sv_formats::Format::detect(path, &text) == sv_formats::Format::Fluka
}

/// Print a report; a closed pipe (`| head`) is not an error.
fn emit(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

fn check_err(e: CheckError) -> CliError {
    let hint = match &e {
        CheckError::UnknownUniverse(_) => "; name a region or body of the deck",
        _ => "",
    };
    CliError::Input(format!("error: {e}{hint}"))
}

fn model(scene: &Scene, u: &UniverseArgs) -> Result<Model, CliError> {
    let choice = match (&u.universe, u.no_universe) {
        (_, true) => UniverseChoice::None,
        (Some(n), false) => UniverseChoice::Named(n.clone()),
        (None, false) => UniverseChoice::Auto,
    };
    if let Some(t) = u.tolerance {
        if !(t >= 0.0 && t.is_finite()) {
            return Err(input(format!(
                "--tolerance must be zero or more, found {t}"
            )));
        }
    }
    let (m, warnings) = Model::new(scene, &choice).map_err(check_err)?;
    for w in warnings {
        eprintln!("warning: {w}");
    }
    Ok(m)
}

pub fn check(a: CheckArgs) -> Result<ExitCode, CliError> {
    let scene = load(Some(&a.scene), &a.input)?;
    let m = model(&scene, &a.check)?;
    if let Some(d) = a.spacing {
        if !(d > 0.0 && d.is_finite()) {
            return Err(input(format!("--spacing must be positive, found {d}")));
        }
    }
    let bounds = match &a.bounds {
        None => None,
        Some(t) => {
            let bad = || {
                input(format!(
                    "--box: expected six numbers X0,Y0,Z0,X1,Y1,Z1 with X0 < X1, Y0 < Y1, Z0 < Z1, found `{t}`"
                ))
            };
            let v = parse_numbers(t).ok_or_else(bad)?;
            if v.len() != 6
                || v.iter().any(|x| !x.is_finite())
                || v[0] >= v[3]
                || v[1] >= v[4]
                || v[2] >= v[5]
            {
                return Err(bad());
            }
            Some(sv_math::Aabb::new(
                sv_math::DVec3::new(v[0], v[1], v[2]),
                sv_math::DVec3::new(v[3], v[4], v[5]),
            ))
        }
    };
    let opts = CheckOptions {
        bounds,
        spacing: a.spacing,
        tolerance: a.check.tolerance,
        random: a.random,
        seed: a.seed,
        strict_air: a.strict_air || is_fluka(&a.scene),
        ..Default::default()
    };
    let report = crate::commands::thread_pool(a.check.threads)?
        .install(|| sv_check::check(&m, &opts))
        .map_err(check_err)?;
    if a.json {
        emit(&format!("{}\n", report.to_json()));
    } else {
        emit(&report.to_table());
    }
    Ok(if report.is_clean() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

fn parse_plane(a: &SliceArgs) -> Result<Plane, CliError> {
    match (&a.plane, &a.origin, &a.normal) {
        (Some(p), None, None) => {
            let bad = || {
                input(format!(
                    "--plane: expected x=VALUE, y=VALUE or z=VALUE, found `{p}`"
                ))
            };
            let (axis, value) = p.split_once('=').ok_or_else(bad)?;
            let axis = match axis.trim().to_ascii_lowercase().as_str() {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                _ => return Err(bad()),
            };
            let v: f64 = value.trim().parse().map_err(|_| bad())?;
            if !v.is_finite() {
                return Err(bad());
            }
            Ok(Plane::axis(axis, v))
        }
        (None, Some(o), Some(n)) => {
            let o = parse_vec3(o, "--origin")?;
            let n = parse_vec3(n, "--normal")?;
            Plane::new(o, n).ok_or_else(|| input("--normal must not be zero"))
        }
        (None, None, None) => Err(input(
            "give the plane: --plane z=VALUE (or x=, y=), or --origin X,Y,Z with --normal X,Y,Z",
        )),
        (Some(_), _, _) => Err(input("--plane cannot be combined with --origin/--normal")),
        _ => Err(input("--origin and --normal go together")),
    }
}

fn parse_extent(s: &str) -> Result<(f64, f64), CliError> {
    let bad = || {
        input(format!(
            "--extent: expected W or W,H (positive numbers), found `{s}`"
        ))
    };
    let v = parse_numbers(s).ok_or_else(bad)?;
    let (w, h) = match v.as_slice() {
        [w] => (*w, *w),
        [w, h] => (*w, *h),
        _ => return Err(bad()),
    };
    if !(w > 0.0 && h > 0.0 && w.is_finite() && h.is_finite()) {
        return Err(bad());
    }
    Ok((w, h))
}

fn sidecar(out: &Path, suffix: &str) -> PathBuf {
    let stem = out
        .file_stem()
        .map_or("slice".into(), |s| s.to_string_lossy().into_owned());
    out.with_file_name(format!("{stem}.{suffix}"))
}

pub fn slice(a: SliceArgs) -> Result<ExitCode, CliError> {
    let plane = parse_plane(&a)?;
    let size = a
        .size
        .as_deref()
        .map(|s| parse_size(s, 16384))
        .transpose()?;
    let extent = a.extent.as_deref().map(parse_extent).transpose()?;
    let out = a.output.clone().unwrap_or_else(|| {
        let stem = a
            .scene
            .file_stem()
            .map_or("slice".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.slice.png"))
    });
    let format = match ImageFormat::from_path(&out) {
        Some(f @ (ImageFormat::Png | ImageFormat::Pnm)) => f,
        _ => {
            return Err(input(format!(
                "cannot tell the picture format of `{}`: use .png or .ppm",
                out.display()
            )))
        }
    };
    let scene = load(Some(&a.scene), &a.input)?;
    let m = model(&scene, &a.check)?;
    let opts = SliceOptions {
        plane,
        extent,
        size,
        tolerance: a.check.tolerance,
        strict_air: a.strict_air || is_fluka(&a.scene),
    };
    let s = crate::commands::thread_pool(a.check.threads)?
        .install(|| sv_check::slice(&m, &opts))
        .map_err(check_err)?;
    let legend = serde_json::json!({
        "image": out.file_name().map(|f| f.to_string_lossy().into_owned()),
        "width": s.width,
        "height": s.height,
        "unit": m.unit,
        "plane": {"origin": s.plane.origin.to_array(), "normal": s.plane.normal.to_array(),
                  "u": s.plane.u.to_array(), "v": s.plane.v.to_array()},
        "centre": s.centre.to_array(),
        "extent": [s.extent.0, s.extent.1],
        "universe": m.universe_note,
        "regions": s.legend,
        "overlaps": s.overlaps,
        "void": s.void,
    });
    let (pw, ph, pixels) = if a.no_legend {
        (s.width, s.height, s.rgb.clone())
    } else {
        sv_check::with_legend(&s)
    };
    let px = Pixels {
        width: pw,
        height: ph,
        rgb: &pixels,
        alpha: None,
    };
    let werr = |e: sv_output::WriteError| CliError::Runtime(format!("error: {e}"));
    write_image(&out, format, &px, &WriteOptions::default()).map_err(werr)?;
    let text = serde_json::to_string_pretty(&legend).expect("legend serialises");
    let side = sidecar(&out, "legend.json");
    write_atomic(&side, |w| {
        w.write_all(text.as_bytes())?;
        w.write_all(b"\n")
    })
    .map_err(werr)?;
    if a.json {
        println!("{text}");
    } else {
        let u = &m.unit;
        println!(
            "{} ({}x{} px, {} x {} {u}, centre ({}, {}, {}))",
            out.display(),
            s.width,
            s.height,
            s.extent.0,
            s.extent.1,
            s.centre.x,
            s.centre.y,
            s.centre.z
        );
        println!(
            "{:<9} {:<32} {:>14}",
            "colour",
            "region",
            format!("area {u}²")
        );
        for e in s.legend.iter().chain(&s.overlaps).chain(&s.void) {
            println!("{:<9} {:<32} {:>14.6}", e.colour, e.label, e.area);
        }
        if !s.overlaps.is_empty() {
            println!("overlaps are drawn in magenta and black stripes");
        }
        if s.void.is_some() {
            println!("voids are drawn in yellow and black stripes");
        }
        println!("legend written to {}", side.display());
    }
    Ok(ExitCode::SUCCESS)
}

pub fn volume(a: VolumeArgs) -> Result<ExitCode, CliError> {
    if !(a.rel_error > 0.0 && a.rel_error < 1.0) {
        return Err(input(format!(
            "--rel-error must lie between 0 and 1, found {}",
            a.rel_error
        )));
    }
    let scene = load(Some(&a.scene), &a.input)?;
    let (m, warnings) = Model::new(&scene, &UniverseChoice::None).map_err(check_err)?;
    for w in warnings {
        eprintln!("warning: {w}");
    }
    let opts = VolumeOptions {
        rel_error: a.rel_error,
        max_rays: a.max_rays,
        seed: a.seed,
        ..Default::default()
    };
    let r = crate::commands::thread_pool(a.threads)?
        .install(|| sv_check::volumes(&m, &opts))
        .map_err(check_err)?;
    if a.json {
        emit(&format!("{}\n", r.to_json()));
    } else {
        emit(&r.to_table());
    }
    Ok(ExitCode::SUCCESS)
}

/// `render --overlaps`: paint the pixels whose primary ray crosses an
/// overlap in magenta and list the pairs on stderr.
pub fn paint_overlaps(
    scene: &Scene,
    path: Option<&Path>,
    r: &Renderer,
    frame: &mut Frame,
    pool: &rayon::ThreadPool,
) -> Result<(), CliError> {
    let strict_air = path.is_some_and(is_fluka);
    let (m, _) = Model::new(scene, &UniverseChoice::None).map_err(check_err)?;
    let tol = sv_check::default_tolerance(&m.prepared);
    let gen = r.camera.rays(frame.width, frame.height);
    let ov = pool.install(|| {
        sv_check::overlap_pixels(&m, frame.width, frame.height, tol, strict_air, |x, y| {
            gen.ray(x as f64 + 0.5, y as f64 + 0.5)
        })
    });
    for (i, hit) in ov.mask.iter().enumerate() {
        if *hit {
            frame.rgb[i] = sv_check::OVERLAP_COLOUR;
            frame.alpha[i] = 1.0;
        }
    }
    if ov.pairs.is_empty() {
        eprintln!("overlaps: none seen");
    } else {
        eprintln!("overlaps seen ({} pairs, magenta):", ov.pairs.len());
        for p in &ov.pairs {
            eprintln!(
                "  {} × {}: {} pixels, longest {:.6}",
                p.regions[0], p.regions[1], p.pixels, p.max_length
            );
        }
    }
    Ok(())
}
