//! What one ray sees: overlaps, voids and space outside the universe.

use crate::model::{Hull, Model};
use crate::refine::{signature, Signer};
use sv_math::Ray;
use sv_trace::{leave_repeats_empty, same_stretches, Partition, RaysShare, Scratch};

/// What kind of problem a stretch of ray is.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub enum FindingKind {
    /// Two regions (lower index first) both claim the stretch.
    Overlap(u32, u32),
    /// Inside the universe, claimed by no region; the regions met just
    /// before and just after the gap along the ray (`None`: the universe's
    /// own boundary), lower first.
    Void(Option<u32>, Option<u32>),
    /// A region claims space outside the universe's hull.
    Outside(u32),
}

/// One problem stretch of a ray, `t0 < t1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Finding {
    /// What it is.
    pub kind: FindingKind,
    /// Start along the ray.
    pub t0: f64,
    /// End along the ray.
    pub t1: f64,
}

/// Per-thread working memory for classifying rays of a [`Model`].
pub struct RayCheck<'a> {
    model: &'a Model,
    s: Scratch,
    hs: Option<Scratch>,
    /// Partitions of the last ray, clipped to its range.
    pub parts: Vec<Partition>,
    hull_parts: Vec<Partition>,
    hull: Vec<(f64, f64)>,
    cover: Vec<(f64, f64)>,
    /// Problems found on the last ray.
    pub findings: Vec<Finding>,
    /// The [`signature`] of the last ray's partitions.
    pub(crate) signature: u64,
}

/// Classify one ray: overlaps longer than `tol` always; voids and
/// stretches outside the universe when the model has a universe. Results
/// are left in [`RayCheck::findings`] (and the partitions in
/// [`RayCheck::parts`]).
pub fn analyse_ray(rc: &mut RayCheck<'_>, ray: &Ray, tmin: f64, tmax: f64, tol: f64) {
    rc.run(ray, tmin, tmax, tol)
}

fn merge_into(out: &mut Vec<(f64, f64)>, a: f64, b: f64) {
    match out.last_mut() {
        Some(last) if a <= last.1 => last.1 = last.1.max(b),
        _ => out.push((a, b)),
    }
}

impl<'a> RayCheck<'a> {
    /// Working memory for `model`.
    pub fn new(model: &'a Model) -> RayCheck<'a> {
        let hs = match &model.hull {
            Some(Hull::Prepared(p)) => Some(Scratch::new(p)),
            _ => None,
        };
        RayCheck {
            model,
            s: Scratch::new(&model.prepared),
            hs,
            parts: Vec::new(),
            hull_parts: Vec::new(),
            hull: Vec::new(),
            cover: Vec::new(),
            findings: Vec::new(),
            signature: signature(&[], 0.0),
        }
    }

    /// The prepared geometry the rays are cast through.
    pub(crate) fn prepared(&self) -> &sv_trace::Prepared {
        &self.model.prepared
    }

    /// Only the partitions of the ray within `(tmin, tmax)`, clipped.
    pub fn partitions(&mut self, ray: &Ray, tmin: f64, tmax: f64) {
        self.model
            .prepared
            .partitions(ray, tmin, tmax, &mut self.s, &mut self.parts);
        self.clip(tmin, tmax);
    }

    /// The partitions clipped to `(tmin, tmax)`.
    fn clip(&mut self, tmin: f64, tmax: f64) {
        // Most rays' partitions lie within their range: read, not
        // rewritten.
        let within = |p: &Partition| p.span.a.t >= tmin && p.span.b.t <= tmax;
        let clipped = |p: &Partition| within(p) && p.span.b.t > p.span.a.t;
        if self.parts.iter().all(clipped) {
            return;
        }
        self.parts.retain_mut(|p| {
            p.span.a.t = p.span.a.t.max(tmin);
            p.span.b.t = p.span.b.t.min(tmax);
            p.span.b.t > p.span.a.t
        });
    }

    /// See [`analyse_ray`].
    pub fn run(&mut self, ray: &Ray, tmin: f64, tmax: f64, tol: f64) {
        self.findings.clear();
        self.partitions(ray, tmin, tmax);
        self.classify(ray, tmin, tmax, tol);
    }

    /// The partitions of each of `rays` within `(tmin, tmax)` (unclipped)
    /// into the same places of `out`, several at once where the processor
    /// can: `zones` must hold every zone whose bounds any of them meets
    /// there; `None`, walk the hierarchy. `share` says what the rays
    /// share (those a check fires together run along one axis). Only the
    /// regions and distances are kept: a check reads nothing else.
    /// Returns the rays (bit `k` for ray `k`) whose partitions are the ray
    /// before's, to the bit, left empty in `out` (see
    /// [`sv_trace::Prepared::stretches_of_rays_in`]).
    pub(crate) fn partitions_of_rays(
        &mut self,
        zones: Option<&[u32]>,
        (rays, share): (&[Ray], RaysShare),
        tmin: f64,
        tmax: f64,
        out: &mut [Vec<Partition>],
    ) -> u64 {
        let prepared = &self.model.prepared;
        match zones {
            Some(zones) => {
                let rays = (rays, share);
                prepared.stretches_of_rays_in(zones, rays, tmin, tmax, &mut self.s, out)
            }
            None => {
                for (ray, parts) in rays.iter().zip(out.iter_mut()) {
                    prepared.partitions(ray, tmin, tmax, &mut self.s, parts);
                }
                leave_repeats_empty(&mut out[..rays.len()])
            }
        }
    }

    /// [`RayCheck::run`] of a ray whose partitions within `(tmin, tmax)`
    /// are already in `parts` (from [`RayCheck::partitions_of_rays`]),
    /// which it takes in exchange for the last ray's.
    pub(crate) fn run_on(
        &mut self,
        parts: &mut Vec<Partition>,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        tol: f64,
    ) {
        self.findings.clear();
        std::mem::swap(&mut self.parts, parts);
        self.clip(tmin, tmax);
        // Most rays meet one region or none: without a universe they find
        // nothing, and are not classified.
        if self.parts.len() > 1 || self.model.hull.is_some() {
            self.classify(ray, tmin, tmax, tol);
        } else {
            self.signature = signature(&self.parts, tol);
        }
    }

    /// [`RayCheck::run_on`], unless `follows` (the last ray run on had the
    /// same `(tmin, tmax)` and `tol`), the model has no universe, and the
    /// ray's partitions are the last ray's after clipping, to the bit:
    /// then its findings are the last ray's, and those are kept. True
    /// when they are kept. With `as_last`, `parts` was left empty: the
    /// ray's partitions are the last ray's, which had the same range and
    /// tolerance (`follows` is then not read).
    pub(crate) fn run_on_unless_repeated(
        &mut self,
        parts: &mut Vec<Partition>,
        ray: &Ray,
        (tmin, tmax, tol): (f64, f64, f64),
        (follows, as_last): (bool, bool),
    ) -> bool {
        // Clipping leaves clipped partitions as they are, so partitions
        // equal to the last ray's clipped ones clip to them.
        let no_universe = self.model.hull.is_none();
        let repeated = no_universe && (as_last || follows && same_stretches(parts, &self.parts));
        if !repeated {
            if as_last {
                parts.clone_from(&self.parts);
            }
            self.run_on(parts, ray, tmin, tmax, tol);
        }
        repeated
    }

    /// [`RayCheck::run_on`] of a ray that meets no region, where that
    /// finds nothing (the model has no universe whose voids it would
    /// cross): false, and nothing done, where it may find something.
    pub(crate) fn run_on_empty(&mut self) -> bool {
        if self.model.hull.is_some() {
            return false;
        }
        self.parts.clear();
        self.findings.clear();
        self.signature = signature(&[], 0.0);
        true
    }

    /// The problems along the ray of the partitions in `self.parts`, and
    /// their signature, read in the same pass.
    fn classify(&mut self, ray: &Ray, tmin: f64, tmax: f64, tol: f64) {
        let parts = &self.parts;
        let mut signer = Signer::NONE;
        for (index, part) in parts.iter().enumerate() {
            if index == 0 {
                signer.first(part);
            } else {
                signer.next(part, tol);
            }
            for later in &parts[index + 1..] {
                if later.span.a.t >= part.span.b.t {
                    break;
                }
                if later.region == part.region {
                    continue;
                }
                let (lo, hi) = (later.span.a.t, part.span.b.t.min(later.span.b.t));
                if hi - lo > tol {
                    let first = part.region.min(later.region);
                    let second = part.region.max(later.region);
                    self.findings.push(Finding {
                        kind: FindingKind::Overlap(first, second),
                        t0: lo,
                        t1: hi,
                    });
                }
            }
        }
        self.signature = signer.hash;
        let Some(hull) = &self.model.hull else {
            return;
        };
        self.hull.clear();
        match hull {
            Hull::Everywhere => self.hull.push((tmin, tmax)),
            Hull::Prepared(hull) => {
                let scratch = self.hs.as_mut().expect("hull scratch");
                hull.partitions(ray, tmin, tmax, scratch, &mut self.hull_parts);
                for part in &self.hull_parts {
                    let (a, b) = (part.span.a.t.max(tmin), part.span.b.t.min(tmax));
                    if b > a {
                        merge_into(&mut self.hull, a, b);
                    }
                }
            }
        }
        self.cover.clear();
        for part in &self.parts {
            merge_into(&mut self.cover, part.span.a.t, part.span.b.t);
        }
        self.find_voids(tol);
        self.find_outside(tol);
    }

    /// Voids: the hull's stretches that no region covers.
    fn find_voids(&mut self, tol: f64) {
        for hull_index in 0..self.hull.len() {
            let (h0, h1) = self.hull[hull_index];
            let mut at = h0;
            for cover_index in 0..self.cover.len() {
                let (c0, c1) = self.cover[cover_index];
                if c1 <= at {
                    continue;
                }
                if c0 >= h1 {
                    break;
                }
                if c0 - at > tol {
                    self.void(at, c0);
                }
                at = at.max(c1);
                if at >= h1 {
                    break;
                }
            }
            if h1 - at > tol {
                self.void(at, h1);
            }
        }
    }

    /// Space claimed outside the hull.
    fn find_outside(&mut self, tol: f64) {
        for part in &self.parts {
            let (a, b) = (part.span.a.t, part.span.b.t);
            let mut at = a;
            for &(h0, h1) in &self.hull {
                if h1 <= at {
                    continue;
                }
                if h0 >= b {
                    break;
                }
                if h0 - at > tol {
                    self.findings.push(Finding {
                        kind: FindingKind::Outside(part.region),
                        t0: at,
                        t1: h0,
                    });
                }
                at = at.max(h1);
                if at >= b {
                    break;
                }
            }
            if b - at > tol {
                self.findings.push(Finding {
                    kind: FindingKind::Outside(part.region),
                    t0: at,
                    t1: b,
                });
            }
        }
    }
}

impl RayCheck<'_> {
    fn void(&mut self, t0: f64, t1: f64) {
        let tol = self.model.prepared.tolerance() * 10.0;
        let before = neighbour_before(&self.parts, t0, tol);
        let after = neighbour_after(&self.parts, t1, tol);
        let (x, y) = match (before, after) {
            (Some(a), Some(b)) => (Some(a.min(b)), Some(a.max(b))),
            (a, b) => (None, a.or(b)),
        };
        self.findings.push(Finding {
            kind: FindingKind::Void(x, y),
            t0,
            t1,
        });
    }
}

fn neighbour_before(parts: &[Partition], t: f64, tol: f64) -> Option<u32> {
    parts
        .iter()
        .filter(|p| (p.span.b.t - t).abs() <= tol.max(1e-12 * t.abs()))
        .max_by(|a, b| a.span.b.t.total_cmp(&b.span.b.t))
        .map(|p| p.region)
}

fn neighbour_after(parts: &[Partition], t: f64, tol: f64) -> Option<u32> {
    parts
        .iter()
        .filter(|p| (p.span.a.t - t).abs() <= tol.max(1e-12 * t.abs()))
        .min_by(|a, b| a.span.a.t.total_cmp(&b.span.a.t))
        .map(|p| p.region)
}
