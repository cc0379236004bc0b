//! Merging scenes: what INCLUDE does with the scene it reads, and what a
//! script does with the scenes it names.

use sv_math::DVec3;
use sv_scene::Scene;

/// Why a scene cannot be merged into another.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MergeError {
    /// A region of this name is in both scenes.
    Region(String),
}

/// What [`merge`] does with a region whose name is taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clash {
    /// Refuse the merge (names matter to the caller, as in a film script).
    Refuse,
    /// Rename the incoming region `tag/name`.
    Rename,
}

/// Add `other` to `scene`: its bodies (a body whose name is taken becomes
/// `tag/name`; regions as `regions` says), its regions (body references shifted), its lights whose
/// names are new, and its notes; camera, picture size and title are taken
/// only where `scene` has none. `other` is scaled from its units into the
/// scene's. A region name in both scenes is an error, and `scene` is then
/// left unchanged.
pub fn merge(
    scene: &mut Scene,
    mut other: Scene,
    tag: &str,
    regions: Clash,
) -> Result<(), MergeError> {
    for region in &mut other.geometry.regions {
        if scene.geometry.region_index(&region.name).is_some() {
            match regions {
                Clash::Refuse => return Err(MergeError::Region(region.name.clone())),
                Clash::Rename => region.name = format!("{tag}/{}", region.name),
            }
        }
    }
    let offset = scene.geometry.bodies.len();
    if other.units != scene.units {
        let factor = other.units.mm() / scene.units.mm();
        let scale = sv_math::DAffine3::from_scale(DVec3::splat(factor));
        for body in &mut other.geometry.bodies {
            // A uniform positive scale is a similarity: it cannot fail.
            if let Ok(scaled) = body.transformed(&scale) {
                *body = scaled;
            }
        }
    }
    for mut body in other.geometry.bodies {
        if scene.geometry.body_index(&body.name).is_some() {
            body.name = format!("{tag}/{}", body.name);
        }
        scene.geometry.bodies.push(body);
    }
    for (mut region, props) in other.geometry.regions.into_iter().zip(other.regions) {
        for zone in &mut region.zones {
            shift_bodies(zone, offset);
        }
        scene.push_region(region, props);
    }
    if scene.title.is_empty() {
        scene.title = other.title;
    }
    scene.notes.extend(other.notes);
    for light in other.lights {
        if !scene
            .lights
            .iter()
            .any(|old| old.name.eq_ignore_ascii_case(&light.name))
        {
            scene.lights.push(light);
        }
    }
    scene.camera = scene.camera.or(other.camera);
    scene.size = scene.size.or(other.size);
    Ok(())
}

/// Every body term of `zone`, its groups' included, moved up by `offset`.
fn shift_bodies(zone: &mut sv_geom::Zone, offset: usize) {
    for term in &mut zone.terms {
        term.body += offset;
    }
    for group in &mut zone.groups {
        for inner in &mut group.zones {
            shift_bodies(inner, offset);
        }
    }
}
