//! Mutated real decks never panic.

use super::*;

#[derive(Clone, Debug)]
enum Mutation {
    Flip(usize, u8),
    DeleteLine(usize),
    DuplicateLine(usize),
    Truncate(usize),
    InsertLine(usize, String),
}

fn mutate(text: &str, muts: &[Mutation]) -> String {
    let mut bytes = text.as_bytes().to_vec();
    for m in muts {
        let lines = |b: &[u8]| {
            b.split(|&c| c == b'\n')
                .map(<[u8]>::to_vec)
                .collect::<Vec<_>>()
        };
        match m {
            Mutation::Flip(i, v) if !bytes.is_empty() => {
                let n = bytes.len();
                bytes[i % n] = *v;
            }
            Mutation::DeleteLine(i) => {
                let mut l = lines(&bytes);
                let n = l.len();
                l.remove(i % n);
                bytes = l.join(&b'\n');
            }
            Mutation::DuplicateLine(i) => {
                let mut l = lines(&bytes);
                let n = l.len();
                let dup = l[i % n].clone();
                l.insert(i % n, dup);
                bytes = l.join(&b'\n');
            }
            Mutation::Truncate(i) => {
                let n = bytes.len().max(1);
                bytes.truncate(i % n);
            }
            Mutation::InsertLine(i, s) => {
                let mut l = lines(&bytes);
                let n = l.len();
                l.insert(i % (n + 1), s.clone().into_bytes());
                bytes = l.join(&b'\n');
            }
            _ => {}
        }
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let nasty = prop_oneof![
        Just("    1ARS  1000000000 999999999".to_string()),
        Just("    6ars           3    100000".to_string()),
        Just("    1      G    1 G    1 G   -1".to_string()),
        Just("   -1".to_string()),
        Just("  end".to_string()),
        Just("99999999999999999999 -9".to_string()),
        "[ -~]{0,90}",
        "\\PC{0,40}",
    ];
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, v)| Mutation::Flip(i, v)),
        any::<usize>().prop_map(Mutation::DeleteLine),
        any::<usize>().prop_map(Mutation::DuplicateLine),
        any::<usize>().prop_map(Mutation::Truncate),
        (any::<usize>(), nasty).prop_map(|(i, s)| Mutation::InsertLine(i, s)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn mutated_real_decks_never_panic(deck in 0usize..3, muts in proptest::collection::vec(mutation(), 1..8), version in 0usize..4) {
        let name = [VDECK, GIFT, GENERATOR][deck];
        let Some(text) = deck_text(name) else { return Ok(()) };
        let text = mutate(&text, &muts);
        let deck_version = [None, Some(DeckVersion::V1), Some(DeckVersion::V4), Some(DeckVersion::V5)][version];
        let src = SourceFile::new(name, text.as_str());
        match comgeom::read(&src, &LoadOptions { deck_version }) {
            Ok(l) => {
                // Whatever reads must write, and what is written must read.
                if let Ok(w) = comgeom::write(&l.scene) {
                    let again = read_text("again.cg", &w.text);
                    prop_assert!(again.is_ok(), "{}", again.unwrap_err().render_plain());
                }
            }
            Err(d) => {
                prop_assert!(d.has_errors());
                for e in d.items {
                    let _ = e.render_plain();
                }
            }
        }
    }
}
