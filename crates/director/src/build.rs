//! Building a [`Timeline`]: checking a [`Spec`] against its scene (indices,
//! what carries what, which bodies move with which objects) and expanding
//! its steps into blocks of frames.

use crate::{
    AimPoint, Block, Change, DirectorError, FrameState, Owner, Spec, Step, Target, Timed, Timeline,
    MAX_BLOCKS, MAX_FRAMES,
};
use sv_geom::{BodyKind, Geometry, ParamKind};
use sv_math::{DAffine3, DVec3};
use sv_scene::Scene;

impl Timeline {
    /// Validate `spec` against the scene it animates and expand it. Every
    /// problem found is returned. `base` must be the scene later passed to
    /// [`Timeline::scene_at`].
    pub fn new(spec: Spec, base: &Scene) -> Result<Timeline, Vec<DirectorError>> {
        let mut errors = Vec::new();
        check_indices(&spec, base, &mut errors);
        if !errors.is_empty() {
            return Err(errors);
        }
        let subtree = carried(&spec)?;
        let geometry = &base.geometry;
        let owners = BodyOwners::of(&spec, geometry, &subtree, &mut errors);
        let subtree_bodies = owners.subtree_bodies(&subtree);
        let mut expanded = Expanded::default();
        if expanded.steps(&spec.steps).is_err() {
            errors.push(DirectorError::TooLong);
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        let initial = FrameState {
            xf: vec![DAffine3::IDENTITY; spec.objects.len()],
            camera: spec.camera.or(base.camera),
            lights: base.lights.iter().map(|l| (l.kind, l.intensity)).collect(),
            spins: Vec::new(),
            track: None,
        };
        let ref_points = geometry.bodies.iter().map(reference_points).collect();
        Ok(Timeline {
            spec,
            subtree,
            subtree_bodies,
            body_owner: owners.first,
            ref_points,
            changes: expanded.changes,
            blocks: expanded.blocks,
            frames: expanded.frames,
            initial,
        })
    }
}

/// Each object's subtree (itself, then what it carries, directly or not),
/// or the errors: an object carried by two others, an object carrying
/// itself.
fn carried(spec: &Spec) -> Result<Vec<Vec<usize>>, Vec<DirectorError>> {
    let count = spec.objects.len();
    let mut errors = Vec::new();
    let mut parent: Vec<Option<usize>> = vec![None; count];
    for (p, o) in spec.objects.iter().enumerate() {
        for &c in &o.children {
            match parent[c] {
                Some(q) if q != p => errors.push(DirectorError::TwoParents {
                    object: c,
                    name: spec.objects[c].name.clone(),
                    first: spec.objects[q].name.clone(),
                    second: o.name.clone(),
                }),
                _ => parent[c] = Some(p),
            }
        }
    }
    for o in 0..count {
        let mut at = parent[o];
        let mut steps = 0;
        while let Some(p) = at {
            if p == o {
                errors.push(DirectorError::Cycle {
                    object: o,
                    name: spec.objects[o].name.clone(),
                });
                break;
            }
            steps += 1;
            if steps > count {
                break;
            }
            at = parent[p];
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok((0..count)
        .map(|o| {
            let mut out = vec![o];
            let mut i = 0;
            while i < out.len() {
                for &c in &spec.objects[out[i]].children {
                    if !out.contains(&c) {
                        out.push(c);
                    }
                }
                i += 1;
            }
            out
        })
        .collect())
}

/// Who owns each body: the objects whose regions use it (`Some`) and, for
/// regions in no object, `None`.
struct BodyOwners {
    /// Every owner of each body, first met first.
    all: Vec<Vec<Option<usize>>>,
    /// The owner that moves each body.
    first: Vec<Option<usize>>,
}

impl BodyOwners {
    /// The owners, with an error for each body whose owners do not move
    /// together.
    fn of(
        spec: &Spec,
        geometry: &Geometry,
        subtree: &[Vec<usize>],
        errors: &mut Vec<DirectorError>,
    ) -> BodyOwners {
        // Which objects ever move, and with which others.
        let mut moved: Vec<usize> = Vec::new();
        collect_moved(&spec.steps, &mut moved);
        moved.sort_unstable();
        moved.dedup();
        let signature = |owner: Option<usize>| -> Vec<bool> {
            moved
                .iter()
                .map(|&t| owner.is_some_and(|o| subtree[t].contains(&o)))
                .collect()
        };
        let body_count = geometry.bodies.len();
        let mut owners: Vec<Vec<Option<usize>>> = vec![Vec::new(); body_count];
        let mut owner_region: Vec<Vec<usize>> = vec![Vec::new(); body_count];
        let mut in_object = vec![false; geometry.regions.len()];
        for (oi, o) in spec.objects.iter().enumerate() {
            for &r in &o.regions {
                in_object[r] = true;
                for b in region_bodies(geometry, r) {
                    if !owners[b].contains(&Some(oi)) {
                        owners[b].push(Some(oi));
                        owner_region[b].push(r);
                    }
                }
            }
        }
        for (r, used) in in_object.iter().enumerate() {
            if !used {
                for b in region_bodies(geometry, r) {
                    if !owners[b].contains(&None) {
                        owners[b].push(None);
                        owner_region[b].push(r);
                    }
                }
            }
        }
        let owner_name = |o: Option<usize>, r: usize| match o {
            Some(o) => Owner::Object(spec.objects[o].name.clone()),
            None => Owner::Region(geometry.regions[r].name.clone()),
        };
        let mut first = vec![None; body_count];
        for b in 0..body_count {
            let Some(&mover) = owners[b].first() else {
                continue;
            };
            first[b] = mover;
            let sig = signature(mover);
            for (j, &other) in owners[b].iter().enumerate().skip(1) {
                if signature(other) != sig {
                    errors.push(DirectorError::SharedBody {
                        body: b,
                        body_name: geometry.bodies[b].name.clone(),
                        first: owner_name(mover, owner_region[b][0]),
                        second: owner_name(other, owner_region[b][j]),
                    });
                    break;
                }
            }
        }
        BodyOwners { all: owners, first }
    }

    /// The bodies each object's subtree moves.
    fn subtree_bodies(&self, subtree: &[Vec<usize>]) -> Vec<Vec<usize>> {
        subtree
            .iter()
            .map(|objects| {
                let mut v: Vec<usize> = (0..self.all.len())
                    .filter(|&b| {
                        self.all[b]
                            .iter()
                            .any(|o| o.is_some_and(|o| objects.contains(&o)))
                    })
                    .collect();
                v.dedup();
                v
            })
            .collect()
    }
}

fn region_bodies(geo: &Geometry, r: usize) -> Vec<usize> {
    let mut v = Vec::new();
    geo.regions[r].for_each_term(&mut |t| {
        if t.body < geo.bodies.len() {
            v.push(t.body);
        }
    });
    v.sort_unstable();
    v.dedup();
    v
}

fn reference_points(b: &sv_geom::Body) -> Vec<DVec3> {
    let p = &b.params;
    let at = |i: usize| -> Option<DVec3> {
        Some(DVec3::new(*p.get(i)?, *p.get(i + 1)?, *p.get(i + 2)?))
    };
    let mut out = Vec::new();
    if b.kind.is_infinite() {
        return out;
    }
    match b.kind {
        BodyKind::Rpp => {
            if p.len() >= 6 {
                for i in 0..8 {
                    out.push(DVec3::new(
                        p[i & 1],
                        p[2 + ((i >> 1) & 1)],
                        p[4 + ((i >> 2) & 1)],
                    ));
                }
            }
        }
        BodyKind::Ars => {
            let mut i = 2;
            while let Some(q) = at(i) {
                out.push(q);
                i += 3;
            }
        }
        _ => {
            let mut i = 0;
            let mut last_point = None;
            for prm in b.kind.info().params {
                match prm.kind {
                    ParamKind::Point => {
                        last_point = at(i);
                        out.extend(last_point);
                    }
                    ParamKind::Vector => {
                        if let (Some(v), Some(q)) = (at(i), last_point) {
                            out.push(q + v);
                        }
                    }
                    _ => {}
                }
                i += prm.kind.width();
            }
        }
    }
    out.retain(|q| q.is_finite());
    out
}

/// Call `f` on every change of the script, inside TOGETHER and REPEAT too.
fn each_change(steps: &[Step], f: &mut dyn FnMut(&Change)) {
    for s in steps {
        match s {
            Step::Change(t) => f(&t.change),
            Step::Together(ts) => ts.iter().for_each(|t| f(&t.change)),
            Step::Shoot(_) => {}
            Step::Repeat(_, body) => each_change(body, f),
        }
    }
}

/// Every index of the spec (objects, regions, axes, lights) must point
/// into its list, and every axis have a direction.
fn check_indices(spec: &Spec, base: &Scene, errors: &mut Vec<DirectorError>) {
    let object_count = spec.objects.len();
    let mut check = |what: &'static str, index: usize, len: usize| {
        if index >= len {
            errors.push(DirectorError::BadIndex { what, index });
        }
    };
    for o in &spec.objects {
        for &r in &o.regions {
            check("region", r, base.geometry.regions.len());
        }
        for &c in &o.children {
            check("object", c, object_count);
        }
    }
    for a in &spec.axes {
        if let Some(o) = a.on {
            check("object", o, object_count);
        }
    }
    let axis_count = spec.axes.len();
    let light_count = base.lights.len();
    each_change(&spec.steps, &mut |c| {
        let target = |t: Target, check: &mut dyn FnMut(&'static str, usize, usize)| match t {
            Target::Object(o) => check("object", o, object_count),
            Target::Light(l) => check("light", l, light_count),
            Target::Camera => {}
        };
        match *c {
            Change::Move { target: t, .. } => target(t, &mut check),
            Change::Turn {
                target: t, axis, ..
            } => {
                target(t, &mut check);
                check("axis", axis, axis_count);
            }
            Change::Aim(AimPoint::Object(o))
            | Change::Stop { object: o }
            | Change::Track(Some(o)) => check("object", o, object_count),
            Change::Spin { object, axis, .. } => {
                check("object", object, object_count);
                check("axis", axis, axis_count);
            }
            Change::Intensity { light, .. } => check("light", light, light_count),
            Change::Aim(AimPoint::Point(_)) | Change::Zoom(_) | Change::Track(None) => {}
        }
    });
    for (i, a) in spec.axes.iter().enumerate() {
        if !(a.dir.length_squared() > 0.0 && a.dir.is_finite() && a.point.is_finite()) {
            errors.push(DirectorError::BadAxis {
                axis: i,
                name: a.name.clone(),
            });
        }
    }
}

fn collect_moved(steps: &[Step], out: &mut Vec<usize>) {
    let mut one = |c: &Change| match *c {
        Change::Move {
            target: Target::Object(o),
            ..
        }
        | Change::Turn {
            target: Target::Object(o),
            ..
        }
        | Change::Spin { object: o, .. } => out.push(o),
        _ => {}
    };
    each_change(steps, &mut one);
}

/// The film is longer than [`MAX_FRAMES`] or [`MAX_BLOCKS`].
struct TooLong;

/// The steps expanded: every change in order, the blocks of frames that
/// shoot them, and the frame count.
#[derive(Default)]
struct Expanded {
    changes: Vec<Timed>,
    blocks: Vec<Block>,
    frames: usize,
}

impl Expanded {
    /// Add a block of `items` shot over `len` frames.
    fn push_block(&mut self, items: &[Timed], len: usize) -> Result<(), TooLong> {
        if items.is_empty() && len == 0 {
            return Ok(());
        }
        let start = self.frames;
        let end = start
            .checked_add(len)
            .filter(|&e| e <= MAX_FRAMES)
            .ok_or(TooLong)?;
        if self.blocks.len() >= MAX_BLOCKS || self.changes.len() + items.len() > 4 * MAX_BLOCKS {
            return Err(TooLong);
        }
        let first_change = self.changes.len();
        self.changes.extend_from_slice(items);
        self.blocks.push(Block {
            start,
            len,
            changes: first_change..self.changes.len(),
        });
        self.frames = end;
        Ok(())
    }

    /// Add the blocks of `steps`, REPEATs unrolled.
    fn steps(&mut self, steps: &[Step]) -> Result<(), TooLong> {
        for s in steps {
            match s {
                Step::Change(t) => self.push_block(std::slice::from_ref(t), t.frames)?,
                Step::Together(ts) => {
                    let len = ts.iter().map(|t| t.frames).max().unwrap_or(0);
                    self.push_block(ts, len)?;
                }
                Step::Shoot(n) => self.push_block(&[], *n)?,
                Step::Repeat(count, body) => {
                    for _ in 0..*count {
                        let before = self.blocks.len();
                        self.steps(body)?;
                        if self.blocks.len() == before {
                            break;
                        }
                    }
                }
            }
        }
        Ok(())
    }
}
