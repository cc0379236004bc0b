//! Mutated real models and arbitrary text never make the reader panic;
//! limits keep hostile inputs cheap.

use super::*;
use crate::mutation::{self, apply, Edit};
use proptest::prelude::*;

/// (geometry.xml, materials.xml) of every model of the set, or a small
/// model when the set is skipped.
fn corpus() -> Vec<(String, String)> {
    let Some(root) = decks_dir() else {
        return vec![(
            r#"<geometry><surface id="1" type="sphere" coeffs="0 0 0 1"/><cell id="1" material="1" region="-1"/></geometry>"#.into(),
            MATERIALS.into(),
        )];
    };
    let mut out = Vec::new();
    let mut stack = vec![root];
    while let Some(dir) = stack.pop() {
        let geometry = dir.join("geometry.xml");
        if geometry.is_file() {
            let text = |p| std::fs::read_to_string(p).unwrap();
            out.push((text(geometry), text(dir.join("materials.xml"))));
        }
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            }
        }
    }
    out.sort();
    out
}

fn edit() -> impl Strategy<Value = Edit> {
    let snippet = prop_oneof![
        Just("(".to_string()),
        Just(")".to_string()),
        Just("~".to_string()),
        Just("|".to_string()),
        Just("-".to_string()),
        Just("\"".to_string()),
        Just("<".to_string()),
        Just("/>".to_string()),
        Just(" 0".to_string()),
        Just(" 99999999999".to_string()),
        Just(" -1e308".to_string()),
        Just(" nan".to_string()),
        Just(r#" fill="1""#.to_string()),
        Just(r#" universe="1""#.to_string()),
        Just(r#" rotation="90 0 0""#.to_string()),
        Just("<hex_lattice id=\"9\" n_rings=\"2\"><center>0 0</center><pitch>1</pitch><universes>1 1 1 1 1 1 1</universes></hex_lattice>".to_string()),
        Just("<lattice id=\"8\" dimension=\"2 2 2\"><lower_left>0 0 0</lower_left><pitch>1 1 1</pitch><universes>1 1 1 1 1 1 1 1</universes></lattice>".to_string()),
        "[ -~]{1,8}",
    ];
    mutation::edit(snippet)
}

fn read_both(geometry: String, materials: String) -> Result<Loaded, Diagnostics> {
    openmc::read_with_materials(
        &SourceFile::new("geometry.xml", geometry),
        Some(&SourceFile::new("materials.xml", materials)),
    )
}

proptest! {
    // 300 cases by default; PROPTEST_CASES=N runs more.
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(300),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn mutated_models_never_panic(
        pick in any::<usize>(),
        geometry_edits in prop::collection::vec(edit(), 0..6),
        materials_edits in prop::collection::vec(edit(), 0..3),
    ) {
        let corpus = corpus();
        let (geometry, materials) = &corpus[pick % corpus.len()];
        let result = read_both(apply(geometry, &geometry_edits), apply(materials, &materials_edits));
        match result {
            Ok(l) => {
                let g = &l.scene.geometry;
                prop_assert_eq!(g.regions.len(), l.scene.regions.len());
                for r in &g.regions {
                    prop_assert!(r.universe < g.universes.len());
                    r.for_each_term(&mut |t| assert!(t.body < g.bodies.len()));
                }
            }
            Err(d) => {
                prop_assert!(d.has_errors());
                for e in &d.items {
                    let _ = e.render_plain();
                }
            }
        }
    }

    #[test]
    fn arbitrary_region_text_never_panics(region in "[-+0-9 ()|~]{0,40}") {
        let _ = read(&format!(
            r#"<geometry><surface id="1" type="sphere" coeffs="0 0 0 1"/><surface id="2" type="z-plane" coeffs="0"/><cell id="1" material="1" region="{region}"/></geometry>"#
        ));
    }
}

#[test]
fn errors_past_the_limit_are_counted() {
    let cells: String = (0..250)
        .map(|i| format!(r#"<cell id="{i}" material="1" region="-{}"/>"#, 1000 + i))
        .collect();
    let d = read(&format!("<geometry>{cells}</geometry>")).unwrap_err();
    assert_eq!(d.items.len(), 201);
    assert_eq!(
        d.items[200].message,
        "… and 50 more errors and warnings not shown"
    );
    assert_eq!(d.error_count(), 250);
}

#[test]
fn huge_lattices_are_refused_without_being_allocated() {
    let e = errors(
        r#"<cell id="1" fill="7"/>
<cell id="2" universe="1" material="1"/>
<lattice id="7" dimension="2000000000 2000000000 2000000000"><lower_left>0 0 0</lower_left><pitch>1 1 1</pitch><universes>1</universes></lattice>
<hex_lattice id="8" n_rings="2000000000" n_axial="2000000000"><center>0 0 0</center><pitch>1 1</pitch><universes>1</universes></hex_lattice>"#,
    );
    assert_eq!(e.len(), 2, "{e:?}");
    assert!(
        e[0].2.starts_with("lattice 7 lists 1 universes"),
        "{}",
        e[0].2
    );
    assert!(
        e[1].2.starts_with("lattice 8 lists 1 universes"),
        "{}",
        e[1].2
    );
}

#[test]
fn long_fill_chains_are_followed_without_recursion() {
    // Universe i is filled into universe i - 1, 20 000 deep, and the last
    // one back into the first: one cycle, found without a deep stack.
    let n = 20_000;
    let mut cells = String::from(r#"<cell id="1" fill="1"/>"#);
    for u in 1..n {
        cells.push_str(&format!(
            r#"<cell id="{}" universe="{u}" fill="{}"/>"#,
            u + 1,
            u + 1
        ));
    }
    cells.push_str(&format!(
        r#"<cell id="{}" universe="{n}" fill="1"/>"#,
        n + 1
    ));
    let d = read(&format!("<geometry>{cells}</geometry>")).unwrap_err();
    assert_eq!(d.error_count(), 1);
    assert!(d.items[0]
        .message
        .starts_with("fill cycle: universe 1 → cell 2 fills 2"));
}

#[test]
fn many_cells_filled_with_one_large_lattice_are_refused() {
    // 1000 × 1000 elements filled into 20 cells: over the limit.
    let n = 1000;
    let universes = "1 ".repeat(n * n);
    let cells: String = (0..20)
        .map(|i| format!(r#"<cell id="{}" universe="{}" fill="7"/>"#, 10 + i, 100 + i))
        .collect();
    let holders: String = (0..20)
        .map(|i| format!(r#"<cell id="{}" fill="{}"/>"#, 100 + i, 100 + i))
        .collect();
    let e = errors(&format!(
        r#"<cell id="1" universe="1" material="1"/>{cells}{holders}
<lattice id="7" dimension="{n} {n}"><lower_left>0 0</lower_left><pitch>1 1</pitch><universes>{universes}</universes></lattice>"#
    ));
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(
        e[0].2
            .starts_with("the lattice fills up to cell 26 hold more than"),
        "{}",
        e[0].2
    );
    assert_eq!(openmc::MAX_LATTICE_ELEMENTS, 1 << 24);
}
