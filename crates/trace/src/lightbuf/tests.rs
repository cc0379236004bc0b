//! The buffers hold the full search's answers on many shadow rays.

use super::binning::*;
use super::point::FaceGrid;
use super::*;
use crate::PrepareOptions;
use sv_geom::{Body, BodyKind, Geometry, Region};
use sv_math::DVec3;

/// A grid of spheres, each its own region, on a much larger ground
/// slab (region 0).
fn spheres(n: usize) -> Prepared {
    let mut g = Geometry::default();
    g.bodies.push(Body::new(
        "ground",
        BodyKind::Rpp,
        vec![-500.0, 500.0, -500.0, 500.0, -3.0, -2.5],
    ));
    g.regions.push(Region::of_body("ground", 0));
    for i in 0..n {
        for j in 0..n {
            let b = g.bodies.len();
            g.bodies.push(Body::new(
                format!("s{i}_{j}"),
                BodyKind::Sph,
                vec![i as f64 * 3.0, j as f64 * 3.0, (i + j) as f64 * 0.5, 1.0],
            ));
            g.regions.push(Region::of_body(format!("r{b}"), b));
        }
    }
    Prepared::new(&g, &PrepareOptions::default()).unwrap().0
}

/// Check that shadow rays toward `lb`'s light from `origins` are
/// blocked exactly when the full search says so; the number blocked.
fn sun_agrees(
    p: &Prepared,
    lb: &LightBuffer,
    origins: impl Iterator<Item = DVec3>,
    s: &mut Scratch,
) -> usize {
    let mut last = None;
    let mut met = 0;
    for o in origins {
        let ray = lb.shadow_ray(o);
        assert_eq!(ray, Ray::new(o, lb.toward()));
        let want = p.occluded(&ray, 1e-6, f64::INFINITY, None, s);
        let got = p.occluded_by(lb, &ray, 1e-6, f64::INFINITY, None, &mut last, s);
        assert_eq!(got, want, "origin {o:?} toward {:?}", lb.toward());
        met += usize::from(want);
    }
    met
}

#[test]
fn agrees_with_the_full_search_on_many_shadow_rays() {
    let p = spheres(6);
    let mut s = Scratch::new(&p);
    let mut met = 0;
    for (k, to_light) in [
        DVec3::new(0.3, 0.2, 1.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::new(-1.0, 1.0, 0.01),
    ]
    .into_iter()
    .enumerate()
    {
        let lb = LightBuffer::new(&p, to_light);
        // Origins on a lattice through and around the spheres.
        let origins = (0..40 * 40 * 3).map(|i| {
            let (a, b, c) = (i / 120, i / 3 % 40, i % 3);
            DVec3::new(
                -3.0 + a as f64 * 0.61,
                -3.0 + b as f64 * 0.59 + k as f64 * 0.01,
                -2.0 + c as f64 * 2.7,
            )
        });
        met += sun_agrees(&p, &lb, origins, &mut s);
    }
    assert!(met > 500, "the lattice should be shadowed often: {met}");
}

#[test]
fn the_point_buffer_agrees_with_the_full_search_on_many_shadow_rays() {
    let p = spheres(6);
    let mut s = Scratch::new(&p);
    let (mut met, mut lit) = (0, 0);
    // Above the lattice, beside it at the height of the spheres, inside
    // a sphere, level with the ground's face, and far off.
    for pos in [
        DVec3::new(7.0, 8.0, 12.0),
        DVec3::new(-4.0, 7.5, 1.25),
        DVec3::new(6.0, 6.0, 2.0),
        DVec3::new(30.0, -20.0, -2.5),
        DVec3::new(-400.0, 300.0, 900.0),
    ] {
        let pb = PointBuffer::new(&p, pos);
        assert_eq!(pb.position(), pos);
        let mut last = None;
        for a in 0..36 {
            for b in 0..36 {
                for c in 0..3 {
                    let o = DVec3::new(
                        -3.0 + a as f64 * 0.61,
                        -3.0 + b as f64 * 0.59,
                        -2.0 + c as f64 * 2.7,
                    );
                    let d = pos - o;
                    let ray = Ray::new(o, d);
                    let r = d.length();
                    let want = p.occluded(&ray, 1e-6, r, None, &mut s);
                    let got = p.occluded_by(&pb, &ray, 1e-6, r, None, &mut last, &mut s);
                    assert_eq!(got, want, "origin {o:?}, light at {pos:?}");
                    met += usize::from(want);
                    lit += usize::from(!want);
                }
            }
        }
    }
    assert!(met > 1000 && lit > 1000, "{met} shadowed, {lit} lit");
}

#[test]
fn the_point_buffer_lists_few_zones_a_cell() {
    let p = spheres(20);
    let pb = PointBuffer::new(&p, DVec3::new(30.0, 28.0, 40.0));
    // The ground holds no light here: it is listed like the spheres.
    assert!(pb.big.is_empty());
    let cells = pb.start.len() - 1;
    let longest = (0..cells)
        .map(|c| pb.start[c + 1] - pb.start[c])
        .max()
        .unwrap();
    let refs = pb.items.len();
    // About four cells a zone, where the zones are seen.
    assert!(cells >= 3 * 401, "{cells} cells");
    assert!(longest <= 10, "a cell lists {longest} of 401 zones");
    assert!(refs <= 4 * cells, "{refs} references in {cells} cells");
    // A light inside a sphere: that sphere is kept apart.
    let inside = PointBuffer::new(&p, DVec3::new(3.0, 3.0, 1.0));
    assert_eq!(inside.big.len(), 1);
}

#[test]
fn a_face_grid_holds_its_far_edges_and_nothing_beyond() {
    let r = [[0.0, -0.5, 0.25, 0.0], [0.5, 0.0, 1.0, 0.5]];
    let g = FaceGrid::new(r.iter(), 1024, 7);
    assert_eq!(g.n, 3);
    assert_eq!(g.cell(0.0, -0.5), Some(7));
    assert_eq!(g.cell(1.0, 0.5), Some(7 + 8));
    assert_eq!(g.span(&r[1]), (1, 2, 1, 2));
    for (u, v) in [(-0.01, 0.0), (0.0, 0.51), (1.01, 0.0), (f64::NAN, 0.0)] {
        assert_eq!(g.cell(u, v), None, "({u}, {v})");
    }
    // A face through which no zone is seen has no cells.
    let empty = FaceGrid::new(std::iter::empty(), 1024, 9);
    assert_eq!(empty.cell(0.0, 0.0), None);
}

#[test]
fn a_cell_lists_few_zones_and_the_ground_stays_apart() {
    let p = spheres(20);
    let lb = LightBuffer::new(&p, DVec3::new(0.1, 0.2, 1.0));
    // The ground does not stretch the grid: it is kept apart for rays
    // from off the grid, and listed in the cells, which it all covers.
    assert_eq!(lb.big, [0], "the ground is kept apart");
    assert!(lb.loose.is_empty());
    let cells = lb.start.len() - 1;
    let longest = (0..cells)
        .map(|c| lb.start[c + 1] - lb.start[c])
        .max()
        .unwrap();
    assert!(cells >= 400, "{cells} cells");
    assert!(
        longest <= 9,
        "a cell lists {longest} of 401 zones, the ground among them"
    );
    assert!(
        (0..cells).all(|c| lb.items[lb.start[c] as usize..lb.start[c + 1] as usize].contains(&0))
    );
}

/// Four long thin boxes turned 30° about z (rotor blades) and a wide
/// plate turned the same way, over a lattice of small spheres on a
/// ground slab; the boxes are large beside the spheres.
fn blades() -> Prepared {
    let mut g = Geometry::default();
    let mut add = |kind, params: Vec<f64>| {
        let b = g.bodies.len();
        g.bodies.push(Body::new(format!("b{b}"), kind, params));
        g.regions.push(Region::of_body(format!("r{b}"), b));
    };
    add(BodyKind::Rpp, vec![-12.0, 12.0, -12.0, 12.0, -1.0, 0.0]);
    for i in 0..5 {
        for j in 0..5 {
            let (x, y) = (-10.0 + 5.0 * i as f64, -10.0 + 5.0 * j as f64);
            add(BodyKind::Sph, vec![x, y, 1.0, 0.5]);
        }
    }
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let plate = [8.0 * c, 8.0 * s, 0.0, -5.0 * s, 5.0 * c, 0.0, 0.0, 0.0, 0.2];
    add(
        BodyKind::Box,
        [vec![-2.0, -6.0, 6.0], plate.to_vec()].concat(),
    );
    for k in 0..4 {
        let z = 3.0 + k as f64 * 0.5;
        let (along, across) = ([10.0 * c, 10.0 * s], [-0.3 * s, 0.3 * c]);
        add(
            BodyKind::Box,
            vec![
                -5.0 * c + k as f64,
                -5.0 * s,
                z,
                along[0],
                along[1],
                0.0,
                across[0],
                across[1],
                0.0,
                0.0,
                0.0,
                0.1,
            ],
        );
    }
    Prepared::new(&g, &PrepareOptions::default()).unwrap().0
}

#[test]
fn turned_thin_boxes_are_listed_only_where_they_lie() {
    let p = blades();
    let mut s = Scratch::new(&p);
    let mut met = 0;
    for to_light in [
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(0.3, -0.2, 1.0),
        DVec3::new(-1.0, 0.5, 0.4),
    ] {
        let lb = LightBuffer::new(&p, to_light);
        // A blade covers a fifth of its box's shadow at most: its
        // outline leaves most of the box's cells alone.
        let listed = lb.items.iter().filter(|&&z| z >= 27).count();
        let boxed: usize = (27..31)
            .map(|zi| lb.cells_in(&project(&p.zones[zi].bounds, lb.u, lb.v, 4.0 * p.tol)))
            .sum();
        assert!(2 * listed < boxed, "{listed} of {boxed} cells");
        let origins = (0..60 * 60 * 4).map(|i| {
            let (a, b, h) = (i / 240, i / 4 % 60, [0.5, 1.2, 3.2, 5.0][i % 4]);
            DVec3::new(-11.0 + a as f64 * 0.37, -11.0 + b as f64 * 0.37, h)
        });
        met += sun_agrees(&p, &lb, origins, &mut s);
    }
    assert!(met > 1000, "the blades should shadow often: {met}");
}

#[test]
fn the_hull_of_points_on_a_plane_runs_counter_clockwise_without_inner_points() {
    let pts = vec![
        [0.0, 0.0],
        [2.0, 0.0],
        [1.0, 1.0],
        [2.0, 2.0],
        [0.0, 2.0],
        [1.0, 0.0],
        [2.0, 0.0],
    ];
    assert_eq!(
        convex_hull_2d(pts),
        [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
    );
}
