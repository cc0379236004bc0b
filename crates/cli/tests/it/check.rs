//! Exit codes and outputs of `check`, `slice`, `volume` and
//! `render --overlaps`, run on the built binary.

use crate::{bin, fresh_dir as dir, run, write};

const OVERLAP: &str =
    "BODY a SPH (0,0,0) 1\nBODY b SPH (1.5,0,0) 1\nREGION A = +a\nREGION B = +b\n";
const CLEAN: &str = "BODY a SPH (0,0,0) 1\nBODY b SPH (3,0,0) 1\nREGION A = +a\nREGION B = +b\n";

#[test]
fn check_exit_status_gates_pipelines() {
    let d = dir("check_exit");
    let bad = write(&d, "bad.sv", OVERLAP);
    let good = write(&d, "good.sv", CLEAN);
    let o = run(bin().arg("check").arg(&bad));
    assert_eq!(o.status.code(), Some(1));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("A × B"), "{out}");
    let o = run(bin().arg("check").arg(&good));
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let o = run(bin().args(["check", "--json"]).arg(&bad));
    assert_eq!(o.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["overlaps"][0]["regions"][1], "B");
}

#[test]
fn bad_input_exits_2() {
    let d = dir("check_bad");
    let good = write(&d, "good.sv", CLEAN);
    let o = run(bin().arg("check").arg(d.join("missing.sv")));
    assert_eq!(o.status.code(), Some(2));
    let o = run(bin().args(["check", "--universe", "nowhere"]).arg(&good));
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("nowhere"));
    let o = run(bin().args(["check", "--spacing", "-1"]).arg(&good));
    assert_eq!(o.status.code(), Some(2));
    for refine in [
        &["--refine-to", "0"][..],
        &["--refine-to", "nan"],
        &["--refine-to", "0.1", "--no-refine"],
    ] {
        let o = run(bin().arg("check").args(refine).arg(&good));
        assert_eq!(o.status.code(), Some(2), "{refine:?}");
    }
    let o = run(bin().args(["volume", "--rel-error", "0"]).arg(&good));
    assert_eq!(o.status.code(), Some(2));
    // A bad plane writes nothing.
    let out = d.join("s.png");
    let o = run(bin()
        .args(["slice", "--plane", "w=3", "-o"])
        .arg(&out)
        .arg(&good));
    assert_eq!(o.status.code(), Some(2));
    assert!(!out.exists());
    let o = run(bin().args(["slice", "-o"]).arg(&out).arg(&good));
    assert_eq!(o.status.code(), Some(2));
    assert!(!out.exists());
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1, "only good.sv");
}

#[test]
fn slice_writes_picture_and_legend() {
    let d = dir("slice_out");
    let bad = write(&d, "bad.sv", OVERLAP);
    let out = d.join("cut.png");
    let o = run(bin()
        .args(["slice", "--plane", "z=0", "--size", "120x60", "-o"])
        .arg(&out)
        .arg(&bad));
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // The legend strip is drawn under the 120×60 section.
    let img = image::open(&out).unwrap().into_rgb8();
    assert_eq!(img.width(), 120);
    assert!(img.height() > 60);
    let bare = d.join("bare.png");
    let o2 = run(bin()
        .args([
            "slice",
            "--plane",
            "z=0",
            "--size",
            "120x60",
            "--no-legend",
            "-o",
        ])
        .arg(&bare)
        .arg(&bad));
    assert_eq!(o2.status.code(), Some(0));
    assert_eq!(
        image::open(&bare).unwrap().into_rgb8().dimensions(),
        (120, 60)
    );
    // Some pixels are the overlap's magenta.
    assert!(img.pixels().any(|p| p.0 == [255, 0, 255]));
    let legend: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("cut.legend.json")).unwrap()).unwrap();
    assert_eq!(legend["regions"].as_array().unwrap().len(), 2);
    assert_eq!(legend["overlaps"][0]["label"], "A × B");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("A × B") && stdout.contains('#'), "{stdout}");
    // An arbitrary plane.
    let o = run(bin()
        .args([
            "slice", "--origin", "0,0,0", "--normal", "1,1,0", "--extent", "3", "-o",
        ])
        .arg(d.join("tilt.png"))
        .arg(&bad));
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn volume_prints_every_region() {
    let d = dir("volume_out");
    let good = write(&d, "good.sv", CLEAN);
    let o = run(bin()
        .args(["volume", "--json", "--rel-error", "0.01"])
        .arg(&good));
    assert_eq!(o.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let regions = v["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 2);
    let vol = regions[0]["volume"].as_f64().unwrap();
    let exact = 4.0 / 3.0 * std::f64::consts::PI;
    assert!((vol - exact).abs() < 0.05 * exact, "{vol}");
}

#[test]
fn render_paints_overlaps() {
    let d = dir("render_overlaps");
    let bad = write(&d, "bad.sv", OVERLAP);
    let out = d.join("r.png");
    let o = run(bin()
        .args(["render", "--overlaps", "--size", "64x48", "-o"])
        .arg(&out)
        .arg(&bad));
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("A × B"), "{err}");
    let img = image::open(&out).unwrap().into_rgb8();
    assert!(img.pixels().any(|p| p.0 == [255, 0, 255]));
}

/// A FLUKA input: a beryllium sphere and a vacuum sphere overlapping
/// inside a black hole.
const FLUKA_VACUUM_OVERLAP: &str =
    "GEOBEGIN                                                              COMBNAME
    0    0
RPP blackhole  -200. 200. -200. 200. -200. 200.
SPH solid      0.0 0.0 0.0 50.
SPH gas        60.0 0.0 0.0 50.
END
blackhole    5 +blackhole -solid -gas
SOLID        5 +solid
GAS          5 +gas
END
GEOEND
ASSIGNMA    BLCKHOLE blackhole
ASSIGNMA    BERYLLIU     SOLID
ASSIGNMA      VACUUM       GAS
";

#[test]
fn fluka_inputs_count_overlaps_with_vacuum() {
    let d = dir("fluka_vacuum");
    // Named .dat, so the format is known from the text alone.
    let deck = write(&d, "vacuum.dat", FLUKA_VACUUM_OVERLAP);
    let o = run(bin().args(["check", "--json"]).arg(&deck));
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(report["overlaps"][0]["regions"][0], "SOLID");
    assert_eq!(report["overlaps"][0]["regions"][1], "GAS");
    assert_eq!(report["air_overlaps"].as_array().unwrap().len(), 0);
    let o = run(bin()
        .args(["render", "--overlaps", "--size", "32x24", "-o"])
        .arg(d.join("r.png"))
        .arg(&deck));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("SOLID × GAS"), "{err}");
    let o = run(bin()
        .args(["slice", "--plane", "z=0", "--json", "--size", "80x60", "-o"])
        .arg(d.join("s.png"))
        .arg(&deck));
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let legend: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(legend["overlaps"][0]["label"], "SOLID × GAS");
}

/// A rod sunk 0.1 into a block, between the rays of a grid of spacing 1
/// (see sv-check's slivers tests).
const SLIVER: &str = "BODY block RPP 0 10 0 10 0 10\nBODY rod RCC (10.4,5.06,0) (0,0,10) 0.5\n\
                      REGION BLOCK = +block\nREGION ROD = +rod\n";

#[test]
fn refinement_is_on_by_default_and_reported() {
    let d = dir("check_refine");
    let deck = write(&d, "sliver.sv", SLIVER);
    let grid = ["check", "--spacing", "1", "--box", "0,0,0,20,11,10"];
    let o = run(bin().args(grid).arg("--no-refine").arg(&deck));
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(String::from_utf8_lossy(&o.stdout).contains("no refinement"));
    let o = run(bin().args(grid).arg(&deck));
    assert_eq!(o.status.code(), Some(1));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("BLOCK × ROD") && out.contains("refined 4 times"),
        "{out}"
    );
    let o = run(bin()
        .args(grid)
        .args(["--refine-to", "0.01", "--json"])
        .arg(&deck));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["refine"], 7);
    assert_eq!(v["smallest_feature"]["at_edges"], 1.0 / 128.0);
    assert!(v["refine_rays"].as_u64().unwrap() > 0);
}
