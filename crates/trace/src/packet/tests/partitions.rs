//! Partitions in packets against the rays traced one by one.

use super::*;
use crate::{same_stretches, Partition, PrepareOptions};
use rand::SeedableRng;

/// Bit-for-bit equality of two partition lists.
fn same_parts(a: &[Partition], b: &[Partition]) -> bool {
    let bits = |p: &Partition| {
        let (x, y) = (p.span.a, p.span.b);
        (
            p.region,
            [x.t.to_bits(), y.t.to_bits()],
            [x.body, y.body, x.face_flip(), y.face_flip()],
        )
    };
    a.len() == b.len() && a.iter().zip(b).all(|(p, q)| bits(p) == bits(q))
}

/// [`Prepared::packet_partitions`] with bodies of a batch (zones, rays
/// and range) in the lanes of `s`: none is left as the ray before's.
fn with_bodies<S: Simd>(
    s: S,
    p: &Prepared,
    (zones, rays, tmin, tmax): (&[u32], &[Ray], f64, f64),
    sc: &mut Scratch,
    out: &mut [Vec<Partition>],
) {
    let repeats =
        p.packet_partitions::<S, true>(s, zones, (rays, RaysShare::Unknown), tmin, tmax, sc, out);
    assert_eq!(repeats, 0, "partitions with bodies are all made");
}

/// The stretches of the rays of `repeats` (bit `k` for ray `k`), left
/// empty as those of the ray before: copied from it. Fails where one was
/// not left empty.
fn repeat(out: &mut [Vec<Partition>], repeats: u64) -> usize {
    for k in 0..out.len().min(64) {
        if repeats >> k & 1 != 0 {
            assert!(
                out[k].is_empty(),
                "ray {k} left as the one before, but made"
            );
            out[k] = out[k - 1].clone();
        }
    }
    repeats.count_ones() as usize
}

#[test]
fn packets_give_the_partitions_of_rays_traced_one_by_one() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(9);
    let (mut stretches, mut two_or_more) = (0, 0);
    // Rays whose stretches the packets left as the ray before's.
    let repeated = std::cell::Cell::new(0);
    for i in 0..31 {
        let g = geometry(&mut rng, i % 2 == 0 || i >= 8, (i >= 8).then(|| i - 8));
        let p = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
        let all: Vec<u32> = (0..p.zones.len() as u32).collect();
        let mut s = Scratch::new(&p);
        // The same, traced one by one (no lanes).
        let brute_force = PrepareOptions {
            brute_force: true,
            ..PrepareOptions::default()
        };
        let alone = Prepared::new(&g, &brute_force).unwrap().0;
        let mut s_alone = Scratch::new(&alone);
        for batch in 0..60 {
            let (mut rays, _, _) = rays(&mut rng, batch);
            // Some batches' rays take the first's direction, some its
            // origin too but for one coordinate (a row); the stretches are
            // then asked for as of rays that share it.
            let shared = match batch % 6 {
                2 => RaysShare::Direction,
                5 => RaysShare::AllBut(batch / 6 % 3),
                _ => RaysShare::Unknown,
            };
            let first = rays[0];
            for (k, ray) in rays.iter_mut().enumerate() {
                *ray = match shared {
                    RaysShare::Unknown => continue,
                    RaysShare::Direction => Ray::new(ray.origin, first.dir),
                    RaysShare::AllBut(varying) => {
                        let mut origin = first.origin;
                        origin[varying] += 0.05 * (k as f64 - 18.0);
                        Ray::new(origin, first.dir)
                    }
                };
            }
            let (tmin, tmax) = match batch % 7 {
                3 => (0.5, f64::INFINITY),
                5 => (0.0, 3.0),
                _ => (0.0, f64::INFINITY),
            };
            let one: Vec<Vec<Partition>> = rays
                .iter()
                .map(|ray| {
                    let mut parts = Vec::new();
                    p.partitions(ray, tmin, tmax, &mut s, &mut parts);
                    parts
                })
                .collect();
            stretches += one.iter().map(Vec::len).sum::<usize>();
            two_or_more += one.iter().filter(|parts| parts.len() > 1).count();
            let compare = |how: &str,
                           same: fn(&[Partition], &[Partition]) -> bool,
                           trace: &mut dyn FnMut(&mut [Vec<Partition>])| {
                let mut many = vec![vec![]; rays.len()];
                trace(&mut many);
                for (k, (a, b)) in one.iter().zip(&many).enumerate() {
                    assert!(same(a, b), "{how}, batch {batch}, ray {k}: {a:?} {b:?}");
                }
            };
            let check = |how: &str, trace: &mut dyn FnMut(&mut [Vec<Partition>])| {
                compare(how, same_parts, trace)
            };
            let check_stretches = |how: &str, trace: &mut dyn FnMut(&mut [Vec<Partition>])| {
                compare(how, same_stretches, trace)
            };
            check("list, ray by ray", &mut |o| {
                for (ray, parts) in rays.iter().zip(o) {
                    p.partitions_in(&all, ray, tmin, tmax, &mut s, parts);
                }
            });
            let batch = (&all[..], &rays[..], tmin, tmax);
            check("four portable lanes", &mut |o| {
                with_bodies(Portable::<4>, &p, batch, &mut s, o)
            });
            check("eight portable lanes", &mut |o| {
                with_bodies(Portable::<8>, &p, batch, &mut s, o)
            });
            check("the widest here", &mut |o| {
                p.partitions_of_rays_in(&all, &rays, tmin, tmax, &mut s, o)
            });
            check_stretches("stretches, four portable lanes", &mut |o| {
                let (zones, rays, tmin, tmax) = batch;
                let repeats = p.packet_partitions::<_, false>(
                    Portable::<4>,
                    zones,
                    (rays, shared),
                    tmin,
                    tmax,
                    &mut s,
                    o,
                );
                repeated.set(repeated.get() + repeat(o, repeats));
            });
            check_stretches("stretches, no lanes", &mut |o| {
                let rays = (&rays[..], shared);
                let repeats = alone.stretches_of_rays_in(&all, rays, tmin, tmax, &mut s_alone, o);
                // Every ray but the first is compared with the ray before.
                for k in 1..one.len().min(64) {
                    let same = same_stretches(&one[k], &one[k - 1]);
                    assert_eq!(repeats >> k & 1 != 0, same, "no lanes, ray {k}");
                }
                repeated.set(repeated.get() + repeat(o, repeats));
            });
            check_stretches("stretches, the widest here", &mut |o| {
                let repeats = p.stretches_of_rays_in(&all, (&rays, shared), tmin, tmax, &mut s, o);
                repeated.set(repeated.get() + repeat(o, repeats));
            });
            #[cfg(target_arch = "x86_64")]
            {
                let unknown = (&rays[..], RaysShare::Unknown);
                // SAFETY (both): the tokens prove the instructions are
                // there.
                if let Some(t) = sv_math::simd::Avx512::detect() {
                    check("AVX-512", &mut |o| unsafe {
                        partitions_avx512(&p, t, &all, unknown, tmin, tmax, &mut s, o);
                    });
                }
                if let Some(t) = sv_math::simd::Avx2::detect() {
                    check("AVX2", &mut |o| unsafe {
                        partitions_avx2(&p, t, &all, unknown, tmin, tmax, &mut s, o);
                    });
                    check_stretches("stretches, AVX2", &mut |o| {
                        // SAFETY: as above.
                        let repeats = unsafe {
                            stretches_avx2(&p, t, &all, (&rays, shared), tmin, tmax, &mut s, o)
                        };
                        repeated.set(repeated.get() + repeat(o, repeats));
                    });
                }
            }
        }
    }
    // Many rays crossed stretches, many of them several, and many saw
    // what the ray before saw.
    assert!(
        stretches > 20_000 && two_or_more > 2_000 && repeated.get() > 1_000,
        "{stretches} {two_or_more} {}",
        repeated.get()
    );
}

#[test]
fn what_rays_share_is_to_the_bit() {
    let along_z = |x: f64, y: f64| Ray::new(DVec3::new(x, y, -1.0), DVec3::Z);
    let row = [along_z(0.0, 2.0), along_z(0.5, 2.0), along_z(1.0, 2.0)];
    assert!(RaysShare::AllBut(0).holds_for(&row));
    assert!(RaysShare::Direction.holds_for(&row));
    assert!(!RaysShare::AllBut(1).holds_for(&row));
    // -0.0 equals 0.0 but its reciprocal is the other infinity: the
    // lanes would copy the wrong one.
    let signed = Ray::new(DVec3::new(0.0, 2.0, -1.0), DVec3::new(-0.0, 0.0, 1.0));
    assert!(!RaysShare::Direction.holds_for(&[row[0], signed]));
    assert!(RaysShare::Unknown.holds_for(&[row[0], signed]));
}
