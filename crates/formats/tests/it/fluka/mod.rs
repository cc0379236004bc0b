//! The FLUKA reader against the pyg4ometry test inputs and hand-made cases.

mod cards;
mod diagnostics;
mod features;
mod field;
mod fixed;
mod inputs;
mod render;
mod robustness;

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use sv_formats::{fluka, Diagnostics, LoadOptions, Loaded, SourceFile};
use sv_geom::{Body, BodyKind, Region};
use sv_math::DVec3;

/// The pyg4ometry test inputs in ../shared/decks; `None` only when
/// `SV_SKIP_SHARED=1` says to skip them (otherwise a missing folder fails
/// the test).
fn data_dir() -> Option<PathBuf> {
    sv_testdata::shared_decks("fluka/pyg4ometry-testdata")
}

/// 1/√2, the cosine and sine of 45°.
const H: f64 = std::f64::consts::FRAC_1_SQRT_2;

fn read_path(path: &Path) -> Result<Loaded, Diagnostics> {
    let text = std::fs::read_to_string(path).expect("test input is readable");
    fluka::read(
        &SourceFile::new(path.display().to_string(), text),
        &LoadOptions::default(),
    )
}

/// Read a test input; `None` when the data set is not there.
fn input(name: &str) -> Option<Loaded> {
    let dir = data_dir()?;
    match read_path(&dir.join(name)) {
        Ok(l) => Some(l),
        Err(d) => panic!("{name} failed:\n{}", d.render_plain()),
    }
}

/// A fresh directory under the system temp dir.
fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sv-fluka-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A card in FLUKA's fixed columns: keyword, six WHATs, SDUM.
fn fixed_card(keyword: &str, what: [&str; 6], sdum: &str) -> String {
    let mut line = format!("{keyword:<10}");
    for w in what {
        line.push_str(&format!("{w:>10}"));
    }
    line + sdum + "\n"
}

/// A `.vxl` file as FLUKA's `writegolem` writes it (little-endian
/// Fortran records): title, NX NY NZ NO MO, DX DY DZ, the organ of each
/// voxel, then the renumbered organs.
fn vxl(counts: [i32; 3], size: [f64; 3], organs: &[i16], renumbered: &[i16]) -> Vec<u8> {
    fn record(out: &mut Vec<u8>, bytes: &[u8]) {
        out.extend((bytes.len() as u32).to_le_bytes());
        out.extend(bytes);
        out.extend((bytes.len() as u32).to_le_bytes());
    }
    let organ_count = renumbered.iter().filter(|k| **k > 0).count() as i32;
    let mut out = Vec::new();
    record(&mut out, format!("{:<80}", "test voxels").as_bytes());
    let ints = [
        counts[0],
        counts[1],
        counts[2],
        organ_count,
        renumbered.len() as i32,
    ];
    record(
        &mut out,
        &ints
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<_>>(),
    );
    record(
        &mut out,
        &size
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<_>>(),
    );
    record(
        &mut out,
        &organs
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<_>>(),
    );
    record(
        &mut out,
        &renumbered
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<_>>(),
    );
    out
}

fn read_text(text: &str) -> Result<Loaded, Diagnostics> {
    fluka::read(&SourceFile::new("test.inp", text), &LoadOptions::default())
}

/// A complete input around a body list and a region list (without STOP,
/// so that tests may append cards).
fn geo(bodies: &str, regions: &str) -> String {
    format!(
        "TITLE\nhand-made\nGEOBEGIN                                                              COMBNAME\n    0    0          test\n{bodies}\nEND\n{regions}\nEND\nGEOEND\n"
    )
}

/// (line and column, message) of every warning.
fn warnings(l: &Loaded) -> Vec<((usize, usize), &str)> {
    l.warnings
        .iter()
        .map(|w| (w.line_col(), w.message.as_str()))
        .collect()
}

/// The names of every body, in order.
fn body_names(l: &Loaded) -> Vec<&str> {
    l.scene
        .geometry
        .bodies
        .iter()
        .map(|b| b.name.as_str())
        .collect()
}

/// The description of every region, in order.
fn descriptions(l: &Loaded) -> Vec<&str> {
    l.scene
        .regions
        .iter()
        .map(|p| p.description.as_str())
        .collect()
}

/// The names of every region, in order.
fn region_names(l: &Loaded) -> Vec<&str> {
    l.scene
        .geometry
        .regions
        .iter()
        .map(|r| r.name.as_str())
        .collect()
}

/// (line, column, message) of every error.
fn errors(text: &str) -> Vec<(usize, usize, String)> {
    match read_text(text) {
        Ok(_) => panic!("expected errors for:\n{text}"),
        Err(d) => d
            .errors()
            .map(|e| {
                let (l, c) = e.line_col();
                (l, c, e.message.clone())
            })
            .collect(),
    }
}

fn body<'a>(l: &'a Loaded, name: &str) -> &'a Body {
    l.scene
        .geometry
        .bodies
        .iter()
        .find(|b| b.name == name)
        .unwrap_or_else(|| panic!("no body {name}"))
}

fn region<'a>(l: &'a Loaded, name: &str) -> &'a Region {
    l.scene
        .geometry
        .regions
        .iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("no region {name}"))
}

/// A region's zones written as `+a -b -(+c | +d)` strings.
fn zones(l: &Loaded, name: &str) -> Vec<String> {
    let bodies = &l.scene.geometry.bodies;
    let name_of = |b: usize| bodies[b].name.as_str();
    region(l, name)
        .zones
        .iter()
        .map(|z| z.expression(&name_of))
        .collect()
}

fn assert_close(got: &[f64], want: &[f64]) {
    assert_eq!(got.len(), want.len(), "got {got:?}, want {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g - w).abs() < 1e-9 * (1.0 + w.abs()),
            "got {got:?}, want {want:?}"
        );
    }
}
