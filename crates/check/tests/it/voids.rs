use crate::{model, scene};
use sv_check::{check, CheckOptions, Model, UniverseChoice};
use sv_math::DVec3;

const WORLD: &str = "
BODY big  RPP -2 2 -2 2 -2 2
BODY hole RPP -1.5 1.5 -1.5 1.5 -1.5 1.5
BODY s    SPH (0,0,0) 1
REGION WORLD = +big -hole
REGION CORE  = +s
";

#[test]
fn planted_void_between_the_world_and_a_sphere() {
    let m = model(WORLD, UniverseChoice::Named("WORLD".into()));
    let r = check(&m, &CheckOptions::default()).unwrap();
    assert!(r.overlaps.is_empty(), "{}", r.to_table());
    assert!(!r.voids.is_empty(), "{}", r.to_table());
    let total: f64 = r.voids.iter().map(|v| v.problem.volume).sum();
    let exact = 27.0 - 4.0 / 3.0 * std::f64::consts::PI;
    assert!((total - exact).abs() < 0.02 * exact, "{total} vs {exact}");
    for v in &r.voids {
        let p = DVec3::from_array(v.problem.point);
        assert!(p.abs().max_element() < 1.5 && p.length() > 1.0, "{p}");
        // Gaps lie between the world's inner wall and the core.
        for n in v.between.iter().flatten() {
            assert!(n == "WORLD" || n == "CORE", "{n}");
        }
    }
    // Rays through the corners of the hole see wall to wall gaps; rays
    // (regions are listed in deck order)
    // through the core see gaps between wall and core.
    let kinds: Vec<_> = r.voids.iter().map(|v| v.between.clone()).collect();
    let w = Some("WORLD".to_string());
    let c = Some("CORE".to_string());
    assert!(kinds.contains(&[w.clone(), c]), "{kinds:?}");
    assert!(kinds.contains(&[w.clone(), w]), "{kinds:?}");
    assert!(r.universe.unwrap().description.contains("WORLD"));
}

#[test]
fn a_filled_universe_is_clean() {
    let text = WORLD.replace("-hole", "-s");
    let r = check(
        &model(&text, UniverseChoice::Named("WORLD".into())),
        &CheckOptions::default(),
    )
    .unwrap();
    assert!(r.is_clean(), "{}", r.to_table());
}

#[test]
fn a_body_can_be_the_universe() {
    // Inside body `hole`: only the core is claimed (WORLD lies outside it).
    let m = model(WORLD, UniverseChoice::Named("hole".into()));
    let r = check(&m, &CheckOptions::default()).unwrap();
    let total: f64 = r.voids.iter().map(|v| v.problem.volume).sum();
    let exact = 27.0 - 4.0 / 3.0 * std::f64::consts::PI;
    assert!((total - exact).abs() < 0.02 * exact, "{total}");
    // WORLD reaches outside the body `hole`.
    assert_eq!(r.outside.len(), 1, "{}", r.to_table());
    assert_eq!(r.outside[0].region, "WORLD");
    assert!(r.universe.unwrap().description.contains("body"));
}

#[test]
fn regions_sticking_out_of_the_universe_are_reported() {
    let text = format!("{WORLD}BODY out SPH (2,0,0) 0.3\nREGION STRAY = +out -big\n");
    let r = check(
        &model(&text, UniverseChoice::Named("WORLD".into())),
        &CheckOptions::default(),
    )
    .unwrap();
    assert_eq!(r.outside.len(), 1, "{}", r.to_table());
    assert_eq!(r.outside[0].region, "STRAY");
    assert!(r.outside[0].problem.point[0] > 2.0);
}

#[test]
fn unknown_universe_is_an_error() {
    let s = scene(WORLD);
    assert!(Model::new(&s, &UniverseChoice::Named("nowhere".into())).is_err());
}

#[test]
fn black_hole_regions_are_found_automatically() {
    // By name.
    let named = WORLD.replace("REGION WORLD", "REGION BLKHOLE");
    let m = model(&named, UniverseChoice::Auto);
    assert_eq!(m.universe, Some(sv_check::Universe::Region(0)));
    let r = check(&m, &CheckOptions::default()).unwrap();
    assert!(!r.voids.is_empty());
    // By the FLUKA material in the description.
    let mut s = scene(WORLD);
    s.regions[0].description = "material BLCKHOLE".into();
    let (m, _) = Model::new(&s, &UniverseChoice::Auto).unwrap();
    assert_eq!(m.universe, Some(sv_check::Universe::Region(0)));
    assert!(m.universe_note.unwrap().contains("automatically"));
    // Nothing marked: no universe, and voids are not looked for.
    let m = model(WORLD, UniverseChoice::Auto);
    assert_eq!(m.universe, None);
    assert!(check(&m, &CheckOptions::default()).unwrap().is_clean());
}
