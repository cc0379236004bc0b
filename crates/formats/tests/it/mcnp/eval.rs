//! A small point classifier for the tests: which region holds a point,
//! following fills and lattices down to the deepest one. Bodies are asked
//! through sv-geom's shapes (a point is inside when the line through it
//! is inside the body on both sides of it); zones, groups, universes and
//! lattices are worked out here, as ENGINE.md describes them.

use sv_geom::{shape::Shape, Fill, Lattice, LatticeKind, Op, Region, Zone};
use sv_math::{DMat3, DVec3, Ray};
use sv_scene::Scene;

pub struct Eval<'a> {
    pub scene: &'a Scene,
    shapes: Vec<Shape>,
}

impl<'a> Eval<'a> {
    pub fn new(scene: &'a Scene) -> Eval<'a> {
        let shapes = scene
            .geometry
            .bodies
            .iter()
            .map(|b| {
                sv_geom::prepare(b, &mut Vec::new())
                    .unwrap_or_else(|e| panic!("body {} does not prepare: {e}", b.name))
                    .0
            })
            .collect();
        Eval { scene, shapes }
    }

    pub fn body(&self, b: usize, p: DVec3) -> bool {
        let dir = DVec3::new(0.267, 0.534, 0.802).normalize();
        let mut segs = Vec::new();
        self.shapes[b].shoot(&Ray::new(p, dir), &mut segs);
        segs.iter().any(|s| s.t0 < 0.0 && s.t1 > 0.0)
    }

    fn zone(&self, z: &Zone, p: DVec3) -> bool {
        z.terms
            .iter()
            .all(|t| self.body(t.body, p) == (t.op == Op::Inside))
            && z.groups
                .iter()
                .all(|g| g.zones.iter().any(|z| self.zone(z, p)) == (g.op == Op::Inside))
    }

    pub fn region(&self, r: &Region, p: DVec3) -> bool {
        r.zones.iter().any(|z| self.zone(z, p))
    }

    /// The names of the regions holding `p`, from the root universe down,
    /// with the lattice elements crossed as `[i,j,k]`.
    pub fn path(&self, p: DVec3) -> Vec<String> {
        let regions = &self.scene.geometry.regions;
        self.steps(p)
            .iter()
            .map(|s| match s {
                Step::Region(r) => regions[*r].name.clone(),
                Step::Element(i) => format!("[{},{},{}]", i[0], i[1], i[2]),
            })
            .collect()
    }

    fn steps(&self, p: DVec3) -> Vec<Step> {
        let mut out = Vec::new();
        self.descend(0, p, &mut out, 0);
        out
    }

    /// Every region on the way down to `p`, outermost first.
    pub fn regions(&self, p: DVec3) -> Vec<usize> {
        self.steps(p)
            .iter()
            .filter_map(|s| match s {
                Step::Region(r) => Some(*r),
                Step::Element(_) => None,
            })
            .collect()
    }

    /// The deepest region holding `p`.
    pub fn deepest(&self, p: DVec3) -> Option<usize> {
        self.regions(p).pop()
    }

    /// The name of the deepest region holding `p`.
    pub fn cell(&self, p: DVec3) -> String {
        self.deepest(p).map_or(String::new(), |r| {
            self.scene.geometry.regions[r].name.clone()
        })
    }

    fn descend(&self, universe: usize, p: DVec3, out: &mut Vec<Step>, depth: usize) {
        assert!(depth < 50, "fills nest too deep at {p}");
        let regions = &self.scene.geometry.regions;
        let Some(r) = (0..regions.len())
            .find(|&r| regions[r].universe == universe && self.region(&regions[r], p))
        else {
            return;
        };
        out.push(Step::Region(r));
        match &regions[r].fill {
            None => {}
            Some(Fill::Universe {
                universe,
                region_from_universe,
            }) => self.descend(
                *universe,
                region_from_universe.inverse().transform_point3(p),
                out,
                depth + 1,
            ),
            Some(Fill::Lattice(l)) => {
                let q = l.region_from_lattice.inverse().transform_point3(p);
                let index = element_of(l, q);
                out.push(Step::Element(index));
                if let Some(u) = l.element(index) {
                    let at = l.origin
                        + l.steps[0] * index[0] as f64
                        + l.steps[1] * index[1] as f64
                        + l.steps[2] * index[2] as f64;
                    self.descend(u, q - at, out, depth + 1);
                }
            }
        }
    }
}

/// One step down from the root: a region, or the lattice element entered.
enum Step {
    Region(usize),
    Element([i32; 3]),
}

/// The element of lattice `l` holding `q` (lattice coordinates).
pub fn element_of(l: &Lattice, q: DVec3) -> [i32; 3] {
    let m = DMat3::from_cols(l.steps[0], l.steps[1], l.steps[2]);
    let f = m.inverse() * (q - l.base);
    match l.kind {
        LatticeKind::Rectangular => [f.x.floor() as i32, f.y.floor() as i32, f.z.floor() as i32],
        LatticeKind::Hexagonal => {
            let k = (f.z + 0.5).floor() as i32;
            let axis = l.steps[2].normalize();
            let flat = |v: DVec3| v - axis * v.dot(axis);
            let mut best = (f64::INFINITY, [0, 0, k]);
            for i in (f.x.floor() as i32 - 1)..=(f.x.floor() as i32 + 2) {
                for j in (f.y.floor() as i32 - 1)..=(f.y.floor() as i32 + 2) {
                    let c = l.base + l.steps[0] * i as f64 + l.steps[1] * j as f64;
                    let d = flat(q - c).length();
                    if d < best.0 {
                        best = (d, [i, j, k]);
                    }
                }
            }
            best.1
        }
    }
}
