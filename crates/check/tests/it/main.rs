//! Integration tests of sv-check: planted overlaps and voids, volumes
//! against closed forms, section views and report shapes.

mod decks;
mod diffs;
mod lattices;
mod overlaps;
mod slices;
mod slivers;
mod voids;
mod volumes;

use sv_check::{Model, UniverseChoice};
use sv_formats::{load_source, Format, LoadOptions, SourceFile};
use sv_scene::Scene;

/// A scene from native-language text.
pub fn scene(text: &str) -> Scene {
    let src = SourceFile::new("test.sv", text);
    load_source(&src, Format::Native, &LoadOptions::default())
        .expect("test scene reads")
        .scene
}

/// A model of `text` with the given universe.
pub fn model(text: &str, u: UniverseChoice) -> Model {
    Model::new(&scene(text), &u).expect("test model prepares").0
}
