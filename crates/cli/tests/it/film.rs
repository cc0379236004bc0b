//! `synthavision film` end to end: a short script, a full run, a range
//! rendered on its own, and a resumed run.

use crate::{examples, sv};

const SCRIPT: &str = r#"# A sphere-and-cylinder region flies past and turns.
SCENE "SCENE_PATH"
FPS 12
SIZE 64 48
OBJECT D REGIONS D
AXIS 1 POINT (0,0,0) DIR (0,0,1) ON D
SHOOT
TOGETHER
  MOVE D (2,0,1) OVER 6 FRAMES
  TURN D (AXIS 1, 90) OVER 6 FRAMES
END
HOLD 3
"#;

#[test]
fn a_range_alone_equals_the_full_run_and_reruns_resume() {
    let dir = tempfile::tempdir().unwrap();
    let scene = examples().join("figure1/figure1.sv");
    let script = dir.path().join("f.svs");
    std::fs::write(
        &script,
        SCRIPT.replace("SCENE_PATH", scene.to_str().unwrap()),
    )
    .unwrap();
    let full = dir.path().join("full");
    let o = sv(&[
        "film",
        script.to_str().unwrap(),
        "-o",
        full.to_str().unwrap(),
        "--no-mp4",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        out.starts_with("10 frames rendered, 0 already done"),
        "{out}"
    );
    assert!(full.join("film.gif").is_file() && full.join("contact.png").is_file());
    // Frame 4 alone, in another folder, is the same file byte for byte.
    let part = dir.path().join("part");
    let o = sv(&[
        "film",
        script.to_str().unwrap(),
        "-o",
        part.to_str().unwrap(),
        "--frames",
        "4..5",
        "--no-mp4",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let a = std::fs::read(full.join("frame_000004.png")).unwrap();
    let b = std::fs::read(part.join("frame_000004.png")).unwrap();
    assert_eq!(
        a, b,
        "frame 4 rendered alone differs from frame 4 of the full run"
    );
    // The moving region really moves: frames 0 and 6 differ.
    assert_ne!(
        std::fs::read(full.join("frame_000000.png")).unwrap(),
        std::fs::read(full.join("frame_000006.png")).unwrap()
    );
    // A second run finds everything done and renders nothing.
    let o = sv(&[
        "film",
        script.to_str().unwrap(),
        "-o",
        full.to_str().unwrap(),
        "--no-mp4",
    ]);
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("0 frames rendered, 10 already done"));
}

#[test]
fn a_script_with_errors_renders_nothing_and_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let scene = examples().join("figure1/figure1.sv");
    let script = dir.path().join("bad.svs");
    std::fs::write(
        &script,
        format!(
            "SCENE \"{}\"\nOBJECT D REGIONS D\nMOVE HELICOPTER (3,0,-1)\nSHOOT\n",
            scene.display()
        ),
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = sv(&[
        "film",
        script.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("HELICOPTER"), "{err}");
    assert!(
        err.ends_with("\n1 error found; no frame was rendered\n"),
        "{err}"
    );
    assert!(
        !out.exists() || std::fs::read_dir(&out).unwrap().count() == 0,
        "no frame may be written"
    );
}
