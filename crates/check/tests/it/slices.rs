use crate::model;
use sv_check::{region_colour, slice, Plane, Slice, SliceOptions, UniverseChoice};
use sv_math::DVec3;

const SPHERES: &str = "
BODY a SPH (0,0,0) 1
BODY b SPH (1.5,0,0) 1
REGION A = +a
REGION B = +b
";

fn opts(plane: Plane) -> SliceOptions {
    SliceOptions {
        plane,
        extent: Some((4.0, 2.0)),
        size: Some((200, 100)),
        centre: None,
        tolerance: None,
        strict_air: false,
    }
}

/// Class of the pixel whose centre is nearest to plane coordinates (u, v)
/// relative to the picture centre.
fn class_at(s: &Slice, u: f64, v: f64) -> u32 {
    let i = ((u + s.extent.0 / 2.0) / s.extent.0 * s.width as f64) as usize;
    let j = ((s.extent.1 / 2.0 - v) / s.extent.1 * s.height as f64) as usize;
    s.class[j * s.width as usize + i]
}

#[test]
fn section_through_overlapping_spheres() {
    let m = model(SPHERES, UniverseChoice::None);
    let s = slice(&m, &opts(Plane::axis(2, 0.0))).unwrap();
    assert_eq!((s.width, s.height), (200, 100));
    // Centre of the view: the middle of the box in x and y.
    assert!((s.centre - DVec3::new(0.75, 0.0, 0.0)).length() < 1e-9);
    // x = -0.5: A only; x = 0.75: both; x = 2.0: B only; x = -1.2: nothing.
    assert_eq!(class_at(&s, -1.25, 0.0), 1);
    assert_eq!(class_at(&s, 0.0, 0.0), Slice::OVERLAP);
    assert_eq!(class_at(&s, 1.25, 0.3), 2);
    assert_eq!(class_at(&s, -1.95, 0.9), 0);
    let labels: Vec<_> = s.legend.iter().map(|e| e.label.as_str()).collect();
    assert_eq!(labels.len(), 2);
    assert!(labels.contains(&"A") && labels.contains(&"B"));
    assert_eq!(s.overlaps.len(), 1);
    assert_eq!(s.overlaps[0].label, "A × B");
    // Region areas in the section: disc minus lens part, within pixels.
    let a = s.legend.iter().find(|e| e.label == "A").unwrap();
    let lens = 2.0 * 0.75f64.acos() - 0.75 * 1.75f64.sqrt();
    let expect = std::f64::consts::PI - lens;
    assert!(
        (a.area - expect).abs() < 0.03 * expect,
        "{} vs {expect}",
        a.area
    );
    assert!(s.void.is_none());
}

#[test]
fn colours_are_the_region_colours_and_outlines_are_dark() {
    let m = model(SPHERES, UniverseChoice::None);
    let s = slice(&m, &opts(Plane::axis(2, 0.0))).unwrap();
    let w = s.width as usize;
    let k = 50 * w + 30; // inside A only
    assert_eq!(s.class[k], 1);
    assert_eq!(s.rgb[k], region_colour("A"));
    let hexa = &s.legend.iter().find(|e| e.label == "A").unwrap().colour;
    assert_eq!(hexa.len(), 7);
    // Along the middle row, the pixel before a change of class is darker.
    let row = &s.class[50 * w..51 * w];
    let i = row.iter().position(|&c| c != 0).unwrap() - 1;
    let lum = |c: [f32; 3]| c[0] + c[1] + c[2];
    assert!(lum(s.rgb[50 * w + i]) < 0.5 * lum([1.0; 3]));
}

#[test]
fn arbitrary_and_axis_planes_agree() {
    let m = model(SPHERES, UniverseChoice::None);
    let a = slice(&m, &opts(Plane::axis(1, 0.0))).unwrap();
    let b = slice(
        &m,
        &opts(Plane::new(DVec3::ZERO, DVec3::new(0.0, -2.0, 0.0)).unwrap()),
    )
    .unwrap();
    // Same plane, same axes up to the direction of u.
    let count = |s: &Slice, c: u32| s.class.iter().filter(|&&x| x == c).count();
    for c in [1, 2, Slice::OVERLAP] {
        let (x, y) = (count(&a, c) as f64, count(&b, c) as f64);
        assert!((x - y).abs() <= 0.02 * x.max(y), "{c}: {x} {y}");
    }
}

#[test]
fn voids_are_drawn_in_sections() {
    let text = "
BODY big  RPP -2 2 -2 2 -2 2
BODY hole RPP -1.5 1.5 -1.5 1.5 -1.5 1.5
BODY s    SPH (0,0,0) 1
REGION WORLD = +big -hole
REGION CORE  = +s
";
    let m = model(text, UniverseChoice::Named("WORLD".into()));
    let s = slice(
        &m,
        &SliceOptions {
            plane: Plane::axis(0, 0.0),
            extent: None,
            size: Some((100, 100)),
            centre: None,
            tolerance: None,
            strict_air: false,
        },
    )
    .unwrap();
    let v = s.void.as_ref().expect("void in the picture");
    let exact = 9.0 - std::f64::consts::PI;
    assert!(
        (v.area - exact).abs() < 0.05 * exact,
        "{} vs {exact}",
        v.area
    );
    assert_eq!(class_at(&s, 0.0, 0.0), 2);
    assert_eq!(class_at(&s, 1.25, 1.25), Slice::VOID);
    assert_eq!(class_at(&s, 1.8, 0.0), 1);
}

#[test]
fn bad_slice_options_are_errors() {
    let m = model(SPHERES, UniverseChoice::None);
    let mut o = opts(Plane::axis(2, 0.0));
    o.size = Some((0, 10));
    assert!(slice(&m, &o).is_err());
    let mut o = opts(Plane::axis(2, 0.0));
    o.extent = Some((-1.0, 1.0));
    assert!(slice(&m, &o).is_err());
    assert!(Plane::new(DVec3::ZERO, DVec3::ZERO).is_none());
}

#[test]
fn a_size_alone_keeps_pixels_square() {
    let m = model(SPHERES, UniverseChoice::None);
    let s = slice(
        &m,
        &SliceOptions {
            plane: Plane::axis(2, 0.0),
            extent: None,
            size: Some((300, 300)),
            centre: None,
            tolerance: None,
            strict_air: false,
        },
    )
    .unwrap();
    assert!((s.extent.0 - s.extent.1).abs() < 1e-9, "{:?}", s.extent);
    // The box is 3.5 × 2: the view is 3.5 · 1.08 square (up to the
    // engine's padding of the bounds).
    assert!((s.extent.0 - 3.5 * 1.08).abs() < 1e-4, "{:?}", s.extent);
}

#[test]
fn air_gives_way_to_solids_in_sections_unless_strict() {
    let mut sc = crate::scene(SPHERES);
    sc.regions[1].air = 5;
    sc.regions[1].description = "INSIDE AIR".into();
    let (m, _) = sv_check::Model::new(&sc, &UniverseChoice::None).unwrap();
    let s = slice(&m, &opts(Plane::axis(2, 0.0))).unwrap();
    assert_eq!(class_at(&s, 0.0, 0.0), 1, "the solid sphere A is drawn");
    assert!(s.overlaps.is_empty());
    let b = s.legend.iter().find(|e| e.label == "B").unwrap();
    assert_eq!(b.description, "INSIDE AIR");
    let mut o = opts(Plane::axis(2, 0.0));
    o.strict_air = true;
    let s = slice(&m, &o).unwrap();
    assert_eq!(class_at(&s, 0.0, 0.0), Slice::OVERLAP);
    assert_eq!(s.overlaps.len(), 1);
}

#[test]
fn huge_pictures_are_refused() {
    let m = model(SPHERES, UniverseChoice::None);
    let mut o = opts(Plane::axis(2, 0.0));
    o.size = Some((16384, 16384));
    assert!(slice(&m, &o).is_err());
}

#[test]
fn a_plane_given_by_a_point_is_centred_on_it() {
    let m = model(SPHERES, UniverseChoice::None);
    let origin = DVec3::new(5.0, -3.0, 0.25);
    let s = slice(
        &m,
        &SliceOptions {
            plane: Plane::new(origin, DVec3::Z).expect("a plane"),
            extent: Some((2.0, 2.0)),
            size: Some((20, 20)),
            tolerance: None,
            strict_air: false,
            centre: Some(origin),
        },
    )
    .expect("slices");
    assert!((s.centre - origin).length() < 1e-12, "{:?}", s.centre);
}
