//! Region expressions lowered as written: intersections, unions,
//! complements and parentheses become zones and groups, never sums of
//! products.

use super::*;

/// Surfaces 1…6 (spheres) and a cell of `region`; its expression.
fn lowered(region: &str) -> String {
    let surfaces: String = (1..=6)
        .map(|i| format!(r#"<surface id="{i}" type="sphere" coeffs="0 0 0 {i}"/>"#))
        .collect();
    let l = model(&format!(
        r#"{surfaces}<cell id="1" material="1" region="{region}"/>"#
    ));
    expression(&l, "1")
}

#[test]
fn a_negative_half_space_is_the_body_inside() {
    assert_eq!(lowered("-1"), "+1");
    assert_eq!(lowered("+1"), "-1");
    assert_eq!(lowered("1"), "-1");
    assert_eq!(lowered(" -1   2 +3 "), "+1 -2 -3");
}

#[test]
fn union_binds_loosest_and_complement_tightest() {
    assert_eq!(lowered("-1 2 | -3"), "+1 -2 | +3");
    assert_eq!(lowered("~-1 2"), "-1 -2");
    assert_eq!(lowered("-1 | ~2 -3 | 4"), "+1 | +2 +3 | -4");
}

#[test]
fn parentheses_and_complements_become_groups() {
    // The manual's example: -3 | ~(5 -2), with 5 and 2 read as 5 and 2.
    assert_eq!(lowered("-3 | ~(5 -2)"), "+3 | -(-5 +2)");
    assert_eq!(lowered("-1 (2 | -3)"), "+1 +(-2 | +3)");
    assert_eq!(
        lowered("-6 ~(-1 | -2 (3 | -4))"),
        "+6 -(+1 | +2 +(-3 | +4))"
    );
    // A parenthesised intersection is part of its zone; ~~x is x.
    assert_eq!(lowered("(-1 2) -3"), "+1 -2 +3");
    assert_eq!(lowered("~(~(-1 | -2))"), "+(+1 | +2)");
    assert_eq!(lowered("~(-1)"), "-1");
}

#[test]
fn tokens_need_no_blanks() {
    assert_eq!(lowered("-1-2+3"), "+1 +2 -3");
    assert_eq!(lowered("(-1)(-2)|~3"), "+1 +2 | +3");
    assert_eq!(lowered("\n\t-1\n2\t"), "+1 -2");
}

#[test]
fn deep_expressions_stay_linear() {
    // (-1 | -2) repeated: a product would have 2^12 zones.
    let region = ["(-1 | -2)"; 12].join(" ");
    let l = lowered(&region);
    assert_eq!(l.matches('|').count(), 12);
    let nested = format!("{}-1{}", "(".repeat(50), ")".repeat(50));
    assert_eq!(lowered(&nested), "+1");
}

#[test]
fn no_region_is_all_space() {
    // All space less an empty union: a zone that subtracts nothing.
    let all = vec![Zone {
        terms: Vec::new(),
        groups: vec![sv_geom::Group {
            op: Op::Outside,
            zones: Vec::new(),
        }],
    }];
    let l = model(r#"<cell id="4" material="1"/>"#);
    assert_eq!(region(&l, "4").zones, all);
    let l = model(r#"<cell id="4" material="1" region="  "/>"#);
    assert_eq!(region(&l, "4").zones, all);
    assert_eq!(cells_at(&l, DVec3::new(1e6, -3.0, 7.0)), ["4"]);
}

#[test]
fn region_errors_point_at_the_token() {
    let s = r#"<surface id="1" type="sphere" coeffs="0 0 0 1"/>"#;
    let one = |region: &str| {
        let e = errors(&format!(
            "{s}\n<cell id=\"1\" material=\"1\" region=\"{region}\"/>"
        ));
        assert_eq!(e.len(), 1, "{region}: {e:?}");
        (e[0].1 as i64 - 35, e[0].2.clone())
    };
    assert_eq!(one("-1 -7"), (3, "surface 7 is not defined".to_string()));
    assert_eq!(
        one("-1 | "),
        (
            3,
            "the region ends where a half-space is expected".to_string()
        )
    );
    assert_eq!(one("(-1"), (0, "this `(` is not closed".to_string()));
    assert_eq!(one("-1)"), (2, "unexpected `)`".to_string()));
    assert_eq!(
        one("| -1"),
        (0, "`|` where a half-space is expected".to_string())
    );
    assert_eq!(
        one("()"),
        (1, "`)` where a half-space is expected".to_string())
    );
    assert_eq!(
        one("-1 # 1"),
        (3, "`#` has no meaning in a region".to_string())
    );
    // Written with an entity, the text is not the file's: the whole
    // attribute is pointed at.
    assert_eq!(
        one("-1 &amp; 1"),
        (-8, "`&` has no meaning in a region".to_string())
    );
    assert_eq!(
        one("- 1"),
        (0, "`-` must be followed by a surface id".to_string())
    );
    assert_eq!(
        one("~"),
        (
            0,
            "the region ends where a half-space is expected".to_string()
        )
    );
    let deep = format!("{}-1{}", "(".repeat(150), ")".repeat(150));
    let (col, msg) = one(&deep);
    assert_eq!(
        (col, msg.as_str()),
        (
            100,
            "the region nests more than 100 parentheses and complements deep"
        )
    );
}

#[test]
fn every_undefined_surface_is_reported() {
    let e = errors(
        r#"<surface id="1" type="sphere" coeffs="0 0 0 1"/>
<cell id="1" material="1" region="-1 -8 | 9"/>
<cell id="2" material="1" region="~(10)"/>"#,
    );
    let got: Vec<(usize, usize)> = e.iter().map(|(l, c, _)| (*l, *c)).collect();
    assert_eq!(got, [(3, 38), (3, 43), (4, 37)]);
}
