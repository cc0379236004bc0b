//! Lattices in checks and volumes: the region a lattice fills counts as
//! met when its contents are, and an element that holds the lattice's own
//! universe is the lattice cell's own material, as MCNP has it.

use sv_check::{check, volumes, CheckOptions, Model, UniverseChoice, VolumeOptions};
use sv_formats::{load_source, Format, LoadOptions, SourceFile};

/// A 3×3 lattice of water pins in a 6 cm square, 10 cm high; the middle
/// element names the lattice's own universe (2), so it is the lattice
/// cell's steel.
const DECK: &str = "\
lattice of pins
1 1 -1.0 -1 u=1 imp:n=1
2 0 1 u=1 imp:n=1
3 2 -7.9 -2 3 -4 5 lat=1 u=2 imp:n=1 fill=-1:1 -1:1 0:0 1 1 1 1 2 1 1 1 1
4 0 -6 7 -8 9 -10 11 fill=2 imp:n=1
5 0 6:-7:8:-9:10:-11 imp:n=0

1 cz 0.4
2 px 1
3 px -1
4 py 1
5 py -1
6 px 3
7 px -3
8 py 3
9 py -3
10 pz 5
11 pz -5

m1 1001 2 8016 1
m2 26000 1
";

fn model() -> Model {
    let src = SourceFile::new("lattice.i", DECK);
    let scene = load_source(&src, Format::Mcnp, &LoadOptions::default())
        .expect("the deck reads")
        .scene;
    Model::new(&scene, &UniverseChoice::None)
        .expect("prepares")
        .0
}

#[test]
fn a_lattice_and_the_cell_it_fills_count_as_met() {
    let model = model();
    let report = check(&model, &CheckOptions::default()).expect("checks");
    assert!(report.is_clean(), "{}", report.to_table());
    assert!(report.unseen.is_empty(), "unseen: {:?}", report.unseen);
}

#[test]
fn an_element_of_the_lattices_own_universe_is_its_material() {
    let model = model();
    let opts = VolumeOptions {
        rel_error: 0.01,
        ..VolumeOptions::default()
    };
    let report = volumes(&model, &opts).expect("measures");
    let volume = |name: &str| {
        let region = report.regions.iter().find(|r| r.region == name);
        region.map_or(0.0, |r| r.volume)
    };
    let pins = 8.0 * std::f64::consts::PI * 0.16 * 10.0;
    for (name, exact) in [("1", pins), ("2", 8.0 * 40.0 - pins), ("3", 40.0)] {
        let measured = volume(name);
        assert!(
            (measured - exact).abs() < 0.03 * exact,
            "cell {name}: {measured} against {exact}"
        );
    }
}
