//! Random mutations of the real inputs, and arbitrary text, never make the
//! reader panic; its limits keep deep and large inputs cheap.

use super::*;
use proptest::prelude::*;
use sv_formats::mcnp::{MAX_DEPTH, MAX_ERRORS};

/// The real inputs and a few hand-made ones using what they do not, read
/// once.
fn corpus() -> &'static [String] {
    static CORPUS: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    CORPUS.get_or_init(read_corpus)
}

fn read_corpus() -> Vec<String> {
    let mut texts: Vec<String> = decks::inputs()
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    texts.push(deck(
        "1 0 -1 fill=5 (1 0 0)\n2 0 1 imp:n=0\n3 0 -3 u=5 lat=2 fill=-1:1 -1:1 0:0 7 2R 7(2) 5 7 3J 7\n4 like 5 but trcl=2\n5 1 -1 -4.1 #(4.2:-4.3) u=7\n6 0 #5 u=7",
        "1 rpp -5 5 -5 5 -5 5\n3 rhp 0 0 -1 0 0 2 1 0 0\n*4 2 trc 0 0 0 0 0 1 0.5 0.2\n+7 k/z 0 0 0 1 -1",
        "*tr2 1 0 0 30 60 90 120 30 90 90 90 0\nm1 92235.80c 1 nlib=80c",
    ));
    texts
}

/// Pieces of MCNP syntax the mutations splice in.
const PIECES: [&str; 24] = [
    "(",
    ")",
    "#",
    ":",
    " &\n",
    "\n     ",
    "\t",
    "\n\n",
    "$ ",
    "c ",
    "lat=2 ",
    "lat=1 ",
    "fill=-1:1 0:0 0:0 1 2 3 ",
    "like 1 but ",
    "trcl=(1 0 0 0 1 0) ",
    "*",
    "read file=x\n",
    "1e308 ",
    "99999999 ",
    "2r ",
    "3j ",
    ".9 ",
    "u=1 ",
    "é",
];

/// Apply each cut `(place, kind, amount)` in turn: remove up to 30
/// characters, splice in a piece of syntax, copy a line elsewhere, or
/// overwrite one character.
fn mutate(text: &str, cuts: &[(usize, u8, usize)]) -> String {
    let mut s: Vec<char> = text.chars().collect();
    for &(place, kind, amount) in cuts {
        let at = place % (s.len() + 1);
        match kind % 4 {
            0 => {
                let end = (at + amount % 30).min(s.len());
                s.drain(at..end);
            }
            1 => {
                let piece = PIECES[amount % PIECES.len()];
                s.splice(at..at, piece.chars());
            }
            2 => {
                let start = s[..at]
                    .iter()
                    .rposition(|c| *c == '\n')
                    .map_or(0, |i| i + 1);
                let end = s[at..]
                    .iter()
                    .position(|c| *c == '\n')
                    .map_or(s.len(), |i| at + i);
                let line: Vec<char> = s[start..end].iter().copied().chain(['\n']).collect();
                let to = amount % (s.len() + 1);
                s.splice(to..to, line);
            }
            _ => {
                if let Some(c) = s.get_mut(at) {
                    *c = char::from(b' ' + (amount % 95) as u8);
                }
            }
        }
    }
    s.into_iter().collect()
}

fn never_panics(text: String) -> Result<(), TestCaseError> {
    match read_text(&text) {
        Ok(l) => {
            prop_assert_eq!(l.scene.geometry.regions.len(), l.scene.regions.len());
            for b in &l.scene.geometry.bodies {
                let prepared = sv_geom::prepare(b, &mut Vec::new());
                prop_assert!(
                    prepared.is_ok(),
                    "body {} does not prepare: {:?}",
                    b.name,
                    prepared.err()
                );
            }
        }
        Err(d) => {
            prop_assert!(d.has_errors());
            for e in &d.items {
                let _ = e.render_plain();
            }
        }
    }
    Ok(())
}

/// Cases per property: 400, or `PROPTEST_CASES`.
fn cases() -> u32 {
    let asked = std::env::var("PROPTEST_CASES").ok();
    asked.and_then(|v| v.parse().ok()).unwrap_or(400)
}

proptest! {
    #![proptest_config(ProptestConfig { failure_persistence: None, ..ProptestConfig::with_cases(cases()) })]

    #[test]
    fn mutated_inputs_never_panic(pick in any::<usize>(), cuts in prop::collection::vec((any::<usize>(), any::<u8>(), any::<usize>()), 1..10)) {
        let corpus = corpus();
        never_panics(mutate(&corpus[pick % corpus.len()], &cuts))?;
    }

    #[test]
    fn arbitrary_text_never_panics(text in "([ -~\t]{0,40}\n){0,30}") {
        never_panics(format!("t\n{text}"))?;
        never_panics(deck(&text, "1 so 1\n2 rpp -1 1 -1 1 -1 1", &text))?;
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    // Cell k is what cell k + 1 is not: lowering cell 1 goes down them all.
    let last = MAX_DEPTH + 10;
    let cells: String = (1..last).map(|k| format!("{k} 0 (#{})\n", k + 1)).collect();
    let e = errors(&deck(&format!("{cells}{last} 0 -1"), "1 so 1", ""));
    assert!(e.iter().any(|e| e.2.contains("nests more than")), "{e:?}");
    // Lines of 100 parentheses (MCNP reads 128 columns).
    let open = vec!["(".repeat(100); 3].join("\n     ");
    let close = vec![")".repeat(100); 3].join("\n     ");
    let parens = format!("1 0 {open}\n     -1\n     {close}");
    let e = errors(&deck(&parens, "1 so 1", ""));
    assert_eq!(e[0].2, "parentheses nest more than 200 deep");
}

#[test]
fn large_counts_are_refused_without_allocating() {
    let e = errors(&deck("1 0 -1\n2 0 1", "1 so 1 999999999r", ""));
    assert!(e[0].2.contains("more than"), "{e:?}");
    let lat = "1 0 -1 fill=5\n2 0 1 imp:n=0\n3 0 -2 3 -4 5 u=5 lat=1 fill=-1073741823:1073741823 -1073741823:1073741823 -1073741823:1073741823 5";
    let e = errors(&deck(lat, "1 so 9\n2 px 1\n3 px -1\n4 py 1\n5 py -1", ""));
    assert!(e[0].2.contains("lists 1 elements"), "{e:?}");
    let many: String = (0..3 * MAX_ERRORS)
        .map(|i| format!("{} 0 -{}\n", i + 1, i + 1000))
        .collect();
    let d = read_text(&deck(many.trim_end(), "1 so 1", "")).unwrap_err();
    assert_eq!(d.items.len(), MAX_ERRORS + 1);
}
