//! Shadow rays toward a parallel light in packets.

use super::*;
use crate::PrepareOptions;
use rand::SeedableRng;

#[test]
fn shadow_packets_agree_with_shadow_rays_one_by_one() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(9);
    let (mut blocked, mut tested) = (0, 0);
    for i in 0..8 {
        let g = geometry(&mut rng, i % 2 == 0, None);
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let all: Vec<u32> = (0..p.zones.len() as u32).collect();
        let mut s = Scratch::new(&p);
        let (mut sorted, mut hits, mut one) = (Vec::new(), Vec::new(), Vec::new());
        for batch in 0..40 {
            // Points on surfaces (with the zones their shadow rays
            // skip), from the first hits of a batch of rays, and a few
            // points in the open.
            let (rays, eye, parallel) = rays(&mut rng, batch + 2);
            p.by_distance(&all, eye, parallel, &mut sorted);
            hits.clear();
            hits.resize(rays.len(), (0, Hit::NONE));
            let n = p.hits_one_by_one(&sorted, &rays, 0.0, f64::INFINITY, &mut s, &mut hits);
            let mut from: Vec<(DVec3, Option<u32>)> = hits[..n]
                .iter()
                .map(|(k, h)| (rays[*k as usize].at(h.t), p.shadow_skip(h)))
                .collect();
            from.extend((0..5).map(|_| {
                (
                    DVec3::new(
                        rng.gen_range(-1.5..1.5),
                        rng.gen_range(-1.5..1.5),
                        rng.gen_range(-1.5..1.5),
                    ),
                    None,
                )
            }));
            // Origins that are not numbers or lie at infinity, and one far
            // off the light buffer's grid.
            from.extend([
                (DVec3::new(f64::NAN, 0.1, 0.2), None),
                (DVec3::new(0.3, f64::INFINITY, -0.2), None),
                (DVec3::new(f64::NEG_INFINITY, 0.0, 0.0), None),
                (DVec3::splat(1e30), None),
            ]);
            // The sun along an axis now and then: shadow rays in face
            // planes, infinite reciprocals.
            let toward = if batch % 4 == 0 {
                [DVec3::X, DVec3::Y, DVec3::Z, -DVec3::Z][batch / 4 % 4]
            } else {
                DVec3::new(
                    rng.gen_range(-1.0..1.0),
                    rng.gen_range(-1.0..1.0),
                    rng.gen_range(-1.0..1.0),
                )
            };
            let lb = LightBuffer::new(&p, toward);
            let tmin = 10.0 * p.tol;
            let mut last = None;
            one.clear();
            one.extend(from.iter().map(|&(o, skip)| {
                p.occluded_by(
                    &lb,
                    &lb.shadow_ray(o),
                    tmin,
                    f64::INFINITY,
                    skip,
                    &mut last,
                    &mut s,
                )
            }));
            blocked += one.iter().filter(|&&b| b).count();
            tested += one.len();
            // Each path starts from the wrong answers: one that leaves a
            // ray alone fails.
            let wrong: Vec<bool> = one.iter().map(|b| !b).collect();
            for (how, many) in shadow_paths(&p, &lb, &from, tmin, &mut s, &wrong) {
                assert_eq!(one, many, "{how}, batch {batch}");
            }
        }
    }
    // Both answers were common.
    assert!(
        blocked * 5 > tested && blocked * 5 < 4 * tested,
        "{blocked} of {tested}"
    );
}
