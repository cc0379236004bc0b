//! Materials, titles, lattices and comments.

use super::*;
use sv_geom::Fill;

#[test]
fn materials_and_black_holes() {
    let Some(l) = input("001_RPP.inp") else {
        return;
    };
    let i = l.scene.geometry.region_index("blackhole").unwrap();
    let black = &l.scene.regions[i];
    assert!(black.transparent && black.outside);
    assert_eq!(black.description, "material: BLCKHOLE");
    assert_eq!(
        (black.material, black.material_name.as_deref()),
        (1, Some("BLCKHOLE"))
    );
    let j = l.scene.geometry.region_index("rppreg").unwrap();
    let beryllium = &l.scene.regions[j];
    assert!(!beryllium.transparent && !beryllium.outside);
    assert_eq!(beryllium.description, "material: BERYLLIU");
    // Beryllium is FLUKA's predefined material 5.
    assert_eq!(
        (beryllium.material, beryllium.material_name.as_deref()),
        (5, Some("BERYLLIU"))
    );
    // `ASSIGNMA BLCKHOLE bbr` names a region that does not exist.
    assert_eq!(
        warnings(&l),
        [((18, 28), "ASSIGNMA refers to undefined region `bbr`")]
    );
    // A range: ASSIGNMA , BERYLLIU, BE3, BE4 (free format).
    let l = input("manualSimpleFileFixed.inp").unwrap();
    assert_eq!(
        descriptions(&l),
        [
            "material: BLCKHOLE",
            "material: VACUUM",
            "material: BERYLLIU",
            "material: BERYLLIU"
        ]
    );
    assert_eq!(l.scene.regions[1].air, 1);
    assert!(
        l.scene.regions[1].transparent,
        "vacuum is air: hidden unless --show-air"
    );
    assert_eq!(
        l.scene.title,
        "Charged pion fluence inside and around a proton-irradiated Be target"
    );
    // No ASSIGNMA at all.
    let l = read_text(&geo("SPH a 0 0 0 1", "r 5 +a")).unwrap();
    assert!(!l.scene.regions[0].transparent);
    assert_eq!(
        l.scene.notes,
        ["no ASSIGNMA cards: every region is drawn opaque"]
    );
}

#[test]
fn titles() {
    let Some(l) = input("104_shift_cylinders.inp") else {
        return;
    };
    assert_eq!(l.scene.title, "Correctly shift the cylinder alon its axis.");
    // With an empty TITLE the geometry title line is used.
    let l = input("601_filter_redundant_halfspaces.inp").unwrap();
    assert_eq!(l.scene.title, "MC-CAD");
    let l = input("manualSimpleFileFree.inp").unwrap();
    assert_eq!(
        l.scene
            .regions
            .iter()
            .map(|p| p.description.as_str())
            .collect::<Vec<_>>(),
        [
            "material: BLCKHOLE",
            "material: VACUUM",
            "material: BERYLLIU",
            "material: BERYLLIU"
        ]
    );
}

#[test]
fn lattice_cells_hold_the_prototype_moved_by_the_inverse_transformation() {
    let Some(l) = input("701_LATTICE.inp") else {
        return;
    };
    assert!(l.scene.notes.is_empty(), "{:?}", l.scene.notes);
    // The container was made by `$start_transform -Rotdefi1` around a copy
    // of the prototype's body: the prototype moved into the cell is the
    // container itself.
    let cell = region(&l, "REPLICA");
    let Some(Fill::Universe {
        universe: 0,
        region_from_universe,
    }) = &cell.fill
    else {
        panic!("REPLICA is not filled with the model: {:?}", cell.fill);
    };
    let moved = body(&l, "target")
        .transformed(region_from_universe)
        .unwrap();
    assert_close(&moved.params, &body(&l, "targRepl").params);
    assert!(region(&l, "TARGET").fill.is_none());
    let l = input("702_LATTICE.inp").unwrap();
    assert_eq!(zones(&l, "REPLICA"), ["+repl -repl2"]);
    for name in ["REPLICA", "REPLIC2"] {
        assert!(matches!(
            region(&l, name).fill,
            Some(Fill::Universe { universe: 0, .. })
        ));
    }
    let text =
        geo("SPH a 0 0 0 1", "r 5 +a").replace("END\nGEOEND", "END\nLATTICE      cell\nGEOEND");
    assert_eq!(
        errors(&text),
        [(
            9,
            14,
            "LATTICE refers to undefined region `cell`".to_string()
        )]
    );
}

#[test]
fn a_comment_before_the_geometry_title_is_skipped() {
    let text = geo("SPH a 0 0 0 1", "r 5 +a").replace("COMBNAME\n", "COMBNAME\n* note\n");
    let l = read_text(&text.replace("TITLE\nhand-made\n", "")).unwrap();
    assert_eq!(l.scene.title, "test");
}

#[test]
fn comments_are_skipped() {
    let text = geo(
        "* a comment\nSPH a 0 0 0 1 ! trailing\n!whole line",
        "* note\nr 5 +a ! comment -b",
    );
    let l = read_text(&text).unwrap();
    assert_eq!(zones(&l, "r"), ["+a"]);
}

#[test]
fn nothing_after_stop_is_read() {
    // FLUKA stops reading at STOP: later cards (even a second geometry)
    // are notes, not input.
    let text = geo("SPH a 0 0 0 1", "r 5 +a")
        + "ASSIGNMA        IRON         r\nSTOP\nASSIGNMA        LEAD         r\nGEOBEGIN\nnotes\n";
    let l = read_text(&text).unwrap();
    assert_eq!(l.scene.regions[0].material_name.as_deref(), Some("IRON"));
    assert!(l.warnings.is_empty());
}
