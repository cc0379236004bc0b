//! The renderer's tile lists against the frusta of its tiles.

use crate::tiles::{BandLists, MAX_TILE_ZONES, TILE};
use crate::*;
use sv_geom::{Body, BodyKind, Region};
use sv_math::DVec3;
use sv_scene::{Camera, Scene};
use sv_scene::{Lens, RegionProps};
use sv_trace::{by_entry, Frustum, RasterExtent};

/// A crowd of spheres and turned boxes about the origin, over a ground
/// half-space, each its own region.
fn crowd() -> Scene {
    let mut s = Scene::default();
    let mut seed = 3u64;
    let mut rnd = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for i in 0..600 {
        let c = [rnd() * 10.0, rnd() * 10.0, rnd() * 10.0];
        let body = if i % 3 == 0 {
            let (a, b) = (rnd(), rnd());
            Body::new(
                format!("b{i}"),
                BodyKind::Box,
                vec![c[0], c[1], c[2], a, b, 0.0, -b, a, 0.0, 0.0, 0.0, 0.8],
            )
        } else {
            Body::new(format!("b{i}"), BodyKind::Sph, vec![c[0], c[1], c[2], 0.4])
        };
        s.geometry.bodies.push(body);
        s.geometry.regions.push(Region::of_body(format!("r{i}"), i));
    }
    // A rod passing beside the first camera's eye, partly behind it.
    let n = s.geometry.bodies.len();
    s.geometry.bodies.push(Body::new(
        "rod",
        BodyKind::Rpp,
        vec![-10.0, 10.0, 0.5, 0.7, -0.2, 0.2],
    ));
    s.geometry.regions.push(Region::of_body("rod", n));
    s.geometry.bodies.push(Body::new(
        "ground",
        BodyKind::Haf,
        vec![0.0, 0.0, 1.0, -11.0],
    ));
    s.geometry.regions.push(Region::of_body("ground", n + 1));
    s.regions = vec![RegionProps::default(); n + 2];
    s
}

#[test]
fn a_picture_without_pixels_is_empty() {
    let (r, _) = Renderer::new(&crowd(), 4.0 / 3.0).unwrap();
    for (width, height) in [(0, 0), (0, 48), (64, 0)] {
        let st = Settings {
            width,
            height,
            ..Settings::default()
        };
        let frame = r.render(&st, &|_| {});
        assert!(frame.rgb.is_empty() && frame.alpha.is_empty());
    }
}

#[test]
fn tile_lists_hold_every_zone_in_front_of_the_eye_their_frustum_keeps() {
    let scene = crowd();
    let (r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
    // From far off (the crowd in a few tiles, too many for their
    // lists), from inside the crowd (zones straddle the eye's plane or
    // lie behind it), from outside, and orthographic.
    let cameras = [
        Camera::looking_at(
            DVec3::new(3000.0, -2500.0, 1200.0),
            DVec3::ZERO,
            DVec3::Z,
            Lens::Fov { vertical_deg: 40.0 },
        ),
        Camera::looking_at(
            DVec3::ZERO,
            DVec3::new(1.0, 2.0, 0.3),
            DVec3::Z,
            Lens::Fov { vertical_deg: 70.0 },
        ),
        Camera::looking_at(
            DVec3::new(30.0, -25.0, 12.0),
            DVec3::ZERO,
            DVec3::Z,
            Lens::Fov { vertical_deg: 40.0 },
        ),
        Camera::looking_at(
            DVec3::new(5.0, 30.0, 8.0),
            DVec3::ZERO,
            DVec3::Z,
            Lens::Ortho { height: 16.0 },
        ),
    ];
    // The picture's centre inside a tile, not on the tiles' corners: the
    // far-off crowd lands in one tile.
    let (w, h) = (328, 248);
    let (mut lists, mut own) = (BandLists::default(), Vec::new());
    let (mut kept, mut extra, mut behind, mut overflowing) = (0, 0, 0, 0);
    for cam in cameras {
        let gen = cam.rays(w as u32, h as u32);
        let parallel = matches!(cam.lens, Lens::Ortho { .. }).then(|| cam.dir.normalize());
        let bins = r.zone_bins(&gen, w, h);
        assert!(!bins.lead.is_empty(), "the ground is in every list");
        for (band, y0) in (0..h).step_by(TILE).enumerate() {
            let y1 = (y0 + TILE).min(h);
            r.band_lists(&bins.lead, &bins.bands[band], &gen, w, (y0, y1), &mut lists);
            for (t, x0) in (0..w).step_by(TILE).enumerate() {
                let x1 = (x0 + TILE).min(w);
                let corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
                    .map(|(x, y)| gen.ray(x as f64, y as f64));
                r.prepared()
                    .frustum_zones(&Frustum::from_corners(corners), usize::MAX, &mut own);
                if lists.over[t] {
                    overflowing += 1;
                    assert!(own.len() > MAX_TILE_ZONES, "tile {t} of band {band}");
                    continue;
                }
                let list = &lists.tiles[t];
                // Each with its entry bound for the camera (a bounded
                // zone's in single precision, rounded down: never above
                // it, and as tight as single precision allows), the
                // unbounded zones among them, in the order of
                // `by_distance`.
                for &(near, z) in list {
                    let exact = r.prepared().entry_bound(z, cam.eye, parallel);
                    assert!(near <= exact, "zone {z}: {near} past {exact}");
                    let close = exact - near <= 1e-6 * exact.abs().max(1.0);
                    assert!(near == exact || close, "zone {z}: {near} for {exact}");
                }
                assert!(bins.lead.iter().all(|e| list.contains(e)));
                assert!(list.is_sorted_by(|a, b| by_entry(a, b).is_lt()));
                let list: Vec<u32> = list.iter().map(|&(_, z)| z).collect();
                for &z in &own {
                    if r.prepared().zone_rect(z, &gen) == RasterExtent::Nowhere {
                        behind += 1;
                    } else {
                        assert!(list.contains(&z), "zone {z}, tile {t} of band {band}");
                        kept += 1;
                    }
                }
                extra += list.iter().filter(|z| !own.contains(z)).count();
            }
        }
    }
    assert!(kept > 3000, "{kept} zones listed");
    assert!(behind > 0, "no zone behind the eye");
    assert!(overflowing > 0, "no tile overflows");
    // A pixel's padding and zones across the eye's plane: a few more.
    assert!(
        extra * 10 < kept,
        "{extra} more than the frusta keep, of {kept}"
    );
}
