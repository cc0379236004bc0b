//! The Scene: geometry plus camera, lights, region looks and metadata.
//!
//! Coordinates are right-handed with `z` up (as in COMGEOM decks and
//! BRL-CAD). Intensities are linear: the shading model is the paper's
//! `I = Σ I₀·k·cosθ·f(R) + A₀`, scaled per channel by the region colour.
#![warn(missing_docs)]

mod camera;
mod light;
mod scene;

pub use camera::{Camera, Lens};
pub use light::{Light, LightKind};
pub use scene::{Background, Component, Material, RegionProps, Scene, Units};
pub use sv_geom as geom;
pub use sv_math::RayGen;
