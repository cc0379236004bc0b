//! `synthavision render`: one picture, with its auxiliary images.

use crate::args::{InputArgs, ViewArgs};
use crate::cmd::colour_by::{self, ColourBy};
use crate::cmd::{beside, check_error};
use crate::error::{bad_input, runtime, CliError};
use crate::load::{load, Input};
use crate::parse::check_memory;
use crate::parse::parse_numbers;
use crate::view::{render_frame, renderer, size, thread_pool};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use sv_check::{Model, UniverseChoice};
use sv_output::{
    write_image, write_pfm, write_region_png, Encoding, ImageFormat, Pixels, WriteOptions,
};
use sv_render::{Frame, Renderer, Settings};
use sv_scene::{Background, Scene};

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene, deck or FLUKA, MCNP or OpenMC input (`-`: standard input);
    /// the bundled helicopter if omitted.
    pub scene: Option<PathBuf>,
    /// Output picture (.png, .pgm/.ppm, .pfm; `-` for a PNG on standard
    /// output); default: the scene's name with .png.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub input: InputArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Supersampling: N×N rays per pixel.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=16))]
    pub samples: u32,
    /// Auxiliary images, comma separated: region (16-bit PNG), depth and normal (PFM).
    #[arg(long, value_delimiter = ',', value_name = "LIST")]
    pub aov: Vec<String>,
    /// 16 bits per channel (PNG, PGM/PPM).
    #[arg(long)]
    pub sixteen_bit: bool,
    /// One grey channel.
    #[arg(long)]
    pub grey: bool,
    /// Quantise to N levels (64 as the paper's display; 2 to 65536).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(2..=65536))]
    pub levels: Option<u32>,
    /// Encode with the sRGB curve (default: linear values, as the paper).
    #[arg(long)]
    pub srgb: bool,
    /// Transparent background (alpha channel; PNG only).
    #[arg(long)]
    pub alpha: bool,
    /// Background: a grey level, an R,G,B colour, or a picture to composite over.
    #[arg(long, value_name = "VALUE|FILE")]
    pub background: Option<String>,
    /// Paint pixels whose ray passes through an overlap in magenta and list the pairs.
    #[arg(long)]
    pub overlaps: bool,
    /// Colour every region by its region or its material, with the stable
    /// colours of `slice` (default: the scene's own colours).
    #[arg(long, value_enum, value_name = "region|material")]
    pub color_by: Option<ColourBy>,
    /// Add a legend strip of the colours seen under the picture (with
    /// --color-by).
    #[arg(long, requires = "color_by")]
    pub legend: bool,
}

/// The auxiliary images asked for with `--aov`.
#[derive(Clone, Copy, Default)]
struct Aovs {
    region: bool,
    depth: bool,
    normal: bool,
}

impl Aovs {
    fn parse(names: &[String]) -> Result<Aovs, CliError> {
        let mut aovs = Aovs::default();
        for name in names {
            match name.to_ascii_lowercase().as_str() {
                "region" => aovs.region = true,
                "depth" => aovs.depth = true,
                "normal" => aovs.normal = true,
                other => {
                    return Err(bad_input(format!(
                        "--aov: unknown image `{other}`; choose from region, depth, normal"
                    )))
                }
            }
        }
        Ok(aovs)
    }

    fn any(self) -> bool {
        self.region || self.depth || self.normal
    }
}

/// Run `render`.
pub fn render(args: RenderArgs) -> Result<ExitCode, CliError> {
    let out = args.output.clone().unwrap_or_else(|| {
        let stem = args
            .scene
            .as_ref()
            .filter(|p| !is_stdio(p))
            .and_then(|p| p.file_stem())
            .map_or("helicopter".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.png"))
    });
    let format = if is_stdio(&out) {
        ImageFormat::Png
    } else {
        ImageFormat::from_path(&out).ok_or_else(|| {
            bad_input(format!(
                "cannot tell the picture format of `{}`: use .png, .pgm, .ppm or .pfm",
                out.display()
            ))
        })?
    };
    let aovs = Aovs::parse(&args.aov)?;
    refuse_conflicts(&args, &out, format, aovs)?;
    let mut input = load(args.scene.as_deref(), &args.input)?;
    let (width, height) = size(&args.view, &input.scene)?;
    let bytes_per_pixel = if aovs.any() { 44 } else { 24 };
    check_memory(width, height, bytes_per_pixel, "a picture")?;
    let plate = background(args.background.as_deref(), &mut input.scene, width, height)?;
    if let Some(by) = args.color_by {
        colour_by::paint(&mut input.scene, by);
    }
    let renderer = renderer(&input.scene, &args.view, width, height)?;
    let pool = thread_pool(args.view.threads)?;
    let settings = Settings {
        width,
        height,
        shadows: input.scene.shadows && !args.view.no_shadows,
        samples: args.samples,
        // The legend lists the regions the picture shows.
        aovs: aovs.any() || args.legend,
    };
    let mut frame = Frame::new(width, height, settings.aovs);
    render_frame(&renderer, &settings, &pool, true, &mut frame);
    if let Some(plate) = &plate {
        composite(&mut frame, plate, &input.scene);
    }
    if args.overlaps {
        show_overlaps(&input, &renderer, &mut frame, &pool)?;
    }
    let legend = match args.color_by {
        Some(by) if args.legend => Some(colour_by::legend(&input.scene, by, &frame.region)),
        _ => None,
    };
    let written_height = write_pictures(&args, &out, format, &frame, aovs, legend)?;
    if !is_stdio(&out) {
        noteln!("wrote {} ({width}x{written_height})", out.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// Whether `path` is `-`: standard input or output.
pub fn is_stdio(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Options that cannot go together, refused before any work.
fn refuse_conflicts(
    args: &RenderArgs,
    out: &Path,
    format: ImageFormat,
    aovs: Aovs,
) -> Result<(), CliError> {
    let shown = out.display();
    if args.alpha && format != ImageFormat::Png {
        return Err(bad_input(format!(
            "--alpha needs a PNG picture: `{shown}` cannot hold an alpha channel"
        )));
    }
    if format == ImageFormat::Pfm {
        let encoding = [
            (args.sixteen_bit, "--sixteen-bit"),
            (args.levels.is_some(), "--levels"),
            (args.srgb, "--srgb"),
        ];
        if let Some((_, name)) = encoding.iter().find(|(given, _)| *given) {
            return Err(bad_input(format!(
                "{name} does not apply to `{shown}`: a PFM holds the floating-point values"
            )));
        }
    }
    if is_stdio(out) && aovs.any() {
        return Err(bad_input(
            "--aov writes files beside the picture: give a file name to -o, not `-`",
        ));
    }
    Ok(())
}

/// `--background`: a grey level or an R,G,B colour becomes the scene's
/// background; anything else is a picture to composite over, read and
/// scaled to the raster here.
fn background(
    value: Option<&str>,
    scene: &mut Scene,
    width: u32,
    height: u32,
) -> Result<Option<image::Rgb32FImage>, CliError> {
    let Some(value) = value else {
        return Ok(None);
    };
    let numeric = value.split(',').all(|x| x.trim().parse::<f64>().is_ok());
    let in_range = |&x: &f64| (0.0..=1.0).contains(&x);
    match parse_numbers(value).as_deref() {
        Some(&[grey]) if in_range(&grey) => scene.background = Background::Colour([grey; 3]),
        Some(rgb @ &[red, green, blue]) if rgb.iter().all(in_range) => {
            scene.background = Background::Colour([red, green, blue])
        }
        _ if numeric => {
            return Err(bad_input(format!(
                "--background: expected a grey level or R,G,B, each from 0 to 1, found `{value}`"
            )))
        }
        _ => {
            let picture = image::open(value)
                .map_err(|e| bad_input(format!("--background: cannot read `{}`: {e}", value)))?;
            return Ok(Some(image::imageops::resize(
                &picture.into_rgb32f(),
                width,
                height,
                image::imageops::FilterType::Triangle,
            )));
        }
    }
    Ok(None)
}

/// Put `plate` where the frame shows the background: the background's
/// share of each pixel is replaced by the plate's colour.
fn composite(frame: &mut Frame, plate: &image::Rgb32FImage, scene: &Scene) {
    let Background::Colour(background) = scene.background;
    for (index, pixel) in frame.rgb.iter_mut().enumerate() {
        let uncovered = 1.0 - frame.alpha[index];
        let plate_colour = &plate.as_raw()[index * 3..index * 3 + 3];
        for channel in 0..3 {
            let geometry = pixel[channel] - uncovered * background[channel] as f32;
            pixel[channel] = geometry + uncovered * plate_colour[channel];
        }
    }
}

/// `--overlaps`: paint the pixels whose primary ray crosses an overlap in
/// magenta and list the pairs on stderr.
fn show_overlaps(
    input: &Input,
    renderer: &Renderer,
    frame: &mut Frame,
    pool: &rayon::ThreadPool,
) -> Result<(), CliError> {
    let (model, _) = Model::new(&input.scene, &UniverseChoice::None).map_err(check_error)?;
    let seen = pool.install(|| {
        sv_check::camera_overlaps(
            &model,
            &renderer.camera,
            frame.width,
            frame.height,
            input.strict_air(),
        )
    });
    seen.paint(&mut frame.rgb, &mut frame.alpha);
    err!("{}", seen.summary());
    Ok(())
}

/// Write the picture and the auxiliary images beside it; returns the
/// picture's height (with its legend strip).
fn write_pictures(
    args: &RenderArgs,
    out: &Path,
    format: ImageFormat,
    frame: &Frame,
    aovs: Aovs,
    legend: Option<Vec<(sv_check::Swatch, String)>>,
) -> Result<u32, CliError> {
    let opts = WriteOptions {
        sixteen_bit: args.sixteen_bit,
        grey: args.grey,
        alpha: args.alpha,
        levels: args.levels,
        encoding: if args.srgb {
            Encoding::Srgb
        } else {
            Encoding::Linear
        },
    };
    let (width, height) = (frame.width, frame.height);
    let with_legend = legend.map(|entries| {
        let (_, full_height, rgb) =
            sv_check::with_legend_entries(width, height, &frame.rgb, entries);
        let mut alpha = frame.alpha.clone();
        alpha.resize(rgb.len(), 1.0);
        (full_height, rgb, alpha)
    });
    let pixels = match &with_legend {
        Some((full_height, rgb, alpha)) => Pixels {
            width,
            height: *full_height,
            rgb,
            alpha: Some(alpha),
        },
        None => Pixels {
            width,
            height,
            rgb: &frame.rgb,
            alpha: Some(&frame.alpha),
        },
    };
    if is_stdio(out) {
        // The encoder writes files; the picture is made in a temporary one
        // and copied out.
        let dir = tempfile::tempdir().map_err(runtime)?;
        let path = dir.path().join("picture.png");
        write_image(&path, format, &pixels, &opts).map_err(runtime)?;
        crate::term::out_bytes(&std::fs::read(&path).map_err(runtime)?);
        return Ok(pixels.height);
    }
    write_image(out, format, &pixels, &opts).map_err(runtime)?;
    if aovs.region {
        write_region_png(
            &beside(out, "region.png", "out"),
            width,
            height,
            &frame.region,
        )
        .map_err(runtime)?;
    }
    if aovs.depth {
        write_pfm(
            &beside(out, "depth.pfm", "out"),
            width,
            height,
            1,
            &frame.depth,
        )
        .map_err(runtime)?;
    }
    if aovs.normal {
        let flat: Vec<f32> = frame.normal.iter().flatten().copied().collect();
        write_pfm(&beside(out, "normal.pfm", "out"), width, height, 3, &flat).map_err(runtime)?;
    }
    Ok(pixels.height)
}
