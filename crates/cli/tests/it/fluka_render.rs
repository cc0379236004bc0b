//! Every FLUKA test input renders a picture that shows something (the
//! issue's "renders a non-empty picture"), framed automatically even when
//! its regions are bounded only by planes and infinite cylinders.

use sv_formats::{load_file, LoadOptions};
use sv_render::{Renderer, Settings};

#[test]
fn every_fluka_test_input_renders_a_non_empty_picture() {
    let Some(files) = sv_testdata::shared_files("fluka/pyg4ometry-testdata", &[".inp"]) else {
        return;
    };
    assert!(files.len() >= 80, "the test set has {} inputs", files.len());
    let mut empty = Vec::new();
    for f in &files {
        let mut scene = load_file(f, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", f.display()))
            .scene;
        // As `render` does: a model that is all vacuum shows its vacuum.
        scene.show_air_if_nothing_else();
        let (r, _) =
            Renderer::new(&scene, 4.0 / 3.0).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        // Small pictures first; a needle-thin model (009_ARB: 7 cm wide and
        // 3572 cm tall, framed whole) is only a pixel or two wide at full size.
        let covered = |w, h| {
            let frame = r.render(
                &Settings {
                    width: w,
                    height: h,
                    shadows: true,
                    samples: 1,
                    aovs: false,
                },
                &|_| {},
            );
            frame.alpha.iter().filter(|a| **a > 0.0).count()
        };
        if covered(48, 36) == 0 && covered(960, 720) == 0 {
            empty.push(f.file_name().unwrap().to_string_lossy().into_owned());
        }
    }
    assert!(empty.is_empty(), "inputs that render nothing: {empty:?}");
}
