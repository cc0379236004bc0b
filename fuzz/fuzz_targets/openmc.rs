//! Fuzz the OpenMC reader: any bytes, read as a geometry (and, after the
//! first NUL byte, as its materials.xml), must give a scene or
//! diagnostics, never a panic or a hang.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sv_formats::{openmc, SourceFile};

fuzz_target!(|data: &[u8]| {
    let (geometry, materials) = match data.iter().position(|b| *b == 0) {
        Some(i) => (&data[..i], Some(&data[i + 1..])),
        None => (data, None),
    };
    let geometry = SourceFile::new("geometry.xml", String::from_utf8_lossy(geometry).into_owned());
    let materials = materials
        .map(|m| SourceFile::new("materials.xml", String::from_utf8_lossy(m).into_owned()));
    if let Err(d) = openmc::read_with_materials(&geometry, materials.as_ref()) {
        for e in &d.items {
            let _ = e.render_plain();
        }
    }
});
