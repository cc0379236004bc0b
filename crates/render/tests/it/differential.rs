//! The renderer's fast paths against single rays, pixel by pixel, on
//! random scenes: tiles of packets walking sorted zone lists (and light
//! buffers for the shadows) must give, bit for bit, the colour that one ray
//! a pixel traced and shaded alone gives, the auxiliary images the same
//! hit, and `shoot`'s crossings the same first surface. The scenes hold
//! every body type, half-spaces and the infinite FLUKA bodies, overlaps,
//! flush faces, transparent regions and groups, seen from outside and from
//! inside regions, in perspective and orthographic views.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use sv_geom::{Body, BodyKind, Group, Op, Region, Term, Zone};
use sv_math::DVec3;
use sv_render::{Renderer, Settings};
use sv_scene::{Camera, Lens, Light, LightKind, RegionProps, Scene};
use sv_trace::Scratch;

/// A body of kind `kind` about `c` of size about `r`, turned by `a`.
fn body(kind: BodyKind, c: DVec3, r: f64, a: DVec3) -> Body {
    use BodyKind::*;
    let (u, v) = sv_math::orthonormal_basis(a.normalize());
    let w = a.normalize();
    let p = |v: DVec3| v.to_array().to_vec();
    let params: Vec<f64> = match kind {
        Sph => [p(c), vec![r]].concat(),
        Rcc => [p(c), p(w * 2.0 * r), vec![0.6 * r]].concat(),
        Rec => [p(c), p(w * 2.0 * r), p(u * 0.7 * r), p(v * 0.4 * r)].concat(),
        Trc => [p(c), p(w * 2.0 * r), vec![0.8 * r, 0.3 * r]].concat(),
        Tec => [
            p(c),
            p(w * 2.0 * r),
            p(u * 0.7 * r),
            p(v * 0.4 * r),
            vec![1.7],
        ]
        .concat(),
        Ell => [p(c - w * 0.4 * r), p(c + w * 0.4 * r), vec![1.6 * r]].concat(),
        Ell1 => [p(c), p(w * r), vec![0.5 * r]].concat(),
        Ellg => [p(c), p(w * r), p(u * 0.6 * r), p(v * 0.4 * r)].concat(),
        Rpp => vec![
            c.x - r,
            c.x + r,
            c.y - 0.7 * r,
            c.y + 0.5 * r,
            c.z - 0.4 * r,
            c.z + r,
        ],
        Box => [p(c), p(w * r), p(u * 0.8 * r), p(v * 1.2 * r)].concat(),
        Raw => [p(c), p(w * r), p(u * r), p(v * 1.3 * r)].concat(),
        Arb4 => [p(c), p(c + w * r), p(c + u * r), p(c + v * r)].concat(),
        Arb5 => [
            p(c),
            p(c + w * r),
            p(c + w * r + u * r),
            p(c + u * r),
            p(c + v * r),
        ]
        .concat(),
        Arb6 => [
            p(c),
            p(c + w * r),
            p(c + w * r + u * r),
            p(c + u * r),
            p(c + v * r),
            p(c + v * r + u * r),
        ]
        .concat(),
        Arb7 => [
            p(c),
            p(c + w * r),
            p(c + w * r + u * r),
            p(c + u * r),
            p(c + v * r),
            p(c + v * r + w * r),
            p(c + v * r + w * r + u * r),
        ]
        .concat(),
        Arb8 => {
            let corners: Vec<f64> = (0..8)
                .flat_map(|i| {
                    let q = c
                        + w * r * ((i & 1) ^ (i >> 1 & 1)) as f64
                        + u * r * (i >> 1 & 1) as f64
                        + v * r * (i >> 2 & 1) as f64;
                    p(q)
                })
                .collect();
            corners
        }
        Tgc => [
            p(c),
            p(w * 2.0 * r),
            p(u * 0.7 * r),
            p(v * 0.5 * r),
            vec![0.2 * r, 0.45 * r],
        ]
        .concat(),
        Tor => [p(c), p(w), vec![r, 0.3 * r]].concat(),
        Haf => [p(w), vec![w.dot(c)]].concat(),
        Ars => {
            let mut v = vec![3.0, 4.0];
            for k in 0..3 {
                for j in 0..4 {
                    let ang = j as f64 * std::f64::consts::FRAC_PI_2;
                    let rad = if k == 1 { r } else { 0.5 * r };
                    let q = c
                        + u * rad * ang.cos()
                        + v_axis(u, w) * rad * ang.sin()
                        + w * (k as f64 - 1.0) * r;
                    v.extend(p(q));
                }
            }
            v
        }
        Xyp => vec![c.z],
        Xzp => vec![c.y],
        Yzp => vec![c.x],
        Pla => [p(w), p(c)].concat(),
        Xcc => vec![c.y, c.z, 0.5 * r],
        Ycc => vec![c.z, c.x, 0.5 * r],
        Zcc => vec![c.x, c.y, 0.5 * r],
        Xec => vec![c.y, c.z, 0.5 * r, 0.3 * r],
        Yec => vec![c.z, c.x, 0.5 * r, 0.3 * r],
        Zec => vec![c.x, c.y, 0.3 * r, 0.5 * r],
        Qua => vec![
            1.0,
            1.0,
            -0.5,
            0.0,
            0.0,
            0.0,
            -2.0 * c.x,
            -2.0 * c.y,
            c.z,
            c.x * c.x + c.y * c.y - r * r,
        ],
        ArbF => {
            let mut v: Vec<f64> = (0..8)
                .flat_map(|i| {
                    p(
                        c + DVec3::new((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2 & 1) as f64)
                            * r,
                    )
                })
                .collect();
            v.extend([1243.0, 5687.0, 1265.0, 3487.0, 1375.0, 2486.0]);
            v
        }
    };
    Body::new(format!("{kind}"), kind, params)
}

/// The third axis of a frame with `u` and `w`.
fn v_axis(u: DVec3, w: DVec3) -> DVec3 {
    w.cross(u)
}

/// A random scene: bodies of random kinds, regions of one or two zones of
/// them (some with groups, some flush: a body less itself, shared faces),
/// some transparent, a sun and a lamp.
fn scene(seed: u64) -> Scene {
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut s = Scene::default();
    let kinds: Vec<BodyKind> = sv_geom::BODY_TYPES.iter().map(|t| t.kind).collect();
    let n = rng.gen_range(3..9);
    for _ in 0..n {
        let kind = kinds[rng.gen_range(0..kinds.len())];
        let c = DVec3::new(
            rng.gen_range(-2.0..2.0),
            rng.gen_range(-2.0..2.0),
            rng.gen_range(-1.0..1.0),
        );
        let a = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(0.1..1.0),
        );
        s.geometry
            .bodies
            .push(body(kind, c, rng.gen_range(0.5..1.5), a));
    }
    let term = |rng: &mut Pcg64| Term {
        op: if rng.gen_bool(0.7) {
            Op::Inside
        } else {
            Op::Outside
        },
        body: rng.gen_range(0..n),
    };
    for i in 0..rng.gen_range(2..6) {
        let mut zone = Zone::new(vec![Term {
            op: Op::Inside,
            body: rng.gen_range(0..n),
        }]);
        if rng.gen_bool(0.5) {
            zone.terms.push(term(&mut rng));
        }
        if rng.gen_bool(0.3) {
            let inner = (0..2).map(|_| Zone::new(vec![term(&mut rng)])).collect();
            zone.groups.push(Group {
                op: if rng.gen_bool(0.5) {
                    Op::Inside
                } else {
                    Op::Outside
                },
                zones: inner,
            });
        }
        let mut zones = vec![zone];
        if rng.gen_bool(0.2) {
            zones.push(Zone::new(vec![Term {
                op: Op::Inside,
                body: rng.gen_range(0..n),
            }]));
        }
        s.push_region(
            Region::new(format!("r{i}"), zones),
            RegionProps {
                transparent: rng.gen_bool(0.15),
                colour: Some([
                    rng.gen_range(0.2..1.0),
                    rng.gen_range(0.2..1.0),
                    rng.gen_range(0.2..1.0),
                ]),
                ..RegionProps::default()
            },
        );
    }
    let light = |name: &str, kind: LightKind, intensity: f64| Light {
        name: name.into(),
        kind,
        intensity,
        colour: [1.0; 3],
    };
    let sun = DVec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), -1.0);
    let lamp = DVec3::new(rng.gen_range(-4.0..4.0), rng.gen_range(-4.0..4.0), 4.0);
    // Half the scenes have a ground: an unbounded body of its own region
    // (half-spaces turned to the axes or along them, infinite cylinders,
    // quadrics), which no hierarchy holds and every tile lists.
    if rng.gen_bool(0.5) {
        let kind = [
            BodyKind::Haf,
            BodyKind::Pla,
            BodyKind::Xyp,
            BodyKind::Ycc,
            BodyKind::Qua,
        ][rng.gen_range(0..5)];
        let c = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.5..0.0),
        );
        let a = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(0.2..1.0),
        );
        s.geometry.bodies.push(body(kind, c, 1.0, a));
        let ground = Region::of_body("ground", s.geometry.bodies.len() - 1);
        s.push_region(ground, RegionProps::default());
    }
    s.lights = vec![
        light("SUN", LightKind::Parallel { dir: sun }, 1.0),
        light(
            "LAMP",
            LightKind::Point {
                pos: lamp,
                decay: 1.0,
            },
            4.0,
        ),
    ];
    // From far off, near, or inside the model; perspective or orthographic.
    let mut eye = DVec3::new(
        rng.gen_range(-8.0..8.0),
        rng.gen_range(-8.0..8.0),
        rng.gen_range(-6.0..6.0),
    ) * [0.1, 0.5, 1.0][rng.gen_range(0..3)];
    let at = DVec3::new(rng.gen_range(-0.5..0.5), rng.gen_range(-0.5..0.5), 0.0);
    // Views in the axes' planes too (rays with a direction component
    // exactly zero), as users' front, side and top views are.
    for a in 0..2 {
        if rng.gen_bool(0.35) {
            eye[a] = at[a];
        }
    }
    let lens = if rng.gen_bool(0.4) {
        Lens::Ortho {
            height: rng.gen_range(3.0..10.0),
        }
    } else {
        Lens::Fov {
            vertical_deg: rng.gen_range(20.0..90.0),
        }
    };
    if eye.distance(at) > 1e-3 {
        s.camera = Some(Camera::looking_at(eye, at, DVec3::Z, lens));
    }
    s
}

/// Render `scene` and trace each pixel centre alone; every pixel must
/// agree bit for bit.
fn agrees_pixel_by_pixel(scene: &Scene, shadows: bool) -> Result<usize, String> {
    let (r, _) = match Renderer::new(scene, 4.0 / 3.0) {
        Ok(r) => r,
        Err(e) => panic!("{e}"),
    };
    let (w, h) = (48u32, 36u32);
    let st = Settings {
        width: w,
        height: h,
        shadows,
        samples: 1,
        aovs: true,
    };
    let frame = r.render(&st, &|_| {});
    let gen = r.camera.rays(w, h);
    let mut s = Scratch::new(r.prepared());
    let mut hits = 0;
    for y in 0..h as usize {
        for x in 0..w as usize {
            let i = y * w as usize + x;
            let ray = gen.ray(x as f64 + 0.5, y as f64 + 0.5);
            let traced = r.trace(&ray, shadows, &mut s);
            let colour = traced.map_or([0.0f32; 3], |(_, c)| c.map(|v| v as f32));
            if frame.rgb[i].map(f32::to_bits) != colour.map(f32::to_bits) {
                return Err(format!(
                    "colour at ({x}, {y}): {:?} vs {colour:?}",
                    frame.rgb[i]
                ));
            }
            hits += usize::from(traced.is_some());
            let region = traced.map_or(0, |(hit, _)| hit.region + 1);
            if frame.region[i] != region {
                return Err(format!(
                    "region at ({x}, {y}): {} vs {region}",
                    frame.region[i]
                ));
            }
            if let Some((hit, _)) = traced {
                if frame.depth[i].to_bits() != (hit.t as f32).to_bits() {
                    return Err(format!("depth at ({x}, {y})"));
                }
                // `shoot`: the first crossing into an opaque region.
                if !hit.inside {
                    let first = r
                        .prepared()
                        .crossings(&ray, 0.0, &mut s)
                        .into_iter()
                        .find(|c| c.entering && r.prepared().is_opaque(c.region as usize));
                    if !first.is_some_and(|c| c.t == hit.t) {
                        return Err(format!("shoot at ({x}, {y})"));
                    }
                }
            }
        }
    }
    Ok(hits)
}

#[test]
fn tiles_packets_and_buffers_give_what_single_rays_give() {
    // Seeded, so that a failure is the same on every run.
    let mut hits = 0;
    for seed in 0..300 {
        let scene = scene(seed);
        hits += agrees_pixel_by_pixel(&scene, seed % 2 == 0)
            .unwrap_or_else(|e| panic!("scene {seed}: {e}"));
    }
    // Most pixels hit something: the pictures compared are not empty.
    assert!(hits > 300 * 48 * 36 / 4, "{hits} pixels hit");
}

#[test]
fn a_half_space_over_other_regions_seen_orthographically() {
    // The case that packets once got wrong: the half-space's entry bound
    // for rays across it was not a number, so the tile lists never tried it.
    let mut s = Scene::default();
    s.geometry.bodies = vec![
        Body::new("h", BodyKind::Haf, vec![0.5774, 0.5774, 0.5774, 5.0]),
        Body::new("c", BodyKind::Rcc, vec![0.0, 0.0, 0.0, 3.0, 3.0, 30.0, 7.0]),
        Body::new("s", BodyKind::Sph, vec![0.0, 0.0, 0.0, 6.0]),
    ];
    for i in 0..3 {
        s.push_region(Region::of_body(format!("r{i}"), i), RegionProps::default());
    }
    s.camera = Some(Camera::looking_at(
        DVec3::new(0.0, -40.0, 69.282),
        DVec3::ZERO,
        DVec3::Z,
        Lens::Ortho { height: 60.0 },
    ));
    for shadows in [true, false] {
        agrees_pixel_by_pixel(&s, shadows).unwrap_or_else(|e| panic!("{e}"));
    }
}
