//! The result of [`diff`](super::diff), as data (JSON) and as a table.

use super::substance::{Distance, Matching, Substances};
use super::{DiffOptions, Sampled};
use crate::model::Model;
use crate::report::fmt_g;
use crate::volume::Stats;
use serde::Serialize;
use std::fmt::Write as _;
use sv_math::Aabb;

/// The volume a class of matched substances fills in each model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClassVolume {
    /// What it is in A (`m12 at 10.5 g/cm³`; `void`), `-` when A has none.
    pub in_a: String,
    /// What it is in B.
    pub in_b: String,
    /// Its volume in A and the standard error (cm³ or model units³).
    pub volume_a: [f64; 2],
    /// Its volume in B and the standard error.
    pub volume_b: [f64; 2],
}

/// A region's volume inside the compared box.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RegionVolumeOf {
    /// `A` or `B`.
    pub model: String,
    /// Region name.
    pub region: String,
    /// What it holds (`void` when nothing).
    pub substance: String,
    /// Volume and standard error.
    pub volume: [f64; 2],
}

/// A place where the models differ.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Place {
    /// A point inside it (the middle of the longest stretch seen).
    pub point: [f64; 3],
    /// Region of A there and what it holds (`-`: no region).
    pub region_a: String,
    /// Region of B there.
    pub region_b: String,
    /// What fills it in A.
    pub substance_a: String,
    /// What fills it in B.
    pub substance_b: String,
    /// Volume where these two regions differ.
    pub volume: f64,
}

/// A substance of one model that matches none of the other's.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UnmatchedSubstance {
    /// `A` or `B`.
    pub model: String,
    /// The substance.
    pub substance: String,
    /// The closest of the other model's, and how far it is.
    pub closest: Option<String>,
}

/// The result of [`diff`](super::diff).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DiffReport {
    /// True when the volume where the models differ is within the
    /// tolerance.
    pub agree: bool,
    /// Bounds of A and B (min, max).
    pub bounds: [[[f64; 3]; 2]; 2],
    /// The box compared: where the bounds overlap.
    pub compared: [[f64; 3]; 2],
    /// Notes on the bounds (they differ, grossly or a little).
    pub bounds_notes: Vec<String>,
    /// Volume where the two differ, and its standard error.
    pub differ_volume: [f64; 2],
    /// Volume holding material in either model.
    pub material_volume: [f64; 2],
    /// `differ_volume / material_volume`.
    pub differ_fraction: f64,
    /// The tolerance on that fraction.
    pub tolerance: f64,
    /// Matched classes of substances and their volumes.
    pub classes: Vec<ClassVolume>,
    /// Every region of both models with its volume in the box.
    pub regions: Vec<RegionVolumeOf>,
    /// Substances with no partner.
    pub unmatched: Vec<UnmatchedSubstance>,
    /// The worst places, most volume first.
    pub worst: Vec<Place>,
    /// Rays fired (in each model).
    pub rays: u64,
    /// Wall-clock seconds.
    pub seconds: f64,
}

pub(crate) struct Inputs<'a> {
    pub models: [&'a Model; 2],
    pub subs: &'a [Substances; 2],
    pub matching: &'a Matching,
    pub bounds: [Aabb; 2],
    pub common: Aabb,
    pub sampled: &'a Sampled,
    pub seconds: f64,
}

const SIDES: [&str; 2] = ["A", "B"];

fn pair(st: &Stats) -> [f64; 2] {
    let error = if st.n >= 2 { st.stderr() } else { 0.0 };
    [st.mean, error]
}

fn corners(b: &Aabb) -> [[f64; 3]; 2] {
    if b.is_empty() {
        [[0.0; 3]; 2]
    } else {
        [b.min.to_array(), b.max.to_array()]
    }
}

/// What a region of one side holds, as a label.
fn held(input: &Inputs, side: usize, region: Option<u32>) -> (String, String) {
    let Some(r) = region else {
        return ("-".into(), "void".into());
    };
    let name = input.models[side].names[r as usize].clone();
    let substance = match input.subs[side]
        .of_region
        .get(r as usize)
        .copied()
        .flatten()
    {
        Some(s) => input.subs[side].list[s].label(),
        None => "void".into(),
    };
    (name, substance)
}

fn bounds_notes(bounds: &[Aabb; 2], common: &Aabb) -> Vec<String> {
    if bounds.iter().any(|b| b.is_empty() || !b.is_finite()) {
        return vec!["a model is unbounded: compared inside the box given".into()];
    }
    if common.is_empty() {
        return vec![
            "the models' bounds do not overlap: nothing to compare (different units or origins?)"
                .into(),
        ];
    }
    let (da, db) = (bounds[0].diagonal(), bounds[1].diagonal());
    let ratio = da.max(db) / da.min(db).max(1e-300);
    let gap = (bounds[0].min - bounds[1].min)
        .abs()
        .max((bounds[0].max - bounds[1].max).abs())
        .max_element();
    if ratio > 2.0 {
        vec![format!(
            "the bounds differ grossly: diagonals {} and {} (different units?); only where they overlap is compared",
            fmt_g(da),
            fmt_g(db)
        )]
    } else if gap > 1e-6 * da.max(db) {
        vec![format!(
            "the bounds differ by up to {} along an axis; only where they overlap is compared",
            fmt_g(gap)
        )]
    } else {
        Vec::new()
    }
}

fn unmatched(input: &Inputs) -> Vec<UnmatchedSubstance> {
    let describe = |side: usize, entry: &(usize, Option<(usize, Distance)>)| {
        let other = 1 - side;
        UnmatchedSubstance {
            model: SIDES[side].into(),
            substance: input.subs[side].list[entry.0].label(),
            closest: entry
                .1
                .map(|(k, d)| format!("{}: {}", input.subs[other].list[k].label(), d.describe())),
        }
    };
    let m = input.matching;
    let a = m.unmatched_a.iter().map(|e| describe(0, e));
    a.chain(m.unmatched_b.iter().map(|e| describe(1, e)))
        .collect()
}

fn classes(input: &Inputs) -> Vec<ClassVolume> {
    let m = input.matching;
    (1..m.classes as u32)
        .map(|class| {
            let names = |side: usize, of: &[u32]| {
                let names: Vec<String> = (0..of.len())
                    .filter(|&i| of[i] == class)
                    .map(|i| input.subs[side].list[i].label())
                    .collect();
                if names.is_empty() {
                    "-".into()
                } else {
                    names.join("; ")
                }
            };
            ClassVolume {
                in_a: names(0, &m.class_a),
                in_b: names(1, &m.class_b),
                volume_a: pair(&input.sampled.classes[0][class as usize]),
                volume_b: pair(&input.sampled.classes[1][class as usize]),
            }
        })
        .collect()
}

pub(crate) fn build(input: Inputs, opts: &DiffOptions) -> DiffReport {
    let sampled = input.sampled;
    let batches = sampled.differ.n.max(1) as f64;
    let mut worst: Vec<Place> = sampled
        .places
        .iter()
        .map(|(&(ra, rb), &(volume, _, point))| {
            let (region_a, substance_a) = held(&input, 0, ra);
            let (region_b, substance_b) = held(&input, 1, rb);
            Place {
                point: point.to_array(),
                region_a,
                region_b,
                substance_a,
                substance_b,
                volume: volume / batches,
            }
        })
        .collect();
    worst.sort_by(|x, y| {
        y.volume
            .total_cmp(&x.volume)
            .then(x.region_a.cmp(&y.region_a))
    });
    worst.truncate(opts.worst);
    let mut regions = Vec::new();
    for (side, name) in SIDES.iter().enumerate() {
        for (r, st) in sampled.regions[side].iter().enumerate() {
            let (region, substance) = held(&input, side, Some(r as u32));
            regions.push(RegionVolumeOf {
                model: name.to_string(),
                region,
                substance,
                volume: pair(st),
            });
        }
    }
    let differ = pair(&sampled.differ);
    let material = pair(&sampled.material);
    let differ_fraction = if material[0] > 0.0 {
        differ[0] / material[0]
    } else {
        0.0
    };
    DiffReport {
        agree: !input.common.is_empty() && differ_fraction <= opts.tolerance,
        bounds: [corners(&input.bounds[0]), corners(&input.bounds[1])],
        compared: corners(&input.common),
        bounds_notes: bounds_notes(&input.bounds, &input.common),
        differ_volume: differ,
        material_volume: material,
        differ_fraction,
        tolerance: opts.tolerance,
        classes: classes(&input),
        regions,
        unmatched: unmatched(&input),
        worst,
        rays: sampled.rays,
        seconds: input.seconds,
    }
}

fn fmt_point(p: &[f64; 3]) -> String {
    format!("({}, {}, {})", fmt_g(p[0]), fmt_g(p[1]), fmt_g(p[2]))
}

impl DiffReport {
    /// The report as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a report serialises")
    }

    /// The report as text: the verdict, the bounds, the matched materials
    /// and their volumes, the unmatched ones and the worst places.
    pub fn to_table(&self) -> String {
        let mut text = String::new();
        for (side, b) in SIDES.iter().zip(&self.bounds) {
            let _ = writeln!(
                text,
                "bounds of {side}: {} to {}",
                fmt_point(&b[0]),
                fmt_point(&b[1])
            );
        }
        for note in &self.bounds_notes {
            let _ = writeln!(text, "note: {note}");
        }
        let _ = writeln!(
            text,
            "\n{:<44} {:<44} {:>24} {:>24}",
            "material in A", "material in B", "volume in A ± 1σ", "volume in B ± 1σ"
        );
        for class in &self.classes {
            let volume = |v: &[f64; 2]| format!("{} ± {}", fmt_g(v[0]), fmt_g(v[1]));
            let _ = writeln!(
                text,
                "{:<44} {:<44} {:>24} {:>24}",
                class.in_a,
                class.in_b,
                volume(&class.volume_a),
                volume(&class.volume_b)
            );
        }
        for u in &self.unmatched {
            let closest = u.closest.as_deref().unwrap_or("nothing to compare with");
            let _ = writeln!(
                text,
                "unmatched in {}: {} (closest: {closest})",
                u.model, u.substance
            );
        }
        if !self.worst.is_empty() {
            let _ = writeln!(
                text,
                "\nworst places (volume, a point, region and material in A | in B):"
            );
        }
        for place in &self.worst {
            let _ = writeln!(
                text,
                "  {:>12}  {}  {} {} | {} {}",
                fmt_g(place.volume),
                fmt_point(&place.point),
                place.region_a,
                place.substance_a,
                place.region_b,
                place.substance_b
            );
        }
        let verdict = if self.agree { "agree" } else { "DIFFER" };
        let _ = writeln!(
            text,
            "\nthe models {verdict}: they differ in {} ± {} of {} holding material ({} %; tolerance {} %); {} rays in each, {:.2} s",
            fmt_g(self.differ_volume[0]),
            fmt_g(self.differ_volume[1]),
            fmt_g(self.material_volume[0]),
            fmt_g(100.0 * self.differ_fraction),
            fmt_g(100.0 * self.tolerance),
            self.rays,
            self.seconds
        );
        text
    }
}
