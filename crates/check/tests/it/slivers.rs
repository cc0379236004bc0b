//! Slivers thinner than the grid: refinement between neighbouring rays
//! that see different regions finds them; flush faces stay clean.

use crate::model;
use sv_check::{check, CheckOptions, UniverseChoice};
use sv_math::{Aabb, DVec3};

/// A block and a thin cylinder lying against its face x = 10, sunk 0.1
/// into it: their overlap is a lens 0.1 thick, 0.6 across (in y) and 10
/// long (in z). With a spacing of 1 through the box (0,0,0)–(20,11,10),
/// the rays of each axis pass at 0.562 and 0.459 of a cell (y = 4.562,
/// 5.562 for rays along x; x = 9.459, 10.459 for rays along y; y = 4.459,
/// 5.459 for rays along z), all outside the lens around y = 5.06.
const SLIVER: &str = "
BODY block RPP 0 10 0 10 0 10
BODY rod RCC (10.4,5.06,0) (0,0,10) 0.5
REGION BLOCK = +block
REGION ROD = +rod
";

fn grid(refine: u32) -> CheckOptions {
    CheckOptions {
        spacing: Some(1.0),
        bounds: Some(Aabb::new(DVec3::ZERO, DVec3::new(20.0, 11.0, 10.0))),
        refine,
        ..Default::default()
    }
}

#[test]
fn the_plain_grid_misses_a_sliver_between_its_rays() {
    let m = model(SLIVER, UniverseChoice::None);
    let r = check(&m, &grid(0)).unwrap();
    assert_eq!(r.refine_rays, 0);
    assert!(r.overlaps.is_empty(), "{}", r.to_table());
    assert!(r.smallest_feature.at_edges.is_none());
}

#[test]
fn refinement_finds_a_sliver_thinner_than_the_grid() {
    let m = model(SLIVER, UniverseChoice::None);
    let r = check(&m, &grid(4)).unwrap();
    assert!(r.refine_rays > 0);
    assert_eq!(r.overlaps.len(), 1, "{}", r.to_table());
    let o = &r.overlaps[0];
    assert_eq!(o.regions, ["BLOCK".to_string(), "ROD".to_string()]);
    // Found by refinement rays alone, which stand for no area.
    assert_eq!(o.problem.volume, 0.0);
    let [x, y, z] = o.problem.point;
    assert!((9.9..=10.0).contains(&x) && (y - 5.06).abs() < 0.31 && (0.0..10.0).contains(&z));
    // The promise: a cell's diagonal anywhere, a sixteenth of the spacing
    // at the edges.
    assert!((r.smallest_feature.anywhere - 2f64.sqrt()).abs() < 1e-9);
    assert_eq!(r.smallest_feature.at_edges, Some(1.0 / 16.0));
    assert!(r.to_table().contains("refined 4 times"), "{}", r.to_table());
}

#[test]
fn refinement_down_to_a_length_sets_the_halvings() {
    assert_eq!(sv_check::refine_levels(1.0, 0.1), 4);
    assert_eq!(sv_check::refine_levels(1.0, 0.0625), 4);
    assert_eq!(sv_check::refine_levels(1.0, 1.0), 0);
    assert_eq!(sv_check::refine_levels(1.0, 1e-30), sv_check::MAX_REFINE);
    let m = model(SLIVER, UniverseChoice::None);
    let opts = CheckOptions {
        refine_to: Some(0.2),
        ..grid(0)
    };
    assert_eq!(check(&m, &opts).unwrap().refine, 3);
    let bad = CheckOptions {
        refine: sv_check::MAX_REFINE + 1,
        ..grid(0)
    };
    assert!(check(&m, &bad).is_err());
}

#[test]
fn refinement_raises_no_false_alarm_on_flush_faces() {
    // Boxes sharing faces, a cylinder standing on one, a ball in a hole
    // of exactly its size, a cone on the cylinder's top.
    let text = "
BODY a RPP 0 10 0 10 0 10
BODY b RPP 10 20 0 10 0 10
BODY c RPP 0 20 10 15 0 10
BODY post RCC (5,5,10) (0,0,4) 2
BODY cap TRC (5,5,14) (0,0,3) 2 0.5
BODY hole SPH (15,5,5) 3
REGION A = +a
REGION B = +b -hole
REGION C = +c
REGION POST = +post
REGION CAP = +cap
REGION BALL = +hole
";
    let m = model(text, UniverseChoice::None);
    let r = check(
        &m,
        &CheckOptions {
            spacing: Some(1.0),
            refine: 10,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(r.refine_rays > 1000, "{}", r.refine_rays);
    assert!(r.is_clean() && r.met_every_region(), "{}", r.to_table());
}

#[test]
fn refined_checks_split_into_parts_merge_to_the_same_report() {
    let m = model(SLIVER, UniverseChoice::None);
    let opts = CheckOptions {
        random: 500,
        ..grid(5)
    };
    let whole = check(&m, &opts).unwrap();
    let chunks = sv_check::check_chunks(&m, &opts).unwrap();
    assert!(chunks >= 5, "{chunks}");
    let cuts = [0, 1, 3, chunks - 1, chunks];
    let parts: Vec<sv_check::CheckPart> = cuts
        .windows(2)
        .map(|w| sv_check::check_part(&m, &opts, w[0]..w[1]).unwrap())
        .collect();
    let mut merged = sv_check::check_merge(&m, &opts, &parts).unwrap();
    merged.seconds = whole.seconds;
    assert_eq!(merged.to_json(), whole.to_json());
    assert!(whole.refine_rays > 0 && !whole.overlaps.is_empty());
}

/// A wire 0.08 across along the block's face x = 10, between the rays of
/// every grid: only refinement rays meet it.
const WIRE: &str = "
BODY block RPP 0 10 0 10 0 10
BODY wire RCC (10,5.06,0) (0,0,10) 0.04
REGION BLOCK = +block
REGION WIRE = +wire
";

#[test]
fn a_region_met_by_refinement_rays_alone_is_met() {
    // Refinement rays mark their regions only where they see other than
    // both ends of their piece; the wire is such a case.
    let m = model(WIRE, UniverseChoice::None);
    let plain = check(&m, &grid(0)).unwrap();
    assert_eq!(plain.unseen, ["WIRE".to_string()], "{}", plain.to_table());
    let refined = check(&m, &grid(4)).unwrap();
    assert!(refined.met_every_region(), "{}", refined.to_table());
}

/// A plate 0.05 thick and 0.3 wide lying in a block against its face
/// y = 10, 200 long in x. The rays along z run in rows along x; those of
/// the rows at y = 9.459 (in the block) and 10.459 (outside) see the same
/// as their neighbours along the row but not as those across it, all
/// along the plate, and the refinement between the two rows passes
/// through it (y = 9.959). The other grids' rays pass beside it (z =
/// 4.562 and 5.562 along y, 4.459 and 5.459 along x), and their
/// refinement too.
const LONG_SLIVER: &str = "
BODY block RPP 0 200 0 10 0 11
BODY plate RPP 0 200 9.95 10 4.9 5.2
REGION BLOCK = +block
REGION PLATE = +plate
";

#[test]
fn refinement_follows_a_sliver_along_the_rows() {
    let m = model(LONG_SLIVER, UniverseChoice::None);
    let bounds = Some(Aabb::new(DVec3::ZERO, DVec3::new(200.0, 11.0, 11.0)));
    let opts = |refine| CheckOptions {
        spacing: Some(1.0),
        bounds,
        refine,
        ..Default::default()
    };
    let plain = check(&m, &opts(0)).unwrap();
    assert!(plain.overlaps.is_empty(), "{}", plain.to_table());
    let refined = check(&m, &opts(4)).unwrap();
    assert_eq!(refined.overlaps.len(), 1, "{}", refined.to_table());
    // Each of the 200 columns along x refines between its two rows and
    // meets the plate there, however long the stretches of rays that see
    // what their neighbours along the row see.
    let hits = refined.overlaps[0].problem.hits;
    assert!(hits >= 200, "{hits} hits\n{}", refined.to_table());
}
