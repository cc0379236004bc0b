//! `diff`: are two models of one experiment the same geometry with the
//! same materials?
//!
//! Both models are sampled by the same jittered grids of rays as
//! [`volumes`](crate::volumes), through the box where their bounds
//! overlap. Along each ray, each model's stretches are cut where either
//! changes region, and each piece is classed by what fills it in each
//! model: void, or a substance (a material at a density), matched between
//! the models by composition and density (see [`DiffOptions`]). Pieces
//! whose classes differ are disagreement; its volume, with the spread of
//! the batches for its error, decides the verdict.

mod atomic;
mod picture;
mod report;
mod substance;

pub use picture::{diff_picture, DiffPicture};
pub use report::{ClassVolume, DiffReport, Place, RegionVolumeOf, UnmatchedSubstance};

use crate::analyse::RayCheck;
use crate::model::{CheckError, Model};
use crate::volume::{jittered_batch, Stats};
use std::collections::HashMap;
use std::time::Instant;
use substance::{match_substances, Matching, Substances};
use sv_math::{Aabb, DVec3, Ray};
use sv_scene::Scene;
use sv_trace::Partition;

/// One of the two models.
#[derive(Clone, Copy)]
pub struct DiffSide<'a> {
    /// The scene as read (its materials and region properties).
    pub scene: &'a Scene,
    /// The scene prepared for checking.
    pub model: &'a Model,
}

/// Options for [`diff`].
#[derive(Clone, Debug)]
pub struct DiffOptions {
    /// Grid cells per side of a batch (64).
    pub rays_per_side: u32,
    /// Batches (8); their spread gives the errors.
    pub batches: u32,
    /// Seed of the jitter.
    pub seed: u64,
    /// The models agree when the volume where they differ is at most this
    /// fraction of the volume holding material in either (1e-3).
    pub tolerance: f64,
    /// Substances are the same when their atom fractions differ by at most
    /// this much in all (half the sum of the differences; 0.01).
    pub composition_tolerance: f64,
    /// … and their atom densities by at most this relative amount (0.01).
    pub density_tolerance: f64,
    /// Material pairs (A's, B's; names or numbers) that are the same
    /// whatever their compositions say; the materials named here match
    /// nothing else.
    pub map: Vec<(String, String)>,
    /// How many of the worst places to list (12).
    pub worst: usize,
    /// Compare inside this box instead of where the models' bounds overlap
    /// (needed when a model is unbounded: an infinite lattice, a pin cell
    /// infinite in z).
    pub region: Option<Aabb>,
}

impl Default for DiffOptions {
    fn default() -> Self {
        DiffOptions {
            rays_per_side: 64,
            batches: 8,
            seed: 1971,
            tolerance: 1e-3,
            composition_tolerance: 0.01,
            density_tolerance: 0.01,
            map: Vec::new(),
            worst: 12,
            region: None,
        }
    }
}

/// The two models' classes, ready for sampling.
pub(crate) struct Classes {
    /// Per region of A (then of B), its class (0: void).
    pub of_region: [Vec<u32>; 2],
    pub count: usize,
}

impl Classes {
    /// The substances of both models, how they match, and the classes.
    pub(crate) fn of(
        a: &DiffSide,
        b: &DiffSide,
        opts: &DiffOptions,
    ) -> ([Substances; 2], Matching, Classes) {
        let subs = [Substances::of_scene(a.scene), Substances::of_scene(b.scene)];
        let matching = match_substances(
            &subs[0].list,
            &subs[1].list,
            &opts.map,
            (opts.composition_tolerance, opts.density_tolerance),
        );
        let classes = Classes::new(&subs, &matching);
        (subs, matching, classes)
    }

    fn new(subs: &[Substances; 2], matching: &Matching) -> Classes {
        let of = |s: &Substances, class: &[u32]| -> Vec<u32> {
            s.of_region
                .iter()
                .map(|sub| sub.map_or(0, |i| class[i]))
                .collect()
        };
        Classes {
            of_region: [
                of(&subs[0], &matching.class_a),
                of(&subs[1], &matching.class_b),
            ],
            count: matching.classes,
        }
    }

    fn class(&self, side: usize, region: Option<u32>) -> u32 {
        region.map_or(0, |r| {
            self.of_region[side].get(r as usize).copied().unwrap_or(0)
        })
    }
}

/// The stretches of `parts` with overlaps resolved (the region entered
/// first keeps the shared stretch), in order: `(t0, t1, region)`.
pub(crate) fn disjoint(parts: &[Partition], out: &mut Vec<(f64, f64, u32)>) {
    out.clear();
    let mut end = f64::NEG_INFINITY;
    for p in parts {
        let a = p.span.a.t.max(end);
        if p.span.b.t > a {
            out.push((a, p.span.b.t, p.region));
            end = p.span.b.t;
        }
    }
}

/// Walk two sets of disjoint stretches together over `(t0, t1)`: `f(a, b,
/// region in A, region in B)` for each piece where neither changes.
pub(crate) fn pieces(
    a: &[(f64, f64, u32)],
    b: &[(f64, f64, u32)],
    (t0, t1): (f64, f64),
    mut f: impl FnMut(f64, f64, Option<u32>, Option<u32>),
) {
    let (mut i, mut j, mut t) = (0, 0, t0);
    while t < t1 {
        while i < a.len() && a[i].1 <= t {
            i += 1;
        }
        while j < b.len() && b[j].1 <= t {
            j += 1;
        }
        let at = |s: &[(f64, f64, u32)], k: usize| -> (Option<u32>, f64) {
            match s.get(k) {
                Some(&(s0, s1, r)) if s0 <= t => (Some(r), s1),
                Some(&(s0, _, _)) => (None, s0),
                None => (None, t1),
            }
        };
        let ((ra, ea), (rb, eb)) = (at(a, i), at(b, j));
        let end = ea.min(eb).min(t1);
        if end > t {
            f(t, end, ra, rb);
        }
        t = end.max(t + f64::EPSILON * t.abs().max(1.0));
    }
}

/// Working memory for one thread: both models' rays.
pub(crate) struct PairRays<'a> {
    checks: [RayCheck<'a>; 2],
    stretches: [Vec<(f64, f64, u32)>; 2],
}

impl<'a> PairRays<'a> {
    pub(crate) fn new(a: &'a Model, b: &'a Model) -> Self {
        PairRays {
            checks: [RayCheck::new(a), RayCheck::new(b)],
            stretches: [Vec::new(), Vec::new()],
        }
    }

    /// Trace `ray` over `(t0, t1)` in both models and walk the pieces.
    pub(crate) fn trace(
        &mut self,
        ray: &Ray,
        (t0, t1): (f64, f64),
        f: impl FnMut(f64, f64, Option<u32>, Option<u32>),
    ) {
        for side in 0..2 {
            self.checks[side].partitions(ray, t0, t1);
            disjoint(&self.checks[side].parts, &mut self.stretches[side]);
        }
        pieces(&self.stretches[0], &self.stretches[1], (t0, t1), f);
    }
}

/// Per (region in A, region in B) where they differ: volume, the longest
/// piece and its middle.
pub(crate) type Places = HashMap<(Option<u32>, Option<u32>), (f64, f64, DVec3)>;

/// What one row of rays of a batch saw.
#[derive(Default)]
struct Tally {
    regions: [Vec<f64>; 2],
    classes: [Vec<f64>; 2],
    differ: f64,
    material: f64,
    places: Places,
}

fn add_at(v: &mut Vec<f64>, i: usize, x: f64) {
    if v.len() <= i {
        v.resize(i + 1, 0.0);
    }
    v[i] += x;
}

/// Compare models `a` and `b`. Runs on the current rayon pool.
pub fn diff(a: DiffSide, b: DiffSide, opts: &DiffOptions) -> Result<DiffReport, CheckError> {
    if opts.rays_per_side == 0 || opts.batches < 2 {
        return Err(CheckError::Option(
            "a diff needs at least one ray per side and two batches".into(),
        ));
    }
    let start = Instant::now();
    let (bounds, common) = compared(&a, &b, opts)?;
    let (subs, matching, classes) = Classes::of(&a, &b, opts);
    let models = [a.model, b.model];
    let mut sampled = Sampled::new(&models, classes.count);
    if !common.is_empty() {
        for batch in 0..opts.batches {
            sampled.batch(&models, &classes, &common, opts, batch);
        }
    }
    Ok(report::build(
        report::Inputs {
            models,
            subs: &subs,
            matching: &matching,
            bounds,
            common,
            sampled: &sampled,
            seconds: start.elapsed().as_secs_f64(),
        },
        opts,
    ))
}

/// The bounds of both models and the box to compare them in.
pub(crate) fn compared(
    a: &DiffSide,
    b: &DiffSide,
    opts: &DiffOptions,
) -> Result<([Aabb; 2], Aabb), CheckError> {
    match opts.region {
        Some(region) => Ok(([a.model.bounds(), b.model.bounds()], region)),
        None => {
            let bounds = [a.model.finite_bounds()?, b.model.finite_bounds()?];
            Ok((bounds, bounds[0].intersection(&bounds[1])))
        }
    }
}

/// Statistics gathered over the batches.
pub(crate) struct Sampled {
    pub regions: [Vec<Stats>; 2],
    pub classes: [Vec<Stats>; 2],
    pub differ: Stats,
    pub material: Stats,
    pub places: Places,
    pub rays: u64,
}

impl Sampled {
    fn new(models: &[&Model; 2], classes: usize) -> Sampled {
        let regions = |m: &Model| vec![Stats::default(); m.names.len()];
        Sampled {
            regions: [regions(models[0]), regions(models[1])],
            classes: [
                vec![Stats::default(); classes],
                vec![Stats::default(); classes],
            ],
            differ: Stats::default(),
            material: Stats::default(),
            places: HashMap::new(),
            rays: 0,
        }
    }

    fn batch(&mut self, models: &[&Model; 2], cl: &Classes, bx: &Aabb, o: &DiffOptions, id: u32) {
        let rows = jittered_batch(
            bx,
            o.rays_per_side,
            (o.seed, id as u64),
            || PairRays::new(models[0], models[1]),
            |pair, ray, _, area, tally: &mut Tally| {
                // Only inside the box: the grid's rays start a little
                // before it, where one model may hold what the other
                // leaves out.
                let axis = (0..3).find(|&k| ray.dir[k] != 0.0).unwrap_or(2);
                let enter = bx.min[axis] - ray.origin[axis];
                let within = (enter, enter + bx.size()[axis]);
                pair.trace(ray, within, |t0, t1, ra, rb| {
                    let volume = (t1 - t0) * area;
                    for (side, region) in [ra, rb].into_iter().enumerate() {
                        if let Some(r) = region {
                            add_at(&mut tally.regions[side], r as usize, volume);
                        }
                    }
                    let (ca, cb) = (cl.class(0, ra), cl.class(1, rb));
                    add_at(&mut tally.classes[0], ca as usize, volume);
                    add_at(&mut tally.classes[1], cb as usize, volume);
                    if ca != 0 || cb != 0 {
                        tally.material += volume;
                    }
                    if ca != cb {
                        tally.differ += volume;
                        let place = tally.places.entry((ra, rb)).or_default();
                        place.0 += volume;
                        if t1 - t0 > place.1 {
                            place.1 = t1 - t0;
                            place.2 = ray.at(0.5 * (t0 + t1));
                        }
                    }
                });
            },
        );
        self.rays += 3 * (o.rays_per_side as u64).pow(2);
        let mut sum = Tally::default();
        for row in rows {
            for side in 0..2 {
                for (i, v) in row.regions[side].iter().enumerate() {
                    add_at(&mut sum.regions[side], i, *v);
                }
                for (i, v) in row.classes[side].iter().enumerate() {
                    add_at(&mut sum.classes[side], i, *v);
                }
            }
            sum.differ += row.differ;
            sum.material += row.material;
            for (key, (volume, longest, point)) in row.places {
                let place = self.places.entry(key).or_default();
                place.0 += volume;
                if longest > place.1 {
                    (place.1, place.2) = (longest, point);
                }
            }
        }
        for side in 0..2 {
            for (i, st) in self.regions[side].iter_mut().enumerate() {
                st.add(
                    sum.regions[side].get(i).copied().unwrap_or(0.0),
                    DVec3::ZERO,
                );
            }
            for (i, st) in self.classes[side].iter_mut().enumerate() {
                st.add(
                    sum.classes[side].get(i).copied().unwrap_or(0.0),
                    DVec3::ZERO,
                );
            }
        }
        self.differ.add(sum.differ, DVec3::ZERO);
        self.material.add(sum.material, DVec3::ZERO);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_cut_where_either_side_changes() {
        let a = [(1.0, 3.0, 0), (3.0, 5.0, 1)];
        let b = [(2.0, 4.0, 7)];
        let mut seen = Vec::new();
        pieces(&a, &b, (0.0, 6.0), |t0, t1, ra, rb| {
            seen.push((t0, t1, ra, rb))
        });
        assert_eq!(
            seen,
            [
                (0.0, 1.0, None, None),
                (1.0, 2.0, Some(0), None),
                (2.0, 3.0, Some(0), Some(7)),
                (3.0, 4.0, Some(1), Some(7)),
                (4.0, 5.0, Some(1), None),
                (5.0, 6.0, None, None),
            ]
        );
    }
}
