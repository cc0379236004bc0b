//! `synthavision slice`: a section view through a plane, coloured by
//! region, with its legend.

use crate::args::{InputArgs, UniverseArgs};
use crate::cmd::{beside, check::model, check_error};
use crate::error::{bad_input, runtime, CliError};
use crate::load::load;
use crate::parse::{check_memory, parse_numbers, parse_size, parse_vec3};
use crate::term::round;
use crate::view::thread_pool;
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use sv_check::{Model, Plane, Slice, SliceOptions};
use sv_output::{write_atomic, write_image, ImageFormat, Pixels, WriteOptions};

#[derive(Args, Debug)]
pub struct SliceArgs {
    /// Scene, deck or FLUKA, MCNP or OpenMC input (`-`: standard input).
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
    /// Frame the section with axes: ticks labelled in the model's units
    /// along both sides, and a scale bar.
    #[arg(long)]
    pub axes: bool,
    /// Draw overlaps with air regions as overlaps (default: the solid
    /// region is drawn there).
    #[arg(long)]
    pub strict_air: bool,
    #[command(flatten)]
    pub check: UniverseArgs,
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `slice`: the picture, the legend beside it as JSON, and the legend
/// on stdout.
pub fn slice(args: SliceArgs) -> Result<ExitCode, CliError> {
    let plane = parse_plane(&args)?;
    let size = args
        .size
        .as_deref()
        .map(|text| parse_size(text, 16384))
        .transpose()?;
    if let Some((width, height)) = size {
        check_memory(width, height, 40, "a slice")?;
    }
    let extent = args.extent.as_deref().map(parse_extent).transpose()?;
    let out = args.output.clone().unwrap_or_else(|| {
        let stem = args
            .scene
            .file_stem()
            .map_or("slice".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.slice.png"))
    });
    let format = match ImageFormat::from_path(&out) {
        Some(format @ (ImageFormat::Png | ImageFormat::Pnm)) => format,
        _ => {
            return Err(bad_input(format!(
                "cannot tell the picture format of `{}`: use .png or .ppm",
                out.display()
            )))
        }
    };
    let input = load(Some(&args.scene), &args.input)?;
    let model = model(&input.scene, &args.check)?;
    let plane_origin = plane.origin;
    let opts = SliceOptions {
        plane,
        extent,
        size,
        // A plane given by a point is centred on it.
        centre: args.origin.is_some().then_some(plane_origin),
        tolerance: args.check.tolerance,
        strict_air: args.strict_air || input.strict_air(),
    };
    let section = thread_pool(args.check.threads)?
        .install(|| sv_check::slice(&model, &opts))
        .map_err(check_error)?;
    let (width, height, rgb) = if args.axes {
        sv_check::with_axes(&section, &model.unit)
    } else {
        (section.width, section.height, section.rgb.clone())
    };
    let (width, height, rgb) = if args.no_legend {
        (width, height, rgb)
    } else {
        let entries = sv_check::legend_entries(&section);
        sv_check::with_legend_entries(width, height, &rgb, entries)
    };
    let pixels = Pixels {
        width,
        height,
        rgb: &rgb,
        alpha: None,
    };
    write_image(&out, format, &pixels, &WriteOptions::default()).map_err(runtime)?;
    let legend = legend_json(&out, &model, &section);
    let legend_path = beside(&out, "legend.json", "slice");
    write_atomic(&legend_path, |w| {
        w.write_all(legend.as_bytes())?;
        w.write_all(b"\n")
    })
    .map_err(runtime)?;
    if args.json {
        outln!("{legend}");
    } else {
        print_legend(&out, &legend_path, &model, &section);
    }
    Ok(ExitCode::SUCCESS)
}

/// The legend as pretty JSON: the picture, the plane and what is in it.
fn legend_json(out: &Path, model: &Model, section: &Slice) -> String {
    let plane = &section.plane;
    let legend = serde_json::json!({
        "image": out.file_name().map(|f| f.to_string_lossy().into_owned()),
        "width": section.width,
        "height": section.height,
        "unit": model.unit,
        "plane": {"origin": plane.origin.to_array(), "normal": plane.normal.to_array(),
                  "u": plane.u.to_array(), "v": plane.v.to_array()},
        "centre": section.centre.to_array(),
        "extent": [section.extent.0, section.extent.1],
        "universe": model.universe_note,
        "regions": section.legend,
        "overlaps": section.overlaps,
        "void": section.void,
    });
    serde_json::to_string_pretty(&legend).expect("legend serialises")
}

/// The legend as a table on stdout.
fn print_legend(out: &Path, legend_path: &Path, model: &Model, section: &Slice) {
    let unit = &model.unit;
    outln!(
        "{} ({}x{} px, {} x {} {unit}, centre ({}, {}, {}))",
        out.display(),
        section.width,
        section.height,
        round(section.extent.0),
        round(section.extent.1),
        round(section.centre.x),
        round(section.centre.y),
        round(section.centre.z)
    );
    outln!(
        "{:<9} {:<32} {:>14}",
        "colour",
        "region",
        format!("area {unit}²")
    );
    let entries = section
        .legend
        .iter()
        .chain(&section.overlaps)
        .chain(&section.void);
    for entry in entries {
        outln!(
            "{:<9} {:<32} {:>14.6}",
            entry.colour,
            entry.label,
            entry.area
        );
    }
    if !section.overlaps.is_empty() {
        outln!("overlaps are drawn in magenta and black stripes");
    }
    if section.void.is_some() {
        outln!("voids are drawn in yellow and black stripes");
    }
    outln!("legend written to {}", legend_path.display());
}

/// `--plane AXIS=VALUE`, or `--origin` with `--normal`.
fn parse_plane(args: &SliceArgs) -> Result<Plane, CliError> {
    match (&args.plane, &args.origin, &args.normal) {
        (Some(text), None, None) => Plane::parse(text).ok_or_else(|| {
            bad_input(format!(
                "--plane: expected x=VALUE, y=VALUE or z=VALUE, found `{text}`"
            ))
        }),
        (None, Some(origin), Some(normal)) => {
            let origin = parse_vec3(origin, "--origin")?;
            let normal = parse_vec3(normal, "--normal")?;
            Plane::new(origin, normal).ok_or_else(|| bad_input("--normal must not be zero"))
        }
        (None, None, None) => Err(bad_input(
            "give the plane: --plane z=VALUE (or x=, y=), or --origin X,Y,Z with --normal X,Y,Z",
        )),
        (Some(_), _, _) => Err(bad_input(
            "--plane cannot be combined with --origin/--normal",
        )),
        _ => Err(bad_input("--origin and --normal go together")),
    }
}

/// `--extent W` or `--extent W,H`.
fn parse_extent(text: &str) -> Result<(f64, f64), CliError> {
    let bad = || {
        bad_input(format!(
            "--extent: expected W or W,H (positive numbers), found `{text}`"
        ))
    };
    let numbers = parse_numbers(text).ok_or_else(bad)?;
    let (width, height) = match numbers[..] {
        [width] => (width, width),
        [width, height] => (width, height),
        _ => return Err(bad()),
    };
    if !(width > 0.0 && height > 0.0 && width.is_finite() && height.is_finite()) {
        return Err(bad());
    }
    Ok((width, height))
}
