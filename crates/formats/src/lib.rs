//! Readers and writers: the native scene language (`.sv`), COMGEOM/GIFT
//! fixed-column decks (`.cg`, v1/v4/v5), FLUKA geometry (`.inp`), MCNP
//! inputs (`.i`, `.inp`, `.mcnp`, `input`) and OpenMC models
//! (`geometry.xml`, `model.xml`); and a POV-Ray scene writer
//! ([`pov`]).
//!
//! Every reader turns text into a [`Scene`] or into [`Diagnostics`] that
//! name file, line and column; none of them panics on any input.
#![warn(missing_docs)]

mod camera_light;
pub mod comgeom;
pub mod diag;
pub mod fluka;
pub mod mcnp;
pub mod native;
pub mod openmc;
pub mod pov;
pub mod script;
mod text;

pub use diag::{did_you_mean, Diagnostic, Diagnostics, Severity, SourceFile, Span, Style};
use std::path::{Path, PathBuf};
use sv_scene::Scene;

/// A scene read from a file, with the warnings met on the way.
#[derive(Debug)]
pub struct Loaded {
    /// The scene.
    pub scene: Scene,
    /// Warnings (the input was used anyway).
    pub warnings: Vec<Diagnostic>,
    /// The format it was read in (what the rules of that format need
    /// later, e.g. FLUKA's overlaps with vacuum counting, comes from here).
    pub format: Format,
}

/// COMGEOM card layout version.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeckVersion {
    /// DoE MORSE/RAFFLE layout (believed to be MAGI's original).
    V1,
    /// GIFT.
    V4,
    /// BRL-CAD `vdeck`/`comgeom-g` default.
    V5,
}

impl DeckVersion {
    /// The layout named `v1`, `v4` or `v5` (or `1`, `4`, `5`; any case).
    pub fn named(text: &str) -> Option<DeckVersion> {
        match text.to_ascii_lowercase().as_str() {
            "v1" | "1" => Some(DeckVersion::V1),
            "v4" | "4" => Some(DeckVersion::V4),
            "v5" | "5" => Some(DeckVersion::V5),
            _ => None,
        }
    }
}

/// Options for reading.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// Force a COMGEOM layout version instead of detecting it.
    pub deck_version: Option<DeckVersion>,
}

/// The input formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The native scene language.
    Native,
    /// A COMGEOM/GIFT deck.
    Comgeom,
    /// A FLUKA input.
    Fluka,
    /// An OpenMC model (`geometry.xml` and `materials.xml`, or `model.xml`).
    OpenMc,
    /// An MCNP input.
    Mcnp,
}

impl Format {
    /// Guess the format from the file name, then from the text. `.inp`
    /// is FLUKA's and MCNP's: a FLUKA input has `GEOBEGIN`, an MCNP input
    /// a title card, cell cards, a blank line and surface cards
    /// ([`mcnp::looks_like`]); `.i`, `.mcnp` and files named `input` are
    /// MCNP's unless their text says otherwise.
    pub fn detect(path: &Path, text: &str) -> Format {
        if openmc::is_openmc(path, text) {
            return Format::OpenMc;
        }
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        let fluka = || text.to_ascii_uppercase().contains("GEOBEGIN");
        match ext.as_deref() {
            Some("sv") => return Format::Native,
            Some("cg") | Some("g") | Some("comgeom") => return Format::Comgeom,
            Some("mcnp") => return Format::Mcnp,
            Some("inp") | Some("i") if fluka() => return Format::Fluka,
            Some("inp") | Some("i") if mcnp::looks_like(text) => return Format::Mcnp,
            Some("inp") => return Format::Fluka,
            Some("i") => return Format::Mcnp,
            Some("flair") | Some("geo") | Some("geom") => return Format::Fluka,
            _ => {}
        }
        let named_input = path
            .file_name()
            .and_then(|n| n.to_str())
            .is_some_and(|n| n.eq_ignore_ascii_case("input"));
        if fluka() {
            Format::Fluka
        } else if named_input || mcnp::looks_like(text) {
            Format::Mcnp
        } else if text.to_ascii_uppercase().lines().any(|l| {
            let w = l.split_whitespace().next().unwrap_or("");
            matches!(
                w,
                "BODY" | "REGION" | "CAMERA" | "LIGHT" | "INCLUDE" | "SCENE"
            )
        }) {
            Format::Native
        } else {
            Format::Comgeom
        }
    }
}

/// Why a file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be opened or read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The text has errors (all of them are listed).
    #[error("{0}")]
    Invalid(Diagnostics),
}

/// Read a scene, deck, FLUKA or MCNP input, choosing the reader by
/// [`Format::detect`]; a folder is read as an OpenMC model
/// ([`openmc::read_dir`]).
pub fn load_file(path: &Path, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    if path.is_dir() {
        return openmc::read_dir(path, opts);
    }
    let text = std::fs::read(path).map_err(|source| LoadError::Io {
        path: path.to_owned(),
        source,
    })?;
    let text = String::from_utf8_lossy(&text).into_owned();
    let src = SourceFile::new(path.display().to_string(), text);
    load_source(&src, Format::detect(path, &src.text), opts)
}

/// Read already loaded text in a given format.
pub fn load_source(
    src: &SourceFile,
    format: Format,
    opts: &LoadOptions,
) -> Result<Loaded, LoadError> {
    match format {
        Format::Comgeom => comgeom::read(src, opts).map_err(LoadError::Invalid),
        Format::Fluka => fluka::read(src, opts).map_err(LoadError::Invalid),
        Format::Native => native::read(src, opts).map_err(LoadError::Invalid),
        Format::OpenMc => openmc::read(src, opts).map_err(LoadError::Invalid),
        Format::Mcnp => mcnp::read(src, opts).map_err(LoadError::Invalid),
    }
}
