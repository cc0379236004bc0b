//! The command line: the subcommands, and the groups of options several of
//! them share. Each command's own options are beside it in [`crate::cmd`].

use crate::{cmd, parse};
use clap::{Args, Parser, Subcommand};

/// SynthaVision: Combinatorial Geometry visual simulation, after MAGI's
/// 1971 system. Reads scenes (.sv), COMGEOM/GIFT decks (.cg) and FLUKA
/// inputs (.inp).
#[derive(Parser, Debug)]
#[command(name = "synthavision", version, about, long_about = None, after_help = EXIT_CODES)]
pub struct Cli {
    /// Print no notes (warnings and errors are still printed).
    #[arg(short, long, global = true)]
    pub quiet: bool,
    #[command(subcommand)]
    pub command: Command,
}

/// The exit codes, shown under every command's help.
pub const EXIT_CODES: &str =
    "Exit codes: 0 done; 1 problems found (check); 2 bad input or options \
(nothing is written); 3 output could not be written or another failure.";

/// The command line's definition, every command's help ending with the
/// exit codes (for parsing, completions and manual pages alike).
pub fn definition() -> clap::Command {
    <Cli as clap::CommandFactory>::command()
        .mut_subcommands(|command| command.after_help(EXIT_CODES))
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a picture (the bundled helicopter when no scene is given).
    Render(cmd::render::RenderArgs),
    /// Counts of bodies by type, regions, bounds and materials.
    Info(cmd::info::InfoArgs),
    /// Every surface crossing along one ray, as the paper walks through Figure 3.
    Shoot(cmd::shoot::ShootArgs),
    /// The body types, their parameters and meaning.
    Bodies,
    /// Measure primary rays per second per core.
    Bench(cmd::bench::BenchArgs),
    /// Write a scene or deck as a v5 COMGEOM deck (.cg) or in the scene language (.sv).
    Convert(cmd::convert::ConvertArgs),
    /// Render a director's script to numbered PNG frames, a GIF, an MP4 and a contact sheet.
    Film(cmd::film::FilmArgs),
    /// Find overlapping regions and voids (exit 1 when any are found).
    Check(cmd::check::CheckArgs),
    /// Section view through a plane, coloured by region.
    Slice(cmd::slice::SliceArgs),
    /// Volume, centroid and mass of every region by ray sampling.
    Volume(cmd::volume::VolumeArgs),
    /// Write a scene as a POV-Ray scene (pov) or in the scene language (sv).
    Export(cmd::export::ExportArgs),
    /// Every region: number, name, material, air code, bodies, bounds.
    Regions(cmd::regions::RegionsArgs),
    /// Shell completions (bash, zsh, fish, elvish, powershell) on stdout.
    Completions(cmd::shell::CompletionsArgs),
    /// The manual page (roff) on stdout, or one per command into a folder.
    Man(cmd::shell::ManArgs),
    /// Look into a model in a browser: turn it, pick, cut, x-ray (a local web page).
    Studio(cmd::studio::StudioArgs),
    /// Compare two models of one experiment: same materials in the same places? (exit 1 when not)
    Diff(cmd::diff::DiffArgs),
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
    /// Azimuth of the default view in degrees [default: 35].
    #[arg(long, value_parser = parse::finite, allow_hyphen_values = true)]
    pub az: Option<f64>,
    /// Elevation of the default view in degrees [default: 25].
    #[arg(long, value_parser = parse::finite, allow_hyphen_values = true)]
    pub el: Option<f64>,
    /// Eye point X,Y,Z (with --at).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub eye: Option<String>,
    /// Aim point X,Y,Z (with --eye).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub at: Option<String>,
    /// Vertical field of view in degrees (more than 0, less than 180).
    #[arg(long, value_parser = parse::positive, allow_hyphen_values = true)]
    pub fov: Option<f64>,
    /// The axis that points up in the default view: z (COMGEOM decks,
    /// BRL-CAD; the default), y (most accelerator halls) or x. --az and
    /// --el turn about it.
    #[arg(long, value_name = "x|y|z")]
    pub up: Option<String>,
    /// Height of an orthographic view in model units (with --ortho;
    /// default: the model's bounding-box diagonal, as rt sizes its view).
    #[arg(
        long,
        value_name = "S",
        value_parser = parse::positive,
        allow_hyphen_values = true
    )]
    pub view_size: Option<f64>,
    /// Cut the model open with a plane: `y=0` takes away everything with
    /// y > 0, `-y=0` everything with y < 0; `NX,NY,NZ,PX,PY,PZ` takes away
    /// the side the normal N points to of the plane through P. May be
    /// given more than once.
    #[arg(long, value_name = "PLANE", allow_hyphen_values = true)]
    pub cut: Vec<String>,
    /// Turn shadows off (the paper's shading exactly).
    #[arg(long)]
    pub no_shadows: bool,
    /// Shade as BRL-CAD's `rt -l1` does: one light at the eye and ambient
    /// 0.4 (`0.4 + 0.6·cos θ`, grey), whatever the scene's lights,
    /// colours and reflectances.
    #[arg(long)]
    pub eye_light: bool,
    /// BRL-CAD `rt`'s picture: its view (orthographic, centred on the
    /// model's box, as wide as its diagonal; --az/--el as rt's -a/-e,
    /// default 35/25; --view-size as its size), its sampling (a ray
    /// through each pixel's lower-left corner) and --eye-light's shading.
    /// `render DECK --rt --size 512x512` is `rt -s512 -a35 -e25 -l1`.
    #[arg(long, conflicts_with_all = ["eye", "at", "fov"])]
    pub rt: bool,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = parse::threads)]
    pub threads: Option<usize>,
}

// The universe and tolerance of `check` and `slice` (a plain comment: a
// doc comment here would become help text).
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
    #[arg(
        long,
        value_name = "T",
        value_parser = parse::non_negative,
        allow_hyphen_values = true
    )]
    pub tolerance: Option<f64>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = parse::threads)]
    pub threads: Option<usize>,
}
