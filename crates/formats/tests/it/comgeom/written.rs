//! Written decks read back to the same scene.

use super::*;

fn assert_same_props(a: &Scene, b: &Scene) {
    assert_eq!(a.title, b.title);
    assert_eq!(a.units, b.units);
    assert_eq!(a.regions.len(), b.regions.len());
    for (x, y) in a.regions.iter().zip(&b.regions) {
        assert_eq!(
            (x.ident, x.air, x.material, x.los, x.transparent),
            (y.ident, y.air, y.material, y.los, y.transparent)
        );
        assert_eq!(x.description, y.description);
    }
}

#[test]
fn written_v5_decks_read_back_to_the_same_geometry() {
    for name in [VDECK, GENERATOR] {
        let Some(l) = load(name) else { return };
        let w = comgeom::write(&l.scene).unwrap();
        assert!(w.notes.is_empty(), "{name}: {:?}", w.notes);
        let again = round_trip(&l.scene);
        assert_eq!(again.geometry, l.scene.geometry, "{name}");
        assert_same_props(&l.scene, &again);
        // Writing is stable.
        assert_eq!(comgeom::write(&again).unwrap().text, w.text);
    }
}

#[test]
fn written_gift_deck_reads_back_with_the_foci_ell_in_centre_form() {
    let Some(l) = load(GIFT) else { return };
    let w = comgeom::write(&l.scene).unwrap();
    assert_eq!(
        w.notes,
        ["body 5: ELL given by its foci is written as ELL1 (centre, semi-major axis, radius)"]
    );
    let again = round_trip(&l.scene);
    let mut expect: Geometry = l.scene.geometry.clone();
    let ell = &mut expect.bodies[4];
    ell.kind = BodyKind::Ell1;
    ell.params = comgeom::ell_foci_to_centre(&ell.params).to_vec();
    assert_eq!(ell.params, [0.0, 0.0, 48.0, -25.0, 0.0, 0.0, 15.0]);
    assert_eq!(again.geometry, expect);
    assert_same_props(&l.scene, &again);
}

#[test]
fn writer_keeps_full_precision_and_says_when_it_cannot() {
    let text = v5_deck(
        1,
        1,
        &[v5_body("1", "SPH", &["1.5e-7", "-2.25", "1e20", "0.1"])],
        &[v5_region("1", &[("", 1)])],
    );
    let mut scene = read_ok("p.cg", &text).scene;
    scene.geometry.bodies[0].params[3] = 0.1 + 0.2;
    let w = comgeom::write(&scene).unwrap();
    let again = read_ok("w.cg", &w.text).scene;
    assert_eq!(again.geometry.bodies[0].params[..3], [1.5e-7, -2.25, 1e20]);
    assert!((again.geometry.bodies[0].params[3] - 0.3).abs() < 1e-9);
    assert_eq!(
        w.notes,
        ["body 1 (SPH): value 4 (0.30000000000000004) written as 0.30000000 to fit 10 columns"]
    );
}

#[test]
fn writer_refuses_bodies_comgeom_cannot_express() {
    let mut scene = Scene::default();
    scene.geometry.bodies.push(sv_geom::Body::new(
        "wall",
        BodyKind::Xcc,
        vec![0.0, 0.0, 1.0],
    ));
    let e = comgeom::write(&scene).unwrap_err();
    assert_eq!(
        e.to_string(),
        "body wall is a XCC, which a COMGEOM deck cannot express"
    );
}
