//! The result of [`check`](crate::check): the problems found, as data
//! (JSON) and as a table.

use serde::Serialize;
use std::fmt::Write as _;

/// How much of a problem was seen.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Problem {
    /// Sum of the problem stretches over every ray (model units).
    pub total_length: f64,
    /// The longest single stretch.
    pub max_length: f64,
    /// Midpoint of the longest stretch: a point inside the problem.
    pub point: [f64; 3],
    /// Number of stretches seen.
    pub hits: u64,
    /// Volume estimate from the grid rays (units³): the summed length times
    /// the area each grid ray stands for, averaged over the three axes.
    pub volume: f64,
}

/// Two regions claiming the same space.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Overlap {
    /// Their names.
    pub regions: [String; 2],
    /// Their indices (0-based, deck order).
    pub region_indices: [usize; 2],
    /// True when at least one of them is an air region.
    pub air: bool,
    /// How much.
    #[serde(flatten)]
    pub problem: Problem,
}

/// Space inside the universe that no region claims.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Void {
    /// The regions met on either side of the gap along the rays (`None`:
    /// the boundary of the universe's hull).
    pub between: [Option<String>; 2],
    /// How much.
    #[serde(flatten)]
    pub problem: Problem,
}

/// A region reaching outside the universe's hull.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Outside {
    /// The region.
    pub region: String,
    /// How much.
    #[serde(flatten)]
    pub problem: Problem,
}

/// The smallest overlap or void a check is sure to meet, given its grid
/// and refinement (model units), as long as it is longer than the
/// tolerance along the rays that cross it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SmallestFeature {
    /// Anywhere: one whose cross-section across one of the axes holds a
    /// circle of this diameter (the diagonal of a grid cell, at most 1.42
    /// times the spacing) is met by a grid ray.
    pub anywhere: f64,
    /// Where neighbouring grid rays see different regions (the edges of
    /// parts, where slivers lie), rays are added down to this distance
    /// apart: a sliver there at least this thick across the rays is met.
    /// `None` without refinement.
    pub at_edges: Option<f64>,
    /// The same in words.
    pub note: String,
}

/// The universe a check used.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UniverseInfo {
    /// What it is and how it was chosen.
    pub description: String,
}

/// The result of [`check`](crate::check()).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// Model unit (`in`, `mm`, …).
    pub unit: String,
    /// Number of regions.
    pub regions: usize,
    /// The box the rays cross: lower and upper corners.
    pub bounds: [[f64; 3]; 2],
    /// Grid spacing used.
    pub spacing: f64,
    /// Grid rays fired (all three axes).
    pub grid_rays: u64,
    /// Random rays fired.
    pub random_rays: u64,
    /// Tolerance used.
    pub tolerance: f64,
    /// Halvings of the spacing down to which rays were added between
    /// neighbouring grid rays that see different regions (0: none).
    pub refine: u32,
    /// Rays added by the refinement.
    pub refine_rays: u64,
    /// The smallest problem the rays are sure to meet.
    pub smallest_feature: SmallestFeature,
    /// The universe, if voids were looked for.
    pub universe: Option<UniverseInfo>,
    /// Overlapping pairs, most severe (largest total length) first. Pairs
    /// with an air region are here only with [`CheckOptions::strict_air`](crate::CheckOptions::strict_air).
    pub overlaps: Vec<Overlap>,
    /// Overlapping pairs in which at least one region is air, when they are
    /// not counted as problems.
    pub air_overlaps: Vec<Overlap>,
    /// Voids, largest first.
    pub voids: Vec<Void>,
    /// Regions outside the universe, largest first.
    pub outside: Vec<Outside>,
    /// Regions no ray crossed: empty (subtracted away entirely) or thinner
    /// than the spacing. Listed for information; not counted as problems.
    pub unseen: Vec<String>,
    /// Regions wholly outside the box checked (the air or vacuum shells
    /// around a transport model are left out of the default box): not
    /// checked, and not counted against the verdict.
    pub beyond_box: Vec<String>,
    /// Wall-clock time of the ray casting, seconds.
    pub seconds: f64,
}

impl Report {
    /// True when nothing was found.
    pub fn is_clean(&self) -> bool {
        self.overlaps.is_empty() && self.voids.is_empty() && self.outside.is_empty()
    }

    /// True when every region of the model was met by some ray: a clean
    /// report of a check that met fewer says nothing of the others.
    pub fn met_every_region(&self) -> bool {
        self.unseen.is_empty()
    }

    /// The report as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a report serialises")
    }
}

impl Report {
    /// The report as a human-readable table.
    pub fn to_table(&self) -> String {
        let mut table = Table {
            text: String::new(),
            diagonal: (0..3)
                .map(|axis| (self.bounds[1][axis] - self.bounds[0][axis]).powi(2))
                .sum::<f64>()
                .sqrt(),
        };
        self.write_summary(&mut table.text);
        self.write_overlaps(&mut table);
        if self.universe.is_some() {
            self.write_universe_problems(&mut table);
        }
        let text = &mut table.text;
        if !self.unseen.is_empty() {
            let _ = writeln!(
                text,
                "{} regions met by no ray (empty, or thinner than the spacing): {}",
                self.unseen.len(),
                self.unseen.join(", ")
            );
        }
        if !self.beyond_box.is_empty() {
            let _ = writeln!(
                text,
                "{} regions lie wholly outside the box and were not checked: {}",
                self.beyond_box.len(),
                self.beyond_box.join(", ")
            );
        }
        let verdict = match (self.is_clean(), self.met_every_region()) {
            (true, true) => "clean".to_string(),
            (true, false) => format!(
                "incomplete: nothing found, but {} of {} regions were met by no ray; give a finer --spacing or a --box around them (or --allow-unsampled)",
                self.unseen.len(),
                self.regions
            ),
            (false, _) => "problems found".to_string(),
        };
        let _ = writeln!(text, "{verdict}");
        table.text
    }

    /// What was fired through which box, and the universe.
    fn write_summary(&self, text: &mut String) {
        let unit = &self.unit;
        let _ = writeln!(
            text,
            "checked {} regions with {} grid rays (spacing {} {unit}), {} refinement rays and {} random rays in {:.2} s; tolerance {} {unit}",
            self.regions,
            self.grid_rays,
            fmt_g(self.spacing),
            self.refine_rays,
            self.random_rays,
            self.seconds,
            fmt_g(self.tolerance)
        );
        let _ = writeln!(text, "{}", self.smallest_feature.note);
        let [lower, upper] = &self.bounds;
        let _ = writeln!(
            text,
            "box ({}, {}, {}) to ({}, {}, {})",
            fmt_g(lower[0]),
            fmt_g(lower[1]),
            fmt_g(lower[2]),
            fmt_g(upper[0]),
            fmt_g(upper[1]),
            fmt_g(upper[2])
        );
        match &self.universe {
            Some(universe) => {
                let _ = writeln!(text, "universe: {}", universe.description);
            }
            None => {
                let _ = writeln!(
                    text,
                    "universe: none (voids not looked for; give --universe REGION|BODY)"
                );
            }
        }
    }

    /// The overlapping pairs, then those with air regions.
    fn write_overlaps(&self, table: &mut Table) {
        let pair = |o: &Overlap| format!("{} × {}", o.regions[0], o.regions[1]);
        if self.overlaps.is_empty() {
            let _ = writeln!(table.text, "no overlaps");
        } else {
            let _ = writeln!(table.text, "{} overlapping pairs:", self.overlaps.len());
            table.header("regions");
            for overlap in &self.overlaps {
                table.row(&pair(overlap), &overlap.problem);
            }
        }
        if !self.air_overlaps.is_empty() {
            let _ = writeln!(
                table.text,
                "{} overlapping pairs with air regions (not counted: air gives way to solids, as in GIFT and BRL-CAD; --strict-air counts them):",
                self.air_overlaps.len()
            );
            table.header("regions");
            for overlap in &self.air_overlaps {
                table.row(&pair(overlap), &overlap.problem);
            }
        }
    }

    /// The voids and the regions outside the universe.
    fn write_universe_problems(&self, table: &mut Table) {
        if self.voids.is_empty() {
            let _ = writeln!(table.text, "no voids");
        } else {
            let _ = writeln!(table.text, "{} voids:", self.voids.len());
            table.header("between");
            let side =
                |region: &Option<String>| region.clone().unwrap_or_else(|| "(universe)".into());
            for void in &self.voids {
                let between = format!("{} | {}", side(&void.between[0]), side(&void.between[1]));
                table.row(&between, &void.problem);
            }
        }
        if !self.outside.is_empty() {
            let _ = writeln!(
                table.text,
                "{} regions reach outside the universe:",
                self.outside.len()
            );
            table.header("region");
            for outside in &self.outside {
                table.row(&outside.region, &outside.problem);
            }
        }
    }
}

/// The text of a report's table, and the diagonal of the box checked
/// (coordinates within rounding of zero print as 0).
struct Table {
    text: String,
    diagonal: f64,
}

impl Table {
    /// The column titles, `first` over the names.
    fn header(&mut self, first: &str) {
        let _ = writeln!(
            self.text,
            "  {:<32} {:>12} {:>12} {:>12} {:>7}  point (x, y, z)",
            first, "total len", "max len", "volume", "hits"
        );
    }

    /// One problem under the name `name`.
    fn row(&mut self, name: &str, problem: &Problem) {
        let coordinate = |v: f64| {
            fmt_g(if v.abs() < 1e-12 * self.diagonal {
                0.0
            } else {
                v
            })
        };
        let _ = writeln!(
            self.text,
            "  {:<32} {:>12} {:>12} {:>12} {:>7}  ({}, {}, {})",
            name,
            fmt_g(problem.total_length),
            fmt_g(problem.max_length),
            fmt_g(problem.volume),
            problem.hits,
            coordinate(problem.point[0]),
            coordinate(problem.point[1]),
            coordinate(problem.point[2])
        );
    }
}

/// A number in a compact form (up to 6 significant digits).
pub(crate) fn fmt_g(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let magnitude = v.abs();
    if !(1e-4..1e7).contains(&magnitude) {
        return format!("{v:.4e}");
    }
    let digits = (5 - magnitude.log10().floor() as i32).clamp(0, 10) as usize;
    let text = format!("{v:.digits$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}
