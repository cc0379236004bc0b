//! The cells beyond a vacuum boundary, marked
//! [`outside`](sv_scene::RegionProps::outside).
//!
//! OpenMC ends a particle's history where it crosses a vacuum surface: the
//! space on the far side belongs to no problem. The near side of each
//! vacuum surface is the side the root cells of material (or fills) use it
//! with, when they agree; when no such cell touches it, a closed surface's
//! (sphere, cylinder, torus) near side is its inside, and otherwise the
//! side the void cells share, if they share one.
//!
//! A root cell is outside when each of its zones is: a zone with a term on
//! the far side of a vacuum surface and none on a near side (a zone inside
//! one vacuum surface but beyond another, such as a gap between two vacuum
//! cylinders, can still be entered through its other surfaces), or a zone
//! that only subtracts the intersection of near sides (`~(1 -2 3 -4)`).

use super::surfaces::{Boundary, Surface};
use std::collections::{HashMap, HashSet};
use sv_geom::{BodyKind, Op, Term, Zone};
use sv_scene::Scene;

/// Mark the root cells beyond a vacuum boundary of `scene` outside.
pub(super) fn mark(scene: &mut Scene, surfaces: &[Surface]) {
    let vacuum: HashSet<usize> = surfaces
        .iter()
        .enumerate()
        .filter(|(_, s)| s.boundary == Boundary::Vacuum)
        .map(|(i, _)| i)
        .collect();
    if vacuum.is_empty() {
        return;
    }
    let near = near_sides(scene, &vacuum);
    let side = |t: &Term| near.get(&t.body).map(|op| *op == t.op);
    let beyond = |z: &Zone| {
        let sides: Vec<bool> = z.terms.iter().filter_map(side).collect();
        let only_subtracts_inside = z.terms.is_empty()
            && matches!(&z.groups[..], [g] if g.op == Op::Outside
                && g.zones.iter().all(|inner| inner.groups.is_empty()
                    && !inner.terms.is_empty()
                    && inner.terms.iter().all(|t| side(t) == Some(true))));
        (sides.contains(&false) && !sides.contains(&true)) || only_subtracts_inside
    };
    let outside: Vec<usize> = scene
        .geometry
        .regions
        .iter()
        .enumerate()
        .filter(|(_, r)| r.universe == 0 && !r.zones.is_empty() && r.zones.iter().all(beyond))
        .map(|(i, _)| i)
        .collect();
    for r in outside {
        scene.regions[r].outside = true;
    }
}

/// The near side (the sign its root cells use) of each vacuum body whose
/// near side can be told.
fn near_sides(scene: &Scene, vacuum: &HashSet<usize>) -> HashMap<usize, Op> {
    // For each vacuum body: the signs cells of material (0) and void (1)
    // use it with, in root regions of one zone.
    let mut used: HashMap<usize, [HashSet<Op>; 2]> = HashMap::new();
    for (region, props) in scene.geometry.regions.iter().zip(&scene.regions) {
        let [zone] = &region.zones[..] else {
            continue;
        };
        if region.universe != 0 {
            continue;
        }
        for t in zone.terms.iter().filter(|t| vacuum.contains(&t.body)) {
            used.entry(t.body).or_default()[usize::from(props.air != 0)].insert(t.op);
        }
    }
    let mut near = HashMap::new();
    for &body in vacuum {
        let [material, void] = used.remove(&body).unwrap_or_default();
        let closed = matches!(
            scene.geometry.bodies[body].kind,
            BodyKind::Sph | BodyKind::Xcc | BodyKind::Ycc | BodyKind::Zcc | BodyKind::Tor
        );
        let side = match (material.len(), void.len()) {
            (1, _) => material.into_iter().next(),
            (0, _) if closed => Some(Op::Inside),
            (0, 1) => void.into_iter().next(),
            _ => None,
        };
        if let Some(op) = side {
            near.insert(body, op);
        }
    }
    near
}
