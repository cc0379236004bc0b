//! The scene a FLUKA input makes: its regions' materials (ASSIGNMA), the
//! materials, the lattice cells filled, and the notes.

use super::card::{self, Card};
use super::materials::Materials;
use super::Reader;
use sv_geom::Geometry;
use sv_scene::{RegionProps, Scene, Units};

impl Reader {
    pub(super) fn scene(&mut self) -> Scene {
        let mut props: Vec<RegionProps> = (0..self.regions.len())
            .map(|r| RegionProps {
                description: self.region_labels.get(&r).cloned().unwrap_or_default(),
                ..RegionProps::default()
            })
            .collect();
        let mut materials = self.materials();
        let assigns = std::mem::take(&mut self.assigns);
        for (i, c) in &assigns {
            self.assignma(*i, c, &mut props, &mut materials);
        }
        let mut regions = std::mem::take(&mut self.regions);
        self.fill_lattice_cells(&mut regions);
        let mut scene = Scene {
            title: self
                .title
                .clone()
                .filter(|t| !t.is_empty())
                .unwrap_or_else(|| self.geo_title.clone()),
            units: Units::Centimetre,
            geometry: Geometry {
                bodies: std::mem::take(&mut self.bodies),
                regions,
                ..Geometry::default()
            },
            regions: props,
            materials: materials.list,
            ..Scene::default()
        };
        if assigns.is_empty() {
            scene
                .notes
                .push("no ASSIGNMA cards: every region is drawn opaque".to_string());
        }
        scene
    }

    /// An ASSIGNMA card: the material of WHAT(1) for regions WHAT(2) to
    /// WHAT(3) in steps of WHAT(4).
    fn assignma(
        &mut self,
        i: usize,
        c: &Card,
        props: &mut [RegionProps],
        materials: &mut Materials,
    ) {
        let (name, known) = match &c.what[0] {
            Some(f) => materials.resolve(&f.text),
            None => materials.resolve("BLCKHOLE"),
        };
        let Some(lo) = &c.what[1] else {
            self.warn(i, 1, 8, "ASSIGNMA names no region");
            return;
        };
        let Some(first) = self.assigned_region(i, lo) else {
            return;
        };
        let last = match &c.what[2] {
            Some(hi) => self.assigned_region(i, hi).unwrap_or(first),
            None => first,
        };
        let step = c.what[3]
            .as_ref()
            .and_then(|f| card::number(&f.text))
            .filter(|v| *v >= 1.0)
            .map_or(1, |v| v.min(1e9) as usize);
        let density = known.index.and_then(|k| materials.list[k].density);
        let mut region = first;
        while region <= last && region < props.len() && self.assign_budget > 0 {
            self.assign_budget -= 1;
            let p = &mut props[region];
            p.description = match self.region_labels.get(&region) {
                Some(label) => format!("{label}; material: {name}"),
                None => format!("material: {name}"),
            };
            let black_hole = name == "BLCKHOLE";
            // Vacuum and air are left out of pictures unless `--show-air`,
            // as air-coded regions of COMGEOM decks are; a black hole is
            // beyond the model.
            let air = name == "VACUUM" || name == "AIR";
            p.outside = black_hole;
            p.transparent = black_hole || air;
            p.air = i64::from(air);
            p.material = known.number;
            p.material_name = Some(name.clone());
            p.material_index = known.index;
            p.density = density;
            region += step;
        }
    }

    /// The region an ASSIGNMA field names; `None` (with a warning, unless
    /// it is a voxel region whose file is missing, already reported) when
    /// there is none.
    fn assigned_region(&mut self, i: usize, f: &card::Field) -> Option<usize> {
        let found = self.region_ref(f);
        if found.is_none() && !self.is_unmade_voxel_region(&f.text) {
            let (col, len) = (f.col, f.len());
            self.warn(
                i,
                col,
                len,
                format!("ASSIGNMA refers to undefined region `{}`", f.text),
            );
        }
        found
    }
}
