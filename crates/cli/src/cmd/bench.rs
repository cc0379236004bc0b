//! `synthavision bench`: primary rays per second per core.

use crate::args::{InputArgs, ViewArgs};
use crate::error::CliError;
use crate::load::{load, load_bundled, BUNDLED};
use crate::parse::check_memory;
use crate::view::{render_frame, renderer, size, thread_pool};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use sv_render::{Frame, Renderer, Settings};

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Scenes or decks to measure (the bundled examples when omitted).
    pub scenes: Vec<PathBuf>,
    /// Renders per scene; the median is reported.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..=1000))]
    pub repeat: u64,
    /// Untimed renders per scene before the timed ones (the steady state
    /// of a film: caches and light buffers made, every worker awake).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(0..=1000))]
    pub warmup: u64,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub input: InputArgs,
    /// Print JSON lines instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Run `bench`: every scene (the bundled examples when none is given)
/// rendered `--repeat` times after `--warmup` untimed renders, the median
/// reported.
pub fn bench(args: BenchArgs) -> Result<ExitCode, CliError> {
    let scenes: Vec<Result<&Path, (&str, &str)>> = if args.scenes.is_empty() {
        BUNDLED.iter().map(|&bundled| Err(bundled)).collect()
    } else {
        args.scenes.iter().map(|path| Ok(path.as_path())).collect()
    };
    let threads = args.view.threads.unwrap_or_else(rayon::current_num_threads);
    let pool = thread_pool(Some(threads))?;
    if !args.json {
        outln!(
            "{:<40} {:>9} {:>8} {:>8} {:>12} {:>14}",
            "scene",
            "size",
            "threads",
            "shadows",
            "median s",
            "Mrays/s/core"
        );
    }
    for source in scenes {
        let scene = match source {
            Ok(path) => load(Some(path), &args.input)?.scene,
            Err((name, text)) => load_bundled(name, text, &args.input)?.scene,
        };
        let (width, height) = size(&args.view, &scene)?;
        check_memory(width, height, 16, "a picture")?;
        let renderer = renderer(&scene, &args.view, width, height)?;
        let settings = Settings {
            width,
            height,
            shadows: scene.shadows && !args.view.no_shadows,
            samples: 1,
            aovs: false,
        };
        let (times, frame) = time_renders(&renderer, &settings, &pool, &args);
        let median = times[times.len() / 2];
        let rays = (width as f64) * (height as f64);
        let per_core = rays / median / threads as f64 / 1e6;
        let coverage = frame.alpha.iter().filter(|a| **a > 0.0).count() as f64 / rays;
        let name = match source {
            Ok(path) => path.display().to_string(),
            Err((name, _)) => name.to_string(),
        };
        if args.json {
            outln!(
                "{}",
                serde_json::json!({"scene": name, "width": width, "height": height, "threads": threads,
                    "shadows": settings.shadows, "median_s": median, "times_s": times,
                    "mrays_per_s_per_core": per_core, "coverage": coverage})
            );
        } else {
            outln!(
                "{:<40} {:>9} {:>8} {:>8} {:>12.4} {:>14.2}",
                name,
                format!("{width}x{height}"),
                threads,
                settings.shadows,
                median,
                per_core
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// The seconds of each timed render, sorted, and the last frame.
fn time_renders(
    renderer: &Renderer,
    settings: &Settings,
    pool: &rayon::ThreadPool,
    args: &BenchArgs,
) -> (Vec<f64>, Frame) {
    // The frame buffers are made once, outside the timing (as a film or an
    // interactive view reuses them).
    let mut frame = Frame::new(settings.width, settings.height, settings.aovs);
    // Fresh zeroed memory is mapped page by page on first write, which
    // would be timed with the first render: write it all now.
    frame.rgb.fill([0.0; 3]);
    frame.alpha.fill(0.0);
    for _ in 0..args.warmup {
        render_frame(renderer, settings, pool, false, &mut frame);
    }
    let mut times = Vec::new();
    for _ in 0..args.repeat {
        let start = Instant::now();
        render_frame(renderer, settings, pool, false, &mut frame);
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    (times, frame)
}
