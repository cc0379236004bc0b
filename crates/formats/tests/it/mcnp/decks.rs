//! Every MCNP input of ../shared/decks/mcnp-openmc loads; its counts of
//! cells, surfaces, universes, lattices and materials match a plain scan of
//! the file; points of the models fall in the cells they should.

use super::*;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use sv_geom::Fill;

/// Every file named `input` under the folder, sorted.
pub(super) fn inputs() -> Vec<PathBuf> {
    let Some(root) = sv_testdata::shared_decks("mcnp-openmc") else {
        return Vec::new();
    };
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.file_name().is_some_and(|n| n == "input") {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    walk(&root, &mut out);
    out.sort();
    assert!(
        out.len() >= 60,
        "expected the 68 MCNP inputs, found {}",
        out.len()
    );
    out
}

fn read_path(path: &Path) -> Loaded {
    let text = std::fs::read_to_string(path).unwrap();
    match read_named(&path.display().to_string(), &text) {
        Ok(l) => l,
        Err(d) => panic!("{} failed:\n{}", path.display(), d.render_plain()),
    }
}

/// What a plain scan of an input finds: cell cards, surface numbers,
/// universes (`U=`), lattices (`LAT=`) and `M` cards.
#[derive(Debug, Default)]
struct Scan {
    cells: usize,
    surfaces: Vec<String>,
    universes: BTreeSet<String>,
    lattices: usize,
    materials: usize,
}

fn scan(text: &str) -> Scan {
    let mut s = Scan::default();
    let mut block = 0;
    for raw in text.lines().skip(1) {
        let line = raw.replace('\t', "        ");
        if line.trim().is_empty() {
            block += 1;
            if block == 3 {
                break;
            }
            continue;
        }
        let head = line.trim_start();
        let lower = head.to_ascii_lowercase();
        if line.len() - head.len() < 5 && (lower == "c" || lower.starts_with("c ")) {
            continue;
        }
        let data = line.split('$').next().unwrap().to_ascii_lowercase();
        let words: Vec<&str> = data.split_whitespace().collect();
        let starts = !line.starts_with("     ");
        match block {
            0 => {
                s.cells += usize::from(starts);
                for w in &words {
                    if let Some(u) = w.strip_prefix("u=") {
                        s.universes.insert(u.trim_start_matches('-').to_string());
                    }
                    s.lattices += usize::from(w.starts_with("lat="));
                }
            }
            1 if starts => s
                .surfaces
                .push(words[0].trim_start_matches(['*', '+']).to_string()),
            2 if starts => {
                let w = words[0];
                s.materials += usize::from(
                    w.len() > 1 && w.starts_with('m') && w[1..].bytes().all(|b| b.is_ascii_digit()),
                );
            }
            _ => {}
        }
    }
    s
}

#[test]
fn every_input_loads_with_the_counts_of_its_file() {
    for path in inputs() {
        let text = std::fs::read_to_string(&path).unwrap();
        let l = read_path(&path);
        let want = scan(&text);
        let g = &l.scene.geometry;
        let name = path.display();
        assert_eq!(g.regions.len(), want.cells, "{name}: cells");
        let found = want
            .surfaces
            .iter()
            .filter(|s| {
                g.bodies
                    .iter()
                    .any(|b| b.name == **s || b.name == format!("{s}.1"))
            })
            .count();
        assert_eq!(found, want.surfaces.len(), "{name}: surfaces");
        let universes = if want.universes.is_empty() {
            0
        } else {
            want.universes.len() + 1
        };
        assert_eq!(g.universes.len(), universes, "{name}: universes");
        let lattices = g
            .regions
            .iter()
            .filter(|r| matches!(r.fill, Some(Fill::Lattice(_))))
            .count();
        assert_eq!(lattices, want.lattices, "{name}: lattices");
        assert_eq!(l.scene.materials.len(), want.materials, "{name}: materials");
        assert_eq!(l.scene.units, sv_scene::Units::Centimetre);
        for (r, p) in g.regions.iter().zip(&l.scene.regions) {
            assert!(!r.zones.is_empty(), "{name}: cell {} has no zones", r.name);
            if p.material > 0 {
                assert_eq!(p.material_name, Some(format!("m{}", p.material)), "{name}");
                assert!(
                    p.density.is_some() != p.atom_density.is_some(),
                    "{name}: cell {}",
                    r.name
                );
            }
        }
        // Far away is the outside of the model, for inputs that have one.
        let e = Eval::new(&l.scene);
        if l.scene.regions.iter().any(|r| r.outside) {
            let far = e
                .deepest(v(1.0e5, 3.0, 7.0))
                .expect("some cell holds every point");
            assert!(
                l.scene.regions[far].outside,
                "{name}: far away is cell {}",
                g.regions[far].name
            );
        }
    }
}

fn deck_named(sub: &str) -> Option<Loaded> {
    let root = sv_testdata::shared_decks("mcnp-openmc")?;
    Some(read_path(&root.join(sub)))
}

/// The material of the deepest cell holding `p`.
fn material_at(e: &Eval, p: DVec3) -> i64 {
    e.scene.regions[e.deepest(p).expect("a cell holds the point")].material
}

#[test]
fn hoogenboom_martin_core_nests_lattices() {
    let Some(l) = deck_named("mc-performance/mcnp/input") else {
        return;
    };
    let g = &l.scene.geometry;
    assert_eq!(g.universes.len(), 11);
    let Some(Fill::Lattice(core)) = &region(&l, "1").fill else {
        panic!("cell 1 is the core lattice");
    };
    assert_eq!((core.lowest, core.counts), ([-10, -10, 0], [21, 21, 1]));
    // Its first surface is px -10.71: element (1,0,0) lies toward -x.
    assert_close(&core.steps[0].to_array(), &[-21.42, 0.0, 0.0]);
    let e = Eval::new(&l.scene);
    // The central assembly's centre: an instrumentation tube, cold water.
    assert_eq!(
        e.path(v(0.0, 0.0, -100.0)),
        ["100", "1", "[0,0,0]", "60", "[0,0,0]", "24"]
    );
    // One pin over: fuel, then cladding.
    assert_eq!(
        e.path(v(1.26, 0.0, -100.0)),
        ["100", "1", "[0,0,0]", "60", "[-1,0,0]", "21"]
    );
    assert_eq!(e.cell(v(1.71, 0.0, -100.0)), "22");
    assert_eq!(material_at(&e, v(1.26, 0.0, -100.0)), 1);
    // The upper half: hot water in the tube.
    assert_eq!(
        e.path(v(0.0, 0.0, 100.0)),
        ["200", "2", "[0,0,0]", "80", "[0,0,0]", "30"]
    );
    assert_eq!(material_at(&e, v(0.0, 0.0, 100.0)), 4);
    // A water assembly near the edge of the core, the reflector, the
    // vessel and beyond.
    assert_eq!(
        e.path(v(85.68, 171.36, -100.0)),
        ["100", "1", "[-4,-8,0]", "50"]
    );
    assert_eq!(e.cell(v(85.68, 171.36, -190.0)), "11");
    assert_eq!(e.cell(v(240.0, 0.0, 0.0)), "10");
    assert_eq!(e.cell(v(300.0, 0.0, 0.0)), "99");
}

#[test]
fn pu_met_fast_003_moves_filled_tubes_with_trcl() {
    let Some(l) = deck_named("icsbep/pu-met-fast-003/mcnp/case-103/input") else {
        return;
    };
    let e = Eval::new(&l.scene);
    assert_eq!(e.path(v(0.0, 0.0, 25.0)), ["46", "36", "21"]);
    assert_eq!(e.path(v(9.6, 9.6, 25.0)), ["46", "40", "21"]);
    assert_eq!(e.path(v(-9.6, 0.0, 17.5)), ["46", "42", "11"]);
    assert_eq!(e.path(v(4.8, 0.0, 25.0)), ["46", "45"]);
    assert_eq!(material_at(&e, v(9.6, -9.6, 32.9)), 1);
    assert_eq!(body(&l, "40033").params, [9.6, 9.6, 3.609]);
}

#[test]
fn u233_lattice_and_control_blades() {
    let Some(l) = deck_named("icsbep/u233-comp-therm-001/mcnp/case-3/input") else {
        return;
    };
    let e = Eval::new(&l.scene);
    assert_eq!(e.path(v(0.46, 0.46, 0.0)), ["12", "11", "[0,0,0]", "1"]);
    assert_eq!(
        e.path(v(0.46 + 3.0 * 0.91948, 0.46, 0.0)),
        ["12", "11", "[3,0,0]", "1"]
    );
    assert_eq!(e.path(v(0.0, -5.5, 20.0)), ["7"]);
    assert_eq!(e.cell(v(30.0, 0.0, 0.0)), "16");
    assert_eq!(e.cell(v(0.0, -30.0, 0.0)), "17");
}

#[test]
fn leu_comp_therm_008_nests_an_infinite_lattice_of_lattices() {
    let Some(l) = deck_named("icsbep/leu-comp-therm-008/mcnp/case-11/input") else {
        return;
    };
    let e = Eval::new(&l.scene);
    // The assembly's centre holds the lattice cell's own water.
    assert_eq!(
        e.path(v(0.1, 0.1, 0.0)),
        ["10", "9", "[0,0,0]", "8", "[0,0,0]"]
    );
    assert_eq!(material_at(&e, v(0.1, 0.1, 0.0)), 3);
    assert_eq!(
        e.path(v(1.63576, 0.05, 0.0)),
        ["10", "9", "[0,0,0]", "8", "[1,0,0]", "1"]
    );
    assert_eq!(e.cell(v(3.27152, 8.1788, 0.0)), "4");
    // The next assembly over: element (-1,0,0) lies toward +x.
    assert_eq!(
        e.path(v(24.5364 + 1.63576, 0.05, 0.0)),
        ["10", "9", "[-1,0,0]", "8", "[1,0,0]", "1"]
    );
}
