//! `synthavision export`: POV-Ray and native output, errors exit 2.

use crate::{bin, examples, fresh_dir};

#[test]
fn exports_pov_with_the_renderers_camera_and_light() {
    let out = fresh_dir("export_pov").join("fig1.pov");
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
    let dir = fresh_dir("export_bare");
    let src = dir.join("bare.sv");
    std::fs::write(&src, "BODY 1 SPH (0,0,0) 1\nREGION A = +1\n").unwrap();
    let out = dir.join("bare.pov");
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
    let out = fresh_dir("export_sv").join("heli.sv");
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
    let dir = fresh_dir("export_bad");
    let src = dir.join("bad.sv");
    std::fs::write(&src, "BODY 1 SPH (0,0,0) -1\nREGION A = +1\n").unwrap();
    let out = dir.join("bad.pov");
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
