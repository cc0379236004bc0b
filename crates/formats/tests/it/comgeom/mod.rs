//! COMGEOM / GIFT deck reader and writer: the real decks, every body type
//! they hold, region references, ident metadata, round trips, every error
//! kind with its exact text, and mutation robustness.

mod decks;
mod diagnostics;
mod references;
mod robustness;
mod versions;
mod written;

use proptest::prelude::*;
use sv_formats::{comgeom, DeckVersion, Diagnostics, LoadOptions, Loaded, Severity, SourceFile};
use sv_geom::{BodyKind, Geometry, Op, Term};
use sv_scene::{Scene, Units};

const VDECK: &str = "vdeck-all-types.cg";
const GIFT: &str = "gift-sample-target-v4.cg";
const GENERATOR: &str = "mep021a-generator-v5.cg";

/// The text of a shared deck; `None` only when `SV_SKIP_SHARED=1` says to
/// skip the shared decks (otherwise a missing folder fails the test).
fn deck_text(name: &str) -> Option<String> {
    let path = sv_testdata::shared_decks("comgeom")?.join(name);
    let bytes =
        std::fs::read(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    Some(String::from_utf8_lossy(&bytes).into_owned())
}

fn read_text(name: &str, text: &str) -> Result<Loaded, Diagnostics> {
    comgeom::read(&SourceFile::new(name, text), &LoadOptions::default())
}

/// Read a deck that must load, showing the diagnostics (not the whole
/// deck) when it does not.
fn read_ok(name: &str, text: &str) -> Loaded {
    read_text(name, text).unwrap_or_else(|d| panic!("{name} does not load:\n{}", d.render_plain()))
}

/// Whether `warning` is about an ARB face that is not planar: real decks
/// have such faces, and the reader reports them at the body's card.
fn is_non_planar(warning: &sv_formats::Diagnostic) -> bool {
    warning.message.contains("is not planar")
}

fn load(name: &str) -> Option<Loaded> {
    let text = deck_text(name)?;
    match read_text(name, &text) {
        Ok(l) => Some(l),
        Err(d) => panic!("{name} does not load:\n{}", d.render_plain()),
    }
}

fn terms(spec: &[i64]) -> Vec<Term> {
    spec.iter()
        .map(|&n| Term {
            op: if n < 0 { Op::Outside } else { Op::Inside },
            body: n.unsigned_abs() as usize - 1,
        })
        .collect()
}

/// Write a scene as a v5 deck and read it back (without warnings).
fn round_trip(scene: &Scene) -> Scene {
    let w = comgeom::write(scene).unwrap();
    assert_eq!(comgeom::detect_version(&w.text), DeckVersion::V5);
    match read_text("written.cg", &w.text) {
        Ok(l) => {
            let other: Vec<_> = l.warnings.iter().filter(|w| !is_non_planar(w)).collect();
            assert!(other.is_empty(), "{other:?}");
            l.scene
        }
        Err(d) => panic!(
            "written deck does not read:\n{}\n{}",
            d.render_plain(),
            w.text
        ),
    }
}

/// The error messages of a deck that must fail.
fn errors(text: &str) -> Vec<String> {
    match read_text("bad.cg", text) {
        Ok(_) => panic!("the deck was accepted:\n{text}"),
        Err(d) => d.errors().map(|e| e.message.clone()).collect(),
    }
}

/// A v5 body card: number, type, values right-aligned in 10 columns.
fn v5_body(num: &str, ty: &str, vals: &[&str]) -> String {
    let mut s = format!("{num:>5}{ty:<5}");
    for v in vals {
        s.push_str(&format!("{v:>10}"));
    }
    s
}

/// A v5 region card: number, then (operator, number) fields.
fn v5_region(num: &str, fields: &[(&str, i64)]) -> String {
    let mut s = format!("{num:>5} ");
    for (op, n) in fields {
        s.push_str(&format!("{op:>2}{n:>5}"));
    }
    s
}

/// A v5 deck from body and region cards.
fn v5_deck(nb: usize, nr: usize, bodies: &[String], regions: &[String]) -> String {
    let mut s = format!("in   test deck\n{nb:>5}{nr:>5}\n");
    for b in bodies.iter().chain(regions) {
        s.push_str(b);
        s.push('\n');
    }
    s.push_str("   -1\n");
    s
}

fn sph(num: usize) -> String {
    v5_body(
        &num.to_string(),
        "SPH",
        &["0.", "0.", "0.", &format!("{num}.")],
    )
}
