//! `render --color-by region|material` and `--legend`: every region
//! painted with the stable colour `slice` gives its name (or its
//! material's), and a legend strip of the colours seen.

use clap::ValueEnum;
use std::collections::BTreeMap;
use sv_check::{region_colour, Swatch};
use sv_scene::Scene;

/// What `--color-by` colours by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ColourBy {
    /// Each region its own colour, as in `slice`.
    Region,
    /// Each material its own colour.
    Material,
}

/// The key a region's colour comes from: its name, or its material (the
/// name the input gives it, else its code).
fn key(scene: &Scene, region: usize, by: ColourBy) -> String {
    let props = &scene.regions[region];
    match by {
        ColourBy::Region => scene.geometry.regions[region].name.clone(),
        ColourBy::Material => match &props.material_name {
            Some(name) => format!("material {name}"),
            None => format!("material {}", props.material),
        },
    }
}

/// Paint every region of `scene` by `by`.
pub fn paint(scene: &mut Scene, by: ColourBy) {
    for region in 0..scene.regions.len() {
        let colour = region_colour(&key(scene, region, by));
        scene.regions[region].colour = Some(colour.map(f64::from));
    }
}

/// The legend entries of the regions seen in a picture (`seen`: region
/// index + 1 per pixel, 0 for the background), one per key, the most
/// seen first.
pub fn legend(scene: &Scene, by: ColourBy, seen: &[u32]) -> Vec<(Swatch, String)> {
    let mut pixels_per_key: BTreeMap<String, (u64, String)> = BTreeMap::new();
    for &id in seen.iter().filter(|&&id| id > 0) {
        let region = id as usize - 1;
        let key = key(scene, region, by);
        let entry = pixels_per_key.entry(key).or_insert_with_key(|key| {
            let description = &scene.regions[region].description;
            let label = if by == ColourBy::Region && !description.is_empty() {
                format!("{key} {description}")
            } else {
                key.clone()
            };
            (0, label)
        });
        entry.0 += 1;
    }
    let mut entries: Vec<(String, u64, String)> = pixels_per_key
        .into_iter()
        .map(|(key, (pixels, label))| (key, pixels, label))
        .collect();
    entries.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
    entries
        .into_iter()
        .map(|(key, _, label)| (Swatch::Solid(region_colour(&key)), label))
        .collect()
}
