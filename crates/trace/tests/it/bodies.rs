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
        "ARB8 `10`: face 2376 is not planar (vertex 2 is 0.2000 off the plane of vertices 3, 7 and 6); using that plane, as BRL-CAD does"
    );
    assert_eq!(
        warnings.len(),
        1,
        "only face 2376 holds the bent vertex 7 off its plane: {warnings:?}"
    );
    let r = Ray::new(DVec3::new(-216.0, -167.0, 100.0), -DVec3::Z);
    let mut s = sv_trace::Scratch::new(&prep);
    assert!(prep.first_hit(&r, 0.0, f64::INFINITY, &mut s).is_some());

    // Beside the bent vertex 7 the face is the plane of vertices 3, 7 and
    // 6, as librt makes it, not the convex hull of the vertices (which
    // would reach out to y = -182.8807 up to the top, z = 30.4801): a ray
    // down at x = -203, y = -182.75 enters the body where it crosses that
    // plane, below the top.
    let v = |i: usize| DVec3::new(p[3 * i - 3], p[3 * i - 2], p[3 * i - 1]);
    let (a, b, c) = (v(3), v(7), v(6));
    let normal = (c - a).cross(b - a);
    let (x, y) = (-203.0, -182.75);
    let z = a.z - (normal.x * (x - a.x) + normal.y * (y - a.y)) / normal.z;
    assert!(z > 0.0 && z < 30.0, "the plane crosses the ray at z = {z}");
    let down = Ray::new(DVec3::new(x, y, 100.0), -DVec3::Z);
    let hit = prep
        .first_hit(&down, 0.0, f64::INFINITY, &mut s)
        .expect("the ray meets the body");
    assert!(
        (hit.t - (100.0 - z)).abs() < 1e-9,
        "entered at z = {}, the plane is at z = {z}",
        100.0 - hit.t
    );
    // Past vertex 2 the plane leaves the vertices' box, to which the body
    // is cut, as librt finds it only along rays that meet that box.
    let outside = Ray::new(DVec3::new(-230.0, -182.95, 100.0), -DVec3::Z);
    assert!(prep
        .first_hit(&outside, 0.0, f64::INFINITY, &mut s)
        .is_none());
}
