//! Film runs: resuming, atomic frames, GIF, contact sheet, MP4 fallback.

use image::{AnimationDecoder, Rgb, RgbImage};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use sv_output::film::*;

const W: u32 = 64;
const H: u32 = 48;

fn colour(f: usize) -> Rgb<u8> {
    Rgb([(f * 20 % 256) as u8, (255 - f * 20 % 256) as u8, 128])
}

fn picture(f: usize) -> RgbImage {
    RgbImage::from_fn(
        W,
        H,
        |x, _| if x < W / 2 { colour(f) } else { Rgb([0, 0, 0]) },
    )
}

fn opts(dir: &Path, hash: &str) -> FilmOptions {
    let mut o = FilmOptions::new(dir, hash);
    o.mp4 = false;
    o
}

fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn resume_renders_only_the_missing_frames() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let dir = tmp.path().join("out");
    let calls = AtomicUsize::new(0);
    let render = |f: usize| -> FrameResult {
        calls.fetch_add(1, Ordering::SeqCst);
        Ok(picture(f))
    };
    // A run over part of the film renders that part and makes no film.
    let mut o = opts(&dir, "h1");
    o.frames = 0..4;
    let r = make_film(10, &o, render, |_, _| {}).expect("run");
    assert_eq!(calls.load(Ordering::SeqCst), 4);
    assert_eq!(r.rendered, vec![0, 1, 2, 3]);
    assert_eq!(r.missing, (4..10).collect::<Vec<_>>());
    assert_eq!((r.gif, r.contact_sheet), (None, None));
    // The full run renders the other six only.
    let r = make_film(10, &opts(&dir, "h1"), render, |_, _| {}).expect("run");
    assert_eq!(calls.load(Ordering::SeqCst), 10);
    assert_eq!(r.reused, vec![0, 1, 2, 3]);
    assert_eq!(r.rendered, (4..10).collect::<Vec<_>>());
    assert!(r.missing.is_empty());
    // Nothing left to do.
    let r = make_film(10, &opts(&dir, "h1"), render, |_, _| {}).expect("run");
    assert_eq!(calls.load(Ordering::SeqCst), 10);
    assert!(r.rendered.is_empty());
    // Another script or scene: every frame again.
    let r = make_film(10, &opts(&dir, "h2"), render, |_, _| {}).expect("run");
    assert_eq!(calls.load(Ordering::SeqCst), 20);
    assert_eq!(r.rendered.len(), 10);
}

#[test]
fn interrupted_run_leaves_whole_frames_only_and_resumes() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let dir = tmp.path().to_path_buf();
    let render_fail = |f: usize| -> FrameResult {
        if f == 7 {
            Err("the renderer was stopped".into())
        } else {
            Ok(picture(f))
        }
    };
    let e = make_film(12, &opts(&dir, "h"), render_fail, |_, _| {}).unwrap_err();
    assert_eq!(e.to_string(), "frame 7: the renderer was stopped");
    // Every PNG present is whole; no temporary files are left.
    let names = files(&dir);
    assert!(names.iter().all(|n| !n.starts_with(".tmp")), "{names:?}");
    assert!(files(&dir.join("hashes"))
        .iter()
        .all(|n| !n.starts_with(".tmp")));
    let done: Vec<usize> = (0..12).filter(|&f| frame_done(&dir, f, "h")).collect();
    assert!(!done.contains(&7));
    for &f in &done {
        let img = image::open(frame_path(&dir, f))
            .expect("whole PNG")
            .to_rgb8();
        assert_eq!(img, picture(f));
    }
    // The next run renders exactly the frames that were not done.
    let rendered = Mutex::new(Vec::new());
    let r = make_film(
        12,
        &opts(&dir, "h"),
        |f| -> FrameResult {
            rendered.lock().expect("lock").push(f);
            Ok(picture(f))
        },
        |_, _| {},
    )
    .expect("run");
    let mut got = rendered.into_inner().expect("lock");
    got.sort();
    let expect: Vec<usize> = (0..12).filter(|f| !done.contains(f)).collect();
    assert_eq!(got, expect);
    assert_eq!(r.rendered, expect);
    assert_eq!(r.reused, done);
}

#[test]
fn failed_write_leaves_nothing_and_keeps_the_old_file() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let p = tmp.path().join("x.png");
    let r = write_atomically(&p, |w| {
        w.write_all(b"half a file")?;
        Err(std::io::Error::other("disk full"))
    });
    assert!(r.is_err());
    assert!(files(tmp.path()).is_empty(), "{:?}", files(tmp.path()));
    write_atomically(&p, |w| w.write_all(b"old")).expect("write");
    let r = write_atomically(&p, |w| {
        w.write_all(b"new but")?;
        Err(std::io::Error::other("killed"))
    });
    assert!(r.is_err());
    assert_eq!(std::fs::read(&p).expect("read"), b"old");
    assert_eq!(files(tmp.path()), vec!["x.png".to_string()]);
}

#[test]
fn gif_has_every_frame_and_is_scaled() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let mut o = opts(tmp.path(), "h");
    o.gif_max_width = 32;
    o.fps = 24.0;
    let r = make_film(6, &o, |f| Ok(picture(f)), |_, _| {}).expect("run");
    let gif = r.gif.expect("gif made");
    let dec = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
        std::fs::File::open(gif).expect("open"),
    ))
    .expect("gif");
    let frames = dec.into_frames().collect_frames().expect("frames");
    assert_eq!(frames.len(), 6);
    for (i, fr) in frames.iter().enumerate() {
        assert_eq!(fr.buffer().dimensions(), (32, 24));
        // The left half keeps the frame's colour (within quantisation).
        let p = fr.buffer().get_pixel(4, 12);
        let c = colour(i);
        for k in 0..3 {
            assert!(
                (p[k] as i32 - c[k] as i32).abs() <= 8,
                "frame {i}: {p:?} vs {c:?}"
            );
        }
    }
}

#[test]
fn gif_delays_keep_the_film_length() {
    let d = gif_delays(24, 24.0);
    assert_eq!(d.iter().map(|&x| x as u32).sum::<u32>(), 100);
    assert!(d.iter().all(|&x| x == 4 || x == 5));
    assert_eq!(gif_delays(3, 10.0), vec![10, 10, 10]);
}

#[test]
fn contact_sheet_has_a_thumbnail_of_every_nth_frame() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let mut o = opts(tmp.path(), "h");
    o.contact_every = 3;
    o.contact_columns = 3;
    o.thumb_width = 40;
    let r = make_film(10, &o, |f| Ok(picture(f)), |_, _| {}).expect("run");
    let sheet = image::open(r.contact_sheet.expect("sheet"))
        .expect("png")
        .to_rgb8();
    // Frames 0, 3, 6, 9 in 3 columns: 2 rows of 40×30 thumbnails.
    assert_eq!(sheet.dimensions(), (120, 60));
    for (i, f) in [0usize, 3, 6, 9].into_iter().enumerate() {
        let (x, y) = ((i as u32 % 3) * 40 + 5, (i as u32 / 3) * 30 + 15);
        assert_eq!(*sheet.get_pixel(x, y), colour(f), "thumbnail of frame {f}");
    }
    // The empty cell stays black.
    assert_eq!(*sheet.get_pixel(100, 45), Rgb([0, 0, 0]));
}

#[test]
fn progress_counts_up_to_the_range() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let seen = Mutex::new(Vec::new());
    make_film(
        5,
        &opts(tmp.path(), "h"),
        |f| Ok(picture(f)),
        |d, t| seen.lock().expect("lock").push((d, t)),
    )
    .expect("run");
    let mut seen = seen.into_inner().expect("lock");
    seen.sort();
    assert_eq!(seen, vec![(0, 5), (1, 5), (2, 5), (3, 5), (4, 5), (5, 5)]);
}

#[test]
fn frames_do_not_depend_on_the_order_they_were_made() {
    let a = tempfile::tempdir().expect("temp dir");
    let b = tempfile::tempdir().expect("temp dir");
    make_film(8, &opts(a.path(), "h"), |f| Ok(picture(f)), |_, _| {}).expect("run");
    for range in [6..8, 0..3, 3..6] {
        let mut o = opts(b.path(), "h");
        o.frames = range;
        make_film(8, &o, |f| Ok(picture(f)), |_, _| {}).expect("run");
    }
    for name in [
        "frame_000000.png",
        "frame_000005.png",
        "film.gif",
        "contact.png",
    ] {
        assert_eq!(
            std::fs::read(a.path().join(name)).ok(),
            std::fs::read(b.path().join(name)).ok(),
            "{name}"
        );
    }
}

#[cfg(unix)]
fn fake_program(dir: &Path, body: &str) -> std::path::PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let p = dir.join("ffmpeg");
    std::fs::write(&p, format!("#!/bin/sh\n{body}\n")).expect("write");
    std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    p
}

#[cfg(unix)]
#[test]
fn mp4_uses_ffmpeg_and_never_fails_the_film() {
    let bin = tempfile::tempdir().expect("temp dir");
    // Not on an empty PATH.
    assert_eq!(
        find_program("ffmpeg", Some(bin.path().as_os_str().to_owned())),
        None
    );
    assert_eq!(
        Mp4Status::FfmpegNotFound.to_string(),
        "ffmpeg not found: MP4 skipped"
    );
    // A stand-in that writes its last argument, as ffmpeg writes its output.
    let ok = fake_program(
        bin.path(),
        "for a; do last=$a; done; echo video > \"$last\"",
    );
    assert_eq!(
        find_program("ffmpeg", Some(bin.path().as_os_str().to_owned())),
        Some(ok.clone())
    );
    let out = tempfile::tempdir().expect("temp dir");
    let mut o = opts(out.path(), "h");
    o.mp4 = true;
    o.ffmpeg = Some(ok);
    let r = make_film(3, &o, |f| Ok(picture(f)), |_, _| {}).expect("run");
    let mp4 = out.path().join("film.mp4");
    assert_eq!(r.mp4, Mp4Status::Written(mp4.clone()));
    assert_eq!(std::fs::read_to_string(mp4).expect("read"), "video\n");
    // A failing ffmpeg is reported, and the rest of the film is made.
    let bad_bin = tempfile::tempdir().expect("temp dir");
    let bad = fake_program(bad_bin.path(), "echo 'Unknown encoder libx264' >&2; exit 1");
    let out = tempfile::tempdir().expect("temp dir");
    let mut o = opts(out.path(), "h");
    o.mp4 = true;
    o.ffmpeg = Some(bad);
    let r = make_film(3, &o, |f| Ok(picture(f)), |_, _| {}).expect("run");
    assert_eq!(r.mp4, Mp4Status::Failed("Unknown encoder libx264".into()));
    assert!(r.gif.is_some() && r.contact_sheet.is_some());
    // With the real PATH: written when ffmpeg is installed, else skipped.
    let out = tempfile::tempdir().expect("temp dir");
    let mut o = opts(out.path(), "h");
    o.mp4 = true;
    let r = make_film(2, &o, |f| Ok(picture(f)), |_, _| {}).expect("run");
    match find_program("ffmpeg", std::env::var_os("PATH")) {
        None => assert_eq!(r.mp4, Mp4Status::FfmpegNotFound),
        Some(_) => assert!(matches!(
            r.mp4,
            Mp4Status::Written(_) | Mp4Status::Failed(_)
        )),
    }
}

#[test]
fn frame_ranges_read_like_rust_ranges() {
    assert_eq!(parse_frame_range("10..20", 720), Ok(10..20));
    assert_eq!(parse_frame_range("10..=20", 720), Ok(10..21));
    assert_eq!(parse_frame_range("700..", 720), Ok(700..720));
    assert_eq!(parse_frame_range("..5", 720), Ok(0..5));
    assert_eq!(parse_frame_range(" 42 ", 720), Ok(42..43));
    assert_eq!(parse_frame_range("700..800", 720), Ok(700..720));
    assert_eq!(parse_frame_range("719", 720), Ok(719..720));
    assert_eq!(
        parse_frame_range("720", 720),
        Err("frames 720 hold no frame of a film of 720 frames (0..720)".to_string())
    );
    assert_eq!(
        parse_frame_range("20..10", 720),
        Err("frames 20..10 hold no frame of a film of 720 frames (0..720)".to_string())
    );
    assert_eq!(
        parse_frame_range("a..b", 720),
        Err("`a` is not a frame number".to_string())
    );
    assert_eq!(
        parse_frame_range("1..-3", 720),
        Err("`-3` is not a frame number".to_string())
    );
}

#[test]
fn content_hash_depends_on_every_part_and_its_boundaries() {
    let h = content_hash(&[b"film", b"960x720"]);
    assert_eq!(h.len(), 64);
    assert_eq!(h, content_hash(&[b"film", b"960x720"]));
    assert_ne!(h, content_hash(&[b"film", b"960x721"]));
    assert_ne!(h, content_hash(&[b"fil", b"m960x720"]));
    assert_eq!(
        content_hash(&[]),
        "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
    );
}

#[test]
fn temporaries_of_a_killed_run_are_cleared_when_stale() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let dir = tmp.path();
    std::fs::create_dir_all(dir.join("hashes")).expect("mkdir");
    let old = std::time::SystemTime::now() - std::time::Duration::from_secs(3600);
    for p in [
        dir.join(".tmp-killed"),
        dir.join("hashes").join(".tmp-killed"),
    ] {
        let f = std::fs::File::create(&p).expect("create");
        f.set_modified(old).expect("mtime");
    }
    std::fs::write(dir.join(".tmp-running"), b"part").expect("write");
    make_film(2, &opts(dir, "h"), |f| Ok(picture(f)), |_, _| {}).expect("run");
    let names = files(dir);
    assert!(!names.contains(&".tmp-killed".to_string()), "{names:?}");
    assert!(
        names.contains(&".tmp-running".to_string()),
        "a young temporary may belong to a live run"
    );
    assert!(files(&dir.join("hashes"))
        .iter()
        .all(|n| !n.starts_with(".tmp")));
}

#[test]
fn a_film_finished_by_another_run_is_assembled_from_its_pngs() {
    // Run A renders 0..4 while 4..8 are still missing; another run makes
    // them while A works (here from within A's first frame). A finds every
    // frame done at its end and assembles the film from the PNGs, the same
    // film as one run makes while rendering.
    let shared = tempfile::tempdir().expect("temp dir");
    let other_run = || {
        let mut o = opts(shared.path(), "h");
        o.frames = 4..8;
        make_film(8, &o, |f| Ok(picture(f)), |_, _| {}).expect("other run");
    };
    let mut o = opts(shared.path(), "h");
    o.frames = 0..4;
    let r = make_film(
        8,
        &o,
        |f| {
            if f == 0 {
                other_run();
            }
            Ok(picture(f))
        },
        |_, _| {},
    )
    .expect("run");
    assert!(r.missing.is_empty());
    assert!(r.gif.is_some() && r.contact_sheet.is_some());
    let single = tempfile::tempdir().expect("temp dir");
    make_film(8, &opts(single.path(), "h"), |f| Ok(picture(f)), |_, _| {}).expect("run");
    for name in ["film.gif", "contact.png"] {
        assert_eq!(
            std::fs::read(shared.path().join(name)).ok(),
            std::fs::read(single.path().join(name)).ok(),
            "{name}"
        );
    }
}

#[test]
fn frames_of_different_sizes_make_no_film() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let e = make_film(
        4,
        &opts(tmp.path(), "h"),
        |f| {
            Ok(if f == 2 {
                RgbImage::new(W + 2, H)
            } else {
                picture(f)
            })
        },
        |_, _| {},
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .ends_with("frame 2 is 66x48, frame 0 is 64x48: a film's frames are all one size"),
        "{e}"
    );
    assert_no_film_nor_temporaries(tmp.path());
}

/// The BT.709 studio-range YUV of an RGB colour, as the MP4's frames hold
/// it (luma, blue difference, red difference).
fn bt709(rgb: [u8; 3]) -> [f64; 3] {
    let [r, g, b] = rgb.map(|c| c as f64 / 255.0);
    let y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    [
        16.0 + 219.0 * y,
        128.0 + 224.0 * (b - y) / 1.8556,
        128.0 + 224.0 * (r - y) / 1.5748,
    ]
}

#[cfg(unix)]
#[test]
fn ffmpeg_is_fed_every_frame_as_bt709_planes_of_even_size() {
    // A stand-in that keeps what it is fed, in its last argument.
    let bin = tempfile::tempdir().expect("temp dir");
    let keep = fake_program(bin.path(), "for a; do last=$a; done; cat > \"$last\"");
    let out = tempfile::tempdir().expect("temp dir");
    let mut o = opts(out.path(), "h");
    o.mp4 = true;
    o.ffmpeg = Some(keep);
    // Odd sizes: the planes are padded to 64×48 with black.
    let (w, h) = (63u32, 47u32);
    let colours = [[255u8, 255, 255], [200, 30, 60], [0, 0, 0], [10, 220, 90]];
    let r = make_film(
        colours.len(),
        &o,
        |f| Ok(RgbImage::from_pixel(w, h, Rgb(colours[f]))),
        |_, _| {},
    )
    .expect("run");
    assert_eq!(r.mp4, Mp4Status::Written(out.path().join("film.mp4")));
    let fed = std::fs::read(out.path().join("film.mp4")).expect("read");
    let (ew, eh) = (64usize, 48usize);
    let frame_len = ew * eh * 3 / 2;
    assert_eq!(fed.len(), colours.len() * frame_len);
    for (f, frame) in fed.chunks_exact(frame_len).enumerate() {
        let (luma, chroma) = frame.split_at(ew * eh);
        let (blue, red) = chroma.split_at(ew * eh / 4);
        let expect = bt709(colours[f]);
        let near = |got: u8, want: f64| (got as f64 - want).abs() <= 1.0;
        assert!(near(luma[5 * ew + 7], expect[0]), "frame {f} luma");
        assert!(near(blue[2 * (ew / 2) + 3], expect[1]), "frame {f} blue");
        assert!(near(red[2 * (ew / 2) + 3], expect[2]), "frame {f} red");
        // The padding column and row are black.
        assert_eq!(
            (luma[5 * ew + 63], luma[47 * ew + 5]),
            (16, 16),
            "frame {f}"
        );
    }
    assert!(!files(out.path()).iter().any(|n| n.starts_with(".tmp")));
}

#[cfg(unix)]
#[test]
fn an_ffmpeg_that_stops_reading_fails_the_mp4_only() {
    let bin = tempfile::tempdir().expect("temp dir");
    let quits = fake_program(
        bin.path(),
        "for a; do last=$a; done; head -c 100 > \"$last\"; echo 'pipe:0: cannot decode' >&2; exit 1",
    );
    let out = tempfile::tempdir().expect("temp dir");
    let mut o = opts(out.path(), "h");
    o.mp4 = true;
    o.ffmpeg = Some(quits.clone());
    let r = make_film(6, &o, |f| Ok(picture(f)), |_, _| {}).expect("run");
    assert_eq!(r.mp4, Mp4Status::Failed("pipe:0: cannot decode".into()));
    assert!(r.gif.is_some() && r.contact_sheet.is_some());
    let names = files(out.path());
    assert!(!names.contains(&"film.mp4".to_string()), "{names:?}");
    assert!(!names.iter().any(|n| n.starts_with(".tmp")), "{names:?}");
    // A film stopped by a failing frame leaves no MP4 either, nor
    // ffmpeg's file.
    let out = tempfile::tempdir().expect("temp dir");
    let mut o = opts(out.path(), "h");
    o.mp4 = true;
    o.ffmpeg = Some(fake_program(
        bin.path(),
        "for a; do last=$a; done; cat > \"$last\"",
    ));
    let e = make_film(
        8,
        &o,
        |f| {
            if f == 5 {
                Err("stopped".into())
            } else {
                Ok(picture(f))
            }
        },
        |_, _| {},
    )
    .unwrap_err();
    assert_eq!(e.to_string(), "frame 5: stopped");
    assert_no_film_nor_temporaries(out.path());
}

/// A film that failed leaves no GIF, no MP4 and no temporary file.
fn assert_no_film_nor_temporaries(dir: &Path) {
    let names = files(dir);
    assert!(
        !names
            .iter()
            .any(|n| n.starts_with(".tmp") || n.starts_with("film.")),
        "{names:?}"
    );
}
