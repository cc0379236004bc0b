//! The numbered fixed-format geometry (GEOBEGIN COMBINAT or blank SDUM),
//! written in the tests in FLUKA's columns.

use super::*;

/// The FLUKA manual's first example (a beryllium target in vacuum) in the
/// numbered fixed format, with numbered ASSIGNMA cards.
pub(super) const MANUAL_EXAMPLE: &str = "\
TITLE
Be target in vacuum, numbered
GEOBEGIN                                                              COMBINAT
    0    0          Be target
  RPP    1-5000000.0+5000000.0-5000000.0+5000000.0-5000000.0+5000000.0
  RPP    2-1000000.0+1000000.0-1000000.0+1000000.0    -100.0+1000000.0
  RPP    3    -10.0     +10.0     -10.0     +10.0       0.0      +5.0
  XYP    4      2.5
  END
* black hole
  BH1    5     +1     -2
* vacuum around
  VA2    5     +2     -3
* Be target 1st half
  BE3    5     +3     +4
* Be target 2nd half
  BE4    5     +3     -4
  END
GEOEND
ASSIGNMA         1.0       1.0
ASSIGNMA         2.0       2.0
ASSIGNMA         5.0       3.0       4.0
STOP
";

#[test]
fn the_manual_example_in_fixed_columns() {
    let l = read_text(MANUAL_EXAMPLE).unwrap();
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    assert_eq!(l.scene.title, "Be target in vacuum, numbered");
    assert_eq!(body_names(&l), ["1", "2", "3", "4"]);
    assert_close(&body(&l, "1").params, &[-5e6, 5e6, -5e6, 5e6, -5e6, 5e6]);
    assert_close(&body(&l, "2").params, &[-1e6, 1e6, -1e6, 1e6, -100.0, 1e6]);
    assert_close(&body(&l, "3").params, &[-10.0, 10.0, -10.0, 10.0, 0.0, 5.0]);
    assert_eq!(body(&l, "4").kind, BodyKind::Xyp);
    assert_close(&body(&l, "4").params, &[2.5]);
    assert_eq!(zones(&l, "1"), ["+1 -2"]);
    assert_eq!(zones(&l, "4"), ["+3 -4"]);
    assert_eq!(
        descriptions(&l),
        [
            "BH1; material: BLCKHOLE",
            "VA2; material: VACUUM",
            "BE3; material: BERYLLIU",
            "BE4; material: BERYLLIU"
        ]
    );
    assert!(l.scene.regions[0].outside);
    assert_eq!(l.scene.regions[2].material, 5);
}

/// A numbered geometry with the title line `0 {idbg}`.
fn numbered(idbg: i32, bodies: &str, regions: &str) -> String {
    format!("GEOBEGIN                                                              COMBINAT\n    0{idbg:>5}          numbered\n{bodies}  END\n{regions}  END\nGEOEND\n")
}

#[test]
fn or_continuations_and_automatic_numbers() {
    // Two spheres and a cone; the second sphere's number is left blank (it
    // is then 2); the cone's last two values (of eight) are on a second
    // line, in the slots of values 7 and 8.
    let bodies = "  SPH    1       0.0       0.0       0.0       1.0\n  SPH            5.0       0.0       0.0       1.0\n  TRC    3       0.0       0.0     -10.0       0.0       0.0      20.0\n                 9.0       1.0\n";
    let regions = "  OUT    5     +3     -1     -2\n  IN     5     +1\n          OR   +2\n";
    let l = read_text(&numbered(0, bodies, regions)).unwrap();
    assert_eq!(zones(&l, "1"), ["+3 -1 -2"]);
    assert_eq!(zones(&l, "2"), ["+1", "+2"]);
    assert_close(&body(&l, "2").params, &[5.0, 0.0, 0.0, 1.0]);
    assert_close(
        &body(&l, "3").params,
        &[0.0, 0.0, -10.0, 0.0, 0.0, 20.0, 9.0, 1.0],
    );
    assert_eq!(l.scene.regions[1].description, "IN");
}

#[test]
fn high_accuracy_bodies_and_wide_region_numbers() {
    // IDBG = -100: three D22.15 values per body line, and regions in
    // (A2,I7) pairs.
    let bodies = format!(
        "  SPH    1{:>22}{:>22}{:>22}\n          {:>22}\n  SPH    2{:>22}{:>22}{:>22}\n          {:>22}\n",
        "0.000000000000001", "0.0", "0.0", "12.345678901234567", "0.0", "0.0", "0.0", "20.0"
    );
    let regions = format!(
        "  OUT    5{:>2}{:>7}{:>2}{:>7}\n  IN     5{:>2}{:>7}\n",
        "", "+2", "", "-1", "", "1"
    );
    let l = read_text(&numbered(-100, &bodies, &regions)).unwrap();
    assert_close(
        &body(&l, "1").params,
        &[1e-15, 0.0, 0.0, 12.345678901234567],
    );
    assert_eq!(zones(&l, "1"), ["+2 -1"]);
    assert_eq!(zones(&l, "2"), ["+1"]);
}

#[test]
fn fortran_readings_are_kept_and_warned_about() {
    // `10` with no decimal point reads as 0.010 in a D10.3 field, as FLUKA
    // reads it; a sign slipped into the operator field still counts.
    let bodies = "  SPH    1       0.0       0.0       0.0        10\n  SPH    2       0.0       0.0       0.0       9.0\n";
    let regions = "  OUT    5     +2 -    1\n  IN     5     +1\n";
    let l = read_text(&numbered(0, bodies, regions)).unwrap();
    assert_close(&body(&l, "1").params, &[0.0, 0.0, 0.0, 0.01]);
    assert_eq!(zones(&l, "1"), ["+2 -1"]);
    assert_eq!(
        warnings(&l),
        [
            ((3, 49), "`10` has no decimal point: FLUKA's fixed format reads it as 0.01"),
            ((6, 18), "the sign `-` stands in the operator field (columns 18-19), not with the body number"),
        ]
    );
}

#[test]
fn numbered_errors_name_their_columns() {
    let bodies = "  SPH    1       0.0       0.0       0.0       1.0\n  SPH    x       0.0       0.0       0.0       2.0\n";
    let regions = "  OUT    5     +9\n  IN     5XX   +1\n";
    assert_eq!(
        errors(&numbered(0, bodies, regions)),
        [
            (
                4,
                6,
                "expected a body number in columns 6-10, found `x`".to_string()
            ),
            (6, 13, "region 1 refers to undefined body 9".to_string()),
            (
                7,
                11,
                "expected `OR` or blanks in columns 11-12, found `XX`".to_string()
            ),
        ]
    );
}

#[test]
fn a_combinat_geometry_written_with_names_is_read_with_names() {
    let text =
        geo("SPH a 0 0 0 1\nSPH w 0 0 0 9", "w 5 +w -a\nball 5 +a").replace("COMBNAME", "COMBINAT");
    let l = read_text(&text).unwrap();
    assert_eq!(zones(&l, "w"), ["+w -a"]);
}
