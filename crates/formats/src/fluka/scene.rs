//! The scene a FLUKA input makes: its regions' materials (ASSIGNMA) and
//! the notes on what is not drawn.

use super::card::{self, Card};
use super::Reader;
use std::collections::HashSet;
use sv_geom::Geometry;
use sv_scene::{RegionProps, Scene, Units};

impl Reader {
    pub(super) fn scene(&mut self) -> Scene {
        let mut props: Vec<RegionProps> = self
            .regions
            .iter()
            .map(|_| RegionProps::default())
            .collect();
        let assigns = std::mem::take(&mut self.assigns);
        for (i, c) in &assigns {
            self.assignma(*i, c, &mut props);
        }
        let mut scene = Scene {
            title: self
                .title
                .clone()
                .filter(|t| !t.is_empty())
                .unwrap_or_else(|| self.geo_title.clone()),
            units: Units::Centimetre,
            geometry: Geometry {
                bodies: std::mem::take(&mut self.bodies),
                regions: std::mem::take(&mut self.regions),
                ..Geometry::default()
            },
            regions: props,
            ..Scene::default()
        };
        if assigns.is_empty() {
            scene
                .notes
                .push("no ASSIGNMA cards: every region is drawn opaque".to_string());
        }
        if !self.lattices.is_empty() {
            let mut names: Vec<&str> = Vec::new();
            let mut seen = HashSet::new();
            for (r, _) in &self.lattices {
                if seen.insert(*r) {
                    names.push(scene.geometry.regions[*r].name.as_str());
                }
            }
            scene.notes.push(format!(
                "LATTICE replicas are not drawn: {}",
                if names.len() == 1 {
                    format!(
                        "lattice cell {} is drawn as a plain region (its container only)",
                        names[0]
                    )
                } else {
                    format!(
                        "lattice cells {} are drawn as plain regions (their containers only)",
                        names.join(", ")
                    )
                },
            ));
        }
        scene
    }

    fn region_ref(&self, f: &card::Field) -> Option<usize> {
        if let Some(&r) = self.region_index.get(&f.text) {
            return Some(r);
        }
        if f.text == "@LASTREG" {
            return self.regions.len().checked_sub(1);
        }
        card::number(&f.text)
            .filter(|v| *v >= 1.0 && v.fract() == 0.0 && *v <= self.regions.len() as f64)
            .map(|v| v as usize - 1)
    }

    fn assignma(&mut self, i: usize, c: &Card, props: &mut [RegionProps]) {
        let material = match &c.what[0] {
            Some(f) => match card::number(&f.text) {
                Some(v) if v <= 1.0 => "BLCKHOLE".to_string(),
                Some(2.0) => "VACUUM".to_string(),
                Some(v) => format!("material #{v}"),
                None => f.text.clone(),
            },
            None => "BLCKHOLE".to_string(),
        };
        let Some(lo) = &c.what[1] else {
            self.warn(i, 1, 8, "ASSIGNMA names no region");
            return;
        };
        let Some(first) = self.region_ref(lo) else {
            let (col, len) = (lo.col, lo.len());
            self.warn(
                i,
                col,
                len,
                format!("ASSIGNMA refers to undefined region `{}`", lo.text),
            );
            return;
        };
        let last = match &c.what[2] {
            Some(hi) => match self.region_ref(hi) {
                Some(r) => r,
                None => {
                    let (col, len) = (hi.col, hi.len());
                    self.warn(
                        i,
                        col,
                        len,
                        format!("ASSIGNMA refers to undefined region `{}`", hi.text),
                    );
                    first
                }
            },
            None => first,
        };
        let step = c.what[3]
            .as_ref()
            .and_then(|f| card::number(&f.text))
            .filter(|v| *v >= 1.0)
            .map_or(1, |v| v.min(1e9) as usize);
        let mut region = first;
        while region <= last && region < props.len() && self.assign_budget > 0 {
            self.assign_budget -= 1;
            let region_props = &mut props[region];
            region_props.description = format!("material: {material}");
            // Vacuum is air: left out of pictures unless `--show-air`, as
            // air-coded regions of COMGEOM decks are.
            region_props.transparent = material == "BLCKHOLE" || material == "VACUUM";
            region_props.material = match material.as_str() {
                "BLCKHOLE" => 1,
                "VACUUM" => 2,
                _ => 0,
            };
            region_props.air = i64::from(material == "VACUUM");
            region += step;
        }
    }
}
