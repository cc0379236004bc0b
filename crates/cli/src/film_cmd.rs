//! `synthavision film`: render a director's script.

use crate::args::FilmArgs;
use crate::commands::thread_pool;
use crate::load::{input, CliError};
use std::process::ExitCode;
use std::time::Instant;
use sv_formats::script::{load_script, ScriptError};
use sv_formats::LoadOptions;
use sv_output::film::{content_hash, make_film, parse_frame_range, FilmOptions};
use sv_render::{Renderer, Settings};

/// Linear intensity to an 8-bit code, optionally sRGB-encoded.
fn code(v: f32, srgb: bool) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let v = if !srgb {
        v
    } else if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (v * 255.0 + 0.5) as u8 // round half up: v is in 0..=1
}

pub fn film(a: FilmArgs) -> Result<ExitCode, CliError> {
    let film = match load_script(&a.script, &LoadOptions::default()) {
        Ok(f) => f,
        Err(ScriptError::Invalid(ds)) => {
            let mut out = String::new();
            let handler = miette::GraphicalReportHandler::new_themed(
                miette::GraphicalTheme::unicode_nocolor(),
            );
            for d in &ds.items {
                let _ = handler.render_report(&mut out, d);
            }
            out.push_str(&format!(
                "{} error(s) in the script; no frame was rendered\n",
                ds.errors().count()
            ));
            return Err(CliError::Input(out));
        }
        Err(e) => return Err(input(e.to_string())),
    };
    for w in &film.warnings {
        eprintln!("warning: {w}");
    }
    let total = film.timeline.frame_count();
    let (w, h) = match &a.size {
        Some(s) => crate::load::parse_size(s, 65536)?,
        None => film
            .timeline
            .size()
            .or(film.scene.size)
            .unwrap_or((960, 720)),
    };
    if w == 0 || h == 0 {
        return Err(input("the picture size must not be zero"));
    }
    let range = match &a.frames {
        Some(r) => parse_frame_range(r, total).map_err(|e| input(format!("--frames: {e}")))?,
        None => 0..total,
    };
    let shadows = !a.no_shadows;
    let settings = format!(
        "{w}x{h} shadows={shadows} srgb={} v{}",
        a.srgb,
        env!("CARGO_PKG_VERSION")
    );
    let hash = content_hash(&[film.fingerprint().as_bytes(), settings.as_bytes()]);
    if a.dry_run {
        println!(
            "{total} frames at {} fps, {w}x{h}; would render frames {}..{}",
            film.timeline.fps(),
            range.start,
            range.end
        );
        return Ok(ExitCode::SUCCESS);
    }
    let mut opts = FilmOptions::new(&a.output, hash);
    opts.frames = range.clone();
    opts.fps = film.timeline.fps();
    opts.gif = !a.no_gif;
    opts.mp4 = !a.no_mp4;
    let pool = thread_pool(a.threads)?;
    let bar = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        let b = indicatif::ProgressBar::new(range.len() as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} frames [{bar:40}] {pos}/{len} {per_sec} ETA {eta}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Some(b)
    } else {
        None
    };
    let st = Settings {
        width: w,
        height: h,
        shadows,
        samples: 1,
        aovs: false,
    };
    let srgb = a.srgb;
    // Frame buffers, reused from frame to frame (frames render side by
    // side, so each takes one from the pile and puts it back).
    let spare: std::sync::Mutex<Vec<sv_render::Frame>> = std::sync::Mutex::new(Vec::new());
    let start = Instant::now();
    let report = pool.install(|| {
        make_film(
            total,
            &opts,
            |frame| {
                let scene = film.scene_at(frame);
                let (r, _) = Renderer::new(&scene, w as f64 / h as f64)?;
                let taken = spare.lock().unwrap_or_else(|e| e.into_inner()).pop();
                let mut f = taken.unwrap_or_else(|| sv_render::Frame::new(w, h, false));
                r.render_into(&st, &mut f, &|_| {});
                let mut img = image::RgbImage::new(w, h);
                for (px, c) in img.pixels_mut().zip(&f.rgb) {
                    px.0 = c.map(|v| code(v, srgb));
                }
                spare.lock().unwrap_or_else(|e| e.into_inner()).push(f);
                Ok(img)
            },
            |done, _| {
                if let Some(b) = &bar {
                    b.set_position(done as u64);
                }
            },
        )
    });
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let report = report.map_err(|e| CliError::Runtime(format!("error: {e}")))?;
    let secs = start.elapsed().as_secs_f64();
    println!(
        "{} frames rendered, {} already done, in {:.1} s ({:.1} frames/s)",
        report.rendered.len(),
        report.reused.len(),
        secs,
        report.rendered.len() as f64 / secs.max(1e-9)
    );
    if !report.missing.is_empty() {
        println!("{} frames of the film are still to be rendered; the film is assembled when all are done", report.missing.len());
    }
    if let Some(g) = &report.gif {
        println!("GIF: {}", g.display());
    }
    if let Some(c) = &report.contact_sheet {
        println!("contact sheet: {}", c.display());
    }
    if report.missing.is_empty() {
        println!("{}", report.mp4);
    }
    Ok(ExitCode::SUCCESS)
}
