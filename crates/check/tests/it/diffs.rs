//! `diff` on every MCNP input and OpenMC model of the same benchmark in
//! ../shared/decks/mcnp-openmc: agreement where the two truly agree, and
//! the real differences found where they do not (docs/diff.md says why).

use std::path::{Path, PathBuf};
use sv_check::{diff, DiffOptions, DiffReport, DiffSide, Model, UniverseChoice};
use sv_formats::{load_file, LoadOptions};
use sv_math::{Aabb, DVec3};

/// What the diff of a pair must show.
enum Expect {
    /// The same materials in the same places.
    Agree,
    /// Agree inside this box (the models are unbounded: pin cells infinite
    /// in z behind reflecting walls).
    AgreeIn([f64; 6]),
    /// A material of A (by name) matches nothing in B: a different
    /// composition.
    Material(&'static str),
    /// The geometry differs: one of the three worst places holds this
    /// material of A.
    Geometry(&'static str),
}

/// The pairs that do not simply agree, by the MCNP case's folder.
fn expectation(case: &str) -> Expect {
    match case {
        // MCNP's M16 gives Fe-54 ten times OpenMC's (5.0170e-02 against
        // 5.0169973e-03): a slip in one of the inputs.
        "icsbep/heu-comp-inter-003/mcnp/case-6" => Expect::Material("m16"),
        // The spheres' radii: 34.4995 and 34.6583 cm in MCNP, 34.6710 and
        // 34.8298 cm in OpenMC.
        "icsbep/leu-sol-therm-002/mcnp/case-3" => Expect::Geometry("m2"),
        // M1 holds U-234 where OpenMC's inner sphere holds U-235.
        "icsbep/u233-met-fast-002/mcnp/case-2" => Expect::Material("m1"),
        case if case.starts_with("indc-usa-107/") => {
            Expect::AgreeIn([-3.0, -3.0, -10.0, 3.0, 3.0, 10.0])
        }
        _ => Expect::Agree,
    }
}

/// Every (MCNP input, OpenMC folder) of the shared benchmarks, the case
/// folder relative to the root.
fn pairs(root: &Path) -> Vec<(String, PathBuf, PathBuf)> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                walk(&path, out);
            } else if path.file_name().is_some_and(|n| n == "input") {
                out.push(path);
            }
        }
    }
    let mut inputs = Vec::new();
    walk(root, &mut inputs);
    inputs
        .into_iter()
        .filter_map(|input| {
            let case = input.parent()?.strip_prefix(root).ok()?;
            let case = case.to_string_lossy().replace('\\', "/");
            let openmc = root.join(case.replace("/mcnp", "/openmc"));
            openmc
                .join("geometry.xml")
                .is_file()
                .then_some((case, input, openmc))
        })
        .collect()
}

fn run(a: &Path, b: &Path, region: Option<Aabb>) -> DiffReport {
    let scenes = [a, b].map(|path| {
        load_file(path, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{} reads: {e}", path.display()))
            .scene
    });
    let models = [&scenes[0], &scenes[1]].map(|scene| {
        Model::new(scene, &UniverseChoice::None)
            .expect("prepares")
            .0
    });
    let opts = DiffOptions {
        rays_per_side: 32,
        batches: 4,
        region,
        ..DiffOptions::default()
    };
    let side = |i: usize| DiffSide {
        scene: &scenes[i],
        model: &models[i],
    };
    diff(side(0), side(1), &opts).expect("the diff runs")
}

fn judge(case: &str, report: &DiffReport) -> Result<(), String> {
    let summary = || {
        format!(
            "{case}: differ {:.3e} of the material; unmatched {:?}; worst {:?}",
            report.differ_fraction,
            report
                .unmatched
                .iter()
                .map(|u| &u.substance)
                .collect::<Vec<_>>(),
            report.worst.first()
        )
    };
    let ok = match expectation(case) {
        Expect::Agree | Expect::AgreeIn(_) => report.agree && report.unmatched.is_empty(),
        Expect::Material(name) => {
            !report.agree
                && report
                    .unmatched
                    .iter()
                    .any(|u| u.model == "A" && u.substance.starts_with(&format!("{name} ")))
        }
        Expect::Geometry(name) => {
            !report.agree
                && report.unmatched.is_empty()
                && report
                    .worst
                    .iter()
                    .take(3)
                    .any(|w| w.substance_a.starts_with(&format!("{name} ")))
        }
    };
    if ok {
        Ok(())
    } else {
        Err(summary())
    }
}

/// Every pair of the benchmark in `folder` (relative to the shared
/// mcnp-openmc root) agrees or shows its real difference.
fn check_benchmark(folder: &str) {
    let Some(root) = sv_testdata::shared_decks("mcnp-openmc") else {
        return;
    };
    let pairs: Vec<_> = pairs(&root)
        .into_iter()
        .filter(|(case, _, _)| case.starts_with(&format!("{folder}/")))
        .collect();
    assert!(!pairs.is_empty(), "no MCNP/OpenMC pair under {folder}");
    let mut failures = Vec::new();
    for (case, mcnp, openmc) in &pairs {
        let region = match expectation(case) {
            Expect::AgreeIn([x0, y0, z0, x1, y1, z1]) => {
                Some(Aabb::new(DVec3::new(x0, y0, z0), DVec3::new(x1, y1, z1)))
            }
            _ => None,
        };
        if let Err(failure) = judge(case, &run(mcnp, openmc, region)) {
            failures.push(failure);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// One named test per benchmark, and the list of their folders.
macro_rules! benchmark_tests {
    ($($name:ident => $folder:literal,)*) => {
        $(
            #[test]
            fn $name() {
                check_benchmark($folder);
            }
        )*
        const BENCHMARK_FOLDERS: &[&str] = &[$($folder),*];
    };
}

benchmark_tests! {
    heu_comp_inter_003 => "icsbep/heu-comp-inter-003",
    heu_met_fast_003 => "icsbep/heu-met-fast-003",
    heu_met_fast_008 => "icsbep/heu-met-fast-008",
    heu_met_fast_011 => "icsbep/heu-met-fast-011",
    heu_met_fast_013 => "icsbep/heu-met-fast-013",
    heu_met_fast_015 => "icsbep/heu-met-fast-015",
    heu_met_fast_019 => "icsbep/heu-met-fast-019",
    heu_met_fast_021 => "icsbep/heu-met-fast-021",
    heu_met_inter_006 => "icsbep/heu-met-inter-006",
    heu_sol_therm_032 => "icsbep/heu-sol-therm-032",
    ieu_met_fast_002 => "icsbep/ieu-met-fast-002",
    ieu_met_fast_004 => "icsbep/ieu-met-fast-004",
    ieu_met_fast_006 => "icsbep/ieu-met-fast-006",
    leu_comp_therm_008 => "icsbep/leu-comp-therm-008",
    leu_sol_therm_002 => "icsbep/leu-sol-therm-002",
    mix_met_fast_003 => "icsbep/mix-met-fast-003",
    pu_comp_inter_001 => "icsbep/pu-comp-inter-001",
    pu_met_fast_002 => "icsbep/pu-met-fast-002",
    pu_met_fast_003 => "icsbep/pu-met-fast-003",
    pu_met_fast_005 => "icsbep/pu-met-fast-005",
    pu_met_fast_008 => "icsbep/pu-met-fast-008",
    pu_met_fast_010 => "icsbep/pu-met-fast-010",
    pu_met_fast_018 => "icsbep/pu-met-fast-018",
    pu_met_fast_020 => "icsbep/pu-met-fast-020",
    pu_met_fast_022 => "icsbep/pu-met-fast-022",
    pu_met_fast_024 => "icsbep/pu-met-fast-024",
    pu_met_fast_026 => "icsbep/pu-met-fast-026",
    pu_sol_therm_011 => "icsbep/pu-sol-therm-011",
    pu_sol_therm_021 => "icsbep/pu-sol-therm-021",
    u233_comp_therm_001 => "icsbep/u233-comp-therm-001",
    u233_met_fast_002 => "icsbep/u233-met-fast-002",
    u233_met_fast_004 => "icsbep/u233-met-fast-004",
    u233_met_fast_006 => "icsbep/u233-met-fast-006",
    u233_sol_therm_001 => "icsbep/u233-sol-therm-001",
    indc_usa_107 => "indc-usa-107",
}

#[test]
fn every_benchmark_with_pairs_has_its_test() {
    let Some(root) = sv_testdata::shared_decks("mcnp-openmc") else {
        return;
    };
    let pairs = pairs(&root);
    assert!(pairs.len() >= 60, "only {} pairs found", pairs.len());
    for (case, _, _) in &pairs {
        assert!(
            BENCHMARK_FOLDERS
                .iter()
                .any(|folder| case.starts_with(&format!("{folder}/"))),
            "{case} has no test: add its benchmark to benchmark_tests!"
        );
    }
}

#[test]
fn a_pair_swapped_gives_the_same_verdict_and_volumes() {
    let Some(root) = sv_testdata::shared_decks("mcnp-openmc") else {
        return;
    };
    let case = root.join("icsbep/leu-sol-therm-002");
    let ab = run(
        &case.join("mcnp/case-3/input"),
        &case.join("openmc/case-3"),
        None,
    );
    let ba = run(
        &case.join("openmc/case-3"),
        &case.join("mcnp/case-3/input"),
        None,
    );
    assert!(!ab.agree && !ba.agree);
    assert!((ab.differ_volume[0] - ba.differ_volume[0]).abs() <= 1e-9 * ab.differ_volume[0]);
    // The solution sphere is 1.3 % larger in OpenMC: both volumes are
    // measured, within a few standard errors of the closed forms.
    let solution = |r: &DiffReport, from_a: bool| {
        let class = r
            .classes
            .iter()
            .find(|c| c.in_a.starts_with(if from_a { "m1 " } else { "Uranium" }))
            .expect("the solution is matched");
        (class.volume_a, class.volume_b)
    };
    let (mcnp, openmc) = solution(&ab, true);
    let cap = |radius: f64| {
        // The sphere below the plane z = 16.7413.
        let h = radius - 16.7413;
        4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
            - std::f64::consts::PI * h * h * (3.0 * radius - h) / 3.0
    };
    for (measured, radius) in [(mcnp, 34.4995), (openmc, 34.6710)] {
        let exact = cap(radius);
        assert!(
            (measured[0] - exact).abs() < 4.0 * measured[1] + 1e-3 * exact,
            "{measured:?} against {exact}"
        );
    }
}
