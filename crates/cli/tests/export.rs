//! `synthavision export`: POV-Ray and native output, errors exit 2.

use std::path::PathBuf;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_synthavision"))
}

fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sv-export-test-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

#[test]
fn exports_pov_with_the_renderers_camera_and_light() {
    let out = tmp("fig1.pov");
    let st = bin()
        .arg("export")
        .arg(examples().join("figure1/figure1.sv"))
        .args(["--format", "pov", "--no-shadows", "-o"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(st.success());
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("#version 3.7;"), "{text}");
    assert!(text.contains("location <0, 4, -15>"), "{text}");
    assert!(text.contains("shadowless"), "{text}");
    assert_eq!(text.matches("// region ").count(), 5, "{text}");
}

#[test]
fn a_scene_without_camera_or_light_gets_the_default_framing() {
    let src = tmp("bare.sv");
    std::fs::write(&src, "BODY 1 SPH (0,0,0) 1\nREGION A = +1\n").unwrap();
    let out = tmp("bare.pov");
    let st = bin()
        .arg("export")
        .arg(&src)
        .args(["--format", "pov", "-o"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(st.success());
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("camera {"), "{text}");
    assert!(text.contains("light_source {"), "{text}");
}

#[test]
fn exports_the_scene_language_and_it_reads_back() {
    let out = tmp("heli.sv");
    let st = bin()
        .arg("export")
        .arg(examples().join("helicopter/helicopter.sv"))
        .args(["--format", "sv", "-o"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(st.success());
    let info = bin().arg("info").arg(&out).output().unwrap();
    assert!(info.status.success());
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(text.contains("regions: 24"), "{text}");
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let src = tmp("bad.sv");
    std::fs::write(&src, "BODY 1 SPH (0,0,0) -1\nREGION A = +1\n").unwrap();
    let out = tmp("bad.pov");
    let o = bin()
        .arg("export")
        .arg(&src)
        .args(["--format", "pov", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!out.exists());
    let o = bin()
        .arg("export")
        .arg(examples().join("figure1/figure1.sv"))
        .args(["--format", "obj", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(!out.exists());
}
