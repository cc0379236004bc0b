//! COMGEOM / GIFT fixed-column decks: the v5, v4 (GIFT) and v1 (DoE
//! MORSE) layouts that BRL-CAD's `comgeom-g` reads, and a v5 writer.
//!
//! A deck is a title card (units in columns 1–2, title from column 4), a
//! control card (body and region counts; not in v1), the body table, the
//! region table ended by a `-1` card (`end` in v1) and the ident table (not in
//! v1). Fields sit in fixed columns; numbers read like C `atof` on a clean
//! field. See `FORMATS.md` §1 for the card layouts.
//!
//! What the reader does, in short:
//!
//! * bodies are named by their number (`"1"`, `"2"`, …) and keep their values
//!   in card order ([`sv_geom::BODY_TYPES`]); ARS values are
//!   `curves, points_per_curve` followed by every point;
//! * `ELL` is the foci form ([`BodyKind::Ell`]) in v1/v4 and the centre form
//!   ([`BodyKind::Ell1`]) in v5, as in `comgeom-g`;
//! * regions are named by their number; `OR` starts a new zone; a `G`
//!   operator refers to a region, which becomes a group of that region's
//!   zones ([`sv_geom::Group`]), `+( … )` or `-( … )`, never expanded;
//! * region fields are read from column 7 (11 in v1) as in `comgeom-g`;
//!   when a deck's numbers straddle those columns (left-aligned or GIFT-style
//!   4- and 5-digit numbers) and another start column reads every region card,
//!   that one is used, with a warning;
//! * the ident table fills [`RegionProps`](sv_scene::RegionProps); a non-zero
//!   air code makes the region transparent; v4 ident cards whose columns
//!   75–80 hold text (the GIFT sample target writes the body type there) keep
//!   it in the description;
//! * every error of a deck is reported (up to 200, then a count), each with
//!   its line and columns; a wrong count on the control card is a warning.
//!
//! The writer ([`write()`]) produces a v5 deck that reads back to the same
//! geometry; see its documentation for what it cannot carry.
//!
//! ```
//! use sv_formats::{comgeom, LoadOptions, SourceFile};
//! let deck = "\
//! in   two spheres
//!     2    1
//!     1sph       0.0       0.0       0.0       2.0
//!     2sph       1.0       0.0       0.0       1.5
//!     1       1     -2
//!    -1
//!     1  100    0    7   80     outer shell
//! ";
//! let loaded = comgeom::read(&SourceFile::new("two.cg", deck), &LoadOptions::default()).unwrap();
//! let scene = &loaded.scene;
//! assert_eq!(scene.geometry.bodies[1].params, vec![1.0, 0.0, 0.0, 1.5]);
//! assert_eq!(scene.regions[0].ident, 100);
//! assert_eq!(scene.regions[0].description, "outer shell");
//! let text = comgeom::write(scene).unwrap().text;
//! let again = comgeom::read(&SourceFile::new("again.cg", text), &LoadOptions::default()).unwrap();
//! assert_eq!(again.scene.geometry, scene.geometry);
//! ```

mod card;
mod read;
mod write;

pub use read::{detect_version, read};
pub use write::{ell_foci_to_centre, write, WriteError, WrittenDeck};

use crate::DeckVersion;
use sv_geom::BodyKind;

/// The body type names a COMGEOM deck may use (any case).
pub const TYPE_NAMES: &[&str] = &[
    "ARB4", "ARB5", "ARB6", "ARB7", "ARB8", "ARS", "BOX", "ELL", "ELL1", "ELLG", "HAF", "RAW",
    "RCC", "REC", "RPP", "SPH", "TEC", "TGC", "TOR", "TRC", "WED",
];

/// The body kind of a COMGEOM type name in a given layout version.
pub fn kind_for(name: &str, version: DeckVersion) -> Option<BodyKind> {
    use BodyKind::*;
    Some(match name.to_ascii_uppercase().as_str() {
        "ELL" if version == DeckVersion::V5 => Ell1,
        "ELL" => Ell,
        "ELL1" => Ell1,
        "ELLG" => Ellg,
        "RAW" | "WED" => Raw,
        "ARB4" => Arb4,
        "ARB5" => Arb5,
        "ARB6" => Arb6,
        "ARB7" => Arb7,
        "ARB8" => Arb8,
        "ARS" => Ars,
        "BOX" => Box,
        "HAF" => Haf,
        "RCC" => Rcc,
        "REC" => Rec,
        "RPP" => Rpp,
        "SPH" => Sph,
        "TEC" => Tec,
        "TGC" => Tgc,
        "TOR" => Tor,
        "TRC" => Trc,
        _ => return None,
    })
}

/// A body's parameters from its card's values. The one difference is
/// HAF's distance: the card's `N d` is the half-space `N·x ≤ −d`, as
/// BRL-CAD's comgeom-g and vdeck read and write it, while a HAF body holds
/// the plane's own distance (`N·x ≤ D`).
pub(crate) fn card_to_body_params(kind: BodyKind, mut values: Vec<f64>) -> Vec<f64> {
    if kind == BodyKind::Haf {
        if let Some(d) = values.get_mut(3) {
            *d = -*d;
        }
    }
    values
}

/// A card's values from a body's parameters: the inverse of
/// [`card_to_body_params`] (the same sign change, undone).
pub(crate) fn body_to_card_params(kind: BodyKind, params: Vec<f64>) -> Vec<f64> {
    card_to_body_params(kind, params)
}
