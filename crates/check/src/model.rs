//! The model to check: the prepared geometry, region names, the declared
//! universe and its hull.

use sv_geom::{Fill, Geometry, Op, Region, Warning, Zone};
use sv_math::Aabb;
use sv_scene::Scene;
use sv_trace::{PrepareError, PrepareOptions, Prepared};

/// Which space the regions are declared to fill.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum UniverseChoice {
    /// No universe: voids are not looked for.
    None,
    /// Look for a black-hole region (see [`Model::new`]); none found means
    /// no universe.
    Auto,
    /// A region or, failing that, a body of this name.
    Named(String),
}

/// The declared universe: every point inside it must belong to a region.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Universe {
    /// A region. Its hull (the union over its zones of the intersection of
    /// the zone's `+` bodies, its `-` bodies ignored) must be filled: by the
    /// region itself and by the regions placed in its holes.
    Region(usize),
    /// A body: its inside must be filled by regions.
    Body(usize),
}

/// A model that cannot be checked.
#[derive(Debug, thiserror::Error)]
pub enum CheckError {
    /// The geometry does not prepare.
    #[error("{0}")]
    Prepare(#[from] PrepareError),
    /// `--universe` names no region and no body.
    #[error("the universe `{0}` is neither a region nor a body")]
    UnknownUniverse(String),
    /// Nothing finite to shoot rays at.
    #[error("the model has no finite region, so there is no box to fire rays through; give one (check --box, slice --extent)")]
    Unbounded,
    /// An option out of range.
    #[error("{0}")]
    Option(String),
}

/// The hull of the universe along a ray.
#[derive(Clone, Debug)]
pub(crate) enum Hull {
    /// A geometry with one region: the hull.
    Prepared(Box<Prepared>),
    /// The universe has a zone without `+` bodies: it is everywhere.
    Everywhere,
}

/// What [`check`](crate::check), [`slice`](crate::slice()) and
/// [`volumes`](crate::volumes) work on.
#[derive(Clone, Debug)]
pub struct Model {
    /// The prepared geometry (every region opaque; transparency plays no
    /// part in checking).
    pub prepared: Prepared,
    /// Region names, by index.
    pub names: Vec<String>,
    /// The universe, when one was given or found.
    pub universe: Option<Universe>,
    /// Name of the universe and how it was chosen, for reports.
    pub universe_note: Option<String>,
    /// Densities (g/cm³) by region, when known.
    pub densities: Vec<Option<f64>>,
    /// COMGEOM air codes by region (0: not air).
    pub air: Vec<i64>,
    /// Regions beyond the model (FLUKA black holes, MCNP cells of
    /// importance zero), by index: never counted as unsampled.
    pub outside: Vec<bool>,
    /// Region descriptions (the deck's comment column), by index.
    pub descriptions: Vec<String>,
    /// Centimetres per model unit.
    pub cm_per_unit: f64,
    /// Short name of the model unit (`in`, `mm`…).
    pub unit: String,
    pub(crate) hull: Option<Hull>,
    pub(crate) region_bounds: Vec<Aabb>,
    /// Per region, the universes its fill holds (empty when not filled).
    filled_with: Vec<Vec<usize>>,
    /// Per region, the universe it belongs to.
    universe_of: Vec<usize>,
    box_: Aabb,
    check_box: Aabb,
}

/// Words that mark a black-hole region in a region's description or in the
/// scene's notes (FLUKA's `BLCKHOLE` material), and region names used for
/// it by convention.
const BLACK_HOLE_WORDS: &[&str] = &["blckhole", "black hole", "blackhole", "black-hole"];
const BLACK_HOLE_NAMES: &[&str] = &["blkhole", "blckhole", "blackhole", "blkbody"];

fn is_word_in(text: &str, word: &str) -> bool {
    text.split(|c: char| !(c.is_alphanumeric() || c == '_' || c == '.' || c == '-'))
        .any(|w| w == word)
}

/// How many times the model's size a universe's cavity may be and still
/// be covered by the rays of a check.
const NEAR_UNIVERSE: f64 = 20.0;

/// The region that looks like a FLUKA black hole, with the reason: of the
/// regions the reader marks beyond the model (FLUKA's BLCKHOLE), the one
/// whose `+` bodies' bounds hold the others' (an inner black hole, such as
/// a dump's, is not the universe); else one whose description or name says
/// so.
fn detect_black_hole(scene: &Scene, p: &Prepared) -> Option<(usize, String)> {
    let outside: Vec<usize> = (0..scene.regions.len())
        .filter(|&i| scene.regions[i].outside)
        .collect();
    let enclosing = outside.iter().copied().max_by(|&a, &b| {
        let size = |r: usize| {
            let b = region_bounds(p, &scene.geometry.regions[r]);
            if b.is_empty() {
                0.0
            } else if b.is_finite() {
                b.diagonal()
            } else {
                f64::INFINITY
            }
        };
        size(a).total_cmp(&size(b)).then(b.cmp(&a))
    });
    if let Some(r) = enclosing {
        let why = if outside.len() > 1 {
            format!(
                "it is the black hole that encloses the other {}",
                outside.len() - 1
            )
        } else {
            "its material is BLCKHOLE".into()
        };
        return Some((r, why));
    }
    for (i, p) in scene.regions.iter().enumerate() {
        let d = p.description.to_ascii_lowercase();
        if let Some(w) = BLACK_HOLE_WORDS.iter().find(|w| d.contains(**w)) {
            return Some((i, format!("its description mentions `{w}`")));
        }
    }
    for note in &scene.notes {
        let n = note.to_ascii_lowercase();
        if BLACK_HOLE_WORDS.iter().any(|w| n.contains(*w)) {
            for (i, r) in scene.geometry.regions.iter().enumerate() {
                if is_word_in(note, &r.name) {
                    return Some((i, format!("the note `{note}` names it")));
                }
            }
        }
    }
    for (i, r) in scene.geometry.regions.iter().enumerate() {
        let n = r.name.to_ascii_lowercase();
        if BLACK_HOLE_NAMES.contains(&n.as_str()) {
            return Some((i, "its name is a black-hole name".into()));
        }
    }
    None
}

/// Bounds of region `r`: union over its zones of the intersection of the
/// zone's `+` bodies' bounds.
fn region_bounds(p: &Prepared, r: &Region) -> Aabb {
    r.zones.iter().fold(Aabb::EMPTY, |acc, z| {
        let zb = z
            .terms
            .iter()
            .filter(|t| t.op == Op::Inside && t.body < p.body_count())
            .fold(Aabb::INFINITE, |b, t| {
                b.intersection(&p.body_bounds(t.body))
            });
        if zb.is_empty() {
            acc
        } else {
            acc.union(&zb)
        }
    })
}

/// The default overlap and void tolerance: 1e-5 of the diagonal of the
/// model's bounds (0.01 mm on a 1 m model).
pub fn default_tolerance(p: &Prepared) -> f64 {
    let b = p.bounds();
    if b.is_empty() || !b.is_finite() {
        1e-9
    } else {
        (1e-5 * b.diagonal()).max(1e-12)
    }
}

/// The boxes a model's samples cover by default: for slices and volumes,
/// every finite region of the model (black holes set aside); for the rays
/// of a check, those that are not air, as the vacuum and air shells a
/// transport model wraps around its detector would leave a grid too
/// coarse to meet it (regions wholly outside the box are listed as such in
/// the report). Each takes in the universe's cavity when that is near it,
/// so that holes between the model and its black hole are found; a far one
/// is left out, as a grid over it could meet nothing smaller than its
/// spacing.
fn default_boxes(scene: &Scene, region_bounds: &[Aabb], hull: Option<&Hull>) -> (Aabb, Aabb) {
    let outside = |r: usize| scene.regions.get(r).is_some_and(|p| p.outside);
    let air = |r: usize| scene.regions.get(r).is_some_and(|p| p.air != 0);
    let union_of = |keep: &dyn Fn(usize) -> bool| {
        region_bounds
            .iter()
            .enumerate()
            .filter(|&(r, b)| keep(r) && b.is_finite() && !b.is_empty())
            .fold(Aabb::EMPTY, |acc, (_, b)| acc.union(b))
    };
    let with_near_cavity = |b: Aabb| match hull {
        Some(Hull::Prepared(hull))
            if hull.bounds().is_finite()
                && (b.is_empty() || hull.bounds().diagonal() <= NEAR_UNIVERSE * b.diagonal()) =>
        {
            b.union(&hull.bounds())
        }
        _ => b,
    };
    let model_box = with_near_cavity(union_of(&|r| !outside(r)));
    let solids_box = union_of(&|r| !outside(r) && !air(r));
    let check_box = if solids_box.is_empty() {
        model_box
    } else {
        with_near_cavity(solids_box)
    };
    (model_box, check_box)
}

impl Model {
    /// Prepare `scene` for checking. With [`UniverseChoice::Auto`], a region
    /// is taken as the universe when its description contains `BLCKHOLE`
    /// (FLUKA's black-hole material), `black hole` or `blackhole` (any
    /// case); else when a note of the scene mentions a black hole and names
    /// the region; else when the region is called `BLKHOLE`, `BLCKHOLE`,
    /// `BLACKHOLE` or `BLKBODY` (any case).
    pub fn new(
        scene: &Scene,
        choice: &UniverseChoice,
    ) -> Result<(Model, Vec<Warning>), CheckError> {
        let geometry = &scene.geometry;
        let (prepared, warnings) = Prepared::new(geometry, &PrepareOptions::default())?;
        let (universe, note) = match choice {
            UniverseChoice::None => (None, None),
            UniverseChoice::Auto => match detect_black_hole(scene, &prepared) {
                Some((region, why)) => (
                    Some(Universe::Region(region)),
                    Some(format!(
                        "region `{}` (found automatically: {why})",
                        geometry.regions[region].name
                    )),
                ),
                None => (None, None),
            },
            UniverseChoice::Named(name) => {
                if let Some(region) = geometry.region_index(name) {
                    (
                        Some(Universe::Region(region)),
                        Some(format!("region `{name}`")),
                    )
                } else if let Some(body) = geometry.body_index(name) {
                    (Some(Universe::Body(body)), Some(format!("body `{name}`")))
                } else {
                    return Err(CheckError::UnknownUniverse(name.clone()));
                }
            }
        };
        let hull = match universe {
            None => None,
            Some(universe) => Some(build_hull(geometry, universe)?),
        };
        // A region bounded only by the outsides of surfaces (MCNP's `5 -6
        // -8 9`, a slab of a cylinder between two planes) has no finite
        // bounds from its `+` bodies: the prepared zones' bounds, which
        // count the planes' outsides too, then bound it.
        let region_bounds: Vec<Aabb> = geometry
            .regions
            .iter()
            .enumerate()
            .map(|(index, r)| {
                let from_plus = region_bounds(&prepared, r);
                if from_plus.is_finite() {
                    from_plus
                } else {
                    from_plus.intersection(&prepared.region_bounds(index))
                }
            })
            .collect();
        let (box_, check_box) = default_boxes(scene, &region_bounds, hull.as_ref());
        Ok((
            Model {
                prepared,
                names: geometry.regions.iter().map(|r| r.name.clone()).collect(),
                universe,
                universe_note: note,
                densities: scene.regions.iter().map(|r| r.density).collect(),
                descriptions: (0..geometry.regions.len())
                    .map(|region| {
                        scene
                            .regions
                            .get(region)
                            .map_or(String::new(), |r| r.description.trim().to_string())
                    })
                    .collect(),
                air: (0..geometry.regions.len())
                    .map(|region| scene.regions.get(region).map_or(0, |r| r.air))
                    .collect(),
                outside: (0..geometry.regions.len())
                    .map(|region| scene.regions.get(region).is_some_and(|r| r.outside))
                    .collect(),
                cm_per_unit: scene.units.mm() / 10.0,
                unit: scene.units.abbrev().to_string(),
                hull,
                region_bounds,
                filled_with: geometry.regions.iter().map(fill_universes).collect(),
                universe_of: geometry.regions.iter().map(|r| r.universe).collect(),
                box_,
                check_box,
            },
            warnings,
        ))
    }

    /// The box that checks and samples cover: the bounds of every finite
    /// zone and of the universe's hull. Empty when every zone is unbounded.
    pub fn bounds(&self) -> Aabb {
        self.box_
    }

    /// The box a check's rays cover by default: [`Model::bounds`] less the
    /// air and vacuum regions around the solid ones, or
    /// [`CheckError::Unbounded`] when it is empty.
    pub fn check_bounds(&self) -> Result<Aabb, CheckError> {
        if self.check_box.is_empty() || !self.check_box.is_finite() {
            Err(CheckError::Unbounded)
        } else {
            Ok(self.check_box)
        }
    }

    /// [`Model::bounds`], or [`CheckError::Unbounded`] when it is empty.
    pub fn finite_bounds(&self) -> Result<Aabb, CheckError> {
        if self.box_.is_empty() || !self.box_.is_finite() {
            Err(CheckError::Unbounded)
        } else {
            Ok(self.box_)
        }
    }

    /// Bounds of region `r` from its `+` bodies, clipped to [`Model::bounds`]
    /// (so unbounded regions are measured inside the model's box).
    pub fn region_bounds(&self, r: usize) -> Aabb {
        self.region_bounds[r].intersection(&self.box_)
    }

    /// True when an overlap of regions `a` and `b` is one with air, which
    /// GIFT and BRL-CAD let a solid win: one of them is air and the other
    /// not, or both are air of the same code. Two airs of different codes
    /// overlapping is a real overlap.
    pub fn is_air_overlap(&self, a: usize, b: usize) -> bool {
        let code = |r: usize| self.air.get(r).copied().unwrap_or(0);
        let (x, y) = (code(a), code(b));
        (x != 0 || y != 0) && (x == 0 || y == 0 || x == y)
    }

    /// True when region `r` is air (a non-zero air code).
    pub fn is_air(&self, r: usize) -> bool {
        self.air.get(r).is_some_and(|&code| code != 0)
    }

    /// Mark a filled region seen when a region of what it holds was seen:
    /// rays report what fills a region, not the region around it.
    pub(crate) fn container_seen(&self, seen: &mut [bool]) {
        let universes = self.universe_of.iter().copied().max().map_or(0, |u| u + 1);
        // Each pass lifts what was seen one level of nesting up.
        loop {
            let mut universe_seen = vec![false; universes];
            for (region, &was_seen) in seen.iter().enumerate() {
                if was_seen {
                    universe_seen[self.universe_of[region]] = true;
                }
            }
            let mut changed = false;
            for (region, filled) in self.filled_with.iter().enumerate() {
                let met = filled.iter().any(|&u| universe_seen.get(u) == Some(&true));
                if met && !seen[region] {
                    seen[region] = true;
                    changed = true;
                }
            }
            if !changed {
                return;
            }
        }
    }

    /// True when region `r` reaches outside [`Model::bounds`].
    pub fn region_is_clipped(&self, r: usize) -> bool {
        let b = self.region_bounds[r];
        !b.is_empty() && b.union(&self.box_) != self.box_
    }
}

/// The universes `region`'s fill holds.
fn fill_universes(region: &Region) -> Vec<usize> {
    match &region.fill {
        None => Vec::new(),
        Some(Fill::Universe { universe, .. }) => vec![*universe],
        Some(Fill::Lattice(lattice)) => {
            let mut universes: Vec<usize> = lattice
                .elements
                .iter()
                .chain(std::iter::once(&lattice.outer))
                .flatten()
                .copied()
                .collect();
            universes.sort_unstable();
            universes.dedup();
            universes
        }
    }
}

fn build_hull(g: &Geometry, u: Universe) -> Result<Hull, CheckError> {
    let zones: Vec<Zone> = match u {
        Universe::Body(b) => vec![Zone::new(vec![sv_geom::Term {
            op: Op::Inside,
            body: b,
        }])],
        Universe::Region(r) => {
            let mut zs = Vec::new();
            for z in &g.regions[r].zones {
                let terms: Vec<_> = z
                    .terms
                    .iter()
                    .copied()
                    .filter(|t| t.op == Op::Inside)
                    .collect();
                if terms.is_empty() {
                    return Ok(Hull::Everywhere);
                }
                zs.push(Zone::new(terms));
            }
            zs
        }
    };
    let hg = Geometry {
        bodies: g.bodies.clone(),
        regions: vec![Region::new("universe", zones)],
        ..Geometry::default()
    };
    let (p, _) = Prepared::new(&hg, &PrepareOptions::default())?;
    Ok(Hull::Prepared(Box::new(p)))
}
