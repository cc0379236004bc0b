//! Every OpenMC model of the benchmark set: counts read from its files,
//! its materials, and spot checks of where cells lie.

use super::*;
use sv_formats::{load_file, LoadError, LoadOptions};

/// What a model's files hold, counted in them: cells, surfaces, universes
/// (those cells name, 0 included), cells filled with a lattice, materials,
/// void cells, and the ids of its first and last cells.
struct Counts {
    path: &'static str,
    cells: usize,
    surfaces: usize,
    universes: usize,
    lattice_fills: usize,
    materials: usize,
    void: usize,
    first: &'static str,
    last: &'static str,
}

/// Read a model of the set by its folder; `None` only when the shared
/// decks are skipped.
fn load(path: &str) -> Option<Loaded> {
    let dir = decks_dir()?.join(path);
    match load_file(&dir, &LoadOptions::default()) {
        Ok(l) => Some(l),
        Err(LoadError::Invalid(d)) => panic!("{path}:\n{}", d.render_plain()),
        Err(e) => panic!("{path}: {e}"),
    }
}

fn check(want: Counts) -> Option<Loaded> {
    let l = load(want.path)?;
    let s = &l.scene;
    let g = &s.geometry;
    let lattice_fills = g
        .regions
        .iter()
        .filter(|r| matches!(r.fill, Some(Fill::Lattice(_))))
        .count();
    let void = s.regions.iter().filter(|p| p.air != 0).count();
    assert_eq!(
        (
            g.regions.len(),
            g.bodies.len(),
            g.universes.len(),
            lattice_fills,
            s.materials.len(),
            void
        ),
        (
            want.cells,
            want.surfaces,
            want.universes,
            want.lattice_fills,
            want.materials,
            want.void
        ),
        "{}: cells, surfaces, universes, lattice fills, materials, void cells",
        want.path
    );
    assert_eq!(g.regions[0].name, want.first);
    assert_eq!(g.regions[g.regions.len() - 1].name, want.last);
    assert_eq!(s.units, sv_scene::Units::Centimetre);
    assert_eq!(l.format, sv_formats::Format::OpenMc);
    assert_eq!(
        g.universes[0].name, "0",
        "{}: the root is universe 0",
        want.path
    );
    for (r, p) in g.regions.iter().zip(&s.regions) {
        assert!(
            !p.outside,
            "{}: cell {} is not beyond a vacuum boundary",
            want.path, r.name
        );
        match (&r.fill, p.air != 0) {
            (Some(_), _) => assert_eq!(p.material_index, None),
            (None, true) => assert_eq!(p.material_name, None),
            (None, false) => {
                let i = p
                    .material_index
                    .unwrap_or_else(|| panic!("{}: cell {} has no material", want.path, r.name));
                assert_eq!(
                    p.material_name.as_deref(),
                    Some(s.materials[i].name.as_str())
                );
                assert!(p.density.is_some() || p.atom_density.is_some());
                assert!(!s.materials[i].components.is_empty());
            }
        }
    }
    Some(l)
}

macro_rules! models {
    ($($name:ident: $path:literal, cells $cells:literal, surfaces $surfaces:literal, universes $universes:literal,
       lattice_fills $lattice_fills:literal, materials $materials:literal, void $void:literal,
       first $first:literal, last $last:literal;)*) => {
        $(
            #[test]
            fn $name() {
                check(Counts {
                    path: $path,
                    cells: $cells,
                    surfaces: $surfaces,
                    universes: $universes,
                    lattice_fills: $lattice_fills,
                    materials: $materials,
                    void: $void,
                    first: $first,
                    last: $last,
                });
            }
        )*

        /// Every model folder of the set.
        const MODELS: &[&str] = &[$($path),*];
    };
}

models! {
    heu_comp_inter_003_case_1: "icsbep/heu-comp-inter-003/openmc/case-1", cells 31, surfaces 28, universes 1, lattice_fills 0, materials 10, void 7, first "1", last "31";
    heu_comp_inter_003_case_2: "icsbep/heu-comp-inter-003/openmc/case-2", cells 36, surfaces 32, universes 1, lattice_fills 0, materials 11, void 7, first "1", last "36";
    heu_comp_inter_003_case_3: "icsbep/heu-comp-inter-003/openmc/case-3", cells 36, surfaces 32, universes 1, lattice_fills 0, materials 11, void 7, first "1", last "36";
    heu_comp_inter_003_case_4: "icsbep/heu-comp-inter-003/openmc/case-4", cells 36, surfaces 32, universes 1, lattice_fills 0, materials 11, void 7, first "1", last "36";
    heu_comp_inter_003_case_5: "icsbep/heu-comp-inter-003/openmc/case-5", cells 31, surfaces 28, universes 1, lattice_fills 0, materials 9, void 7, first "1", last "31";
    heu_comp_inter_003_case_6: "icsbep/heu-comp-inter-003/openmc/case-6", cells 31, surfaces 28, universes 1, lattice_fills 0, materials 8, void 7, first "1", last "31";
    heu_comp_inter_003_case_7: "icsbep/heu-comp-inter-003/openmc/case-7", cells 37, surfaces 32, universes 1, lattice_fills 0, materials 11, void 8, first "1", last "37";
    heu_met_fast_003_case_1: "icsbep/heu-met-fast-003/openmc/case-1", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_10: "icsbep/heu-met-fast-003/openmc/case-10", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_11: "icsbep/heu-met-fast-003/openmc/case-11", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_12: "icsbep/heu-met-fast-003/openmc/case-12", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_2: "icsbep/heu-met-fast-003/openmc/case-2", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_3: "icsbep/heu-met-fast-003/openmc/case-3", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_4: "icsbep/heu-met-fast-003/openmc/case-4", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_5: "icsbep/heu-met-fast-003/openmc/case-5", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_6: "icsbep/heu-met-fast-003/openmc/case-6", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_7: "icsbep/heu-met-fast-003/openmc/case-7", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_8: "icsbep/heu-met-fast-003/openmc/case-8", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_003_case_9: "icsbep/heu-met-fast-003/openmc/case-9", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    heu_met_fast_008: "icsbep/heu-met-fast-008/openmc", cells 21, surfaces 20, universes 1, lattice_fills 0, materials 4, void 14, first "1", last "21";
    heu_met_fast_011: "icsbep/heu-met-fast-011/openmc", cells 10, surfaces 10, universes 1, lattice_fills 0, materials 3, void 6, first "1", last "10";
    heu_met_fast_013: "icsbep/heu-met-fast-013/openmc", cells 17, surfaces 18, universes 1, lattice_fills 0, materials 4, void 9, first "1", last "17";
    heu_met_fast_015: "icsbep/heu-met-fast-015/openmc", cells 11, surfaces 12, universes 1, lattice_fills 0, materials 3, void 6, first "1", last "11";
    heu_met_fast_019_case_1: "icsbep/heu-met-fast-019/openmc/case-1", cells 9, surfaces 9, universes 1, lattice_fills 0, materials 8, void 1, first "1", last "9";
    heu_met_fast_019_case_2: "icsbep/heu-met-fast-019/openmc/case-2", cells 3, surfaces 3, universes 1, lattice_fills 0, materials 2, void 1, first "1", last "3";
    heu_met_fast_021_case_2: "icsbep/heu-met-fast-021/openmc/case-2", cells 4, surfaces 4, universes 1, lattice_fills 0, materials 3, void 1, first "1", last "4";
    heu_met_inter_006_case_1: "icsbep/heu-met-inter-006/openmc/case-1", cells 52, surfaces 52, universes 1, lattice_fills 0, materials 4, void 10, first "1", last "52";
    heu_met_inter_006_case_2: "icsbep/heu-met-inter-006/openmc/case-2", cells 46, surfaces 49, universes 1, lattice_fills 0, materials 4, void 10, first "1", last "46";
    heu_met_inter_006_case_3: "icsbep/heu-met-inter-006/openmc/case-3", cells 45, surfaces 50, universes 1, lattice_fills 0, materials 4, void 9, first "1", last "45";
    heu_met_inter_006_case_4: "icsbep/heu-met-inter-006/openmc/case-4", cells 45, surfaces 50, universes 1, lattice_fills 0, materials 4, void 9, first "1", last "45";
    heu_sol_therm_032: "icsbep/heu-sol-therm-032/openmc", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    ieu_met_fast_002: "icsbep/ieu-met-fast-002/openmc", cells 4, surfaces 6, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "4";
    ieu_met_fast_004_case_2: "icsbep/ieu-met-fast-004/openmc/case-2", cells 3, surfaces 3, universes 1, lattice_fills 0, materials 2, void 1, first "1", last "3";
    ieu_met_fast_006_case_2: "icsbep/ieu-met-fast-006/openmc/case-2", cells 4, surfaces 4, universes 1, lattice_fills 0, materials 3, void 1, first "1", last "4";
    leu_comp_therm_008_case_1: "icsbep/leu-comp-therm-008/openmc/case-1", cells 29, surfaces 11, universes 26, lattice_fills 23, materials 3, void 0, first "111", last "1111";
    leu_comp_therm_008_case_11: "icsbep/leu-comp-therm-008/openmc/case-11", cells 32, surfaces 11, universes 27, lattice_fills 23, materials 5, void 0, first "111", last "1111";
    leu_comp_therm_008_case_2: "icsbep/leu-comp-therm-008/openmc/case-2", cells 29, surfaces 11, universes 26, lattice_fills 23, materials 3, void 0, first "111", last "1111";
    leu_comp_therm_008_case_5: "icsbep/leu-comp-therm-008/openmc/case-5", cells 31, surfaces 11, universes 27, lattice_fills 23, materials 4, void 0, first "111", last "1111";
    leu_comp_therm_008_case_7: "icsbep/leu-comp-therm-008/openmc/case-7", cells 31, surfaces 11, universes 27, lattice_fills 23, materials 4, void 0, first "111", last "1111";
    leu_comp_therm_008_case_8: "icsbep/leu-comp-therm-008/openmc/case-8", cells 31, surfaces 11, universes 27, lattice_fills 23, materials 4, void 0, first "111", last "1111";
    leu_sol_therm_002_case_1: "icsbep/leu-sol-therm-002/openmc/case-1", cells 3, surfaces 3, universes 1, lattice_fills 0, materials 3, void 0, first "1", last "3";
    leu_sol_therm_002_case_2: "icsbep/leu-sol-therm-002/openmc/case-2", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    leu_sol_therm_002_case_3: "icsbep/leu-sol-therm-002/openmc/case-3", cells 4, surfaces 4, universes 1, lattice_fills 0, materials 3, void 1, first "1", last "4";
    mix_met_fast_003: "icsbep/mix-met-fast-003/openmc", cells 16, surfaces 18, universes 1, lattice_fills 0, materials 5, void 10, first "1", last "16";
    pu_comp_inter_001: "icsbep/pu-comp-inter-001/openmc", cells 1, surfaces 1, universes 1, lattice_fills 0, materials 1, void 0, first "1", last "1";
    pu_met_fast_002: "icsbep/pu-met-fast-002/openmc", cells 1, surfaces 1, universes 1, lattice_fills 0, materials 1, void 0, first "1", last "1";
    pu_met_fast_003_case_103: "icsbep/pu-met-fast-003/openmc/case-103", cells 41, surfaces 37, universes 2, lattice_fills 1, materials 8, void 15, first "1", last "40";
    pu_met_fast_005: "icsbep/pu-met-fast-005/openmc", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_met_fast_008_case_1: "icsbep/pu-met-fast-008/openmc/case-1", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_met_fast_008_case_2: "icsbep/pu-met-fast-008/openmc/case-2", cells 2, surfaces 4, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_met_fast_010: "icsbep/pu-met-fast-010/openmc", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_met_fast_018: "icsbep/pu-met-fast-018/openmc", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_met_fast_020: "icsbep/pu-met-fast-020/openmc", cells 18, surfaces 19, universes 1, lattice_fills 0, materials 4, void 9, first "1", last "18";
    pu_met_fast_022_case_1: "icsbep/pu-met-fast-022/openmc/case-1", cells 7, surfaces 7, universes 1, lattice_fills 0, materials 6, void 1, first "1", last "7";
    pu_met_fast_022_case_2: "icsbep/pu-met-fast-022/openmc/case-2", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 1, void 1, first "1", last "2";
    pu_met_fast_024_case_1: "icsbep/pu-met-fast-024/openmc/case-1", cells 7, surfaces 7, universes 1, lattice_fills 0, materials 7, void 0, first "1", last "7";
    pu_met_fast_024_case_2: "icsbep/pu-met-fast-024/openmc/case-2", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_met_fast_026_case_1: "icsbep/pu-met-fast-026/openmc/case-1", cells 8, surfaces 8, universes 1, lattice_fills 0, materials 7, void 1, first "1", last "8";
    pu_met_fast_026_case_2: "icsbep/pu-met-fast-026/openmc/case-2", cells 4, surfaces 4, universes 1, lattice_fills 0, materials 3, void 1, first "1", last "4";
    pu_sol_therm_011_case_16_1: "icsbep/pu-sol-therm-011/openmc/case-16-1", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_sol_therm_011_case_16_2: "icsbep/pu-sol-therm-011/openmc/case-16-2", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_sol_therm_011_case_16_3: "icsbep/pu-sol-therm-011/openmc/case-16-3", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_sol_therm_011_case_16_4: "icsbep/pu-sol-therm-011/openmc/case-16-4", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_sol_therm_011_case_16_5: "icsbep/pu-sol-therm-011/openmc/case-16-5", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_sol_therm_011_case_18_1: "icsbep/pu-sol-therm-011/openmc/case-18-1", cells 3, surfaces 3, universes 1, lattice_fills 0, materials 3, void 0, first "1", last "3";
    pu_sol_therm_011_case_18_2: "icsbep/pu-sol-therm-011/openmc/case-18-2", cells 3, surfaces 3, universes 1, lattice_fills 0, materials 3, void 0, first "1", last "3";
    pu_sol_therm_011_case_18_3: "icsbep/pu-sol-therm-011/openmc/case-18-3", cells 3, surfaces 3, universes 1, lattice_fills 0, materials 3, void 0, first "1", last "3";
    pu_sol_therm_011_case_18_4: "icsbep/pu-sol-therm-011/openmc/case-18-4", cells 3, surfaces 3, universes 1, lattice_fills 0, materials 3, void 0, first "1", last "3";
    pu_sol_therm_011_case_18_5: "icsbep/pu-sol-therm-011/openmc/case-18-5", cells 3, surfaces 3, universes 1, lattice_fills 0, materials 3, void 0, first "1", last "3";
    pu_sol_therm_011_case_18_6: "icsbep/pu-sol-therm-011/openmc/case-18-6", cells 3, surfaces 3, universes 1, lattice_fills 0, materials 3, void 0, first "1", last "3";
    pu_sol_therm_011_case_18_7: "icsbep/pu-sol-therm-011/openmc/case-18-7", cells 3, surfaces 3, universes 1, lattice_fills 0, materials 3, void 0, first "1", last "3";
    pu_sol_therm_021_case_1: "icsbep/pu-sol-therm-021/openmc/case-1", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    pu_sol_therm_021_case_3: "icsbep/pu-sol-therm-021/openmc/case-3", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    u233_comp_therm_001_case_3: "icsbep/u233-comp-therm-001/openmc/case-3", cells 81, surfaces 29, universes 8, lattice_fills 1, materials 5, void 7, first "101", last "31";
    u233_met_fast_002_case_1: "icsbep/u233-met-fast-002/openmc/case-1", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    u233_met_fast_002_case_2: "icsbep/u233-met-fast-002/openmc/case-2", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    u233_met_fast_004_case_1: "icsbep/u233-met-fast-004/openmc/case-1", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    u233_met_fast_004_case_2: "icsbep/u233-met-fast-004/openmc/case-2", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    u233_met_fast_006: "icsbep/u233-met-fast-006/openmc", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    u233_sol_therm_001_case_1: "icsbep/u233-sol-therm-001/openmc/case-1", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    u233_sol_therm_001_case_2: "icsbep/u233-sol-therm-001/openmc/case-2", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    u233_sol_therm_001_case_3: "icsbep/u233-sol-therm-001/openmc/case-3", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    u233_sol_therm_001_case_4: "icsbep/u233-sol-therm-001/openmc/case-4", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    u233_sol_therm_001_case_5: "icsbep/u233-sol-therm-001/openmc/case-5", cells 2, surfaces 2, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    indc_usa_107_problem1: "indc-usa-107/openmc/problem1", cells 2, surfaces 5, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    indc_usa_107_problem2: "indc-usa-107/openmc/problem2", cells 2, surfaces 5, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
    indc_usa_107_problem3: "indc-usa-107/openmc/problem3", cells 2, surfaces 5, universes 1, lattice_fills 0, materials 2, void 0, first "1", last "2";
}

#[test]
fn every_model_folder_of_the_set_is_tested() {
    let Some(root) = decks_dir() else { return };
    let mut found = Vec::new();
    let mut stack = vec![root.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.file_name().is_some_and(|n| n == "geometry.xml") {
                let folder = path.parent().unwrap().strip_prefix(&root).unwrap();
                found.push(folder.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    found.sort();
    let mut listed: Vec<String> = MODELS.iter().map(|m| m.to_string()).collect();
    listed.sort();
    assert_eq!(found, listed);
}

#[test]
fn a_folder_with_only_the_script_that_writes_the_xml_is_refused() {
    let Some(root) = decks_dir() else { return };
    let Err(LoadError::Invalid(d)) =
        load_file(&root.join("mc-performance/openmc"), &LoadOptions::default())
    else {
        panic!("mc-performance ships only build.py");
    };
    let e = &d.items[0];
    assert!(e.source.name.ends_with("build.py"), "{}", e.source.name);
    assert!(e
        .message
        .starts_with("build.py is a Python script that writes the OpenMC model"));
    assert!(e
        .message
        .ends_with("its XML has to be generated by running it"));
    // The line that writes the XML.
    let (line, _) = e.line_col();
    let text = std::fs::read_to_string(root.join("mc-performance/openmc/build.py")).unwrap();
    assert!(text
        .lines()
        .nth(line - 1)
        .unwrap()
        .contains("export_to_xml"));
    // A folder whose models are in its subfolders says where they are.
    let Err(LoadError::Io { source, .. }) =
        load_file(&root.join("indc-usa-107/openmc"), &LoadOptions::default())
    else {
        panic!("indc-usa-107/openmc holds folders of models");
    };
    assert_eq!(
        source.to_string(),
        "it holds no geometry.xml or model.xml; the models are in its folders problem1, problem2, problem3"
    );
}

#[test]
fn pu_met_fast_003_stacks_its_buttons_in_a_three_by_three_lattice() {
    let Some(l) = load("icsbep/pu-met-fast-003/openmc/case-103") else {
        return;
    };
    assert_eq!(l.scene.title, "3x3x3 Pu Buttons (PU-MET-FAST-003 Case 103)");
    let lat = lattice(&l, "36");
    assert_eq!(lat.counts, [3, 3, 1]);
    assert!(close(
        lat.base,
        DVec3::new(-14.4, -14.4, -openmc::UNBOUNDED)
    ));
    assert!(close(lat.origin, DVec3::new(-9.6, -9.6, 0.0)));
    assert!(lat.elements.iter().all(|e| *e == Some(1)));
    // A button at the centre of every element, the table below, voids
    // around the tubes.
    for (x, y) in [(0.0, 0.0), (9.6, 9.6), (-9.6, 0.0)] {
        assert_eq!(
            cells_at(&l, DVec3::new(x, y, 17.0)),
            ["36", "11"],
            "({x}, {y})"
        );
        assert_eq!(
            cells_at(&l, DVec3::new(x, y, 33.0)),
            ["36", "31"],
            "({x}, {y})"
        );
    }
    assert_eq!(cells_at(&l, DVec3::new(4.0, 0.0, 17.0)), ["36", "80"]);
    assert_eq!(cells_at(&l, DVec3::new(0.0, 0.0, -10.0)), ["1"]);
    assert_eq!(cells_at(&l, DVec3::new(20.0, 0.0, 10.0)), ["39"]);
    let button = &l.scene.regions[l.scene.geometry.region_index("11").unwrap()];
    assert_eq!(button.material, 1);
}

#[test]
fn leu_comp_therm_008_places_assemblies_and_pins_from_the_top_row() {
    let Some(l) = load("icsbep/leu-comp-therm-008/openmc/case-1") else {
        return;
    };
    // Core lattice 99, row 2 from the top, column 3: assembly 230 (lattice
    // 23), whose top left pins are water and bottom right ones fuel.
    let (cx, cy) = (-85.8774 + 2.5 * 24.5364, -85.8774 + 5.5 * 24.5364);
    let corner = 12.2682 - 1.63576 / 2.0;
    assert_eq!(
        cells_at(&l, DVec3::new(cx - corner, cy + corner, 0.0)),
        ["1111", "230", "11"]
    );
    assert_eq!(
        cells_at(&l, DVec3::new(cx + corner, cy - corner, 0.0)),
        ["1111", "230", "21"]
    );
    assert_eq!(
        cells_at(&l, DVec3::new(cx + corner + 0.55, cy - corner, 0.0)),
        ["1111", "230", "22"]
    );
    // The centre of the core is assembly 111 (lattice 11).
    assert_eq!(
        cells_at(&l, DVec3::new(0.0, 0.0, 0.0))[..2],
        ["1111", "111"]
    );
    let core = lattice(&l, "1111");
    assert_eq!(core.counts, [7, 7, 1]);
    assert_eq!(l.scene.geometry.universes.len(), 26);
}

#[test]
fn u233_comp_therm_001_puts_its_control_blades_where_the_rows_say() {
    let Some(l) = load("icsbep/u233-comp-therm-001/openmc/case-3") else {
        return;
    };
    // Row 2 from the top (iy = 14), column 5: universe 4, blade at the
    // lower right above z = 16.05.
    let pitch = 0.91948;
    let (x, y) = (-8.27532 + 4.5 * pitch, -7.35584 + 14.5 * pitch);
    assert_eq!(cells_at(&l, DVec3::new(x, y, 0.0)), ["11", "401"]);
    assert_eq!(
        cells_at(&l, DVec3::new(x + 0.42, y - 0.42, 17.0)),
        ["11", "409"]
    );
    assert_eq!(
        cells_at(&l, DVec3::new(x - 0.42, y + 0.42, 17.0)),
        ["11", "407"]
    );
    assert_eq!(cells_at(&l, DVec3::new(x, y, 22.0)), ["11", "403"]);
}

#[test]
fn pu_met_fast_002_reads_surface_values_written_as_elements() {
    let Some(l) = load("icsbep/pu-met-fast-002/openmc") else {
        return;
    };
    let b = &l.scene.geometry.bodies[0];
    assert_eq!(
        (b.kind, b.params.clone()),
        (sv_geom::BodyKind::Sph, vec![0.0, 0.0, 0.0, 6.6595])
    );
    assert_eq!(cells_at(&l, DVec3::new(0.0, 0.0, 6.6)), ["1"]);
    assert!(cells_at(&l, DVec3::new(0.0, 0.0, 6.7)).is_empty());
    let m = &l.scene.materials[0];
    assert!(m.components.iter().any(|c| c.zam == (94, 240, 0)));
}

#[test]
fn heu_met_fast_008_reads_its_y_cylinders() {
    let Some(l) = load("icsbep/heu-met-fast-008/openmc") else {
        return;
    };
    let b = &l.scene.geometry.bodies[l.scene.geometry.body_index("8").unwrap()];
    // y-cylinder x0 = 0, z0 = 1.207: YCC's centre is written z, x.
    assert_eq!(
        (b.kind, b.params.clone()),
        (sv_geom::BodyKind::Ycc, vec![1.207, 0.0, 0.6])
    );
    assert_eq!(cells_at(&l, DVec3::new(0.0, 9.0, 1.5)), ["8"]);
}
