//! A tool people can trust (issue 26): closed pipes, sizes beyond memory,
//! values out of range, empty models and conflicting options are refused
//! up front or end quietly, never with a panic or a silently wrong picture.

use crate::{examples, fresh_dir, sv, write};
use std::path::Path;
use std::process::{Command, Output};

/// Run the binary with `args` writing into a pipe whose reader has gone:
/// the shell starts it after `true` has exited. `both` sends stderr into
/// the pipe too. Returns the exit code and what reached the terminal.
fn into_closed_pipe(args: &str, both: bool) -> (i32, String) {
    let redirect = if both { "2>&1" } else { "" };
    let script = format!(
        "(sleep 0.3; \"$0\" {args} {redirect}; echo \"exit $?\" >&3) 3>&2 | true",
        args = args
    );
    let o = Command::new("sh")
        .arg("-c")
        .arg(script)
        .arg(env!("CARGO_BIN_EXE_synthavision"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr).to_string();
    let code = stderr
        .lines()
        .find_map(|l| l.strip_prefix("exit "))
        .and_then(|c| c.trim().parse().ok())
        .unwrap_or(-1);
    (code, stderr)
}

#[test]
fn closed_pipes_end_quietly() {
    let figure1 = examples().join("figure1/figure1.sv");
    let figure1 = figure1.to_str().unwrap();
    let dir = fresh_dir("trust-pipes");
    let bad = write(&dir, "bad.svs", "FPS 12\nFOO\n");
    for (args, both, expected) in [
        ("bodies".to_string(), false, 0),
        (format!("info {figure1}"), false, 0),
        (
            format!("shoot {figure1} --from 0,-5,0 --dir 0,1,0"),
            false,
            0,
        ),
        (format!("film {}", bad.display()), true, 2),
    ] {
        let (code, stderr) = into_closed_pipe(&args, both);
        assert_eq!(code, expected, "{args}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args}: {stderr}");
    }
}

/// Run the binary with `args`, which must succeed.
fn succeeds(args: &[&str]) -> Output {
    let o = sv(args);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{args:?}: {stderr}");
    o
}

/// A run that must be refused with exit 2 before writing `out`.
fn refused(o: &Output, out: &std::path::Path, says: &str) {
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains(says), "expected `{says}` in: {stderr}");
    assert!(!out.exists(), "{} was written", out.display());
}

#[test]
fn sizes_beyond_memory_are_refused_before_allocating() {
    let dir = fresh_dir("trust-size");
    let out = dir.join("x.png");
    let o = sv(&[
        "render",
        "--size",
        "65536x65536",
        "-o",
        out.to_str().unwrap(),
    ]);
    refused(&o, &out, "of memory");
    let scene = examples().join("figure1/figure1.sv");
    let text = format!("SCENE \"{}\"\nFPS 12\nSHOOT\n", scene.display());
    let script = write(&dir, "f.svs", &text);
    let film = dir.join("film");
    let o = sv(&[
        "film",
        script.to_str().unwrap(),
        "--size",
        "65536x65536",
        "-o",
        film.to_str().unwrap(),
    ]);
    refused(&o, &film, "of memory");
}

#[test]
fn numbers_that_are_not_finite_are_refused() {
    let dir = fresh_dir("trust-finite");
    let out = dir.join("x.png");
    let out_text = out.to_str().unwrap();
    for args in [
        &["--az", "nan"][..],
        &["--el", "inf"],
        &["--background", "nan"],
        &["--background", "2,0,0"],
        &["--fov", "-inf"],
        &["--levels", "0"],
        &["--levels", "1"],
        &["--samples", "0"],
        &["--threads", "0"],
    ] {
        let mut all = vec!["render", "--size", "8x6", "-o", out_text];
        all.extend_from_slice(args);
        refused(&sv(&all), &out, args[0]);
    }
}

#[test]
fn scene_values_out_of_range_are_refused_where_they_stand() {
    let dir = fresh_dir("trust-scene-values");
    let out = dir.join("x.png");
    let body = "BODY a SPH (0,0,0) 1\nREGION r = +a\n";
    for (line, column, statement) in [
        (3, 44, "CAMERA ORTHO EYE (5,5,5) AT (0,0,0) HEIGHT 0"),
        (3, 9, "AMBIENT -1"),
        (3, 43, "LIGHT sun PARALLEL DIR (0,0,-1) INTENSITY -5"),
        (3, 35, "LIGHT lamp POINT AT (0,0,5) DECAY -3"),
        (3, 43, "LIGHT sun PARALLEL DIR (0,0,-1) COLOR 0.5 -1 0.5"),
        (3, 16, "REGION r COLOR 2 0 0.5"),
    ] {
        let scene = write(&dir, "s.sv", &format!("{body}{statement}\n"));
        let o = sv(&[
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        refused(&o, &out, &format!("s.sv:{line}:{column}"));
    }
}

#[test]
fn an_empty_model_is_an_error_and_the_old_picture_stays() {
    let dir = fresh_dir("trust-empty");
    let out = write(&dir, "x.png", "an earlier picture");
    for text in ["", "# nothing\n", "BODY a SPH (0,0,0) 1\n"] {
        let scene = write(&dir, "e.sv", text);
        let o = sv(&[
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("e.sv:1:1"), "{stderr}");
        assert!(stderr.contains("no region"), "{stderr}");
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "an earlier picture");
    }
}

#[test]
fn a_stray_carriage_return_does_not_shift_the_snippet() {
    let dir = fresh_dir("trust-cr");
    let scene = write(&dir, "cr.sv", "TITLE a\rb\nFOO 1\n");
    let o = sv(&["info", scene.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("cr.sv:2:1"), "{stderr}");
    assert!(stderr.contains(" 2 │ FOO 1"), "{stderr}");
    assert!(!stderr.contains(" 3 │"), "{stderr}");
}

#[test]
fn a_ray_budget_too_small_to_estimate_is_refused() {
    let figure1 = examples().join("figure1/figure1.sv");
    let o = sv(&["volume", figure1.to_str().unwrap(), "--max-rays", "1"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--max-rays 1 is too few"), "{stderr}");
    assert!(o.stdout.is_empty());
}

#[test]
fn conflicting_options_are_refused_before_rendering() {
    let dir = fresh_dir("trust-conflicts");
    for (name, option, says) in [
        ("x.ppm", "--alpha", "--alpha needs a PNG"),
        ("x.pfm", "--srgb", "--srgb does not apply"),
        ("x.pfm", "--sixteen-bit", "--sixteen-bit does not apply"),
    ] {
        let out = dir.join(name);
        let started = std::time::Instant::now();
        // A size that would take long to render: refused before it is.
        let o = sv(&[
            "render",
            "--size",
            "8000x6000",
            option,
            "-o",
            out.to_str().unwrap(),
        ]);
        refused(&o, &out, says);
        assert!(started.elapsed().as_secs() < 20, "rendered first");
    }
}

#[test]
fn bench_measures_scenes_built_into_the_binary() {
    let o = sv(&["bench", "--size", "16x12", "--repeat", "1", "--warmup", "0"]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("figure1.sv (bundled)"), "{stdout}");
    assert!(stdout.contains("helicopter.sv (bundled)"), "{stdout}");
}

#[test]
fn render_reads_stdin_writes_stdout_and_says_what_it_wrote() {
    let dir = fresh_dir("trust-stdio");
    let scene = std::fs::read(examples().join("figure1/figure1.sv")).unwrap();
    let mut child = crate::bin()
        .args(["render", "-", "--size", "32x24", "-o", "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .current_dir(&dir)
        .spawn()
        .unwrap();
    std::io::Write::write_all(&mut child.stdin.take().unwrap(), &scene).unwrap();
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let picture = image::load_from_memory(&o.stdout).unwrap();
    assert_eq!((picture.width(), picture.height()), (32, 24));
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    let out = dir.join("f.png");
    let o = sv(&["render", "--size", "8x6", "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains(&format!("wrote {} (8x6)", out.display())),
        "{stderr}"
    );
    let o = sv(&[
        "render",
        "--quiet",
        "--size",
        "8x6",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn a_film_re_run_at_another_size_leaves_no_old_film() {
    let dir = fresh_dir("trust-film-stale");
    let scene = examples().join("figure1/figure1.sv");
    let script = write(
        &dir,
        "f.svs",
        &format!(
            "SCENE \"{}\"\nFPS 12\nSIZE 32 24\nSHOOT 3\n",
            scene.display()
        ),
    );
    let film = dir.join("film");
    let run = |extra: &[&str]| {
        let mut args = vec!["film", script.to_str().unwrap(), "--no-mp4", "-o"];
        args.push(film.to_str().unwrap());
        args.extend_from_slice(extra);
        succeeds(&args);
    };
    run(&[]);
    assert!(film.join("film.gif").exists() && film.join("contact.png").exists());
    // Part of the film at another size: the old GIF and sheet are gone.
    run(&["--size", "16x12", "--frames", "0..2"]);
    assert!(!film.join("film.gif").exists());
    assert!(!film.join("contact.png").exists());
    // The rest of it: made again, from the new frames.
    run(&["--size", "16x12"]);
    let gif = image::open(film.join("film.gif")).unwrap();
    assert_eq!((gif.width(), gif.height()), (16, 12));
}

/// A FLUKA input in free format: `bodies` (from line 5), `regions` and
/// the cards after the geometry.
fn fluka(bodies: &[&str], regions: &[&str], after: &[&str]) -> String {
    let mut lines = vec![
        "TITLE",
        "test",
        "GEOBEGIN                                                              COMBNAME",
        "    0    0          test",
    ];
    lines.extend_from_slice(bodies);
    lines.push("END");
    lines.extend_from_slice(regions);
    lines.extend_from_slice(&["END", "GEOEND"]);
    lines.extend_from_slice(after);
    lines.push("STOP");
    lines.join("\n")
}

#[test]
fn geometry_rules_are_reported_at_the_body_card_in_every_reader() {
    let dir = fresh_dir("trust-body-rules");
    let cases = [
        (
            "s.sv",
            "BODY 1 SPH (0,0,0) -1\nREGION r = +1\n".to_string(),
            "s.sv:1:8",
            "radius must be positive",
        ),
        (
            "s.sv",
            "BODY 1 SPH (1e300,0,0) 1\nREGION r = +1\n".to_string(),
            "s.sv:1:8",
            "bounds would overflow",
        ),
        (
            "d.cg",
            [
                "cm bad sphere",
                "    2    1",
                "    1SPH          0.        0.        0.       -1.",
                "    2SPH          0.        0.        0.        2.",
                "    1       2     -1",
                "   -1",
                "    1    0    0    1  100",
            ]
            .join("\n"),
            "d.cg:3:6",
            "radius must be positive",
        ),
        (
            "f.inp",
            fluka(
                &["SPH blk 0 0 0 100", "PLA p 0 0 0 1 1 1"],
                &["BLKBODY 5 +blk -p", "R1 5 +blk +p"],
                &[],
            ),
            "f.inp:6:1",
            "normal",
        ),
    ];
    for (name, text, place, says) in cases {
        let input = write(&dir, name, &text);
        let o = sv(&["info", input.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{stderr}");
        assert!(
            stderr.contains(place) && stderr.contains(says),
            "{name}: {stderr}"
        );
        assert_eq!(stderr.matches("error").count(), 1, "one error: {stderr}");
    }
}

#[test]
fn convert_writes_fluka_half_spaces_as_haf_and_they_cut_alike() {
    let dir = fresh_dir("trust-haf");
    let input = write(
        &dir,
        "h.inp",
        &fluka(
            &[
                "SPH blk 0 0 0 1000",
                "RPP box -5 5 -5 5 -5 5",
                "XYP top 2",
                "XZP side 1",
                "YZP back -1",
                "PLA slant 1 1 1 0 0 0",
            ],
            &["BLKBODY 5 +blk -box", "R1 5 +box +top +side -back +slant"],
            &[
                "ASSIGNMA    BLCKHOLE   BLKBODY",
                "ASSIGNMA      IRON        R1",
            ],
        ),
    );
    let deck = dir.join("h.cg");
    succeeds(&[
        "convert",
        input.to_str().unwrap(),
        "-o",
        deck.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&deck).unwrap();
    assert_eq!(text.matches("HAF").count(), 4, "{text}");
    // The same crossings along rays through each cut.
    let crossings = |file: &std::path::Path, from: &str, dir: &str| {
        let o = succeeds(&[
            "shoot",
            file.to_str().unwrap(),
            "--from",
            from,
            "--dir",
            dir,
        ]);
        let stdout = String::from_utf8_lossy(&o.stdout).to_string();
        let columns: Vec<String> = stdout
            .lines()
            .skip(2)
            .map(|l| l.split_whitespace().take(2).collect::<Vec<_>>().join(" "))
            .collect();
        columns
    };
    for (from, dir) in [
        ("-10,-0.5,-0.5", "1,0,0"),
        ("0.5,-0.5,-10", "0,0,1"),
        ("0.5,-10,-0.5", "0,1,0"),
    ] {
        let fluka = crossings(&input, from, dir);
        assert!(fluka.len() >= 3, "{fluka:?}");
        assert_eq!(fluka, crossings(&deck, from, dir), "{from} {dir}");
    }
}

#[test]
fn regions_lists_and_filters_every_region() {
    let dir = fresh_dir("trust-regions");
    let scene = write(
        &dir,
        "r.sv",
        "BODY a SPH (0,0,0) 1\nBODY b RPP -3 3 -3 3 -3 3\nBODY c SPH (5,0,0) 0.5\n\
         REGION core = +a\nREGION shell = +b -a\nREGION moon = +c\n",
    );
    let o = sv(&["regions", scene.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(stdout.lines().count(), 4, "{stdout}");
    assert!(stdout.contains("(-3, -3, -3) to (3, 3, 3)"), "{stdout}");
    let o = sv(&[
        "regions",
        scene.to_str().unwrap(),
        "--json",
        "--matching",
        "SHE",
    ]);
    let listed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(listed.as_array().unwrap().len(), 1);
    assert_eq!(listed[0]["name"], "shell");
    assert_eq!(listed[0]["bodies"], 2);
    let high_x = listed[0]["bounds"][1][0].as_f64().unwrap();
    assert!((high_x - 3.0).abs() < 1e-3, "{high_x}");
    let o = sv(&["regions", scene.to_str().unwrap(), "--material", "7"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn completions_and_manual_pages_come_from_the_commands() {
    let o = sv(&["completions", "bash"]);
    let script = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success());
    assert!(
        script.contains("--view-size") && script.contains("regions"),
        "{script}"
    );
    let o = sv(&["man"]);
    let page = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success());
    assert!(page.contains(".TH synthavision 1"), "{page}");
    let dir = fresh_dir("trust-man");
    let o = sv(&["man", "--dir", dir.to_str().unwrap()]);
    assert!(o.status.success());
    assert!(dir.join("synthavision-render.1").exists());
}

#[test]
fn render_colours_by_material_with_a_legend() {
    let dir = fresh_dir("trust-colour-by");
    let scene = write(
        &dir,
        "m.sv",
        "BODY a SPH (0,0,0) 1\nBODY b SPH (3,0,0) 1\nREGION one = +a\nREGION two = +b\n",
    );
    let out = dir.join("m.png");
    let (scene, out_text) = (scene.to_str().unwrap(), out.to_str().unwrap());
    succeeds(&[
        "render",
        scene,
        "--size",
        "64x48",
        "--color-by",
        "region",
        "-o",
        out_text,
    ]);
    let picture = image::open(&out).unwrap().into_rgb8();
    // Two regions of one grey scene now differ in hue.
    let hues: std::collections::BTreeSet<[u8; 3]> = picture
        .pixels()
        .filter(|p| p.0 != [0, 0, 0])
        .map(|p| {
            let max = *p.0.iter().max().unwrap() as u32;
            p.0.map(|c| (c as u32 * 4 / max.max(1)) as u8)
        })
        .collect();
    assert!(hues.len() >= 2, "{hues:?}");
    succeeds(&[
        "render",
        scene,
        "--size",
        "64x48",
        "--color-by",
        "material",
        "--legend",
        "-o",
        out_text,
    ]);
    let picture = image::open(&out).unwrap();
    assert!(
        picture.height() > 48,
        "the legend strip is below the picture"
    );
    assert_eq!(
        sv(&["render", scene, "--legend", "-o", out_text])
            .status
            .code(),
        Some(2)
    );
}

#[test]
fn slices_can_have_axes_and_print_rounded_numbers() {
    let dir = fresh_dir("trust-axes");
    let scene = examples().join("figure1/figure1.sv");
    let plain = dir.join("plain.png");
    let framed = dir.join("framed.png");
    let slice = |out: &Path, extra: &[&str]| {
        let mut args = vec!["slice", scene.to_str().unwrap(), "--plane", "z=0.1"];
        args.extend_from_slice(&["--no-legend", "-o", out.to_str().unwrap()]);
        args.extend_from_slice(extra);
        let o = succeeds(&args);
        String::from_utf8_lossy(&o.stdout).to_string()
    };
    let report = slice(&plain, &[]);
    slice(&framed, &["--axes"]);
    let first = report.lines().next().unwrap();
    // `centre (0.4, 0, 0.1)`, not `centre (0.40000000000000036, …)`.
    assert!(!first.contains("0000"), "{first}");
    let (plain, framed) = (
        image::open(plain).unwrap().into_rgb8(),
        image::open(framed).unwrap().into_rgb8(),
    );
    assert!(framed.width() > plain.width() && framed.height() > plain.height());
    // Tick labels and the scale bar are black ink on white margins.
    let ink = framed.pixels().filter(|p| p.0 == [0, 0, 0]).count();
    assert!(ink > 200, "{ink} black pixels");
}
