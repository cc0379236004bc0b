//! The MCNP reader against the ICSBEP and Hoogenboom–Martin inputs of
//! ../shared/decks/mcnp-openmc and hand-made cases, each a few cards.

mod cards;
mod cells;
mod decks;
mod diagnostics;
mod eval;
mod render;
mod robustness;
mod surfaces;

use eval::Eval;
use sv_formats::{mcnp, Diagnostics, LoadOptions, Loaded, SourceFile};
use sv_geom::{Body, Region};
use sv_math::DVec3;

fn read_named(name: &str, text: &str) -> Result<Loaded, Diagnostics> {
    mcnp::read(&SourceFile::new(name, text), &LoadOptions::default())
}

fn read_text(text: &str) -> Result<Loaded, Diagnostics> {
    read_named("test.i", text)
}

/// Read an input that must load.
fn load(text: &str) -> Loaded {
    match read_text(text) {
        Ok(l) => l,
        Err(d) => panic!("failed:\n{}\n{text}", d.render_plain()),
    }
}

/// An input of the given cell, surface and data blocks.
fn deck(cells: &str, surfaces: &str, data: &str) -> String {
    format!("hand-made\n{cells}\n\n{surfaces}\n\n{data}\n")
}

/// (line, column, message) of every error.
fn errors(text: &str) -> Vec<(usize, usize, String)> {
    let Err(report) = read_text(text) else {
        panic!("expected errors for:\n{text}");
    };
    let located = |e: &sv_formats::Diagnostic| (e.line_col(), e.message.clone());
    report
        .errors()
        .map(located)
        .map(|((line, col), msg)| (line, col, msg))
        .collect()
}

fn body<'a>(l: &'a Loaded, name: &str) -> &'a Body {
    let g = &l.scene.geometry;
    let Some(i) = g.body_index(name) else {
        panic!("no body {name}");
    };
    &g.bodies[i]
}

fn region<'a>(l: &'a Loaded, name: &str) -> &'a Region {
    let g = &l.scene.geometry;
    let Some(i) = g.region_index(name) else {
        panic!("no region {name}");
    };
    &g.regions[i]
}

/// A region's expression with body names, as `Region::expression` writes
/// it.
fn expression(l: &Loaded, name: &str) -> String {
    let bodies = &l.scene.geometry.bodies;
    region(l, name).expression(&|b| bodies[b].name.as_str())
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn assert_close(got: &[f64], want: &[f64]) {
    let near = |(g, w): (&f64, &f64)| (g - w).abs() < 1e-9 * (1.0 + w.abs());
    let same = got.len() == want.len() && got.iter().zip(want).all(near);
    assert!(same, "got {got:?}, want {want:?}");
}
