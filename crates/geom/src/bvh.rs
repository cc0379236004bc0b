//! A bounding volume hierarchy over zones, built with the binned surface
//! area heuristic (Wald 2007, "On fast construction of SAH-based bounding
//! volume hierarchies") and flattened depth-first.

use sv_math::{Aabb, Ray};

/// A node: interior nodes have `count == 0` and their children at
/// `first` and `first + 1`; leaves list `count` items from `first`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    pub bounds: Aabb,
    pub first: u32,
    pub count: u32,
}

/// The hierarchy; `items` are the indices given to [`Bvh::build`],
/// reordered so each leaf's are contiguous.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh {
    pub nodes: Vec<Node>,
    pub items: Vec<u32>,
}

const BINS: usize = 12;
const MAX_LEAF: usize = 4;

impl Bvh {
    /// Build over `(item, bounds)` pairs (finite bounds only).
    pub fn build(input: &[(u32, Aabb)]) -> Bvh {
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * input.len().max(1)),
            items: Vec::new(),
        };
        if input.is_empty() {
            return bvh;
        }
        let mut refs: Vec<(u32, Aabb)> = input.to_vec();
        bvh.nodes.push(Node {
            bounds: Aabb::EMPTY,
            first: 0,
            count: 0,
        });
        bvh.split(0, &mut refs, 0);
        bvh.items = refs.iter().map(|r| r.0).collect();
        bvh
    }

    fn split(&mut self, node: usize, refs: &mut [(u32, Aabb)], offset: usize) {
        let bounds = refs.iter().fold(Aabb::EMPTY, |b, r| b.union(&r.1));
        self.nodes[node].bounds = bounds;
        let leaf = |s: &mut Bvh| {
            s.nodes[node].first = offset as u32;
            s.nodes[node].count = refs.len() as u32;
        };
        if refs.len() <= MAX_LEAF {
            return leaf(self);
        }
        let cb = refs
            .iter()
            .fold(Aabb::EMPTY, |b, r| b.including(r.1.center()));
        let ext = cb.size();
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        if ext[axis] <= 0.0 {
            // All centroids coincide: split in the middle of the list.
            return self.children(node, refs, refs.len() / 2, offset);
        }
        let bin_of = |r: &(u32, Aabb)| {
            let f = (r.1.center()[axis] - cb.min[axis]) / ext[axis];
            ((f * BINS as f64) as usize).min(BINS - 1)
        };
        let mut bins = [(Aabb::EMPTY, 0usize); BINS];
        for r in refs.iter() {
            let b = &mut bins[bin_of(r)];
            b.0 = b.0.union(&r.1);
            b.1 += 1;
        }
        // Sweep to find the cheapest of the BINS-1 planes.
        let mut left_area = [0.0; BINS];
        let mut left_count = [0usize; BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for i in 0..BINS - 1 {
            acc = acc.union(&bins[i].0);
            n += bins[i].1;
            left_area[i] = acc.area();
            left_count[i] = n;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        let mut best = (f64::INFINITY, 0);
        for i in (1..BINS).rev() {
            acc = acc.union(&bins[i].0);
            n += bins[i].1;
            let cost = left_area[i - 1] * left_count[i - 1] as f64 + acc.area() * n as f64;
            if cost < best.0 {
                best = (cost, i);
            }
        }
        let leaf_cost = bounds.area() * refs.len() as f64;
        if best.0 >= leaf_cost && refs.len() <= 16 {
            return leaf(self);
        }
        let mid = partition(refs, |r| bin_of(r) < best.1);
        let mid = if mid == 0 || mid == refs.len() {
            refs.len() / 2
        } else {
            mid
        };
        self.children(node, refs, mid, offset);
    }

    fn children(&mut self, node: usize, refs: &mut [(u32, Aabb)], mid: usize, offset: usize) {
        let first = self.nodes.len();
        self.nodes.push(Node {
            bounds: Aabb::EMPTY,
            first: 0,
            count: 0,
        });
        self.nodes.push(Node {
            bounds: Aabb::EMPTY,
            first: 0,
            count: 0,
        });
        self.nodes[node].first = first as u32;
        self.nodes[node].count = 0;
        let (l, r) = refs.split_at_mut(mid);
        self.split(first, l, offset);
        self.split(first + 1, r, offset + mid);
    }

    /// Visit leaves whose bounds the ray meets within `[tmin, *tmax]`,
    /// nearer children first; `visit` may lower `*tmax` to prune the rest.
    /// `visit` returns `true` to stop the traversal.
    #[inline]
    pub fn traverse(
        &self,
        ray: &Ray,
        tmin: f64,
        tmax: &mut f64,
        mut visit: impl FnMut(&[u32], &mut f64) -> bool,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0u32; 64];
        let mut sp = 0;
        let mut node = 0usize;
        if hits(&self.nodes[0].bounds, ray, tmin, *tmax).is_none() {
            return;
        }
        loop {
            let n = self.nodes[node];
            if n.count > 0 {
                let items = &self.items[n.first as usize..(n.first + n.count) as usize];
                if visit(items, tmax) {
                    return;
                }
            } else {
                let (a, b) = (n.first as usize, n.first as usize + 1);
                let ha = hits(&self.nodes[a].bounds, ray, tmin, *tmax);
                let hb = hits(&self.nodes[b].bounds, ray, tmin, *tmax);
                match (ha, hb) {
                    (Some(ta), Some(tb)) => {
                        let (near, far) = if ta <= tb { (a, b) } else { (b, a) };
                        if sp < stack.len() {
                            stack[sp] = far as u32;
                            sp += 1;
                        }
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = b;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop the next node still worth visiting.
            loop {
                if sp == 0 {
                    return;
                }
                sp -= 1;
                let cand = stack[sp] as usize;
                if hits(&self.nodes[cand].bounds, ray, tmin, *tmax).is_some() {
                    node = cand;
                    break;
                }
            }
        }
    }
}

/// `min` and `max` that compile to single `minsd`/`maxsd` instructions.
/// With a NaN operand they return the other one (`b`), which is what the
/// slab test wants: a NaN comes from `0 · inf` when the origin lies on a
/// slab plane of an axis the ray runs parallel to, and that axis must then
/// not restrict the range.
#[inline(always)]
fn fmin(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

#[inline(always)]
fn fmax(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// Entry distance of the ray into `b` if it meets it within `[tmin, tmax]`
/// (slab test, Kay & Kajiya 1986).
#[inline(always)]
pub(crate) fn hits(b: &Aabb, ray: &Ray, tmin: f64, tmax: f64) -> Option<f64> {
    let (o, inv) = (ray.origin, ray.inv_dir);
    let (x0, x1) = ((b.min.x - o.x) * inv.x, (b.max.x - o.x) * inv.x);
    let (y0, y1) = ((b.min.y - o.y) * inv.y, (b.max.y - o.y) * inv.y);
    let (z0, z1) = ((b.min.z - o.z) * inv.z, (b.max.z - o.z) * inv.z);
    // Slab values come first: a NaN there yields the accumulated bound.
    let t0 = fmax(fmin(z0, z1), fmax(fmin(y0, y1), fmax(fmin(x0, x1), tmin)));
    let t1 = fmin(fmax(z0, z1), fmin(fmax(y0, y1), fmin(fmax(x0, x1), tmax)));
    (t0 <= t1).then_some(t0)
}

fn partition<T>(v: &mut [T], pred: impl Fn(&T) -> bool) -> usize {
    let mut i = 0;
    for j in 0..v.len() {
        if pred(&v[j]) {
            v.swap(i, j);
            i += 1;
        }
    }
    i
}
