//! Each surface type becomes the body whose inside is its negative side.

use super::*;
use sv_geom::{Body, BodyKind};

/// The body of one surface `type` with `coeffs` (a cell uses it).
fn body(kind: &str, coeffs: &str) -> Body {
    let l = model(&format!(
        r#"<surface id="9" type="{kind}" coeffs="{coeffs}"/>
           <cell id="1" material="1" region="-9"/>"#
    ));
    l.scene.geometry.bodies[0].clone()
}

/// The value of OpenMC's surface function, from the body's inside test:
/// negative inside.
fn negative_at(b: &Body, p: DVec3) -> bool {
    sv_geom::prepare(b, &mut Vec::new()).unwrap().0.contains(p)
}

#[test]
fn planes_become_axis_half_spaces_below_them() {
    let x = body("x-plane", "2.5");
    assert_eq!((x.kind, x.params.as_slice()), (BodyKind::Yzp, &[2.5][..]));
    assert_eq!(body("y-plane", "-1").kind, BodyKind::Xzp);
    let z = body("z-plane", "3");
    assert_eq!((z.kind, z.params.as_slice()), (BodyKind::Xyp, &[3.0][..]));
    assert!(negative_at(&z, DVec3::new(0.0, 0.0, 2.9)));
    assert!(!negative_at(&z, DVec3::new(0.0, 0.0, 3.1)));
    assert_eq!(x.name, "9");
}

#[test]
fn a_general_plane_keeps_its_normal_through_its_nearest_point() {
    // x + y = 4: the point nearest the origin is (2, 2, 0).
    let p = body("plane", "1 1 0 4");
    assert_eq!(p.kind, BodyKind::Pla);
    assert_eq!(p.params, [1.0, 1.0, 0.0, 2.0, 2.0, 0.0]);
    assert!(negative_at(&p, DVec3::new(1.0, 1.0, 7.0)));
    assert!(!negative_at(&p, DVec3::new(3.0, 3.0, 0.0)));
    assert_eq!(
        errors(
            r#"<surface id="1" type="plane" coeffs="0 0 0 1"/><cell id="1" material="1" region="-1"/>"#
        ),
        [(
            2,
            38,
            "surface 1: the plane's normal (A, B, C) is zero".to_string()
        )]
    );
}

#[test]
fn cylinders_and_spheres_keep_their_centres() {
    let x = body("x-cylinder", "1 2 3");
    assert_eq!(
        (x.kind, x.params.clone()),
        (BodyKind::Xcc, vec![1.0, 2.0, 3.0])
    );
    // OpenMC writes x0 z0 R; YCC takes its centre as z, x.
    let y = body("y-cylinder", "1 2 3");
    assert_eq!(
        (y.kind, y.params.clone()),
        (BodyKind::Ycc, vec![2.0, 1.0, 3.0])
    );
    assert!(negative_at(&y, DVec3::new(1.0, 50.0, 2.0 + 2.9)));
    assert!(!negative_at(&y, DVec3::new(1.0 + 3.1, 50.0, 2.0)));
    let z = body("z-cylinder", "1 2 3");
    assert_eq!(
        (z.kind, z.params.clone()),
        (BodyKind::Zcc, vec![1.0, 2.0, 3.0])
    );
    let s = body("sphere", "1 2 3 4");
    assert_eq!(
        (s.kind, s.params.clone()),
        (BodyKind::Sph, vec![1.0, 2.0, 3.0, 4.0])
    );
}

#[test]
fn cones_are_double_cones() {
    // (x-1)² + (z-3)² = 4 (y-2)²
    let c = body("y-cone", "1 2 3 4");
    assert_eq!(c.kind, BodyKind::Qua);
    for (p, inside) in [
        (DVec3::new(1.0, 2.0 + 1.0, 3.0 + 1.9), true),
        (DVec3::new(1.0, 2.0 - 1.0, 3.0 - 1.9), true),
        (DVec3::new(1.0, 2.0 + 1.0, 3.0 + 2.1), false),
        (DVec3::new(1.0 + 0.1, 2.0, 3.0), false),
    ] {
        assert_eq!(negative_at(&c, p), inside, "{p}");
    }
    for (kind, axis) in [("x-cone", DVec3::X), ("z-cone", DVec3::Z)] {
        let c = body(kind, "0 0 0 1");
        let across = if axis == DVec3::X { DVec3::Y } else { DVec3::X };
        assert!(negative_at(&c, axis * 2.0 + across * 1.9), "{kind}");
        assert!(!negative_at(&c, axis * 2.0 + across * 2.1), "{kind}");
    }
}

#[test]
fn a_quadric_maps_its_cross_terms() {
    // OpenMC: A..K with D xy, E yz, F xz; QUA: xx yy zz xy xz yz x y z 1.
    let q = body("quadric", "1 2 3 4 5 6 7 8 9 -10");
    assert_eq!(q.kind, BodyKind::Qua);
    assert_eq!(
        q.params,
        [1.0, 2.0, 3.0, 4.0, 6.0, 5.0, 7.0, 8.0, 9.0, -10.0]
    );
    // x² + y² - 4 as a quadric is a z-cylinder of radius 2.
    let cyl = body("quadric", "1 1 0 0 0 0 0 0 0 -4");
    assert!(negative_at(&cyl, DVec3::new(1.9, 0.0, 9.0)));
    assert!(!negative_at(&cyl, DVec3::new(2.1, 0.0, 9.0)));
}

#[test]
fn circular_tori_are_tor_and_elliptic_ones_are_refused() {
    let t = body("z-torus", "1 2 3 10 2 2");
    assert_eq!(t.kind, BodyKind::Tor);
    assert_eq!(t.params, [1.0, 2.0, 3.0, 0.0, 0.0, 1.0, 10.0, 2.0]);
    assert!(negative_at(&t, DVec3::new(11.0, 2.0, 3.0)));
    assert!(!negative_at(&t, DVec3::new(1.0, 2.0, 3.0)));
    let x = body("x-torus", "0 0 0 5 1 1");
    assert_eq!(&x.params[3..6], [1.0, 0.0, 0.0]);
    assert!(negative_at(&x, DVec3::new(0.0, 5.0, 0.5)));
    assert_eq!(
        &body("y-torus", "0 0 0 5 1 1").params[3..6],
        [0.0, 1.0, 0.0]
    );
    let e = errors(
        r#"<surface id="4" type="y-torus" coeffs="0 0 0 5 1 2"/><cell id="1" material="1" region="-4"/>"#,
    );
    assert_eq!(e.len(), 1);
    assert_eq!((e[0].0, e[0].1), (2, 40));
    assert!(e[0].2.contains("elliptic torus"), "{}", e[0].2);
}

#[test]
fn values_may_be_attributes_or_elements() {
    let l = model(
        "<surface>\n  <id>3</id>\n  <type>sphere</type>\n  <coeffs>0 0 0 2</coeffs>\n  <boundary>vacuum</boundary>\n</surface>\n\
         <cell><id>5</id><material>1</material><region> -3 </region></cell>",
    );
    assert_eq!(l.scene.geometry.bodies[0].params, [0.0, 0.0, 0.0, 2.0]);
    assert_eq!(expression(&l, "5"), "+3");
}

#[test]
fn surface_errors_are_located() {
    let e = errors(
        r#"<surface id="1" type="sphear" coeffs="0 0 0 1"/>
<surface id="2" type="sphere" coeffs="0 0 1"/>
<surface id="3" type="z-cylinder" coeffs="0 0 -1"/>
<surface id="4" type="z-plane" coeffs="x"/>
<surface id="5" type="z-plane" coeffs="1" boundary="mirror"/>
<surface type="z-plane" coeffs="1"/>
<surface id="6" type="z-plane"/>
<cell id="1" material="1" region="-1 -3"/>"#,
    );
    // Cell 1 uses two surfaces with errors: they are not reported again.
    let want: Vec<(usize, usize, &str)> = vec![
        (2, 23, "unknown surface type `sphear`"),
        (3, 39, "a sphere takes 4 coefficients, found 3"),
        (4, 43, "z-cylinder 3: radius must be positive (is -1)"),
        (5, 40, "`x` in the coeffs of a z-plane is not a number"),
        (6, 53, "unknown boundary condition `mirror`"),
        (7, 1, "surface without an id"),
        (8, 1, "z-plane surface without coeffs"),
    ];
    assert_eq!(by_place(&e), want);
}
