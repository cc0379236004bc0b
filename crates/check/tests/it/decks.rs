//! The real decks in ../shared/decks: what the check finds there (see
//! docs/checking.md). They fail when the folder is missing (see
//! `sv_testdata`).

use std::path::{Path, PathBuf};
use sv_check::{check, CheckOptions, Model, Report, Universe, UniverseChoice};
use sv_formats::{load_file, LoadOptions};

/// The shared deck `folder/file`; `None` only when the shared decks are
/// missing and `SV_SKIP_SHARED=1` is set.
fn deck(rel: &str) -> Option<PathBuf> {
    let (folder, file) = rel.rsplit_once('/').expect("a path folder/file");
    let path = sv_testdata::shared_decks(folder)?.join(file);
    assert!(
        path.is_file(),
        "the shared deck {} is missing",
        path.display()
    );
    Some(path)
}

fn run(p: &Path, strict_air: bool) -> (Model, Report) {
    let scene = load_file(p, &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
        .scene;
    let (m, _) = Model::new(&scene, &UniverseChoice::Auto).unwrap();
    let r = check(
        &m,
        &CheckOptions {
            strict_air,
            ..Default::default()
        },
    )
    .unwrap();
    (m, r)
}

#[test]
fn generator_deck_overlaps_and_empty_regions() {
    let Some(p) = deck("comgeom/mep021a-generator-v5.cg") else {
        return;
    };
    let (_, r) = run(&p, false);
    // Region 98 is written with body 96, which region 96 already fills.
    assert_eq!(r.overlaps[0].regions, ["96".to_string(), "98".to_string()]);
    assert!(r.overlaps.len() >= 30, "{}", r.to_table());
    assert!(r.air_overlaps.len() >= 100);
    assert!(r.air_overlaps.iter().all(|o| o.air));
    // FUEL (+282 -161) lies inside body 161.
    assert!(r.unseen.contains(&"282".to_string()));
    assert!(!r.is_clean());
}

#[test]
fn generator_regions_met_are_the_same_refined_or_not() {
    // The refined check marks a grid ray's regions only where its
    // signature differs from the ray's before it; ten regions here are
    // met by no ray, so marking never stops early.
    let Some(p) = deck("comgeom/mep021a-generator-v5.cg") else {
        return;
    };
    let scene = load_file(&p, &LoadOptions::default()).unwrap().scene;
    let (m, _) = Model::new(&scene, &UniverseChoice::Auto).unwrap();
    let unseen = |refine| {
        let opts = CheckOptions {
            refine,
            ..Default::default()
        };
        check(&m, &opts).unwrap().unseen
    };
    let refined = unseen(4);
    assert!(refined.contains(&"282".to_string()), "{refined:?}");
    assert_eq!(refined, unseen(0));
}

#[test]
fn gift_sample_target_overlaps_only_its_air() {
    let Some(p) = deck("comgeom/gift-sample-target-v4.cg") else {
        return;
    };
    let (_, r) = run(&p, false);
    assert!(r.overlaps.is_empty(), "{}", r.to_table());
    assert_eq!(r.air_overlaps.len(), 20, "{}", r.to_table());
    assert!(r.is_clean());
    let (_, strict) = run(&p, true);
    assert_eq!(strict.overlaps.len(), 20);
}

#[test]
fn fluka_test_inputs_with_planted_problems() {
    let Some(p104) = deck("fluka/pyg4ometry-testdata/104_shift_cylinders.inp") else {
        return;
    };
    // The yoke outside the beam pipe belongs to no region, nor does the
    // pipe outside the yoke (the black hole subtracts the whole infinite
    // pipe, BPVC keeps only its part inside the yoke).
    let (m, r) = run(&p104, true);
    assert!(matches!(m.universe, Some(Universe::Region(_))));
    assert!(!r.voids.is_empty(), "{}", r.to_table());
    let void: f64 = r.voids.iter().map(|v| v.problem.volume).sum();
    // Yoke 20 × 20 × 17 minus the pipe (π·3·1.5) inside it, plus the pipe
    // over the rest of the black hole's 100 in z.
    let pipe = std::f64::consts::PI * 4.5;
    let exact = 17.0 * (400.0 - pipe) + 83.0 * pipe;
    assert!((void - exact).abs() < 0.05 * exact, "{void} vs {exact}");
    assert!(r.overlaps.is_empty());

    // Expanded 20 times, the inner box outgrows the black hole.
    let p801 = deck("fluka/pyg4ometry-testdata/801_nested_expansion.inp").unwrap();
    let (_, r) = run(&p801, true);
    assert_eq!(r.outside.len(), 1, "{}", r.to_table());
    assert_eq!(r.outside[0].region, "rppreg");
    // The black hole, wholly inside the inner box, meets no ray; being
    // beyond the model it is not reported as unseen.
    assert!(r.unseen.is_empty(), "{:?}", r.unseen);

    // Two boxes placed on top of each other on purpose.
    let p806 = deck("fluka/pyg4ometry-testdata/806_combined_translat_transform.inp").unwrap();
    let (_, r) = run(&p806, true);
    assert_eq!(r.overlaps.len(), 1, "{}", r.to_table());
    assert_eq!(
        r.overlaps[0].regions,
        ["rpptrf".to_string(), "rpptrflt".to_string()]
    );

    // A clean one.
    let p003 = deck("fluka/pyg4ometry-testdata/003_SPH.inp").unwrap();
    let (_, r) = run(&p003, true);
    assert!(r.is_clean(), "{}", r.to_table());
}
