//! Tiles of the raster, and the public calls with packets on and off.

use super::*;
use crate::PrepareOptions;
use rand::SeedableRng;

#[test]
fn tiles_of_the_raster_find_the_hits_rays_and_normals_of_pixels_traced_one_by_one() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(21);
    let (mut hits_seen, mut pixels) = (0, 0);
    let inf = f64::INFINITY;
    for i in 0..6 {
        let g = if i < 4 {
            geometry(&mut rng, i % 2 == 0, None)
        } else {
            hollows()
        };
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let all: Vec<u32> = (0..p.zones.len() as u32).collect();
        let mut s = Scratch::new(&p);
        let mut sorted = Vec::new();
        for view in 0..12 {
            // A camera from outside the model or inside it, perspective or
            // orthographic, on a raster whose tiles end short at the edges.
            let eye = DVec3::new(
                rng.gen_range(-3.0..3.0),
                rng.gen_range(-3.0..3.0),
                rng.gen_range(-3.0..3.0),
            );
            let forward = (DVec3::new(0.1, -0.2, 0.05) - eye).normalize();
            let (r, u) = sv_math::orthonormal_basis(forward);
            let ortho = view % 3 == 0;
            let half = if ortho { 1.5 } else { 0.6 };
            let gen = RayGen::new(eye, r * half * 1.2, u * half, forward, ortho, 37, 29);
            p.by_distance(&all, eye, ortho.then_some(forward), &mut sorted);
            let tile = |x0, x1, y0, y1| Tile { x0, x1, y0, y1 };
            for tile in [
                tile(0, 16, 0, 16),
                tile(32, 37, 16, 29),
                tile(16, 32, 27, 29),
                tile(3, 4, 5, 6),
            ] {
                for zones in [Some(&sorted[..]), None] {
                    let mut want = Traced::new(tile.len());
                    let n = p.tile_one_by_one(
                        &gen,
                        tile,
                        zones,
                        0.0,
                        inf,
                        &mut s,
                        &mut want.hits,
                        &mut want.rays,
                        &mut want.normals,
                    );
                    let want = want.sorted(n);
                    hits_seen += n;
                    pixels += tile.len();
                    // Each hit's ray is `gen.ray` through its pixel's centre,
                    // and its normal the scalar tracer's.
                    for (((k, h), ray), normal) in
                        want.hits.iter().zip(&want.rays).zip(&want.normals)
                    {
                        let w = tile.x1 - tile.x0;
                        let (x, y) = (tile.x0 + *k as usize % w, tile.y0 + *k as usize / w);
                        assert_eq!(*ray, gen.ray(x as f64 + 0.5, y as f64 + 0.5));
                        assert!(same_bits(&[*normal], &[p.normal(h, ray)]));
                    }
                    let check = |how: &str, got: &Traced, m: usize| {
                        let got = got.sorted(m);
                        assert!(same(&want.hits, &got.hits), "{how}, view {view}, {tile:?}");
                        let (a, b): (Vec<f64>, Vec<f64>) = (
                            Ray::coordinates(&want.rays).to_vec(),
                            Ray::coordinates(&got.rays).to_vec(),
                        );
                        assert!(
                            a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
                            "{how} rays, view {view}, {tile:?}"
                        );
                        assert!(
                            same_bits(&want.normals, &got.normals),
                            "{how} normals, view {view}, {tile:?}"
                        );
                    };
                    // Each path into fresh buffers: none sees another's.
                    for (how, got, m) in tile_paths(&p, &gen, tile, zones, &mut s) {
                        check(how, &got, m);
                    }
                    // How each pixel faces its ray: the scalar answer for
                    // each hit's pixel, and no other pixel written.
                    let mut facing = vec![FACING_MISS; tile.len()];
                    for ((k, h), ray) in want.hits.iter().zip(&want.rays) {
                        facing[*k as usize] = p.facing(h, ray, &mut s);
                    }
                    let bits = |f: &[f64]| f.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    for (how, got, m) in facing_paths(&p, &gen, tile, zones, &mut s) {
                        assert_eq!(m, n, "{how} facing hits, view {view}, {tile:?}");
                        assert_eq!(
                            bits(&got),
                            bits(&facing),
                            "{how} facing, view {view}, {tile:?}"
                        );
                    }
                }
            }
        }
    }
    assert!(
        hits_seen * 5 > pixels,
        "{hits_seen} hits of {pixels} pixels"
    );
}

#[test]
fn the_public_calls_answer_as_the_rays_one_by_one_with_packets_or_without() {
    // Whatever lanes this processor has: each call as the renderer makes
    // it, against the same geometry with packets turned off.
    let mut rng = rand_pcg::Pcg64::seed_from_u64(33);
    let inf = f64::INFINITY;
    let (mut hits_seen, mut blocked) = (0, 0);
    for i in 0..6 {
        let g = geometry(&mut rng, i % 2 == 0, None);
        let with = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let mut without = with.clone();
        without.packets = false;
        let all: Vec<u32> = (0..with.zones.len() as u32).collect();
        let mut s = Scratch::new(&with);
        let mut sorted = Vec::new();
        let (mut a, mut b) = (Traced::new(0), Traced::new(0));
        let (mut fa, mut fb) = (Vec::new(), Vec::new());
        for batch in 0..30 {
            let (rays, eye, parallel) = rays(&mut rng, batch);
            if batch % 5 < 2 {
                sorted.clear();
                sorted.extend(all.iter().map(|&z| (f64::NEG_INFINITY, z)));
            } else {
                with.by_distance(&all, eye, parallel, &mut sorted);
            }
            let n = with.first_hits_in(&sorted, &rays, 0.0, inf, &mut s, &mut a.hits);
            let m = without.first_hits_in(&sorted, &rays, 0.0, inf, &mut s, &mut b.hits);
            assert!(same(&a.hits[..n], &b.hits[..m]), "list, batch {batch}");
            let n = with.first_hits(&rays, 0.0, inf, &mut s, &mut a.hits);
            let m = without.first_hits(&rays, 0.0, inf, &mut s, &mut b.hits);
            assert!(same(&a.hits[..n], &b.hits[..m]), "walk, batch {batch}");
            hits_seen += n;

            let from: Vec<(DVec3, Option<u32>)> = b.hits[..m]
                .iter()
                .map(|(k, h)| (rays[*k as usize].at(h.t), with.shadow_skip(h)))
                .collect();
            let lb = LightBuffer::new(&with, DVec3::new(0.3, -0.5, 0.8));
            let (mut x, mut y) = (Vec::new(), Vec::new());
            let tmin = 10.0 * with.tol;
            with.occluded_toward(&lb, &from, tmin, &mut None, &mut s, &mut x);
            without.occluded_toward(&lb, &from, tmin, &mut None, &mut s, &mut y);
            assert_eq!(x, y, "shadows, batch {batch}");
            blocked += x.iter().filter(|&&b| b).count();

            let forward = (DVec3::new(0.1, -0.2, 0.05) - eye).normalize();
            let (r, u) = sv_math::orthonormal_basis(forward);
            let ortho = batch % 2 == 0;
            let gen = RayGen::new(eye, r * 1.2, u, forward, ortho, 21, 19);
            let tile = Tile {
                x0: 3,
                x1: 21,
                y0: 2,
                y1: 19,
            };
            for zones in [Some(&sorted[..]), None] {
                let n = with.tile_hits(
                    &gen,
                    tile,
                    zones,
                    0.0,
                    inf,
                    &mut s,
                    &mut a.hits,
                    &mut a.rays,
                    &mut a.normals,
                );
                let m = without.tile_hits(
                    &gen,
                    tile,
                    zones,
                    0.0,
                    inf,
                    &mut s,
                    &mut b.hits,
                    &mut b.rays,
                    &mut b.normals,
                );
                let (x, y) = (a.sorted(n), b.sorted(m));
                assert!(same(&x.hits, &y.hits), "tile, batch {batch}");
                let n = with.tile_facing(&gen, tile, zones, 0.0, inf, &mut s, &mut fa);
                let m = without.tile_facing(&gen, tile, zones, 0.0, inf, &mut s, &mut fb);
                assert_eq!(n, m, "tile facing hits, batch {batch}");
                assert!(
                    fa[..tile.len()]
                        .iter()
                        .zip(&fb[..tile.len()])
                        .all(|(p, q)| p.to_bits() == q.to_bits()),
                    "tile facing, batch {batch}"
                );
                assert!(
                    same_bits(&x.normals, &y.normals),
                    "tile normals, batch {batch}"
                );
                assert!(
                    x.rays.iter().zip(&y.rays).all(|(p, q)| same_bits(
                        &[p.origin, p.dir, p.inv_dir],
                        &[q.origin, q.dir, q.inv_dir]
                    )),
                    "tile rays, batch {batch}"
                );
            }
        }
    }
    assert!(
        hits_seen > 1000 && blocked > 100,
        "{hits_seen} hits, {blocked} blocked"
    );
}
