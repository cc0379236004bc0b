//! Region classification: booleans of bodies along rays, the paper's
//! Figure 3 walk-through, coincident faces and region volumes.

use sv_geom::{Body, BodyKind, Geometry, Op, Region, Term, Zone};
use sv_math::{DVec3, Ray};
use sv_trace::{PrepareOptions, Prepared, Scratch};

fn term(op: char, body: usize) -> Term {
    Term {
        op: if op == '+' { Op::Inside } else { Op::Outside },
        body,
    }
}

fn region(name: &str, zones: &[&[(char, usize)]]) -> Region {
    Region::new(
        name,
        zones
            .iter()
            .map(|z| Zone::new(z.iter().map(|&(o, b)| term(o, b)).collect()))
            .collect(),
    )
}

/// Figure 1: sphere (body 0) and cylinder (body 1), the five regions.
fn figure1() -> Geometry {
    Geometry {
        bodies: vec![
            Body::new("1", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0]),
            Body::new(
                "2",
                BodyKind::Rcc,
                vec![0.45, -0.2, -1.4, 0.0, 0.0, 2.8, 0.6],
            ),
        ],
        regions: vec![
            region("B", &[&[('+', 0)]]),
            region("C", &[&[('+', 1)]]),
            region("D", &[&[('+', 0), ('-', 1)]]),
            region("E", &[&[('+', 1), ('-', 0)]]),
            region("F", &[&[('+', 0), ('+', 1)]]),
        ],
        ..Geometry::default()
    }
}

/// Volume of region `r` by a grid of parallel rays along z.
fn grid_volume(p: &Prepared, r: u32, n: usize) -> f64 {
    let b = p.bounds().padded(0.01);
    let (dx, dy) = (
        (b.max.x - b.min.x) / n as f64,
        (b.max.y - b.min.y) / n as f64,
    );
    let mut s = Scratch::new(p);
    let mut parts = Vec::new();
    let mut total = 0.0;
    for i in 0..n {
        for j in 0..n {
            let o = DVec3::new(
                b.min.x + (i as f64 + 0.5) * dx,
                b.min.y + (j as f64 + 0.5) * dy,
                b.min.z - 1.0,
            );
            p.partitions(
                &Ray::new(o, DVec3::Z),
                0.0,
                f64::INFINITY,
                &mut s,
                &mut parts,
            );
            total += parts
                .iter()
                .filter(|q| q.region == r)
                .map(|q| q.span.len())
                .sum::<f64>();
        }
    }
    total * dx * dy
}

#[test]
fn sphere_minus_cylinder_volume_matches_closed_form_within_half_a_percent() {
    // Isolate each region so the grid covers it.
    let g = figure1();
    let (p, _) = Prepared::new(&g, &PrepareOptions::default()).unwrap();
    // Closed forms: sphere 4/3 π; the cylinder (radius 0.6, axis 0.45 off
    // centre) pierces the sphere completely, so sphere ∩ cylinder is the
    // volume of the sphere within distance 0.6 of the axis line:
    // V = ∫∫_disc 2 sqrt(1 - ρ²) dA over the disc of radius 0.6 centred at
    // distance 0.45 — evaluated here by fine quadrature.
    let mut inter = 0.0;
    let m = 2000;
    let h = 1.2 / m as f64;
    for i in 0..m {
        for j in 0..m {
            let (x, y) = (-0.6 + (i as f64 + 0.5) * h, -0.6 + (j as f64 + 0.5) * h);
            if x * x + y * y < 0.36 {
                let rho2 = (x + 0.45).powi(2) + (y - 0.2).powi(2);
                if rho2 < 1.0 {
                    inter += 2.0 * (1.0 - rho2).sqrt() * h * h;
                }
            }
        }
    }
    let sphere = 4.0 / 3.0 * std::f64::consts::PI;
    let want_d = sphere - inter;
    let got_d = grid_volume(&p, 2, 400);
    assert!(
        (got_d / want_d - 1.0).abs() < 0.005,
        "D: {got_d} vs {want_d}"
    );
    let got_f = grid_volume(&p, 4, 400);
    assert!((got_f / inter - 1.0).abs() < 0.005, "F: {got_f} vs {inter}");
}

/// Figure 3: body 1 a sphere, body 2 a cylinder, body 3 a box inside both;
/// region A = +2 -3, B = +3, C = the enclosing box minus the others.
fn figure3() -> Geometry {
    Geometry {
        bodies: vec![
            Body::new("1", BodyKind::Sph, vec![0.0, 0.0, 0.0, 3.0]),
            Body::new(
                "2",
                BodyKind::Rcc,
                vec![-6.0, 0.0, 0.0, 12.0, 0.0, 0.0, 2.0],
            ),
            Body::new("3", BodyKind::Rpp, vec![-4.0, 1.0, -1.0, 1.0, -1.0, 1.0]),
            Body::new(
                "4",
                BodyKind::Rpp,
                vec![-20.0, 20.0, -20.0, 20.0, -20.0, 20.0],
            ),
        ],
        regions: vec![
            region("A", &[&[('+', 1), ('-', 2)]]),
            region("B", &[&[('+', 2)]]),
            region("C", &[&[('+', 3), ('-', 0), ('-', 1)]]),
            region("S", &[&[('+', 0), ('-', 1)]]),
        ],
        ..Geometry::default()
    }
}

#[test]
fn figure3_walkthrough_with_camera_inside_a_transparent_region() {
    let g = figure3();
    let opaque = vec![false, false, false, true];
    let (p, _) = Prepared::new(
        &g,
        &PrepareOptions {
            opaque: Some(opaque),
            ..Default::default()
        },
    )
    .unwrap();
    let mut s = Scratch::new(&p);
    // Camera at P0 in region C, looking along +x through the box, sphere,
    // cylinder.
    let ray = Ray::new(DVec3::new(-10.0, 0.0, 0.0), DVec3::X);
    let c = p.crossings(&ray, 0.0, &mut s);
    let seq: Vec<(f64, bool, &str)> = c
        .iter()
        .map(|c| (c.t, c.entering, g.regions[c.region as usize].name.as_str()))
        .collect();
    // E2 (cylinder) at x=-6 enters A; E3 (box) at x=-4 leaves A, enters B;
    // L3 at x=1 leaves B, enters A; L1 (sphere) then L2 (cylinder end).
    let names: Vec<String> = seq
        .iter()
        .map(|(t, e, r)| format!("{}{r}@{}", if *e { "+" } else { "-" }, t))
        .collect();
    assert_eq!(
        names[..6],
        ["-C@4", "+A@4", "-A@6", "+B@6", "-B@11", "+A@11"],
        "{names:?}"
    );
    // With A, B and C transparent, the ray passes through everything and
    // only the opaque sphere shell S stops it — at L1? No: S = sphere minus
    // cylinder, which this axial ray never enters.
    assert!(p.first_hit(&ray, 0.0, f64::INFINITY, &mut s).is_none());
    // An off-axis ray from the same camera does meet S.
    let r2 = Ray::new(DVec3::new(-10.0, 0.0, 2.5), DVec3::X);
    let h = p.first_hit(&r2, 0.0, f64::INFINITY, &mut s).unwrap();
    assert_eq!(g.regions[h.region as usize].name, "S");
    assert!((h.t - (10.0 - (9.0f64 - 6.25).sqrt())).abs() < 1e-9);
}

#[test]
fn body_subtracted_flush_with_a_face_leaves_no_speckles() {
    // A unit box minus a box sharing its top face: rays straight down onto
    // the top must all land on the cut (z = 0.5), never on the shared face.
    let g = Geometry {
        bodies: vec![
            Body::new("a", BodyKind::Rpp, vec![0.0, 1.0, 0.0, 1.0, 0.0, 1.0]),
            Body::new("b", BodyKind::Rpp, vec![0.2, 0.8, 0.2, 0.8, 0.5, 1.0]),
            Body::new("c", BodyKind::Sph, vec![0.5, 0.5, 1.0, 0.3]),
        ],
        regions: vec![
            region("a", &[&[('+', 0), ('-', 1)]]),
            region("top", &[&[('+', 0), ('-', 2)]]),
        ],
        ..Geometry::default()
    };
    let (p, _) = Prepared::new(
        &g,
        &PrepareOptions {
            opaque: Some(vec![true, false]),
            ..Default::default()
        },
    )
    .unwrap();
    let mut s = Scratch::new(&p);
    for i in 0..200 {
        for j in 0..200 {
            let (x, y) = (
                0.2 + 0.6 * (i as f64 + 0.5) / 200.0,
                0.2 + 0.6 * (j as f64 + 0.5) / 200.0,
            );
            let h = p
                .first_hit(
                    &Ray::new(DVec3::new(x, y, 3.0), -DVec3::Z),
                    0.0,
                    f64::INFINITY,
                    &mut s,
                )
                .unwrap();
            assert!(
                (h.t - 2.5).abs() < 1e-9,
                "speckle at ({x}, {y}): t = {}",
                h.t
            );
            let n = p.normal(&h, &Ray::new(DVec3::new(x, y, 3.0), -DVec3::Z));
            assert!(
                (n - DVec3::Z).length() < 1e-12,
                "normal of the cut floor must face up (flipped)"
            );
        }
    }
}

#[test]
fn or_zones_union_and_region_names_resolve() {
    // +1 -2 OR +3: a sphere with a bite, unioned with a far box.
    let g = Geometry {
        bodies: vec![
            Body::new("1", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0]),
            Body::new("2", BodyKind::Sph, vec![-1.0, 0.0, 0.0, 0.5]),
            Body::new("3", BodyKind::Rpp, vec![3.0, 4.0, -1.0, 1.0, -1.0, 1.0]),
        ],
        regions: vec![region("u", &[&[('+', 0), ('-', 1)], &[('+', 2)]])],
        ..Geometry::default()
    };
    let (p, _) = Prepared::new(&g, &PrepareOptions::default()).unwrap();
    let mut s = Scratch::new(&p);
    let mut parts = vec![];
    p.partitions(
        &Ray::new(DVec3::new(-5.0, 0.0, 0.0), DVec3::X),
        0.0,
        f64::INFINITY,
        &mut s,
        &mut parts,
    );
    let spans: Vec<(f64, f64)> = parts.iter().map(|q| (q.span.a.t, q.span.b.t)).collect();
    assert_eq!(spans, vec![(4.5, 6.0), (8.0, 9.0)]);
    assert!(p.region_contains(0, DVec3::new(3.5, 0.0, 0.0)));
    assert!(!p.region_contains(0, DVec3::new(-0.9, 0.0, 0.0)));
}

#[test]
fn bodies_keep_their_indices_though_stored_in_space_order() {
    // Spheres on a line, out of order along it and named by the regions in
    // yet another order, and one body no zone names.
    let at = |b: usize| DVec3::new(3.0 * [2, 5, 0, 4, 1, 3][b] as f64, 0.0, 0.0);
    let order = [5, 0, 3, 1, 4, 2];
    let mut bodies: Vec<Body> = (0..6)
        .map(|i| {
            let c = at(i);
            Body::new(format!("s{i}"), BodyKind::Sph, vec![c.x, c.y, c.z, 1.0])
        })
        .collect();
    bodies.push(Body::new("unused", BodyKind::Sph, vec![0.0, 9.0, 0.0, 0.5]));
    let g = Geometry {
        bodies,
        regions: order
            .iter()
            .map(|&b| region(&format!("r{b}"), &[&[('+', b)]]))
            .collect(),
        ..Geometry::default()
    };
    let (p, _) = Prepared::new(&g, &PrepareOptions::default()).unwrap();
    let mut s = Scratch::new(&p);
    for b in 0..7 {
        let c = if b == 6 {
            DVec3::new(0.0, 9.0, 0.0)
        } else {
            at(b)
        };
        assert!(p.body_bounds(b).contains(c), "body {b}");
        assert!(p.shape(b).contains(c), "body {b}");
    }
    for (r, &b) in order.iter().enumerate() {
        // Down onto sphere `b`: its region is hit, through its surface.
        let ray = Ray::new(at(b) + DVec3::new(0.0, 0.0, 5.0), -DVec3::Z);
        let hit = p.first_hit(&ray, 0.0, f64::INFINITY, &mut s).unwrap();
        assert_eq!(hit.region as usize, r);
        assert_eq!(p.body_index(hit.bound.body), b);
        let steps = p.walk(&ray, 0.0, &mut s);
        assert_eq!(
            steps.iter().map(|st| st.body as usize).collect::<Vec<_>>(),
            [b, b]
        );
        let crossings = p.crossings(&ray, 0.0, &mut s);
        assert!(
            crossings.iter().all(|c| c.body as usize == b),
            "{crossings:?}"
        );
    }
}
