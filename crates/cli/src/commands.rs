use crate::args::{BenchArgs, Cli, Command, ConvertArgs, InfoArgs, RenderArgs, ShootArgs};
use crate::load::{input, load, parse_numbers, parse_vec3, renderer, size, CliError};
use clap::Parser;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use sv_geom::BODY_TYPES;
use sv_math::Ray;
use sv_output::{
    write_image, write_pfm, write_region_png, Encoding, ImageFormat, Pixels, WriteOptions,
};
use sv_render::{Frame, Renderer, Settings};
use sv_trace::Scratch;

pub fn run() -> Result<ExitCode, CliError> {
    let cli = Cli::parse();
    match cli.command {
        Command::Render(a) => render(a),
        Command::Info(a) => info(a),
        Command::Shoot(a) => shoot(a),
        Command::Bodies => bodies(),
        Command::Bench(a) => bench(a),
        Command::Film(a) => crate::film_cmd::film(a),
        Command::Convert(a) => convert(a),
        Command::Check(a) => crate::check_cmd::check(a),
        Command::Slice(a) => crate::check_cmd::slice(a),
        Command::Volume(a) => crate::check_cmd::volume(a),
        Command::Export(a) => crate::export_cmd::export(a),
    }
}

/// The worker threads. The calling thread is one of them, so a picture
/// begins at once on the thread that asks for it instead of waiting for a
/// sleeping worker to be woken (one thread's renders of the helicopter took
/// 11.0–12.9 ms so, against 11.1–17.8 ms handed to a worker; BENCHMARKS.md).
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool, CliError> {
    let mut b = rayon::ThreadPoolBuilder::new().use_current_thread();
    if let Some(n) = threads {
        if n == 0 {
            return Err(input("--threads must be at least 1"));
        }
        b = b.num_threads(n);
    }
    b.build()
        .map_err(|e| CliError::Runtime(format!("error: cannot start threads: {e}")))
}

/// Render into `frame` (its memory reused when it fits).
fn render_frame(
    r: &Renderer,
    st: &Settings,
    pool: &rayon::ThreadPool,
    show_progress: bool,
    frame: &mut Frame,
) {
    let bar = if show_progress && std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        let b = indicatif::ProgressBar::new(st.height as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} rendering [{bar:40}] {pos}/{len} rows {elapsed_precise} ETA {eta}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Some(b)
    } else {
        None
    };
    let progress = |rows: usize| {
        if let Some(b) = &bar {
            b.set_position(rows as u64);
        }
    };
    pool.install(|| r.render_into(st, frame, &progress));
    if let Some(b) = bar {
        b.finish_and_clear();
    }
}

/// Parse `--background`: a grey level, R,G,B, or a picture file.
enum Backdrop {
    Colour([f64; 3]),
    Plate(PathBuf),
}

fn backdrop(s: &str) -> Backdrop {
    match parse_numbers(s) {
        Some(v) if v.len() == 1 => Backdrop::Colour([v[0]; 3]),
        Some(v) if v.len() == 3 => Backdrop::Colour([v[0], v[1], v[2]]),
        _ => Backdrop::Plate(PathBuf::from(s)),
    }
}

fn render(a: RenderArgs) -> Result<ExitCode, CliError> {
    let mut scene = load(a.scene.as_deref(), &a.input)?;
    let (w, h) = size(&a.view, &scene)?;
    let plate = match a.background.as_deref().map(backdrop) {
        Some(Backdrop::Colour(c)) => {
            scene.background = sv_scene::Background::Colour(c);
            None
        }
        Some(Backdrop::Plate(p)) => {
            let img = image::open(&p)
                .map_err(|e| input(format!("--background: cannot read `{}`: {e}", p.display())))?;
            Some(image::imageops::resize(
                &img.into_rgb32f(),
                w,
                h,
                image::imageops::FilterType::Triangle,
            ))
        }
        None => None,
    };
    let out = a.output.clone().unwrap_or_else(|| {
        let stem = a
            .scene
            .as_ref()
            .and_then(|p| p.file_stem())
            .map_or("helicopter".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.png"))
    });
    let format = ImageFormat::from_path(&out).ok_or_else(|| {
        input(format!(
            "cannot tell the picture format of `{}`: use .png, .pgm, .ppm or .pfm",
            out.display()
        ))
    })?;
    let mut aovs = (false, false, false);
    for k in &a.aov {
        match k.to_ascii_lowercase().as_str() {
            "region" => aovs.0 = true,
            "depth" => aovs.1 = true,
            "normal" => aovs.2 = true,
            o => {
                return Err(input(format!(
                    "--aov: unknown image `{o}`; choose from region, depth, normal"
                )))
            }
        }
    }
    if a.samples == 0 || a.samples > 16 {
        return Err(input("--samples must lie between 1 and 16"));
    }
    let r = renderer(&scene, &a.view, w, h)?;
    let pool = thread_pool(a.view.threads)?;
    let st = Settings {
        width: w,
        height: h,
        shadows: scene.shadows && !a.view.no_shadows,
        samples: a.samples,
        aovs: aovs.0 || aovs.1 || aovs.2,
    };
    let mut frame = Frame::new(st.width, st.height, st.aovs);
    render_frame(&r, &st, &pool, true, &mut frame);
    if let Some(p) = &plate {
        for (i, px) in frame.rgb.iter_mut().enumerate() {
            let al = frame.alpha[i];
            let bg = p.as_raw()[i * 3..i * 3 + 3].to_vec();
            for c in 0..3 {
                // The frame's background share is replaced by the plate.
                let geom = px[c]
                    - (1.0 - al)
                        * match scene.background {
                            sv_scene::Background::Colour(b) => b[c] as f32,
                        };
                px[c] = geom + (1.0 - al) * bg[c];
            }
        }
    }
    if a.overlaps {
        crate::check_cmd::paint_overlaps(&scene, a.scene.as_deref(), &r, &mut frame, &pool)?;
    }
    let opts = WriteOptions {
        sixteen_bit: a.sixteen_bit,
        grey: a.grey,
        alpha: a.alpha,
        levels: a.levels,
        encoding: if a.srgb {
            Encoding::Srgb
        } else {
            Encoding::Linear
        },
    };
    let px = Pixels {
        width: w,
        height: h,
        rgb: &frame.rgb,
        alpha: Some(&frame.alpha),
    };
    let werr = |e: sv_output::WriteError| CliError::Runtime(format!("error: {e}"));
    write_image(&out, format, &px, &opts).map_err(werr)?;
    let side = |suffix: &str| {
        let stem = out
            .file_stem()
            .map_or("out".into(), |s| s.to_string_lossy().into_owned());
        out.with_file_name(format!("{stem}.{suffix}"))
    };
    if aovs.0 {
        write_region_png(&side("region.png"), w, h, &frame.region).map_err(werr)?;
    }
    if aovs.1 {
        write_pfm(&side("depth.pfm"), w, h, 1, &frame.depth).map_err(werr)?;
    }
    if aovs.2 {
        let flat: Vec<f32> = frame.normal.iter().flatten().copied().collect();
        write_pfm(&side("normal.pfm"), w, h, 3, &flat).map_err(werr)?;
    }
    Ok(ExitCode::SUCCESS)
}

fn info(a: InfoArgs) -> Result<ExitCode, CliError> {
    let scene = load(Some(&a.scene), &a.input)?;
    let g = &scene.geometry;
    println!(
        "{}",
        if scene.title.is_empty() {
            a.scene.display().to_string()
        } else {
            scene.title.clone()
        }
    );
    println!("units: {}", scene.units.abbrev());
    let mut by: BTreeMap<&str, usize> = BTreeMap::new();
    for b in &g.bodies {
        *by.entry(b.kind.name()).or_default() += 1;
    }
    println!("bodies: {}", g.bodies.len());
    for (k, n) in &by {
        println!("  {k:<5} {n}");
    }
    let transparent = scene.regions.iter().filter(|p| p.transparent).count();
    let zones: usize = g.regions.iter().map(|r| r.zones.len()).sum();
    println!(
        "regions: {} ({} zones; {} transparent)",
        g.regions.len(),
        zones,
        transparent
    );
    let (p, warnings) = sv_trace::Prepared::new(g, &Default::default())
        .map_err(|e| CliError::Input(format!("error: {e}")))?;
    for w in warnings {
        println!("warning: {w}");
    }
    let b = p.bounds();
    if b.is_empty() {
        println!("bounds: empty");
    } else {
        println!(
            "bounds: ({:.4}, {:.4}, {:.4}) to ({:.4}, {:.4}, {:.4})",
            b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
        );
    }
    let mut mats: BTreeMap<i64, usize> = BTreeMap::new();
    let mut air = 0;
    for r in &scene.regions {
        *mats.entry(r.material).or_default() += 1;
        air += usize::from(r.air != 0);
    }
    println!(
        "materials: {}",
        mats.iter()
            .map(|(m, n)| format!("{m}×{n}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    println!("air regions: {air}");
    for n in &scene.notes {
        println!("note: {n}");
    }
    Ok(ExitCode::SUCCESS)
}

fn shoot(a: ShootArgs) -> Result<ExitCode, CliError> {
    let scene = load(Some(&a.scene), &a.input)?;
    let from = parse_vec3(&a.from, "--from")?;
    let dir = parse_vec3(&a.dir, "--dir")?;
    if dir.length_squared() == 0.0 {
        return Err(input("--dir must not be zero"));
    }
    let (p, _) = sv_trace::Prepared::new(&scene.geometry, &Default::default())
        .map_err(|e| CliError::Input(format!("error: {e}")))?;
    let mut s = Scratch::new(&p);
    let ray = Ray::new(from, dir);
    let g = &scene.geometry;
    let start: Vec<String> = (0..g.regions.len())
        .filter(|&r| p.region_contains(r, from))
        .map(|r| g.regions[r].name.clone())
        .collect();
    println!(
        "start ({}, {}, {}) in {}",
        from.x,
        from.y,
        from.z,
        if start.is_empty() {
            "no region".into()
        } else {
            start.join(", ")
        }
    );
    println!(
        "{:>12}  {:<8} {:<10} {:<10} region after",
        "t", "", "body", "type"
    );
    for st in p.walk(&ray, 0.0, &mut s) {
        let b = &g.bodies[st.body as usize];
        let after = if st.regions_after.is_empty() {
            "(outside the geometry)".to_string()
        } else {
            let names: Vec<String> = st
                .regions_after
                .iter()
                .map(|r| g.regions[*r as usize].name.clone())
                .collect();
            let mut s = names.join(" + ");
            if st.regions_after.len() > 1 {
                s.push_str("  (overlap)");
            }
            s
        };
        println!(
            "{:>12.6}  {:<8} {:<10} {:<10} {}",
            st.t,
            if st.entering { "enters" } else { "leaves" },
            b.name,
            b.kind.name(),
            after
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn bodies() -> Result<ExitCode, CliError> {
    for t in BODY_TYPES {
        let params: Vec<&str> = t.params.iter().map(|p| p.name).collect();
        let alias = if t.aliases.is_empty() {
            String::new()
        } else {
            format!(" (also {})", t.aliases.join(", "))
        };
        println!("{:<5} {:<8} {}{alias}", t.name, t.family, t.doc);
        if !params.is_empty() {
            println!("      values: {}", params.join(" "));
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn bench(a: BenchArgs) -> Result<ExitCode, CliError> {
    let scenes: Vec<Option<PathBuf>> = if a.scenes.is_empty() {
        let ex = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
        vec![Some(ex.join("figure1/figure1.sv")), None]
    } else {
        a.scenes.iter().cloned().map(Some).collect()
    };
    let threads = a.view.threads.unwrap_or_else(rayon::current_num_threads);
    let pool = thread_pool(Some(threads))?;
    if !a.json {
        println!(
            "{:<40} {:>9} {:>8} {:>8} {:>12} {:>14}",
            "scene", "size", "threads", "shadows", "median s", "Mrays/s/core"
        );
    }
    for sc in scenes {
        let scene = load(sc.as_deref(), &a.input)?;
        let (w, h) = size(&a.view, &scene)?;
        let r = renderer(&scene, &a.view, w, h)?;
        let st = Settings {
            width: w,
            height: h,
            shadows: scene.shadows && !a.view.no_shadows,
            samples: 1,
            aovs: false,
        };
        // The frame buffers are made once, outside the timing (as a film
        // or an interactive view reuses them).
        let mut frame = Frame::new(st.width, st.height, st.aovs);
        // Fresh zeroed memory is mapped page by page on first write, which
        // would be timed with the first render: write it all now.
        frame.rgb.fill([0.0; 3]);
        frame.alpha.fill(0.0);
        for _ in 0..a.warmup {
            render_frame(&r, &st, &pool, false, &mut frame);
        }
        let mut times = Vec::new();
        for _ in 0..a.repeat.max(1) {
            let t = Instant::now();
            render_frame(&r, &st, &pool, false, &mut frame);
            times.push(t.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        let med = times[times.len() / 2];
        let rays = (w as f64) * (h as f64);
        let per_core = rays / med / threads as f64 / 1e6;
        let cover = frame.alpha.iter().filter(|a| **a > 0.0).count() as f64 / rays;
        let name = sc
            .as_ref()
            .map_or("helicopter (bundled)".into(), |p| p.display().to_string());
        if a.json {
            println!(
                "{}",
                serde_json::json!({"scene": name, "width": w, "height": h, "threads": threads, "shadows": st.shadows,
                    "median_s": med, "times_s": times, "mrays_per_s_per_core": per_core, "coverage": cover})
            );
        } else {
            println!(
                "{:<40} {:>9} {:>8} {:>8} {:>12.4} {:>14.2}",
                name,
                format!("{w}x{h}"),
                threads,
                st.shadows,
                med,
                per_core
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn convert(a: ConvertArgs) -> Result<ExitCode, CliError> {
    let scene = load(Some(&a.input), &a.input_args)?;
    let ext = a
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let text = match ext.as_deref() {
        Some("cg") => {
            let deck = sv_formats::comgeom::write(&scene).map_err(|e| input(e.to_string()))?;
            for n in &deck.notes {
                eprintln!("note: {n}");
            }
            deck.text
        }
        Some("sv") => sv_formats::native::write(&scene),
        _ => {
            return Err(input(format!(
                "cannot tell the format of `{}`: use .cg or .sv",
                a.output.display()
            )))
        }
    };
    sv_output::write_atomic(&a.output, |w| w.write_all(text.as_bytes()))
        .map_err(|e| CliError::Runtime(format!("error: {e}")))?;
    Ok(ExitCode::SUCCESS)
}
