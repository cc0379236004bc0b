//! Primary rays in packets, from a list and walking the hierarchy.

use super::*;
use crate::PrepareOptions;
use rand::SeedableRng;

#[test]
fn packets_find_the_hits_of_rays_traced_one_by_one() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(5);
    let (mut lanes_zones, mut other_zones, mut hits, mut rays_cast) = (0, 0, 0, 0);
    for i in 0..31 {
        let g = geometry(&mut rng, i % 2 == 0 || i >= 8, (i >= 8).then(|| i - 8));
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        lanes_zones += p.zones.iter().filter(|z| z.lanes).count();
        other_zones += p.zones.iter().filter(|z| !z.lanes).count();
        let all: Vec<u32> = (0..p.zones.len() as u32).collect();
        let mut s = Scratch::new(&p);
        let (mut sorted, mut one, mut many) = (Vec::new(), Vec::new(), Vec::new());
        for batch in 0..100 {
            let (rays, eye, parallel) = rays(&mut rng, batch);
            // The rays along the axes, through edges and along the
            // generators share no plane of origins: their list is every
            // zone from the lowest entry.
            if batch % 5 < 2 {
                sorted.clear();
                sorted.extend(all.iter().map(|&z| (f64::NEG_INFINITY, z)));
            } else {
                p.by_distance(&all, eye, parallel, &mut sorted);
            }
            let tmin = if batch % 7 == 3 { 0.5 } else { 0.0 };
            one.clear();
            one.resize(rays.len(), (0, Hit::NONE));
            let n = p.hits_one_by_one(&sorted, &rays, tmin, f64::INFINITY, &mut s, &mut one);
            one.truncate(n);
            hits += n;
            rays_cast += rays.len();
            // Every way of tracing them: the tile's list and the
            // hierarchy, ray by ray and in packets of every width.
            let inf = f64::INFINITY;
            let mut check = |how: &str, trace: &mut Tracer| {
                many.clear();
                many.resize(rays.len(), (0, Hit::NONE));
                let m = trace(&mut many);
                assert!(same(&one, &many[..m]), "{how}, batch {batch}");
            };
            check("list, four portable lanes", &mut |o| {
                p.rays_in_packets(Portable::<4>, Some(&sorted), &rays, tmin, inf, &mut s, o)
            });
            check("list, eight portable lanes", &mut |o| {
                p.rays_in_packets(Portable::<8>, Some(&sorted), &rays, tmin, inf, &mut s, o)
            });
            check("walk, ray by ray", &mut |o| {
                p.walk_one_by_one(&rays, tmin, inf, &mut s, o)
            });
            check("walk, four portable lanes", &mut |o| {
                p.rays_in_packets(Portable::<4>, None, &rays, tmin, inf, &mut s, o)
            });
            check("walk, eight portable lanes", &mut |o| {
                p.rays_in_packets(Portable::<8>, None, &rays, tmin, inf, &mut s, o)
            });
            #[cfg(target_arch = "x86_64")]
            {
                // SAFETY (all four): the tokens prove the instructions
                // are there.
                if let Some(t) = sv_math::simd::Avx512::detect() {
                    check("list, AVX-512", &mut |o| unsafe {
                        rays_avx512(&p, t, Some(&sorted), &rays, tmin, inf, &mut s, o)
                    });
                    check("walk, AVX-512", &mut |o| unsafe {
                        rays_avx512(&p, t, None, &rays, tmin, inf, &mut s, o)
                    });
                }
                if let Some(t) = sv_math::simd::Avx2::detect() {
                    check("list, AVX2", &mut |o| unsafe {
                        rays_avx2(&p, t, Some(&sorted), &rays, tmin, inf, &mut s, o)
                    });
                    check("walk, AVX2", &mut |o| unsafe {
                        rays_avx2(&p, t, None, &rays, tmin, inf, &mut s, o)
                    });
                }
            }
        }
    }
    // Zones in lanes and zones left to the scalar code were both met,
    // and many rays hit.
    assert!(
        lanes_zones > 100 && other_zones > 10,
        "{lanes_zones} {other_zones}"
    );
    assert!(hits * 4 > rays_cast, "{hits} of {rays_cast}");
}
