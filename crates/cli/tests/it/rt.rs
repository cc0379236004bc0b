//! `--rt` and `--eye-light`: BRL-CAD `rt -l1`'s view, sampling and
//! shading. The figures below are what `rt` 7.36 printed and drew for the
//! same decks (`rt -v -s512 -a35 -e25 -l1`, and the ground deck at 64²).

use crate::{fresh_dir, sv};
use sv_formats::{load_file, LoadOptions};
use sv_render::{rt_camera, Renderer, ViewSpec};
use sv_scene::Lens;

#[test]
fn the_rt_view_of_the_vdeck_is_rts_own() {
    let Some(decks) = sv_testdata::shared_decks("comgeom") else {
        return;
    };
    let scene = load_file(&decks.join("vdeck-all-types.cg"), &LoadOptions::default())
        .unwrap()
        .scene;
    let (r, _) = Renderer::new(&scene, 1.0).unwrap();
    let cam = rt_camera(&scene, r.prepared(), 512, 512, &ViewSpec::default());
    // rt: "Model: X(-10, 100), Y(-9, 100), Z(-8, 200)", "Size: 259.316mm",
    // "Eye_pos: 181.13, 140.82, 173.493" (the view's centre; our eye sits
    // half a pixel left and down of it, where rt's first ray starts).
    let Lens::Ortho { height } = cam.lens else {
        panic!("rt's view is orthographic: {:?}", cam.lens)
    };
    assert!((height - 259.316).abs() < 1e-3, "{height}");
    let (right, up, _) = cam.basis();
    let centre = cam.eye + (right + up) * (0.5 * height / 512.0);
    for (ours, rts) in centre.to_array().into_iter().zip([181.13, 140.82, 173.493]) {
        assert!((ours - rts).abs() < 0.01, "{centre} vs rt's eye");
    }
}

/// A ground half-space `z ≤ 0` (card `0 0 1 0`), a box above it and a
/// sphere below it, in millimetres.
const GROUND: &str = "\
mm   ground test
    3    3
    1haf       .0000     .0000    1.0000     .0000                    half.s
    2rpp     -5.0000    5.0000   -5.0000    5.0000    1.0000   10.0000box.s
    3sph      .0000     .0000   -6.0000    3.0000                    sph.s
    1       1                                                        half.r
    2       2                                                        box.r
    3       3                                                        sph.r
   -1
    1 1000    0    1  100     all/half.r
    2 1001    0    1  100     all/box.r
    3 1002    0    1  100     all/sph.r
";

/// The commonest grey of `render GROUND --rt` seen from elevation `el`,
/// with the ground as written and with `N` and `d` turned about (`z ≥
/// −100`, a sky the eye is always in), and how many pixels have it.
fn commonest_grey(name: &str, deck: &str, el: &str) -> (u8, usize) {
    let dir = fresh_dir(name);
    let (path, out) = (dir.join("deck.cg"), dir.join("out.png"));
    std::fs::write(&path, deck).unwrap();
    let o = sv(&[
        "render",
        path.to_str().unwrap(),
        "--rt",
        &format!("--el={el}"),
        "--size",
        "64x64",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let picture = image::open(&out).unwrap().to_luma8();
    let mut counts = [0usize; 256];
    for p in picture.pixels() {
        counts[p.0[0] as usize] += 1;
    }
    let (grey, count) = counts.iter().enumerate().max_by_key(|c| c.1).unwrap();
    (grey as u8, *count)
}

#[test]
fn a_ray_that_starts_in_the_ground_is_shaded_as_rt_shades_it() {
    // From above, the lit ground: 0.4 + 0.6 sin 25° = 0.654 → 167.
    assert_eq!(commonest_grey("rt-ground-above", GROUND, "25"), (167, 3281));
    // From below, every ray starts inside the ground: rt shades it with
    // the ground's own normal, which faces away: ambient alone, 102 (a
    // face toward the viewer would be 255).
    assert_eq!(
        commonest_grey("rt-ground-below", GROUND, "-25"),
        (102, 3328)
    );
    let sky = GROUND.replace(
        "    1haf       .0000     .0000    1.0000     .0000 ",
        "    1haf       .0000     .0000   -1.0000 -100.0000 ",
    );
    // Inside the sky looking down, its normal (down) faces away: 102; from
    // below looking up it faces the eye at 25°: 167. rt drew all 4,096.
    assert_eq!(commonest_grey("rt-sky-above", &sky, "25"), (102, 4096));
    assert_eq!(commonest_grey("rt-sky-below", &sky, "-25"), (167, 4096));
}

#[test]
fn eye_light_is_rts_shading_whatever_the_regions_colour() {
    let dir = fresh_dir("rt-eye-light");
    let (path, out) = (dir.join("s.sv"), dir.join("out.png"));
    std::fs::write(
        &path,
        "BODY b SPH (0,0,0) 1\nREGION R = +b COLOR (1,0,0) K 0.3\n\
         CAMERA ORTHO EYE (0,0,10) AT (0,0,0) UP (0,1,0) HEIGHT 4\n",
    )
    .unwrap();
    let o = sv(&[
        "render",
        path.to_str().unwrap(),
        "--eye-light",
        "--size",
        "65x65",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let picture = image::open(&out).unwrap().to_rgb8();
    // The sphere's centre faces the eye: 0.4 + 0.6 = white, in grey.
    assert_eq!(picture.get_pixel(32, 32).0, [255, 255, 255]);
    // Half way out, cos θ = √(1 − 0.5²): 0.4 + 0.6 · 0.866 = 0.92 → 235.
    let [r, g, b] = picture.get_pixel(32 + 8, 32).0;
    assert!(r == g && g == b, "{r} {g} {b}");
    assert!((i32::from(r) - 235).abs() <= 1, "{r}");
}
