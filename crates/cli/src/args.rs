use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// SynthaVision: Combinatorial Geometry visual simulation, after MAGI's
/// 1971 system. Reads scenes (.sv), COMGEOM/GIFT decks (.cg) and FLUKA
/// inputs (.inp).
#[derive(Parser, Debug)]
#[command(name = "synthavision", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a picture (the bundled helicopter when no scene is given).
    Render(RenderArgs),
    /// Counts of bodies by type, regions, bounds and materials.
    Info(InfoArgs),
    /// Every surface crossing along one ray, as the paper walks through Figure 3.
    Shoot(ShootArgs),
    /// The body types, their parameters and meaning.
    Bodies,
    /// Measure primary rays per second per core.
    Bench(BenchArgs),
    /// Write a scene or deck as a v5 COMGEOM deck (.cg) or in the scene language (.sv).
    Convert(ConvertArgs),
    /// Render a director's script to numbered PNG frames, a GIF, an MP4 and a contact sheet.
    Film(FilmArgs),
    /// Find overlapping regions and voids (exit 1 when any are found).
    Check(crate::check_cmd::CheckArgs),
    /// Section view through a plane, coloured by region.
    Slice(crate::check_cmd::SliceArgs),
    /// Volume, centroid and mass of every region by ray sampling.
    Volume(crate::check_cmd::VolumeArgs),
    /// Write a scene as a POV-Ray scene (pov) or in the scene language (sv).
    Export(ExportArgs),
}

#[derive(Args, Debug, Clone)]
pub struct InputArgs {
    /// Force the COMGEOM layout version (v1, v4, v5) instead of detecting it.
    #[arg(long, value_name = "V")]
    pub deck_version: Option<String>,
    /// Make these regions transparent (names or numbers, comma separated).
    #[arg(long, value_delimiter = ',', value_name = "REGIONS")]
    pub transparent: Vec<String>,
    /// Make regions transparent whose description contains this text (any case).
    #[arg(long, value_name = "TEXT")]
    pub transparent_matching: Vec<String>,
    /// Show air regions (non-zero air code), which are transparent by default.
    #[arg(long)]
    pub show_air: bool,
}

#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    /// Raster size, e.g. 960x720.
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Orthographic view (BRL-CAD's default), fitted to the model.
    #[arg(long)]
    pub ortho: bool,
    /// Azimuth of the default view in degrees.
    #[arg(long)]
    pub az: Option<f64>,
    /// Elevation of the default view in degrees.
    #[arg(long)]
    pub el: Option<f64>,
    /// Eye point X,Y,Z (with --at).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub eye: Option<String>,
    /// Aim point X,Y,Z (with --eye).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub at: Option<String>,
    /// Vertical field of view in degrees.
    #[arg(long)]
    pub fov: Option<f64>,
    /// Turn shadows off (the paper's shading exactly).
    #[arg(long)]
    pub no_shadows: bool,
    /// A single light at the eye (BRL-CAD's `rt -l1`), no ambient.
    #[arg(long)]
    pub eye_light: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene, deck or FLUKA input; the bundled helicopter if omitted.
    pub scene: Option<PathBuf>,
    /// Output picture (.png, .pgm/.ppm, .pfm); default: the scene's name with .png.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub input: InputArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Supersampling: N×N rays per pixel.
    #[arg(long, default_value_t = 1)]
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
    /// Quantise to N levels (64 as the paper's display).
    #[arg(long, value_name = "N")]
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
}

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Scene, deck or FLUKA input.
    pub scene: PathBuf,
    #[command(flatten)]
    pub input: InputArgs,
}

#[derive(Args, Debug)]
pub struct ShootArgs {
    /// Scene, deck or FLUKA input.
    pub scene: PathBuf,
    /// Ray origin X,Y,Z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub from: String,
    /// Ray direction DX,DY,DZ.
    #[arg(long, value_name = "DX,DY,DZ", allow_hyphen_values = true)]
    pub dir: String,
    #[command(flatten)]
    pub input: InputArgs,
}

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Scenes or decks to measure (the bundled examples when omitted).
    pub scenes: Vec<PathBuf>,
    /// Renders per scene; the median is reported.
    #[arg(long, default_value_t = 5)]
    pub repeat: usize,
    /// Untimed renders per scene before the timed ones (the steady state
    /// of a film: caches and light buffers made, every worker awake).
    #[arg(long, default_value_t = 1)]
    pub warmup: usize,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub input: InputArgs,
    /// Print JSON lines instead of a table.
    #[arg(long)]
    pub json: bool,
}

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
    #[arg(long)]
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

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Scene, deck or FLUKA input.
    pub input: PathBuf,
    /// Output: `.cg` for a v5 COMGEOM deck, `.sv` for the scene language.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub input_args: InputArgs,
}

/// Output formats of `export`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// POV-Ray 3.7 scene.
    Pov,
    /// SynthaVision scene language.
    Sv,
}

#[derive(Args, Debug)]
pub struct ExportArgs {
    /// Scene, deck or FLUKA input.
    pub scene: PathBuf,
    /// Output format.
    #[arg(long, value_enum)]
    pub format: ExportFormat,
    /// Output file.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub input: InputArgs,
    #[command(flatten)]
    pub view: ViewArgs,
}
