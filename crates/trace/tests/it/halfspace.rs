//! Packets and single rays agree where a half-space region overlaps others.

use sv_geom::{Body, BodyKind, Geometry, Region};
use sv_math::{DVec3, RayGen};
use sv_trace::{PrepareOptions, Prepared, Scratch, Tile};

#[test]
fn a_half_space_over_other_regions_is_hit_alike_by_packets_and_single_rays() {
    let mut g = Geometry::default();
    g.bodies.push(Body::new(
        "h",
        BodyKind::Haf,
        vec![0.5774, 0.5774, 0.5774, 5.0],
    ));
    g.bodies.push(Body::new(
        "c",
        BodyKind::Rcc,
        vec![0.0, 0.0, 0.0, 3.0, 3.0, 30.0, 7.0],
    ));
    g.bodies
        .push(Body::new("s", BodyKind::Sph, vec![0.0, 0.0, 0.0, 6.0]));
    for i in 0..3 {
        g.regions.push(Region::of_body(format!("r{i}"), i));
    }
    let with = Prepared::new(&g, &PrepareOptions::default()).unwrap().0;
    let without = Prepared::new(
        &g,
        &PrepareOptions {
            brute_force: true,
            ..PrepareOptions::default()
        },
    )
    .unwrap()
    .0;
    let eye = DVec3::new(0.0, -40.0, 69.282);
    let forward = (-eye).normalize();
    let up0 = DVec3::Z;
    let right = forward.cross(up0).normalize();
    let up = right.cross(forward);
    let gen = RayGen::new(eye, right * 30.0, up * 30.0, forward, true, 256, 256);
    let mut differ = 0;
    let mut hits_seen = 0;
    // The tile lists as a renderer makes them: every zone by entry bound.
    let all: Vec<u32> = (0..3).collect();
    let mut sorted = Vec::new();
    with.by_distance(&all, eye, Some(forward), &mut sorted);
    assert!(sorted.iter().all(|(near, _)| !near.is_nan()), "{sorted:?}");
    for ty in 0..16 {
        for tx in 0..16 {
            let tile = Tile {
                x0: tx * 16,
                x1: tx * 16 + 16,
                y0: ty * 16,
                y1: ty * 16 + 16,
            };
            let mut out = Vec::new();
            for (p, zones) in [(&with, Some(&sorted[..])), (&without, None)] {
                let mut s = Scratch::new(p);
                let (mut hits, mut rays, mut normals) = (Vec::new(), Vec::new(), Vec::new());
                let n = p.tile_hits(
                    &gen,
                    tile,
                    zones,
                    0.0,
                    f64::INFINITY,
                    &mut s,
                    &mut hits,
                    &mut rays,
                    &mut normals,
                );
                let mut v: Vec<_> = hits[..n]
                    .iter()
                    .map(|(k, h)| (*k, h.region, h.t.to_bits()))
                    .collect();
                v.sort();
                out.push(v);
            }
            hits_seen += out[0].len();
            differ += out[0].iter().zip(&out[1]).filter(|(a, b)| a != b).count()
                + out[0].len().abs_diff(out[1].len());
        }
    }
    assert!(hits_seen > 10_000);
    assert_eq!(differ, 0);
}
