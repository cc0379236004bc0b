//! Fuzz the COMGEOM reader: no input may make it panic, hang or allocate
//! without bound, and whatever it reads must write as a v5 deck that reads
//! back.
//!
//! Run from the repository root (needs a nightly toolchain):
//! `cargo +nightly fuzz run comgeom fuzz/corpus/comgeom ../shared/decks/comgeom`
#![no_main]

use libfuzzer_sys::fuzz_target;
use sv_formats::{comgeom, DeckVersion, LoadOptions, SourceFile};

fuzz_target!(|data: &[u8]| {
    // The first byte picks the layout (or detection); the rest is the deck.
    let (version, deck) = match data.split_first() {
        Some((v, rest)) => (*v, rest),
        None => (0, data),
    };
    let deck_version = match version % 4 {
        0 => None,
        1 => Some(DeckVersion::V1),
        2 => Some(DeckVersion::V4),
        _ => Some(DeckVersion::V5),
    };
    let text = String::from_utf8_lossy(deck);
    let src = SourceFile::new("fuzz.cg", text.as_ref());
    match comgeom::read(&src, &LoadOptions { deck_version }) {
        Ok(loaded) => {
            if let Ok(written) = comgeom::write(&loaded.scene) {
                let again = SourceFile::new("written.cg", written.text);
                if let Err(d) = comgeom::read(&again, &LoadOptions::default()) {
                    panic!("a written deck does not read back:\n{}", d.render_plain());
                }
            }
        }
        Err(d) => {
            for item in &d.items {
                let _ = item.render_plain();
            }
        }
    }
});
