//! Random option values for every command (NaN, infinities, huge,
//! negative, empty, words): no panic, no abort, exit 0 to 3 only, and
//! nothing written when the run is refused.

use crate::{examples, fresh_dir, sv, write};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use std::path::Path;

/// Values that probe the edges of every kind of option.
fn value() -> impl Strategy<Value = String> {
    let edges = [
        "nan",
        "NaN",
        "inf",
        "-inf",
        "1e400",
        "-1e400",
        "1e308",
        "-1e308",
        "0",
        "-0",
        "-1",
        "1",
        "2",
        "",
        " ",
        "1e-300",
        "18446744073709551616",
        "100000000000",
        "0x0",
        "1x1",
        "8x6",
        "65536x65536",
        "0,0,0",
        "nan,0,0",
        "1,2",
        "x=0",
        "z=nan",
        "0..1",
        "5..2",
        "..",
        "v9",
        "a,b",
        "-",
        "1,1,1,1,1,1",
    ];
    prop_oneof![
        proptest::sample::select(edges.to_vec()).prop_map(str::to_string),
        any::<f64>().prop_map(|x| x.to_string()),
        any::<i64>().prop_map(|x| x.to_string()),
        (-400.0..400.0f64).prop_map(|x| x.to_string()),
        (1..8u32).prop_map(|x| x.to_string()),
        "[a-z0-9,.x=-]{0,10}",
    ]
}

/// A command to run with one of its options given a random value: the
/// arguments before the option, its options, and the file it writes
/// (`None` for commands that only print).
struct Case {
    args: Vec<String>,
    options: &'static [&'static str],
    writes: Option<&'static str>,
}

fn cases(dir: &Path) -> Vec<Case> {
    let scene = examples().join("figure1/figure1.sv");
    let scene = scene.to_str().unwrap().to_string();
    let script = write(
        dir,
        "f.svs",
        &format!("SCENE \"{scene}\"\nFPS 12\nSIZE 8 6\nSHOOT 2\n"),
    );
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let with = |words: &[&str]| words.iter().map(|w| w.to_string()).collect::<Vec<_>>();
    vec![
        Case {
            args: with(&["render", &scene, "--size", "8x6", "-o", &out("r.png")]),
            options: &[
                "--size",
                "--az",
                "--el",
                "--fov",
                "--eye",
                "--up",
                "--view-size",
                "--cut",
                "--threads",
                "--samples",
                "--levels",
                "--background",
                "--aov",
                "--deck-version",
                "--transparent",
            ],
            writes: Some("r.png"),
        },
        Case {
            args: with(&["slice", &scene, "--size", "16x12", "-o", &out("s.png")]),
            options: &[
                "--plane",
                "--origin",
                "--normal",
                "--extent",
                "--size",
                "--tolerance",
            ],
            writes: Some("s.png"),
        },
        Case {
            args: with(&["check", &scene, "--spacing", "0.5"]),
            options: &[
                "--spacing",
                "--random",
                "--box",
                "--seed",
                "--tolerance",
                "--universe",
            ],
            writes: None,
        },
        Case {
            args: with(&[
                "volume",
                &scene,
                "--rel-error",
                "0.3",
                "--max-rays",
                "400000",
            ]),
            options: &["--rel-error", "--max-rays", "--seed", "--threads"],
            writes: None,
        },
        Case {
            args: with(&["shoot", &scene, "--from", "0,-5,0", "--dir", "0,1,0"]),
            options: &["--from", "--dir"],
            writes: None,
        },
        Case {
            args: with(&["info", &scene]),
            options: &["--deck-version", "--transparent-matching"],
            writes: None,
        },
        Case {
            args: with(&[
                "film",
                script.to_str().unwrap(),
                "--no-mp4",
                "--no-gif",
                "-o",
                &out("film"),
            ]),
            options: &["--frames", "--size", "--threads"],
            writes: Some("film"),
        },
        Case {
            args: with(&[
                "bench", &scene, "--size", "8x6", "--repeat", "1", "--warmup", "0",
            ]),
            options: &["--repeat", "--warmup", "--size", "--az"],
            writes: None,
        },
        Case {
            args: with(&["convert", &scene, "-o", &out("c.cg")]),
            options: &["--deck-version", "--transparent"],
            writes: Some("c.cg"),
        },
        Case {
            args: with(&["export", &scene, "--format", "pov", "-o", &out("e.pov")]),
            options: &[
                "--transparent",
                "--az",
                "--el",
                "--fov",
                "--size",
                "--cut",
                "--format",
            ],
            writes: Some("e.pov"),
        },
    ]
}

#[test]
fn random_option_values_never_panic_and_refusals_write_nothing() {
    let dir = fresh_dir("options-random");
    let cases = cases(&dir);
    let config = Config {
        cases: 160,
        failure_persistence: None,
        ..Config::default()
    };
    let strategy = (0..cases.len(), any::<prop::sample::Index>(), value());
    // How many runs ended with each exit code: both work done and
    // refusals must be among them, or the values probe nothing.
    let exits = std::cell::RefCell::new([0usize; 4]);
    TestRunner::new(config)
        .run(&strategy, |(which, option, value)| {
            let case = &cases[which];
            let option = case.options[option.index(case.options.len())];
            if let Some(name) = case.writes {
                let path = dir.join(name);
                let _ = std::fs::remove_file(&path);
                let _ = std::fs::remove_dir_all(&path);
            }
            let mut args: Vec<&str> = case.args.iter().map(String::as_str).collect();
            // An option of the baseline gets the value in its place.
            match args.iter().position(|a| *a == option) {
                Some(at) => args[at + 1] = &value,
                None => args.extend([option, &value]),
            }
            let o = sv(&args);
            let stderr = String::from_utf8_lossy(&o.stderr);
            let code = o.status.code();
            prop_assert!(
                matches!(code, Some(0..=3)),
                "{args:?}: exit {code:?}\n{stderr}"
            );
            prop_assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
            if let Some(code @ 0..=3) = code {
                exits.borrow_mut()[code as usize] += 1;
            }
            if code == Some(2) {
                if let Some(name) = case.writes {
                    prop_assert!(!dir.join(name).exists(), "{args:?} wrote {name}");
                }
            }
            Ok(())
        })
        .unwrap();
    let exits = exits.into_inner();
    assert!(
        exits[0] > 0 && exits[2] > 0,
        "exit codes 0..3 seen {exits:?} times"
    );
}
