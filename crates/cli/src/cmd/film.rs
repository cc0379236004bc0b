//! `synthavision film`: render a director's script.

use crate::error::{bad_input, load_failure, runtime, CliError};
use crate::parse::{check_memory, parse_size};
use crate::view::{progress_bar, thread_pool};
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Mutex;
use std::time::Instant;
use sv_formats::script::{load_script, Film};
use sv_formats::LoadOptions;
use sv_output::film::{frames_hash, make_film, parse_frame_range, FilmOptions, FilmReport};
use sv_output::{to_rgb8, Encoding};
use sv_render::{Frame, Renderer, Settings};

#[derive(Args, Debug)]
pub struct FilmArgs {
    /// The director's script (.svs).
    pub script: PathBuf,
    /// Output folder for the frames and the film.
    #[arg(short, long, default_value = "film")]
    pub output: PathBuf,
    /// Frames to render, e.g. 0..240, 240.., 100 (default: all).
    #[arg(long, value_name = "A..B")]
    pub frames: Option<String>,
    /// Raster size (default: the script's SIZE).
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Turn shadows off.
    #[arg(long)]
    pub no_shadows: bool,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = crate::parse::threads)]
    pub threads: Option<usize>,
    /// Encode frames with the sRGB curve (default: linear, as stills).
    #[arg(long)]
    pub srgb: bool,
    /// Skip the GIF.
    #[arg(long)]
    pub no_gif: bool,
    /// Skip the MP4.
    #[arg(long)]
    pub no_mp4: bool,
    /// Print what would be rendered and exit.
    #[arg(long)]
    pub dry_run: bool,
}

/// Run `film`: the frames of `--frames` (all by default) that are not
/// already done, and the GIF, the MP4 and the contact sheet once every
/// frame is (while the last frames render, when the others were done).
pub fn film(args: FilmArgs) -> Result<ExitCode, CliError> {
    let film = load_script(&args.script, &LoadOptions::default())
        .map_err(|e| load_failure(e, "no frame was rendered"))?;
    for warning in &film.warnings {
        errln!("warning: {warning}");
    }
    let total = film.timeline.frame_count();
    let (width, height) = match &args.size {
        Some(text) => parse_size(text, 65536)?,
        None => film
            .timeline
            .size()
            .or(film.scene.size)
            .unwrap_or((960, 720)),
    };
    if width == 0 || height == 0 {
        return Err(bad_input("the picture size must not be zero"));
    }
    let range = match &args.frames {
        Some(text) => {
            parse_frame_range(text, total).map_err(|e| bad_input(format!("--frames: {e}")))?
        }
        None => 0..total,
    };
    let shadows = !args.no_shadows;
    let hash = frames_hash(&film.fingerprint(), width, height, shadows, args.srgb);
    if args.dry_run {
        outln!(
            "{total} frames at {} fps, {width}x{height}; would render frames {}..{}",
            film.timeline.fps(),
            range.start,
            range.end
        );
        return Ok(ExitCode::SUCCESS);
    }
    let mut opts = FilmOptions::new(&args.output, hash);
    opts.frames = range;
    opts.fps = film.timeline.fps();
    opts.gif = !args.no_gif;
    opts.mp4 = !args.no_mp4;
    let settings = Settings {
        width,
        height,
        shadows,
        samples: 1,
        aovs: false,
    };
    let encoding = if args.srgb {
        Encoding::Srgb
    } else {
        Encoding::Linear
    };
    let pool = thread_pool(args.threads)?;
    // Frames render side by side, each with its buffers.
    let frames_at_once = pool.current_num_threads() as u64;
    check_memory(width, height, 24 * frames_at_once, "a film's frames")?;
    let start = Instant::now();
    let report = pool.install(|| render_film(&film, &opts, &settings, encoding))?;
    print_report(&report, start.elapsed().as_secs_f64());
    Ok(ExitCode::SUCCESS)
}

/// Render the frames of `opts` and assemble the film, on the current
/// rayon pool, with a progress bar of frames on a terminal.
fn render_film(
    film: &Film,
    opts: &FilmOptions,
    settings: &Settings,
    encoding: Encoding,
) -> Result<FilmReport, CliError> {
    let (width, height) = (settings.width, settings.height);
    let bar = progress_bar(
        opts.frames.len() as u64,
        "{spinner} frames [{bar:40}] {pos}/{len} {per_sec} ETA {eta}",
    );
    // Frame buffers, reused from frame to frame (frames render side by
    // side, so each takes one from the pile and puts it back).
    let spare_frames: Mutex<Vec<Frame>> = Mutex::new(Vec::new());
    let report = make_film(
        film.timeline.frame_count(),
        opts,
        |frame_number| {
            let scene = film.scene_at(frame_number);
            let (renderer, _) = Renderer::new(&scene, width as f64 / height as f64)?;
            let taken = spare_frames.lock().unwrap_or_else(|e| e.into_inner()).pop();
            let mut frame = taken.unwrap_or_else(|| Frame::new(width, height, false));
            renderer.render_into(settings, &mut frame, &|_| {});
            let picture = to_rgb8(width, height, &frame.rgb, encoding);
            spare_frames
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(frame);
            Ok(picture)
        },
        |done, _| {
            if let Some(bar) = &bar {
                bar.set_position(done as u64);
            }
        },
    );
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    report.map_err(runtime)
}

/// What was rendered in `seconds`, and where the film went.
fn print_report(report: &FilmReport, seconds: f64) {
    outln!(
        "{} frames rendered, {} already done, in {:.1} s ({:.1} frames/s)",
        report.rendered.len(),
        report.reused.len(),
        seconds,
        report.rendered.len() as f64 / seconds.max(1e-9)
    );
    if !report.missing.is_empty() {
        outln!(
            "{} frames of the film are still to be rendered; the film is assembled when all are done",
            report.missing.len()
        );
    }
    if let Some(gif) = &report.gif {
        outln!("GIF: {}", gif.display());
    }
    if let Some(sheet) = &report.contact_sheet {
        outln!("contact sheet: {}", sheet.display());
    }
    if report.missing.is_empty() {
        outln!("{}", report.mp4);
    }
}
