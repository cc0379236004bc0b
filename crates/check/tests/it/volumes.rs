use crate::model;
use std::f64::consts::PI;
use sv_check::{volumes, UniverseChoice, VolumeOptions, VolumeReport};

fn measure(text: &str) -> VolumeReport {
    let m = model(text, UniverseChoice::None);
    volumes(
        &m,
        &VolumeOptions {
            rel_error: 2e-3,
            rays_per_side: 64,
            region_rays_per_side: 32,
            max_rays: 4_000_000,
            ..Default::default()
        },
    )
    .unwrap()
}

/// The region's volume agrees with `exact` within four reported standard
/// errors, and the reported error met the target.
fn agrees(r: &VolumeReport, region: &str, exact: f64) {
    let v = r
        .regions
        .iter()
        .find(|v| v.region == region)
        .unwrap_or_else(|| panic!("no region {region}"));
    assert!(v.converged, "{region} did not converge:\n{}", r.to_table());
    assert!(v.rel_error <= 2e-3, "{region}: {}", v.rel_error);
    assert!(
        (v.volume - exact).abs() <= 4.0 * v.error + 1e-12 * exact,
        "{region}: {} ± {} vs exact {exact}",
        v.volume,
        v.error
    );
}

#[test]
fn every_body_type_alone() {
    let ell_b2 = 9.0 - 17.0 / 4.0;
    let cases: &[(&str, &str, f64)] = &[
        ("SPH", "(1,2,3) 1.5", 4.0 / 3.0 * PI * 3.375),
        ("RCC", "(0,0,0) (1,2,3) 0.7", PI * 0.49 * 14f64.sqrt()),
        ("REC", "(0,0,0) (0,0,3) (2,0,0) (0,1,0)", PI * 2.0 * 3.0),
        (
            "TRC",
            "(0,0,0) (0,1,4) 2 0.5",
            PI * 17f64.sqrt() / 3.0 * (4.0 + 1.0 + 0.25),
        ),
        (
            "TEC",
            "(0,0,0) (0,0,10) (5,0,0) (0,3,0) 0.6",
            PI * 15.0 * 10.0 / 3.0 * (1.0 + 1.0 / 0.6 + 1.0 / 0.36),
        ),
        ("TGC", "(0,0,0) (0,0,10) (5,0,0) (0,8,0) 2 9", 295.0 * PI),
        ("ELL", "(0,0,0) (4,1,0) 6", 4.0 / 3.0 * PI * 3.0 * ell_b2),
        (
            "ELL1",
            "(3,2,8) (3,-1,8) 4",
            4.0 / 3.0 * PI * 74f64.sqrt() * 16.0,
        ),
        (
            "ELLG",
            "(10,0,0) (-12,0,0) (0,-3,0) (0,0,5)",
            4.0 / 3.0 * PI * 180.0,
        ),
        ("RPP", "-1 2 -3 4 0.5 1.5", 21.0),
        ("BOX", "(0,0,0) (1,1,0) (-2,2,0) (0,0,3)", 12.0),
        ("RAW", "(-70,0,35) (0,-11,11) (0,11,11) (40,0,0)", 4840.0),
        ("ARB4", "(3,0,-3) (3,0,0) (3,-3,-3) (0,0,-3)", 4.5),
        ("ARB5", "(1,0,0) (1,2,0) (3,2,0) (3,0,0) (1.5,1.5,5)", 20.0 / 3.0),
        (
            "ARB6",
            "(0,0,0) (2,0,0) (2,2,0) (0,2,0) (1,0,3) (1,2,3)",
            6.0,
        ),
        // A unit cube whose corner (0,1,1) is cut off (P8 = P5).
        (
            "ARB7",
            "(0,0,0) (1,0,0) (1,1,0) (0,1,0) (0,0,1) (1,0,1) (1,1,1)",
            5.0 / 6.0,
        ),
        (
            "ARB8",
            "(-2,-2,0) (2,-2,0) (2,2,0) (-2,2,0) (-1,-1,3) (1,-1,3) (1,1,3) (-1,1,3)",
            28.0,
        ),
        // A unit cube as four curves of four points, the end curves
        // shrunk to points.
        (
            "ARS",
            "4 4  0.5 0.5 0 0.5 0.5 0 0.5 0.5 0 0.5 0.5 0  0 0 0 1 0 0 1 1 0 0 1 0  \
             0 0 1 1 0 1 1 1 1 0 1 1  0.5 0.5 1 0.5 0.5 1 0.5 0.5 1 0.5 0.5 1",
            1.0,
        ),
        ("TOR", "(0,0,0) (0.3,0.3,0.9) 5 2", 40.0 * PI * PI),
        (
            "ARBF",
            "(0,0,0) (1,0,0) (1,1,0) (0,1,0) (0,0,1) (1,0,1) (1,1,1) (0,1,1) 4321 5678 2376 1485 1265 4378",
            1.0,
        ),
    ];
    for (kind, params, exact) in cases {
        let text = format!("BODY b {kind} {params}\nREGION R = +b\n");
        let r = measure(&text);
        agrees(&r, "R", *exact);
        let _ = kind;
    }
}

#[test]
fn unbounded_bodies_cut_by_a_box() {
    let cube = "BODY c RPP -1 1 -1 1 -1 1\n";
    let cases: &[(&str, f64)] = &[
        ("HAF (0,0,1) 0.5", 6.0),
        ("XYP 0.2", 4.8),
        ("XZP -0.5", 2.0),
        ("YZP 0", 4.0),
        ("PLA (1,1,0) (0,0,0)", 4.0),
        ("XCC 0 0 0.5", PI * 0.25 * 2.0),
        ("YEC 0 0 0.5 0.8", PI * 0.4 * 2.0),
        ("ZCC 0.2 0.1 0.3", PI * 0.09 * 2.0),
        ("QUA 1 1 1 0 0 0 0 0 0 -0.64", 4.0 / 3.0 * PI * 0.512),
    ];
    for (body, exact) in cases {
        let text = format!("{cube}BODY q {body}\nREGION R = +c +q\n");
        let r = measure(&text);
        agrees(&r, "R", *exact);
        assert!(!r.regions[0].clipped);
    }
}

#[test]
fn booleans_against_closed_forms() {
    let text = "
BODY c RPP -1 1 -1 1 -1 1
BODY s SPH (0,0,0) 0.5
BODY a SPH (3,0,0) 1
BODY b SPH (4.5,0,0) 1
REGION HOLLOW = +c -s
REGION UNION = +a OR +b
REGION LENS = +a +b
";
    let r = measure(text);
    let sph = 4.0 / 3.0 * PI;
    let lens = PI * 5.5 * 0.25 / 12.0;
    agrees(&r, "HOLLOW", 8.0 - sph / 8.0);
    agrees(&r, "UNION", 2.0 * sph - lens);
    agrees(&r, "LENS", lens);
    // Centroids: the hollow cube's is its centre; the lens's is midway.
    let c = r.regions[0].centroid.unwrap();
    assert!(c.iter().all(|x| x.abs() < 0.01), "{c:?}");
    let c = r.regions[2].centroid.unwrap();
    assert!((c[0] - 3.75).abs() < 0.01 && c[1].abs() < 0.01, "{c:?}");
}

/// Volume of the sphere |x| < 1 inside the infinite cylinder of radius
/// `rc` about the z-parallel axis through (cx, cy): for each direction φ
/// about the axis the integral over ρ is done in closed form; over φ,
/// Simpson's rule with many points.
fn sphere_cylinder_intersection(cx: f64, cy: f64, rc: f64) -> f64 {
    let c2 = cx * cx + cy * cy;
    let inner = |phi: f64| {
        let p = cx * phi.cos() + cy * phi.sin();
        let a = 1.0 - c2 + p * p;
        let hi = rc.min(-p + a.sqrt());
        // ∫₀^hi 2ρ√(A − (ρ+p)²) dρ with s = ρ + p.
        let f = |s: f64| {
            let g = (a - s * s).max(0.0);
            -2.0 / 3.0 * g.powf(1.5)
                - p * (s * g.sqrt() + a * (s / a.sqrt()).clamp(-1.0, 1.0).asin())
        };
        f(hi + p) - f(p)
    };
    let n = 20_000;
    let h = 2.0 * PI / n as f64;
    let mut sum = inner(0.0) + inner(2.0 * PI);
    for i in 1..n {
        sum += inner(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0
}

#[test]
fn figure_1_regions() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/figure1/figure1.sv"
    ))
    .unwrap();
    let r = measure(&text);
    let sph = 4.0 / 3.0 * PI;
    let cyl = PI * 0.36 * 2.8;
    // The cylinder's axis is 0.45, -0.2 from the sphere's centre and it is
    // longer than the sphere: the intersection is that of an infinite one.
    let both = sphere_cylinder_intersection(0.45, -0.2, 0.6);
    // Sanity of the reference: a centred cylinder of radius 1 holds the
    // whole sphere.
    assert!((sphere_cylinder_intersection(0.0, 0.0, 1.0) - sph).abs() < 1e-6);
    agrees(&r, "B", sph);
    agrees(&r, "C", cyl);
    agrees(&r, "D", sph - both);
    agrees(&r, "E", cyl - both);
    agrees(&r, "F", both);
}

#[test]
fn masses_use_density_and_units() {
    // 1 in cube of density 2 g/cm³: 2 × 2.54³ g.
    let text = "UNITS in\nBODY c RPP 0 1 0 1 0 1\nREGION R = +c DENSITY 2\nBODY s SPH (5,5,5) 1\nREGION S = +s\n";
    let r = measure(text);
    let m = r.regions[0].mass_g.unwrap();
    let expect = 2.0 * 2.54f64.powi(3);
    assert!(
        (m - expect).abs() <= 4.0 * r.regions[0].mass_error_g.unwrap() + 1e-9,
        "{m}"
    );
    assert!(r.regions[1].mass_g.is_none());
    let v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
    assert!(v["regions"][0]["mass_g"].is_number());
    assert!(v["regions"][1]["mass_g"].is_null());
}

#[test]
fn unreachable_targets_are_reported_as_not_converged() {
    let m = model(
        "BODY a SPH (0,0,0) 1\nREGION A = +a\nBODY b SPH (3,0,0) 0.5\nREGION B = +b\n",
        UniverseChoice::None,
    );
    let r = volumes(
        &m,
        &VolumeOptions {
            rel_error: 1e-7,
            rays_per_side: 16,
            region_rays_per_side: 8,
            max_rays: 20_000,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(r.not_converged.len(), 2, "{}", r.to_table());
    assert!(r.rays <= 20_000);
    assert!(r.to_table().contains("did not converge"));
    assert!(volumes(
        &m,
        &VolumeOptions {
            rel_error: 0.0,
            ..Default::default()
        }
    )
    .is_err());
}
