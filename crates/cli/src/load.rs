//! Loading the scene a command works on, with the input options applied.

use crate::args::InputArgs;
use crate::error::{bad_input, load_failure, CliError};
use std::path::Path;
use sv_formats::{DeckVersion, Format, LoadOptions, Loaded};
use sv_scene::Scene;

/// The bundled default scene: the paper's helicopter.
pub const HELICOPTER: &str = include_str!("../../../examples/helicopter/helicopter.sv");

/// The bundled scenes `bench` measures when given none: the paper's
/// Figure 1 and its helicopter, in the binary so that it runs anywhere.
pub const BUNDLED: [(&str, &str); 2] = [
    (
        "figure1.sv (bundled)",
        include_str!("../../../examples/figure1/figure1.sv"),
    ),
    ("helicopter.sv (bundled)", HELICOPTER),
];

/// Up to this many warnings are drawn with their lines; more are listed
/// one line each.
const FULL_WARNINGS: usize = 3;

/// A loaded scene and the format it was read in.
pub struct Input {
    /// The scene, with the input options applied.
    pub scene: Scene,
    /// The format of the file (the bundled helicopter is a native scene).
    pub format: Format,
}

impl Input {
    /// Whether overlaps with air regions count. FLUKA, MCNP and OpenMC
    /// have no rule that air gives way (their readers give FLUKA's `VACUUM`
    /// and `AIR` regions and MCNP's and OpenMC's void cells air code 1):
    /// for their inputs every overlap counts.
    pub fn strict_air(&self) -> bool {
        matches!(self.format, Format::Fluka | Format::Mcnp | Format::OpenMc)
    }
}

/// Load a scene (`-`: from standard input; `None`: the bundled
/// helicopter) and apply the input options.
pub fn load(path: Option<&Path>, args: &InputArgs) -> Result<Input, CliError> {
    let opts = load_options(args)?;
    let loaded = match path {
        Some(path) if path.as_os_str() == "-" => {
            let mut text = String::new();
            std::io::Read::read_to_string(&mut std::io::stdin(), &mut text)
                .map_err(|e| bad_input(format!("cannot read standard input: {e}")))?;
            let source = sv_formats::SourceFile::new("<stdin>", text);
            // Without a file name, the text alone tells the format.
            let format = Format::detect(Path::new("stdin"), &source.text);
            sv_formats::load_source(&source, format, &opts)
        }
        Some(path) => sv_formats::load_file(path, &opts),
        None => return load_bundled(BUNDLED[1].0, HELICOPTER, args),
    };
    finish(loaded, args)
}

/// Load a bundled scene in the scene language, named `name`.
pub fn load_bundled(name: &str, text: &str, args: &InputArgs) -> Result<Input, CliError> {
    let source = sv_formats::SourceFile::new(name, text);
    let loaded = sv_formats::load_source(&source, Format::Native, &load_options(args)?);
    finish(loaded, args)
}

/// The reader's options from the input options.
fn load_options(args: &InputArgs) -> Result<LoadOptions, CliError> {
    Ok(LoadOptions {
        deck_version: deck_version(args.deck_version.as_deref())?,
    })
}

/// Report what reading said and apply the input options.
fn finish(
    loaded: Result<Loaded, sv_formats::LoadError>,
    args: &InputArgs,
) -> Result<Input, CliError> {
    let Loaded {
        mut scene,
        warnings,
        format,
    } = loaded.map_err(|e| load_failure(e, "nothing was written"))?;
    if warnings.len() > FULL_WARNINGS {
        // Many warnings (a deck's non-planar faces): one line each, so the
        // picture's own messages are not lost among them.
        for warning in &warnings {
            let (line, column) = warning.line_col();
            let file = &warning.source.name;
            errln!("warning: {file}:{line}:{column}: {}", warning.message);
        }
    } else if !warnings.is_empty() {
        let warnings = sv_formats::Diagnostics { items: warnings };
        err!(
            "{}",
            crate::error::diagnostics_text(&warnings, "nothing was written")
        );
    }
    for note in &scene.notes {
        noteln!("note: {note}");
    }
    show_air(&mut scene, args.show_air);
    make_transparent(&mut scene, args)?;
    Ok(Input { scene, format })
}

/// `--deck-version`.
fn deck_version(text: Option<&str>) -> Result<Option<DeckVersion>, CliError> {
    let Some(text) = text else {
        return Ok(None);
    };
    DeckVersion::named(text).map(Some).ok_or_else(|| {
        bad_input(format!(
            "unknown deck version `{}`; use v1, v4 or v5",
            text.to_ascii_lowercase()
        ))
    })
}

/// Air regions are shown with `--show-air`, and when nothing else is.
fn show_air(scene: &mut Scene, asked: bool) {
    if asked {
        for region in scene.regions.iter_mut().filter(|r| r.air != 0) {
            region.transparent = false;
        }
    }
    if scene.show_air_if_nothing_else() {
        noteln!("note: every region that is not air is transparent, so the air regions are shown");
    }
}

/// `--transparent` and `--transparent-matching`.
fn make_transparent(scene: &mut Scene, args: &InputArgs) -> Result<(), CliError> {
    for name in &args.transparent {
        match scene.geometry.region_index(name) {
            Some(index) => scene.regions[index].transparent = true,
            None => {
                let hint = sv_formats::did_you_mean(
                    name,
                    scene.geometry.regions.iter().map(|r| r.name.as_str()),
                )
                .map(|s| format!("; did you mean `{s}`?"))
                .unwrap_or_default();
                return Err(bad_input(format!(
                    "--transparent: no region `{name}`{hint}"
                )));
            }
        }
    }
    for text in &args.transparent_matching {
        let wanted = text.to_ascii_lowercase();
        let mut any = false;
        for region in scene.regions.iter_mut() {
            if region.description.to_ascii_lowercase().contains(&wanted) {
                region.transparent = true;
                any = true;
            }
        }
        if !any {
            return Err(bad_input(format!(
                "--transparent-matching: no region description contains `{text}`"
            )));
        }
    }
    Ok(())
}
