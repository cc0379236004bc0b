//! Mutated and arbitrary inputs never panic; limits keep large inputs cheap.

use super::*;

/// Every input of the data sets, and a numbered one, for mutation.
fn corpus() -> Vec<String> {
    let mut texts = vec![
        geo("SPH a 0 0 0 1", "r 5 +a -(+a | -a)"),
        super::fixed::MANUAL_EXAMPLE.to_string(),
    ];
    let Some(dir) = data_dir() else {
        return texts;
    };
    let field = sv_testdata::shared_decks("fluka/field").unwrap();
    let mut names: Vec<_> = [dir, field.clone(), field.join("cosmic_atm")]
        .iter()
        .flat_map(|d| std::fs::read_dir(d).unwrap().map(|e| e.unwrap().path()))
        .filter(|p| p.is_file() && !p.ends_with("README.md"))
        .collect();
    names.sort();
    texts.extend(names.iter().map(|p| std::fs::read_to_string(p).unwrap()));
    texts
}

#[derive(Clone, Debug)]
enum Edit {
    Insert(usize, String),
    Delete(usize, usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    let snippet = prop_oneof![
        Just("(".to_string()),
        Just(")".to_string()),
        Just("-(".to_string()),
        Just("|".to_string()),
        Just("\n".to_string()),
        Just("#if X\n".to_string()),
        Just("#endif\n".to_string()),
        Just("#include 904_preprocessor_include.inp\n".to_string()),
        Just("$start_transform -x\n".to_string()),
        Just("$end_expansion\n".to_string()),
        Just("END\n".to_string()),
        Just("GEOEND\n".to_string()),
        Just("1e308 ".to_string()),
        Just("é".to_string()),
        "[ -~]{0,8}",
    ];
    prop_oneof![
        (any::<usize>(), snippet).prop_map(|(p, s)| Edit::Insert(p, s)),
        (any::<usize>(), 0usize..40).prop_map(|(p, n)| Edit::Delete(p, n)),
        any::<usize>().prop_map(Edit::DuplicateLine),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Edit::SwapLines(a, b)),
    ]
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for e in edits {
        match e {
            Edit::Insert(p, s) => {
                let at = p % (chars.len() + 1);
                chars.splice(at..at, s.chars());
            }
            Edit::Delete(p, n) => {
                let at = p % (chars.len() + 1);
                let end = (at + n).min(chars.len());
                chars.drain(at..end);
            }
            Edit::DuplicateLine(i) | Edit::SwapLines(i, _) => {
                let s: String = chars.iter().collect();
                let mut lines: Vec<&str> = s.split('\n').collect();
                let a = i % lines.len();
                if let Edit::SwapLines(_, j) = e {
                    let b = j % lines.len();
                    lines.swap(a, b);
                } else {
                    lines.insert(a, lines[a]);
                }
                chars = lines.join("\n").chars().collect();
            }
        }
    }
    chars.into_iter().collect()
}

proptest! {
    // 400 cases by default; PROPTEST_CASES=N runs more.
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(400),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn mutated_inputs_never_panic(pick in any::<usize>(), edits in prop::collection::vec(edit(), 1..8)) {
        let corpus = corpus();
        let text = apply(&corpus[pick % corpus.len()], &edits);
        // Named inside the data folder so #include resolves against it.
        let name = data_dir().map_or_else(|| "mutated.inp".into(), |d| d.join("mutated.inp").display().to_string());
        let result = fluka::read(&SourceFile::new(name, text), &LoadOptions::default());
        if let Err(d) = result {
            prop_assert!(d.has_errors());
            for e in &d.items {
                let _ = e.render_plain();
            }
        }
    }

    #[test]
    fn arbitrary_geometry_text_never_panics(text in "([ -~\t]{0,30}\n){0,30}") {
        let input = format!("GEOBEGIN                                                              COMBNAME\n{text}");
        let _ = read_text(&input);
        let _ = read_text(&format!("{input}\nEND\nr 5 +a\nEND\nGEOEND\n"));
    }

    #[test]
    fn arbitrary_numbered_geometry_never_panics(text in "(( {0,4}[A-Z0-9+ORD.-]{0,12}){0,8}\n){0,20}") {
        let input = format!("GEOBEGIN                                                              COMBINAT\n    0  -10\n{text}");
        let _ = read_text(&input);
        let _ = read_text(&format!("{input}\n  END\n  R1     5     +1\n  END\nGEOEND\n"));
    }
}

#[test]
fn errors_past_the_limit_are_counted() {
    let bodies: String = (0..150).map(|i| format!("SHP s{i} 0 0 0 1\n")).collect();
    let e = read_text(&geo(&bodies, "r 5 +s0")).unwrap_err();
    assert_eq!(e.items.len(), fluka::MAX_ERRORS + 1);
    assert_eq!(e.items.last().unwrap().message, "… and 50 more errors");
    assert_eq!(e.error_count(), 150);
    assert!(e
        .report(sv_formats::Style::Plain, None)
        .ends_with("\n150 errors found\n"));
}

#[test]
fn values_driven_out_of_range_by_directives_are_errors() {
    let text = geo(
        "$start_expansion 1e100\nSPH big 0 0 0 1e300\n$end_expansion",
        "r 5 +big",
    );
    assert_eq!(
        errors(&text),
        [(
            6,
            1,
            "body `big` has a value out of range after its transformation".to_string()
        )]
    );
    let text = geo(
        "$start_expansion 1e200\n$start_expansion 1e200\nSPH big 0 0 0 1\n$end_expansion\n$end_expansion",
        "r 5 +big",
    );
    assert_eq!(
        errors(&text),
        [(
            7,
            1,
            "the directives around body `big` make a transformation out of range".to_string()
        )]
    );
}

#[test]
fn free_format_cards_after_free() {
    let text = "FREE\nTITLE\nfree cards\nGEOBEGIN COMBNAME\n0 0 geometry\nSPH a 0 0 0 1\nRPP w -2 2 -2 2 -2 2\nEND\nvoid 5 +w -a\nball 5 +a\nEND\nGEOEND\nASSIGNMA BLCKHOLE void\nASSIGNMA LEAD ball\nROT-DEFI 100 0 90 0 0 0 unused\n";
    let l = read_text(text).unwrap();
    assert_eq!(l.scene.title, "free cards");
    assert!(l.scene.regions[0].transparent);
    assert_eq!(l.scene.regions[1].description, "material: LEAD");
}

#[test]
fn lattice_ranges_cover_every_region_between() {
    let text = geo(
        "SPH a 0 0 0 1\nSPH b 0 0 0 2\nSPH c 0 0 0 3",
        "r1 5 +a\nr2 5 +b -a\nr3 5 +c -b",
    )
    .replace("END\nGEOEND", "END\nLATTICE   , r1, r3, , , , , t\nGEOEND");
    let l = read_text(&text).unwrap();
    // No ROT-DEFI `t`: the cells are left empty, with FLUKA's rule in the hint.
    assert!(l.scene.geometry.regions.iter().all(|r| r.fill.is_none()));
    assert_eq!(
        l.warnings[0].message,
        "LATTICE transformation `t` has no ROT-DEFI card"
    );
    assert!(l.warnings[0].hint.as_deref().unwrap().contains(
        "bringing any point of the lattice cell to the corresponding point of the basic unit"
    ));
    let defined = format!("{text}ROT-DEFI  , 0, 0, 0, 10, 0, 0, t\n");
    let l = read_text(&defined).unwrap();
    let filled: Vec<&str> = l
        .scene
        .geometry
        .regions
        .iter()
        .filter(|r| r.fill.is_some())
        .map(|r| r.name.as_str())
        .collect();
    assert_eq!(filled, ["r1", "r2", "r3"]);
}

#[test]
fn large_inputs_stay_cheap() {
    // 20 000 bodies, regions and ASSIGNMA ranges, and 20 000 references to
    // missing bodies (only the first errors are kept, without hints).
    let n = 20_000;
    let bodies: String = (0..n)
        .map(|i| format!("SPH b{i} 0 0 0 {}\n", i + 1))
        .collect();
    let regions: String = (0..n)
        .map(|i| format!("r{i} 5 +b{i} -missing{i}\n"))
        .collect();
    let mut text = geo(&bodies, &regions);
    for _ in 0..100 {
        text.push_str(&format!("ASSIGNMA  , LEAD, r0, r{}\n", n - 1));
    }
    let e = read_text(&text).unwrap_err();
    assert_eq!(e.items.len(), fluka::MAX_ERRORS + 1);
    assert_eq!(e.items[0].hint, None);
    let fine: String = (0..n).map(|i| format!("r{i} 5 +b{i}\n")).collect();
    let mut text = geo(&bodies, &fine);
    for _ in 0..100 {
        text.push_str(&format!("ASSIGNMA  , LEAD, r0, r{}\n", n - 1));
    }
    let l = read_text(&text).unwrap();
    assert_eq!(l.scene.geometry.regions.len(), n);
    assert!(l
        .scene
        .regions
        .iter()
        .all(|p| p.description == "material: LEAD"));
}
