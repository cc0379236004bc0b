//! Fuzz the FLUKA reader: any bytes, read as text, must give a scene or
//! diagnostics, never a panic or a hang.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sv_formats::{fluka, LoadOptions, SourceFile};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    // A name with no directory: `#include` resolves against the working
    // directory, and a missing file is only a diagnostic.
    let src = SourceFile::new("fuzz.inp", text);
    if let Err(d) = fluka::read(&src, &LoadOptions::default()) {
        for e in &d.items {
            let _ = e.render_plain();
        }
    }
});
