//! Boundary conditions: the root cells beyond a vacuum surface are outside
//! the model; reflective, white and periodic surfaces are named in a note.

use super::*;

/// The names of the cells marked outside.
fn outside(l: &Loaded) -> Vec<&str> {
    l.scene
        .geometry
        .regions
        .iter()
        .zip(&l.scene.regions)
        .filter(|(_, p)| p.outside)
        .map(|(r, _)| r.name.as_str())
        .collect()
}

#[test]
fn the_cell_beyond_a_vacuum_sphere_is_outside() {
    let l = model(
        r#"<surface id="1" type="sphere" coeffs="0 0 0 10" boundary="vacuum"/>
<surface id="2" type="sphere" coeffs="0 0 0 5"/>
<cell id="1" material="1" region="-2"/>
<cell id="2" material="void" region="2 -1"/>
<cell id="3" material="void" region="1"/>"#,
    );
    assert_eq!(outside(&l), ["3"]);
    assert!(l.scene.notes.is_empty());
}

#[test]
fn the_outside_of_a_vacuum_box_may_be_a_union_or_a_complement() {
    let planes = r#"<surface id="1" type="x-plane" coeffs="-1" boundary="vacuum"/>
<surface id="2" type="x-plane" coeffs="1" boundary="vacuum"/>
<surface id="3" type="y-plane" coeffs="-1" boundary="vacuum"/>
<surface id="4" type="y-plane" coeffs="1" boundary="vacuum"/>
<cell id="1" material="1" region="1 -2 3 -4"/>"#;
    let l = model(&format!(
        r#"{planes}<cell id="9" material="void" region="-1 | 2 | -3 | 4"/>"#
    ));
    assert_eq!(outside(&l), ["9"]);
    let l = model(&format!(
        r#"{planes}<cell id="9" material="void" region="~(1 -2 3 -4)"/>"#
    ));
    assert_eq!(outside(&l), ["9"]);
    // A cell of the union that is partly inside is not outside.
    let l = model(&format!(
        r#"{planes}<surface id="5" type="sphere" coeffs="0 0 0 0.5"/><cell id="9" material="void" region="-1 | -5"/>"#
    ));
    assert!(outside(&l).is_empty());
}

#[test]
fn a_gap_beyond_an_inner_vacuum_surface_is_still_inside() {
    // heu-met-fast-008's diaphragm: a void ring beyond vacuum cylinder 2
    // but inside vacuum sphere 1, which particles reach through its planes.
    let l = model(
        r#"<surface id="1" type="sphere" coeffs="0 0 0 16" boundary="vacuum"/>
<surface id="2" type="z-cylinder" coeffs="0 0 15" boundary="vacuum"/>
<surface id="3" type="z-plane" coeffs="0"/>
<surface id="4" type="z-plane" coeffs="1"/>
<cell id="1" material="1" region="3 -4 -2"/>
<cell id="2" material="void" region="3 -4 2 -1"/>
<cell id="3" material="void" region="-1 -3"/>
<cell id="4" material="void" region="-1 4"/>"#,
    );
    assert!(outside(&l).is_empty());
}

#[test]
fn cells_of_filled_universes_are_never_outside() {
    let l = model(
        r#"<surface id="1" type="sphere" coeffs="0 0 0 10" boundary="vacuum"/>
<cell id="1" fill="5" region="-1"/>
<cell id="51" universe="5" material="1" region="1"/>
<cell id="52" universe="5" material="2" region="-1"/>"#,
    );
    assert!(outside(&l).is_empty());
}

#[test]
fn reflective_white_and_periodic_boundaries_are_noted() {
    let l = model(
        r#"<surface id="1" type="x-plane" coeffs="-1" boundary="reflective"/>
<surface id="2" type="x-plane" coeffs="1" boundary="reflective"/>
<surface id="3" type="y-plane" coeffs="-1" boundary="periodic"/>
<surface id="4" type="y-plane" coeffs="1" boundary="white"/>
<cell id="1" material="1" region="1 -2 3 -4"/>"#,
    );
    assert_eq!(
        l.scene.notes,
        [
            "surfaces 1, 2 are reflective (OpenMC's boundaries mirror particles back): \
             only the model itself is drawn",
            "surface 4 is white (OpenMC's boundaries send particles back in random directions): \
             only the model itself is drawn",
            "surface 3 is periodic (OpenMC's boundaries send particles on through their partners): \
             only the model itself is drawn",
        ]
    );
    assert!(outside(&l).is_empty());
}
