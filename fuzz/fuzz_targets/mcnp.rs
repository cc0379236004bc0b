//! Fuzz the MCNP reader: no input may make it panic, hang or allocate
//! without bound, and every body of what it reads must be a valid body.
//!
//! Run from the repository root (needs a nightly toolchain):
//! `cargo +nightly fuzz run mcnp fuzz/corpus/mcnp ../shared/decks/mcnp-openmc`
#![no_main]

use libfuzzer_sys::fuzz_target;
use sv_formats::{mcnp, LoadOptions, SourceFile};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    // A name with no directory: `READ FILE=` resolves against the working
    // directory, and a missing file is only a diagnostic.
    let src = SourceFile::new("fuzz.i", text);
    match mcnp::read(&src, &LoadOptions::default()) {
        Ok(loaded) => {
            let g = &loaded.scene.geometry;
            assert_eq!(g.regions.len(), loaded.scene.regions.len());
            for b in &g.bodies {
                if let Err(e) = sv_geom::prepare(b, &mut Vec::new()) {
                    panic!("the reader made body {} that does not prepare: {e}", b.name);
                }
            }
        }
        Err(d) => {
            for e in &d.items {
                let _ = e.render_plain();
            }
        }
    }
});
