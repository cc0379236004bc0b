//! Geometry checking: overlaps, voids, section views and volumes.
//!
//! Everything here is built on one primitive of the engine,
//! [`Prepared::partitions`](sv_trace::Prepared::partitions): the stretches of
//! a ray inside every region. Two stretches of different regions that share
//! a piece of the ray are an *overlap*; a piece of the ray inside the
//! declared universe that no region claims is a *void*.
//!
//! * [`check`]: grids of rays along x, y and z through the model's bounds
//!   (and optional random directions), in parallel, gathered into a
//!   [`Report`] of overlapping pairs and voids.
//! * [`slice()`]: a section view through any plane, coloured by region, with
//!   overlaps, voids and region outlines drawn.
//! * [`volumes`]: volume, statistical error, centroid and mass of every
//!   region by ray sampling, refined until a relative error is reached.
//! * [`diff()`]: whether two models of one experiment (an MCNP input and
//!   an OpenMC model, say) hold the same materials in the same places, with
//!   [`diff_picture`] to show where not.
//! * [`overlap_pixels`]: which pixels of a picture see an overlap;
//!   [`camera_overlaps`] for a camera's picture, and
//!   [`OverlapPixels::paint`] to mark them on it (`render --overlaps`).
//!
//! ```
//! use sv_check::{check, CheckOptions, Model, UniverseChoice};
//! use sv_geom::{Body, BodyKind, Op, Region, Term, Zone};
//! use sv_scene::{RegionProps, Scene};
//! let mut s = Scene::default();
//! s.geometry.bodies.push(Body::new("a", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0]));
//! s.geometry.bodies.push(Body::new("b", BodyKind::Sph, vec![1.5, 0.0, 0.0, 1.0]));
//! for (name, body) in [("A", 0), ("B", 1)] {
//!     let zone = Zone::new(vec![Term { op: Op::Inside, body }]);
//!     s.push_region(Region::new(name, vec![zone]), RegionProps::default());
//! }
//! let (model, _) = Model::new(&s, &UniverseChoice::None).unwrap();
//! let report = check(&model, &CheckOptions::default()).unwrap();
//! assert_eq!(report.overlaps.len(), 1);
//! assert_eq!(report.overlaps[0].regions, ["A", "B"]);
//! assert!(!report.is_clean());
//! ```
#![warn(missing_docs)]

mod analyse;
mod axes;
mod check;
mod colour;
mod diff;
mod fire;
mod grid;
mod legend;
mod model;
mod overlay;
mod refine;
mod report;
mod rng;
mod slice;
mod volume;

pub use analyse::{analyse_ray, Finding, FindingKind, RayCheck};
pub use axes::with_axes;
pub use check::{
    check, check_chunks, check_merge, check_part, refine_levels, CheckOptions, CheckPart,
    MAX_REFINE,
};
pub use colour::{region_colour, OVERLAP_COLOUR, VOID_COLOUR};
pub use diff::{
    diff, diff_picture, ClassVolume, DiffOptions, DiffPicture, DiffReport, DiffSide, Place,
    RegionVolumeOf, UnmatchedSubstance,
};
pub use legend::{legend_entries, with_legend, with_legend_entries, Swatch};
pub use model::{default_tolerance, CheckError, Model, Universe, UniverseChoice};
pub use overlay::{camera_overlaps, overlap_pixels, OverlapPixels, PairSeen};
pub use report::{Outside, Overlap, Problem, Report, SmallestFeature, UniverseInfo, Void};
pub use slice::{slice, LegendEntry, Plane, Slice, SliceOptions};
pub use volume::{volumes, RegionVolume, VolumeOptions, VolumeReport};
