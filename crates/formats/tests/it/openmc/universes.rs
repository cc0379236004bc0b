//! Universes, fills with their rotations and translations, rectangular and
//! hexagonal lattices, and fill cycles.

use super::*;
use sv_math::DAffine3;

/// The names of the universes, the root first.
fn universe_names(l: &Loaded) -> Vec<&str> {
    let universes = &l.scene.geometry.universes;
    universes.iter().map(|u| u.name.as_str()).collect()
}

/// The transform of the universe filling cell `name`.
fn fill_transform(l: &Loaded, name: &str) -> DAffine3 {
    match &region(l, name).fill {
        Some(Fill::Universe {
            region_from_universe,
            ..
        }) => *region_from_universe,
        other => panic!("cell {name} is filled with {other:?}"),
    }
}

/// A pin universe 5 (cell 51 of fuel inside z-cylinder 10, cell 52 of
/// water around it), plus `rest`.
fn with_pin(rest: &str) -> Loaded {
    model(&format!(
        r#"<surface id="10" type="z-cylinder" coeffs="0 0 0.4"/>
<cell id="51" universe="5" material="1" region="-10"/>
<cell id="52" universe="5" material="2" region="10"/>
{rest}"#
    ))
}

#[test]
fn a_fill_names_a_universe_moved_by_its_translation() {
    let l = with_pin(
        r#"<surface id="1" type="sphere" coeffs="0 0 0 5" boundary="vacuum"/>
<cell id="1" fill="5" region="-1" translation="1 2 3"/>"#,
    );
    assert_eq!(universe_names(&l), ["0", "5"]);
    assert_eq!(region(&l, "51").universe, 1);
    assert_eq!(region(&l, "1").universe, 0);
    let Some(Fill::Universe {
        universe,
        region_from_universe,
    }) = &region(&l, "1").fill
    else {
        panic!("cell 1 is not filled with a universe");
    };
    assert_eq!(*universe, 1);
    assert_eq!(
        *region_from_universe,
        DAffine3::from_translation(DVec3::new(1.0, 2.0, 3.0))
    );
    assert_eq!(cells_at(&l, DVec3::new(1.1, 2.0, 0.0)), ["1", "51"]);
    assert_eq!(cells_at(&l, DVec3::new(0.0, 0.0, 0.0)), ["1", "52"]);
}

#[test]
fn rotations_turn_the_fill_as_openmc_does() {
    // A fuel slab x < 1 in universe 5, turned 90° about z: it lies at
    // y < 1 of the cell (OpenMC's universe point (1, 0, 0) is the cell's
    // (0, 1, 0)).
    let l = model(
        r#"<surface id="10" type="x-plane" coeffs="1"/>
<cell id="51" universe="5" material="1" region="-10"/>
<cell id="52" universe="5" material="2" region="10"/>
<surface id="1" type="sphere" coeffs="0 0 0 5"/>
<cell id="1" fill="5" region="-1" rotation="0 0 90"/>"#,
    );
    let m = fill_transform(&l, "1");
    assert!(close(m.transform_point3(DVec3::X), DVec3::Y));
    assert_eq!(cells_at(&l, DVec3::new(3.0, 0.5, 0.0)), ["1", "51"]);
    assert_eq!(cells_at(&l, DVec3::new(0.5, 3.0, 0.0)), ["1", "52"]);
}

#[test]
fn three_angles_compose_about_x_then_y_then_z() {
    // cell.cpp: the fill sees R = Rz(-ψ) Ry(-θ) Rx(-φ) (x - t); so the
    // cell's point of a fill point u is Rx(φ) Ry(θ) Rz(ψ) u + t.
    let l = with_pin(
        r#"<surface id="1" type="sphere" coeffs="0 0 0 50"/>
<cell id="1" fill="5" region="-1" rotation="30 45 60" translation="1 -2 3"/>"#,
    );
    let m = fill_transform(&l, "1");
    let r = DAffine3::from_translation(DVec3::new(1.0, -2.0, 3.0))
        * DAffine3::from_rotation_x(30f64.to_radians())
        * DAffine3::from_rotation_y(45f64.to_radians())
        * DAffine3::from_rotation_z(60f64.to_radians());
    for u in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(1.0, 2.0, 3.0)] {
        assert!(close(m.transform_point3(u), r.transform_point3(u)), "{u}");
    }
}

#[test]
fn a_rotation_matrix_is_given_by_rows() {
    // The rows of a 90° turn about z as OpenMC applies it to the cell's
    // points: (x, y) → (y, -x).
    let l = with_pin(
        r#"<surface id="1" type="sphere" coeffs="0 0 0 50"/>
<cell id="1" fill="5" region="-1" rotation="0 1 0 -1 0 0 0 0 1"/>"#,
    );
    let m = fill_transform(&l, "1");
    assert!(close(
        m.inverse().transform_point3(DVec3::new(1.0, 2.0, 0.0)),
        DVec3::new(2.0, -1.0, 0.0)
    ));
    assert_eq!(
        errors(
            r#"<surface id="1" type="sphere" coeffs="0 0 0 50"/>
<cell id="7" universe="5" material="1"/>
<cell id="1" fill="5" region="-1" rotation="1 1 0 0 1 0 0 0 1"/>
<cell id="2" universe="5" material="1" region="-1" translation="1 1 1"/>"#
        ),
        [
            (4, 45, "this rotation matrix is not a rotation".to_string()),
            (
                5,
                65,
                "a translation applies to a fill, and this cell has none".to_string()
            ),
        ]
    );
}

#[test]
fn the_root_is_universe_zero_or_the_one_no_fill_uses() {
    // No universe 0: universe 7 fills nothing and is the root.
    let l = with_pin(
        r#"<surface id="1" type="sphere" coeffs="0 0 0 5"/>
<cell id="1" universe="7" fill="5" region="-1"/>"#,
    );
    assert_eq!(universe_names(&l), ["7", "5"]);
    assert_eq!(region(&l, "1").universe, 0);
    // Two unused universes and no 0: which is the root?
    let e = errors(
        r#"<cell id="1" universe="3" material="1"/>
<cell id="2" universe="4" material="1"/>"#,
    );
    assert_eq!(
        e,
        [(
            3,
            24,
            "universes 3, 4 are not filled into anything: which one is the root?".to_string()
        )]
    );
    // With universe 0, an unused universe is only a warning.
    let l = model(
        r#"<cell id="1" material="1"/>
<cell id="2" universe="4" material="1"/>"#,
    );
    assert_eq!(l.warnings.len(), 1, "{:?}", l.warnings);
    assert_eq!(
        l.warnings[0].message,
        "universe 4 is not filled into anything: its cells are not drawn"
    );
    assert_eq!(l.warnings[0].line_col(), (3, 24));
}

#[test]
fn fill_cycles_are_errors_at_the_fill_that_closes_them() {
    let e = errors(
        r#"<cell id="1" fill="2"/>
<cell id="20" universe="2" fill="3"/>
<cell id="30" universe="3" fill="2"/>
<cell id="40" universe="4" fill="4"/>
<cell id="50" universe="2" fill="77"/>"#,
    );
    assert_eq!(
        e,
        [
            (
                4,
                34,
                "fill cycle: universe 2 → cell 20 fills 3 → cell 30 fills 2".to_string()
            ),
            (
                5,
                34,
                "cell 40 is filled with universe 4, the universe it belongs to".to_string()
            ),
            (
                6,
                34,
                "fill 77 of cell 50 is neither a universe nor a lattice".to_string()
            ),
        ]
    );
    let e = errors(
        r#"<cell id="1" fill="2"/>
<cell id="20" universe="2" fill="3"/>
<cell id="30" universe="3" fill="10"/>
<lattice id="10" dimension="1 1"><lower_left>0 0</lower_left><pitch>1 1</pitch><universes>2</universes></lattice>"#,
    );
    assert_eq!(
        e,
        [(
            4,
            34,
            "fill cycle: universe 2 → cell 20 fills 3 → cell 30 fills 10".to_string()
        )]
    );
}

/// A 3×2 lattice of pins (5) and water cells (6), listed top row first.
const RECT: &str = r#"<cell id="61" universe="6" material="2"/>
<surface id="1" type="x-plane" coeffs="-3"/>
<surface id="2" type="x-plane" coeffs="3"/>
<surface id="3" type="y-plane" coeffs="-2"/>
<surface id="4" type="y-plane" coeffs="2"/>
<cell id="1" fill="100" region="1 -2 3 -4"/>
<lattice id="100">
  <dimension>3 2</dimension>
  <lower_left>-3 -2</lower_left>
  <pitch>2 2</pitch>
  <universes>
    5 6 6
    6 6 5
  </universes>
</lattice>"#;

#[test]
fn rectangular_lattices_list_rows_from_the_top() {
    let l = with_pin(RECT);
    let lat = lattice(&l, "1");
    assert_eq!(lat.kind, LatticeKind::Rectangular);
    assert_eq!(lat.counts, [3, 2, 1]);
    assert_eq!(lat.lowest, [0, 0, 0]);
    assert_eq!(lat.steps[0], DVec3::new(2.0, 0.0, 0.0));
    assert_eq!(lat.steps[1], DVec3::new(0.0, 2.0, 0.0));
    assert_eq!(lat.base.truncate(), sv_math::DVec2::new(-3.0, -2.0));
    assert_eq!(lat.origin, DVec3::new(-2.0, -1.0, 0.0));
    // Universe 5 is index 1, 6 index 2: the bottom row (listed last) is
    // element row 0.
    assert_eq!(
        lat.elements,
        [Some(2), Some(2), Some(1), Some(1), Some(2), Some(2)]
    );
    assert_eq!(lat.outer, None);
    // Pins at the top left and bottom right, centred in their elements.
    assert_eq!(cells_at(&l, DVec3::new(-2.0, 1.0, 7.0)), ["1", "51"]);
    assert_eq!(cells_at(&l, DVec3::new(2.0, -1.0, -7.0)), ["1", "51"]);
    assert_eq!(cells_at(&l, DVec3::new(2.0, 1.0, 0.0)), ["1", "61"]);
    assert_eq!(cells_at(&l, DVec3::new(-1.5, 1.0, 0.0)), ["1", "52"]);
}

#[test]
fn a_two_dimensional_lattice_leaves_z_alone() {
    let l = with_pin(RECT);
    let lat = lattice(&l, "1");
    assert_eq!(lat.base.z, -openmc::UNBOUNDED);
    assert_eq!(lat.steps[2], DVec3::new(0.0, 0.0, 2.0 * openmc::UNBOUNDED));
    assert_eq!(lat.origin.z, 0.0);
}

#[test]
fn three_dimensional_lattices_stack_layers_from_the_bottom() {
    let l = with_pin(
        r#"<cell id="61" universe="6" material="2"/>
<cell id="1" fill="100"/>
<lattice id="100" dimension="1 2 2" outer="6">
  <lower_left>0 0 -4</lower_left>
  <pitch>1 1 4</pitch>
  <universes>5 6  6 6</universes>
</lattice>"#,
    );
    let lat = lattice(&l, "1");
    assert_eq!(lat.counts, [1, 2, 2]);
    assert_eq!(lat.origin, DVec3::new(0.5, 0.5, -2.0));
    assert_eq!(lat.elements, [Some(2), Some(1), Some(2), Some(2)]);
    assert_eq!(lat.outer, Some(2));
    assert_eq!(cells_at(&l, DVec3::new(0.5, 1.5, -2.0)), ["1", "51"]);
    assert_eq!(cells_at(&l, DVec3::new(0.5, 1.5, 2.0)), ["1", "61"]);
    // Beyond the elements: the outer universe.
    assert_eq!(cells_at(&l, DVec3::new(7.5, 0.5, 0.0)), ["1", "61"]);
}

/// A 2-ring hexagonal lattice: pins (5) on the outer ring's listed
/// positions given, water (6) elsewhere.
fn hex(orientation: &str, universes: &str) -> Loaded {
    with_pin(&format!(
        r#"<cell id="61" universe="6" material="2"/>
<cell id="62" universe="7" material="2"/>
<cell id="1" fill="200"/>
<hex_lattice id="200" n_rings="2" {orientation} outer="7">
  <center>10 20</center>
  <pitch>2</pitch>
  <universes>{universes}</universes>
</hex_lattice>"#
    ))
}

#[test]
fn hexagonal_lattices_map_rings_onto_the_skewed_grid() {
    // Orientation y: rows from the top; the first is the element above the
    // centre, the fourth the centre.
    let l = hex("", "5  6 6  6  6 6  6");
    let lat = lattice(&l, "1");
    assert_eq!(lat.kind, LatticeKind::Hexagonal);
    assert_eq!((lat.lowest, lat.counts), ([-1, -1, 0], [3, 3, 1]));
    let r3 = 3f64.sqrt();
    assert!(close(lat.steps[0], DVec3::new(r3, 1.0, 0.0)));
    assert!(close(lat.steps[1], DVec3::new(0.0, 2.0, 0.0)));
    assert_eq!(lat.base, DVec3::new(10.0, 20.0, 0.0));
    assert_eq!(lat.origin, lat.base);
    assert_eq!(lat.element([0, 1, 0]), Some(1));
    assert_eq!(lat.element([0, 0, 0]), Some(2));
    // Corners of the 3×3 grid beyond the ring hold the outer universe.
    assert_eq!(lat.element([1, 1, 0]), Some(3));
    assert_eq!(lat.element([-1, -1, 0]), Some(3));
    assert_eq!(cells_at(&l, DVec3::new(10.0, 22.0, 0.0)), ["1", "51"]);
    assert_eq!(cells_at(&l, DVec3::new(10.0, 18.0, 0.0)), ["1", "61"]);
    assert_eq!(cells_at(&l, DVec3::new(10.0, 26.0, 0.0)), ["1", "62"]);
    // The second word is the upper left element, the third the upper right.
    let l = hex("", "6  5 6  6  6 6  6");
    assert_eq!(cells_at(&l, DVec3::new(10.0 - r3, 21.0, 0.0)), ["1", "51"]);
    let l = hex("", "6  6 5  6  6 6  6");
    assert_eq!(cells_at(&l, DVec3::new(10.0 + r3, 21.0, 0.0)), ["1", "51"]);
    // The last word is the element below the centre.
    let l = hex("", "6  6 6  6  6 6  5");
    assert_eq!(cells_at(&l, DVec3::new(10.0, 18.0, 0.0)), ["1", "51"]);
}

#[test]
fn x_oriented_hexagonal_lattices_list_rows_left_to_right() {
    // Orientation x: rows of 2, 3, 2 from the top, each from the left.
    let l = hex(r#"orientation="x""#, "5 6  6 6 6  6 6");
    let lat = lattice(&l, "1");
    let r3 = 3f64.sqrt();
    assert!(close(lat.steps[0], DVec3::new(2.0, 0.0, 0.0)));
    assert!(close(lat.steps[1], DVec3::new(1.0, r3, 0.0)));
    assert_eq!(cells_at(&l, DVec3::new(9.0, 20.0 + r3, 0.0)), ["1", "51"]);
    let l = hex(r#"orientation="x""#, "6 6  6 6 5  6 6");
    assert_eq!(cells_at(&l, DVec3::new(12.0, 20.0, 0.0)), ["1", "51"]);
    let l = hex(r#"orientation="x""#, "6 6  6 6 6  6 5");
    assert_eq!(cells_at(&l, DVec3::new(11.0, 20.0 - r3, 0.0)), ["1", "51"]);
}

#[test]
fn hexagonal_layers_are_centred_on_the_lattice() {
    let l = with_pin(
        r#"<cell id="61" universe="6" material="2"/>
<cell id="1" fill="200"/>
<hex_lattice id="200" n_rings="1" n_axial="2">
  <center>0 0 10</center>
  <pitch>1 4</pitch>
  <universes>5 6</universes>
</hex_lattice>"#,
    );
    let lat = lattice(&l, "1");
    assert_eq!(lat.base, DVec3::new(0.0, 0.0, 8.0));
    assert_eq!(lat.steps[2], DVec3::new(0.0, 0.0, 4.0));
    assert_eq!(cells_at(&l, DVec3::new(0.0, 0.0, 9.0)), ["1", "51"]);
    assert_eq!(cells_at(&l, DVec3::new(0.0, 0.0, 11.0)), ["1", "61"]);
}

#[test]
fn lattice_errors_are_located_and_reported_together() {
    let e = errors(
        r#"<cell id="61" universe="6" material="2"/>
<cell id="1" fill="100"/>
<cell id="2" fill="200"/>
<lattice id="100" dimension="2 2">
  <lower_left>0 0</lower_left>
  <pitch>1 1</pitch>
  <universes>6 6 6</universes>
</lattice>
<hex_lattice id="200" n_rings="2" outer="9">
  <center>0 0</center>
  <pitch>1</pitch>
  <universes>6 6 6 8 6 6 6</universes>
</hex_lattice>
<lattice id="300" dimension="1 1">
  <lower_left>0 0 0</lower_left>
  <pitch>1 -1</pitch>
  <universes>6</universes>
</lattice>"#,
    );
    assert_eq!(
        by_place(&e),
        [
            (
                8,
                14,
                "lattice 100 lists 3 universes; a 2×2 lattice takes 4"
            ),
            (10, 42, "the outer universe 9 of lattice 200 has no cells"),
            (
                13,
                20,
                "lattice 200 holds universe 8, which no cell belongs to"
            ),
            (16, 15, "the lower left corner takes 2 numbers, found 3"),
            (17, 10, "a pitch must be positive"),
        ]
    );
}
