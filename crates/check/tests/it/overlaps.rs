use crate::model;
use sv_check::{check, CheckOptions, UniverseChoice};
use sv_math::DVec3;

const SPHERES: &str = "
BODY a SPH (0,0,0) 1
BODY b SPH (1.5,0,0) 1
REGION A = +a
REGION B = +b
";

#[test]
fn two_intersecting_spheres_are_reported_with_pair_point_and_volume() {
    let m = model(SPHERES, UniverseChoice::None);
    let r = check(&m, &CheckOptions::default()).unwrap();
    assert_eq!(r.overlaps.len(), 1, "{}", r.to_table());
    let o = &r.overlaps[0];
    assert_eq!(o.regions, ["A".to_string(), "B".to_string()]);
    assert_eq!(o.region_indices, [0, 1]);
    let p = DVec3::from_array(o.problem.point);
    assert!(
        p.length() < 1.0 && (p - DVec3::new(1.5, 0.0, 0.0)).length() < 1.0,
        "{p}"
    );
    // The lens is 0.5 thick along the line of centres and 2·√(1 − 0.75²)
    // across: the longest stretch is nearly that.
    let across = 2.0 * (1.0f64 - 0.5625).sqrt();
    assert!(o.problem.max_length <= across + 1e-9);
    assert!(
        o.problem.max_length > across - 0.02,
        "{}",
        o.problem.max_length
    );
    // Lens volume π(4R+d)(2R−d)²/12.
    let lens = std::f64::consts::PI * 5.5 * 0.25 / 12.0;
    assert!(
        (o.problem.volume - lens).abs() < 0.02 * lens,
        "{} vs {lens}",
        o.problem.volume
    );
    assert!(!r.is_clean());
    assert!(r.voids.is_empty() && r.outside.is_empty());
}

#[test]
fn cylinder_poking_through_a_box_is_found_inside_both() {
    let text = "
BODY box RPP -1 1 -1 1 -1 1
BODY rod RCC (0.2,0.1,-2) (0,0,4) 0.3
BODY far SPH (5,5,5) 0.5
REGION BLOCK = +box
REGION ROD = +rod
REGION BALL = +far
";
    let m = model(text, UniverseChoice::None);
    let r = check(&m, &CheckOptions::default()).unwrap();
    assert_eq!(r.overlaps.len(), 1, "{}", r.to_table());
    let o = &r.overlaps[0];
    assert_eq!(o.regions, ["BLOCK".to_string(), "ROD".to_string()]);
    let p = DVec3::from_array(o.problem.point);
    assert!(p.abs().max_element() <= 1.0 + 1e-9, "{p}");
    assert!(
        ((p.x - 0.2).powi(2) + (p.y - 0.1).powi(2)).sqrt() <= 0.3 + 1e-9,
        "{p}"
    );
    // Along z the rod crosses the whole box.
    assert!((o.problem.max_length - 2.0).abs() < 1e-6);
    let v = std::f64::consts::PI * 0.09 * 2.0;
    assert!(
        (o.problem.volume - v).abs() < 0.03 * v,
        "{} vs {v}",
        o.problem.volume
    );

    // Subtracting the rod from the block removes the overlap.
    let fixed = text.replace("REGION BLOCK = +box", "REGION BLOCK = +box -rod");
    let r = check(
        &model(&fixed, UniverseChoice::None),
        &CheckOptions::default(),
    )
    .unwrap();
    assert!(r.is_clean(), "{}", r.to_table());
}

#[test]
fn touching_faces_are_not_overlaps() {
    // Boxes sharing the face x = 1, a cylinder standing on the top face,
    // and a sphere touching the side face at one point; random rays too.
    let text = "
BODY a RPP 0 1 0 1 0 1
BODY b RPP 1 2 0 1 0 1
BODY c RCC (0.5,0.5,1) (0,0,1) 0.4
BODY s SPH (2.5,0.5,0.5) 0.5
REGION A = +a
REGION B = +b
REGION C = +c
REGION S = +s
";
    let m = model(text, UniverseChoice::None);
    let r = check(
        &m,
        &CheckOptions {
            random: 5000,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(r.is_clean(), "{}", r.to_table());
    assert_eq!(r.random_rays, 5000);
    // A fine grid whose rays fall exactly on the shared faces' lines is
    // still clean.
    let r = check(
        &m,
        &CheckOptions {
            spacing: Some(0.05),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(r.is_clean(), "{}", r.to_table());
}

#[test]
fn tolerance_hides_thin_overlaps_only() {
    // The boxes overlap by 0.001 in x.
    let text = "
BODY a RPP 0 1.001 0 1 0 1
BODY b RPP 1 2 0 1 0 1
REGION A = +a
REGION B = +b
";
    let m = model(text, UniverseChoice::None);
    // The grid's rays cross the sliver or miss it.
    let loose = CheckOptions {
        tolerance: Some(0.01),
        refine: 0,
        ..Default::default()
    };
    let grid_only = check(&m, &loose).unwrap();
    assert!(grid_only.is_clean(), "{}", grid_only.to_table());
    // Refinement rays between the grid rays on either side of x = 1 run
    // inside it, along its whole length: a stretch far longer than the
    // tolerance.
    let refined = check(&m, &CheckOptions { refine: 4, ..loose }).unwrap();
    assert_eq!(refined.overlaps.len(), 1, "{}", refined.to_table());
    assert!(refined.overlaps[0].problem.max_length > 0.9);
    let strict = check(
        &m,
        &CheckOptions {
            tolerance: Some(1e-6),
            spacing: Some(0.01),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(strict.overlaps.len(), 1, "{}", strict.to_table());
    let o = &strict.overlaps[0].problem;
    assert!(o.point[0] > 1.0 && o.point[0] < 1.001, "{:?}", o.point);
    // The grid is coarser than the sliver: every ray along x crosses its
    // 0.001 thickness; rays along y and z see it only if they happen to run
    // inside it.
    assert!(o.hits >= 100 * 100, "{}", o.hits);
    assert!(o.max_length >= 0.001 - 1e-9 && o.max_length <= 1.0 + 1e-9);
}

#[test]
fn pairs_are_sorted_by_severity() {
    let text = "
BODY a SPH (0,0,0) 1
BODY b SPH (1.9,0,0) 1
BODY c SPH (0,1.2,0) 1
REGION A = +a
REGION B = +b
REGION C = +c
";
    let r = check(&model(text, UniverseChoice::None), &CheckOptions::default()).unwrap();
    let names: Vec<_> = r.overlaps.iter().map(|o| o.regions.join("×")).collect();
    assert_eq!(names[0], "A×C", "{}", r.to_table());
    assert!(names.contains(&"A×B".to_string()));
    for w in r.overlaps.windows(2) {
        assert!(w[0].problem.total_length >= w[1].problem.total_length);
    }
}

#[test]
fn json_report_has_the_documented_shape() {
    let m = model(SPHERES, UniverseChoice::None);
    let r = check(&m, &CheckOptions::default()).unwrap();
    let v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
    for key in [
        "unit",
        "regions",
        "bounds",
        "spacing",
        "grid_rays",
        "random_rays",
        "tolerance",
        "refine",
        "refine_rays",
        "smallest_feature",
        "universe",
        "overlaps",
        "air_overlaps",
        "voids",
        "outside",
        "unseen",
        "seconds",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    let o = &v["overlaps"][0];
    assert_eq!(o["regions"], serde_json::json!(["A", "B"]));
    assert_eq!(o["point"].as_array().unwrap().len(), 3);
    for key in [
        "total_length",
        "max_length",
        "hits",
        "volume",
        "region_indices",
    ] {
        assert!(o.get(key).is_some(), "missing overlaps[].{key}");
    }
    for key in ["anywhere", "at_edges", "note"] {
        assert!(
            v["smallest_feature"].get(key).is_some(),
            "missing smallest_feature.{key}"
        );
    }
    assert!(v["universe"].is_null());
    assert_eq!(v["regions"], 2);
}

#[test]
fn bad_options_are_errors_not_panics() {
    let m = model(SPHERES, UniverseChoice::None);
    for o in [
        CheckOptions {
            spacing: Some(0.0),
            ..Default::default()
        },
        CheckOptions {
            spacing: Some(1e-6),
            ..Default::default()
        },
        CheckOptions {
            tolerance: Some(-1.0),
            ..Default::default()
        },
        CheckOptions {
            random: u64::MAX,
            ..Default::default()
        },
    ] {
        assert!(check(&m, &o).is_err());
    }
}

#[test]
fn pictures_mark_pixels_that_see_an_overlap() {
    let m = model(SPHERES, UniverseChoice::None);
    // Orthographic rays down -z over x in [-1.5, 3], y = 0.
    let ov = sv_check::overlap_pixels(&m, 90, 1, 1e-6, false, |x, _| {
        sv_math::Ray::new(
            DVec3::new(-1.5 + 0.05 * (x as f64 + 0.5), 0.0, 5.0),
            -DVec3::Z,
        )
    });
    for (x, hit) in ov.mask.iter().enumerate() {
        let px = -1.5 + 0.05 * (x as f64 + 0.5);
        let expect = px > 0.5 && px < 1.0;
        assert_eq!(*hit, expect, "x = {px}");
    }
    assert_eq!(ov.pairs.len(), 1);
    assert_eq!(ov.pairs[0].regions, ["A".to_string(), "B".to_string()]);
    assert_eq!(ov.pairs[0].pixels, 10);
}

#[test]
fn a_cameras_picture_is_painted_where_it_sees_an_overlap() {
    let m = model(SPHERES, UniverseChoice::None);
    // Looking down -z at the middle of the lens A and B share.
    let camera = sv_scene::Camera::looking_at(
        DVec3::new(0.75, 0.0, 10.0),
        DVec3::new(0.75, 0.0, 0.0),
        DVec3::Y,
        sv_scene::Lens::Fov { vertical_deg: 60.0 },
    );
    let seen = sv_check::camera_overlaps(&m, &camera, 9, 9, false);
    let centre = 4 * 9 + 4;
    assert!(seen.mask[centre] && !seen.mask[0]);
    let mut rgb = vec![[0.25f32; 3]; 81];
    let mut alpha = vec![0.0f32; 81];
    seen.paint(&mut rgb, &mut alpha);
    assert_eq!(
        (rgb[centre], alpha[centre]),
        (sv_check::OVERLAP_COLOUR, 1.0)
    );
    assert_eq!((rgb[0], alpha[0]), ([0.25; 3], 0.0));
    let pixels = seen.mask.iter().filter(|m| **m).count();
    assert_eq!(
        seen.summary(),
        format!(
            "overlaps seen (1 pairs, magenta):\n  A × B: {pixels} pixels, longest {:.6}\n",
            seen.pairs[0].max_length
        )
    );
    let apart = model(
        "BODY a SPH (0,0,0) 1\nBODY b SPH (3,0,0) 1\nREGION A = +a\nREGION B = +b\n",
        UniverseChoice::None,
    );
    let none = sv_check::camera_overlaps(&apart, &camera, 9, 9, false);
    assert_eq!(none.summary(), "overlaps: none seen\n");
}

#[test]
fn default_spacing_follows_the_model_shape() {
    // A long thin rod gets as many rays as a cube would, not 200 along its
    // length and 2 across.
    let text = "BODY r RPP 0 100 0 1 0 1\nREGION R = +r\n";
    let r = check(&model(text, UniverseChoice::None), &CheckOptions::default()).unwrap();
    assert!(r.spacing < 0.1, "{}", r.spacing);
    assert!(
        r.grid_rays > 100_000 && r.grid_rays < 140_000,
        "{}",
        r.grid_rays
    );
}

#[test]
fn two_airs_of_different_codes_overlapping_is_a_real_overlap() {
    // GIFT and BRL-CAD let air give way to a solid, and one air to air of
    // its own code, but two different airs meeting is a modelling error.
    let mut s = crate::scene(SPHERES);
    s.regions[0].air = 1;
    s.regions[1].air = 2;
    let (m, _) = sv_check::Model::new(&s, &UniverseChoice::None).unwrap();
    let r = check(&m, &CheckOptions::default()).unwrap();
    assert_eq!(r.overlaps.len(), 1);
    assert!(r.air_overlaps.is_empty());
    assert!(!r.is_clean());
    s.regions[1].air = 1;
    let (m, _) = sv_check::Model::new(&s, &UniverseChoice::None).unwrap();
    let r = check(&m, &CheckOptions::default()).unwrap();
    assert!(r.overlaps.is_empty());
    assert_eq!(r.air_overlaps.len(), 1);
}

#[test]
fn overlaps_with_air_are_listed_apart_unless_strict() {
    let mut s = crate::scene(SPHERES);
    s.regions[1].air = 2;
    let (m, _) = sv_check::Model::new(&s, &UniverseChoice::None).unwrap();
    let r = check(&m, &CheckOptions::default()).unwrap();
    assert!(r.overlaps.is_empty());
    assert_eq!(r.air_overlaps.len(), 1);
    assert!(r.air_overlaps[0].air);
    assert!(r.is_clean());
    assert!(r.to_table().contains("air"));
    let strict = check(
        &m,
        &CheckOptions {
            strict_air: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(strict.overlaps.len(), 1);
    assert!(!strict.is_clean());
}

#[test]
fn empty_regions_are_listed_as_unseen() {
    let text =
        format!("{SPHERES}BODY c RPP 5 6 5 6 5 6\nBODY d RPP 4 7 4 7 4 7\nREGION GONE = +c -d\n");
    let r = check(
        &model(&text, UniverseChoice::None),
        &CheckOptions::default(),
    )
    .unwrap();
    assert_eq!(r.unseen, ["GONE".to_string()]);
    assert!(r.to_table().contains("met by no ray"));
    let clean = check(
        &model(CLEAN_PAIR, UniverseChoice::None),
        &CheckOptions::default(),
    )
    .unwrap();
    assert!(clean.unseen.is_empty());
}

const CLEAN_PAIR: &str =
    "BODY a SPH (0,0,0) 1\nBODY b SPH (3,0,0) 1\nREGION A = +a\nREGION B = +b\n";

#[test]
fn a_box_looks_closely_at_part_of_a_model() {
    // Two thin plates overlap by 0.2 inside a world 2000 across: the
    // default grid (spacing 10) runs past them; a box around them finds it.
    let text = "
BODY w RPP -1000 1000 -1000 1000 -1000 1000
BODY p RPP 0 0.5 0 3 0 3
BODY q RPP 0.3 0.8 1 4 1 4
REGION WORLD = +w -p -q
REGION P = +p
REGION Q = +q
";
    let m = model(text, UniverseChoice::Named("WORLD".into()));
    let coarse = check(&m, &CheckOptions::default()).unwrap();
    assert!(coarse.overlaps.is_empty(), "{}", coarse.to_table());
    let close = check(
        &m,
        &CheckOptions {
            bounds: Some(sv_math::Aabb::new(DVec3::splat(-1.0), DVec3::splat(5.0))),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(close.overlaps.len(), 1, "{}", close.to_table());
    assert_eq!(
        close.overlaps[0].regions,
        ["P".to_string(), "Q".to_string()]
    );
    let p = DVec3::from_array(close.overlaps[0].problem.point);
    assert!(p.x > 0.3 && p.x < 0.5 && p.y > 1.0 && p.y < 3.0, "{p}");
    assert!(close.voids.is_empty(), "{}", close.to_table());
}

#[test]
fn a_model_without_finite_regions_needs_a_box() {
    let text = "BODY a XCC 0 0 1\nBODY b YCC 0 0 1\nREGION A = +a\nREGION B = +b\n";
    let m = model(text, UniverseChoice::None);
    assert!(matches!(
        check(&m, &CheckOptions::default()),
        Err(sv_check::CheckError::Unbounded)
    ));
    let r = check(
        &m,
        &CheckOptions {
            bounds: Some(sv_math::Aabb::new(DVec3::splat(-2.0), DVec3::splat(2.0))),
            ..Default::default()
        },
    )
    .unwrap();
    // The two infinite cylinders cross at the origin (a Steinmetz solid of
    // volume 16/3).
    assert_eq!(r.overlaps.len(), 1);
    assert!(
        (r.overlaps[0].problem.volume - 16.0 / 3.0).abs() < 0.05,
        "{}",
        r.overlaps[0].problem.volume
    );
}

#[test]
fn pictures_skip_air_overlaps_unless_strict() {
    let mut s = crate::scene(SPHERES);
    s.regions[0].air = 1;
    let (m, _) = sv_check::Model::new(&s, &UniverseChoice::None).unwrap();
    let ray = |x: u32, _| {
        sv_math::Ray::new(
            DVec3::new(-1.5 + 0.05 * (x as f64 + 0.5), 0.0, 5.0),
            -DVec3::Z,
        )
    };
    let lax = sv_check::overlap_pixels(&m, 90, 1, 1e-6, false, ray);
    assert!(lax.mask.iter().all(|m| !m) && lax.pairs.is_empty());
    let strict = sv_check::overlap_pixels(&m, 90, 1, 1e-6, true, ray);
    assert_eq!(strict.mask.iter().filter(|m| **m).count(), 10);
}

#[test]
fn reports_do_not_depend_on_the_number_of_threads() {
    let text = "
BODY a SPH (0,0,0) 1
BODY b SPH (1.5,0,0) 1
BODY c RCC (0,0,-2) (0,0,4) 0.3
REGION A = +a
REGION B = +b
REGION C = +c
";
    let m = model(text, UniverseChoice::None);
    // 129,000 grid rays: over 500 chunks, which the refinement takes in
    // groups whose size follows the number of threads.
    let opts = CheckOptions {
        random: 3000,
        spacing: Some(0.015),
        ..Default::default()
    };
    let run = |n: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        let mut r = pool.install(|| check(&m, &opts)).unwrap();
        r.seconds = 0.0;
        r
    };
    let one = run(1);
    assert_eq!(one.overlaps.len(), 2);
    assert!(one.grid_rays > 100_000 && one.refine_rays > 0);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
}

#[test]
fn a_check_split_into_parts_merges_to_the_same_report() {
    let m = model(SPHERES, UniverseChoice::None);
    let opts = CheckOptions {
        random: 3000,
        ..CheckOptions::default()
    };
    let whole = sv_check::check(&m, &opts).unwrap();
    let chunks = sv_check::check_chunks(&m, &opts).unwrap();
    assert!(chunks > 3, "{chunks}");
    // Three uneven shares, merged out of order after a JSON round trip.
    let cuts = [0, 1, chunks / 2, chunks];
    let mut parts: Vec<sv_check::CheckPart> = cuts
        .windows(2)
        .map(|w| sv_check::check_part(&m, &opts, w[0]..w[1]).unwrap())
        .map(|part| serde_json::from_str(&serde_json::to_string(&part).unwrap()).unwrap())
        .collect();
    parts.reverse();
    let mut merged = sv_check::check_merge(&m, &opts, &parts).unwrap();
    merged.seconds = whole.seconds;
    assert_eq!(merged.to_json(), whole.to_json());
    assert!(!whole.overlaps.is_empty());
    // A missing share is refused.
    assert!(sv_check::check_merge(&m, &opts, &parts[1..]).is_err());
}

#[test]
fn a_leaning_ground_is_found_where_it_reaches_into_the_box() {
    // The ground is unbounded; the rows and tiles of rays beside its
    // corner of the checked box do not list it, and those through that
    // corner find all of its overlap with the cube, a tetrahedron.
    let text = "
BODY cube RPP 0 1 0 1 0 1
BODY ground PLA (1,1,1) (0.5,0,0)
BODY far SPH (3,3,3) 0.5
REGION CUBE = +cube
REGION GROUND = +ground
REGION FAR = +far
";
    let m = model(text, UniverseChoice::None);
    let opts = CheckOptions {
        spacing: Some(0.02),
        ..CheckOptions::default()
    };
    let r = check(&m, &opts).unwrap();
    assert_eq!(r.overlaps.len(), 1, "{}", r.to_table());
    let o = &r.overlaps[0];
    assert_eq!(o.regions, ["CUBE".to_string(), "GROUND".to_string()]);
    let tetrahedron = 0.5f64.powi(3) / 6.0;
    assert!(
        (o.problem.volume - tetrahedron).abs() < 0.03 * tetrahedron,
        "{} vs {tetrahedron}",
        o.problem.volume
    );
}

#[test]
fn a_sphere_and_a_faceted_solid_are_met_across_each_rows_cut() {
    // Each row of rays lists a sphere or a mesh only where the row's
    // plane cuts it: the overlaps inside the octahedron `|x| + |y| + |z|
    // <= 1` (an ARS) must come out whole, a ball at its centre and the
    // pyramid a box cuts off its corner.
    let text = "
BODY octa ARS 3 4  0 0 -1 0 0 -1 0 0 -1 0 0 -1  1 0 0 0 1 0 -1 0 0 0 -1 0  0 0 1 0 0 1 0 0 1 0 0 1
BODY ball SPH (0,0,0) 0.5
BODY corner RPP 0.5 2 -2 2 -2 2
REGION OCTA = +octa
REGION BALL = +ball
REGION CORNER = +corner
";
    let m = model(text, UniverseChoice::None);
    let opts = CheckOptions {
        spacing: Some(0.01),
        ..CheckOptions::default()
    };
    let r = check(&m, &opts).unwrap();
    assert_eq!(r.overlaps.len(), 2, "{}", r.to_table());
    let volume_of = |a: &str, b: &str| {
        let pair = [a.to_string(), b.to_string()];
        let o = r.overlaps.iter().find(|o| o.regions == pair);
        o.unwrap_or_else(|| panic!("no {a} × {b}: {}", r.to_table()))
            .problem
            .volume
    };
    let ball = 4.0 / 3.0 * std::f64::consts::PI * 0.125;
    let pyramid = 1.0 / 12.0;
    for (found, exact) in [
        (volume_of("OCTA", "BALL"), ball),
        (volume_of("OCTA", "CORNER"), pyramid),
    ] {
        assert!((found - exact).abs() < 0.002 * exact, "{found} vs {exact}");
    }
}
