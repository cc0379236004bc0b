//! What preparing a geometry says about bad bodies: every problem named
//! with the body and the rule, and warnings that still render.

use sv_geom::{Body, BodyKind, Geometry, Region};
use sv_math::{DVec3, Ray};
use sv_trace::{PrepareOptions, Prepared};

#[test]
fn invalid_parameters_name_the_body_and_rule() {
    use BodyKind::*;
    let cases: &[(BodyKind, &[f64], &str)] = &[
        (
            Sph,
            &[0.0, 0.0, 0.0, 0.0],
            "SPH `bad`: radius must be positive (is 0)",
        ),
        (
            Rcc,
            &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
            "RCC `bad`: height vector is zero",
        ),
        (
            Box,
            &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            "BOX `bad`: edges A and B are not perpendicular",
        ),
        (
            Arb4,
            &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0],
            "ARB4 `bad`: the vertices span no volume (degenerate polyhedron)",
        ),
        (
            Rpp,
            &[1.0, 0.0, 0.0, 1.0, 0.0, 1.0],
            "RPP `bad`: xmin (1) must be less than xmax (0)",
        ),
        (
            Tor,
            &[0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 2.0],
            "TOR `bad`: minor radius 2 must be smaller than major radius 1",
        ),
        (
            Ell,
            &[0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 3.0],
            "ELL `bad`: major axis length 3 must exceed the distance between the foci (4)",
        ),
        (
            Sph,
            &[0.0, 0.0, f64::NAN, 1.0],
            "SPH `bad`: value 3 is not a finite number",
        ),
    ];
    for (kind, params, want) in cases {
        let g = Geometry {
            bodies: vec![Body::new("bad", *kind, params.to_vec())],
            regions: vec![Region::of_body("r", 0)],
            ..Geometry::default()
        };
        let err = Prepared::new(&g, &PrepareOptions::default()).unwrap_err();
        assert_eq!(err.to_string(), *want);
    }
}

#[test]
fn non_planar_arb8_warns_naming_the_face_and_still_renders() {
    // Body 10 of the generator deck: one vertex is 0.2 off its face.
    let p = [
        -230.5059, -152.4006, 0.0, -230.5059, -182.8807, 0.0, -230.5059, -182.8807, 30.4801,
        -230.5059, -152.4006, 30.4801, -202.5658, -152.4006, 0.0, -202.5658, -182.8807, 0.0,
        -202.5658, -182.6807, 30.4801, -202.5658, -152.4006, 30.4801,
    ];
    let g = Geometry {
        bodies: vec![Body::new("10", BodyKind::Arb8, p.to_vec())],
        regions: vec![Region::of_body("r", 0)],
        ..Geometry::default()
    };
    let (prep, warnings) = Prepared::new(&g, &PrepareOptions::default()).unwrap();
    assert!(!warnings.is_empty());
    let text = warnings[0].to_string();
    assert_eq!(
        text,
        "ARB8 `10`: face 2376 is not planar (a vertex is 0.2000 off the plane of the other three); using the convex hull of the vertices"
    );
    assert_eq!(
        warnings.len(),
        1,
        "only face 2376 holds the bent vertex 7 off its plane: {warnings:?}"
    );
    let r = Ray::new(DVec3::new(-216.0, -167.0, 100.0), -DVec3::Z);
    let mut s = sv_trace::Scratch::new(&prep);
    assert!(prep.first_hit(&r, 0.0, f64::INFINITY, &mut s).is_some());
}
