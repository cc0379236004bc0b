//! The FLUKA reader against the pyg4ometry test inputs and hand-made cases.

mod cards;
mod diagnostics;
mod inputs;
mod robustness;

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use sv_formats::{fluka, Diagnostics, LoadOptions, Loaded, SourceFile};
use sv_geom::{Body, BodyKind, Op, Region};
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

fn read_text(text: &str) -> Result<Loaded, Diagnostics> {
    fluka::read(&SourceFile::new("test.inp", text), &LoadOptions::default())
}

/// A complete input around a body list and a region list.
fn geo(bodies: &str, regions: &str) -> String {
    format!(
        "TITLE\nhand-made\nGEOBEGIN                                                              COMBNAME\n    0    0          test\n{bodies}\nEND\n{regions}\nEND\nGEOEND\nSTOP\n"
    )
}

/// (line, column, message) of every error.
fn errors(text: &str) -> Vec<(usize, usize, String)> {
    match read_text(text) {
        Ok(_) => panic!("expected errors for:\n{text}"),
        Err(d) => crate::mutation::located(&d),
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

/// A region's zones written as `+a -b` strings.
fn zones(l: &Loaded, name: &str) -> Vec<String> {
    let bodies = &l.scene.geometry.bodies;
    region(l, name)
        .zones
        .iter()
        .map(|z| {
            z.terms
                .iter()
                .map(|t| {
                    format!(
                        "{}{}",
                        if t.op == Op::Inside { '+' } else { '-' },
                        bodies[t.body].name
                    )
                })
                .collect::<Vec<_>>()
                .join(" ")
        })
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
