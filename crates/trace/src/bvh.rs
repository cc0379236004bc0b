//! A bounding volume hierarchy over zones, built with the binned surface
//! area heuristic (Wald 2007, "On fast construction of SAH-based bounding
//! volume hierarchies") and flattened depth-first.
//!
//! Rays walk a four-wide copy of it (Dammertz et al. 2008, "Shallow
//! bounding volume hierarchies for fast SIMD ray tracing of incoherent
//! rays"; Wald et al. 2008, "Getting rid of packets"): each node holds the
//! boxes of up to four children side by side, one array per coordinate, so
//! the four slab tests run as one vector loop, and a ray visits about half
//! as many nodes. The binary tree stays for the frustum and box
//! queries, which walk it from the top.

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
    pub wide: Vec<WideNode>,
}

/// Up to four children: their boxes one coordinate array at a time, and
/// for each a [`Child`] code.
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
pub(crate) struct WideNode {
    pub lo: [[f64; 4]; 3],
    pub hi: [[f64; 4]; 3],
    pub child: [Child; 4],
}

impl WideNode {
    /// No children. An empty slot's box lies at infinity on every axis,
    /// so the slab test passes it only as entered at `t = inf` (a ray going
    /// up every axis with no far limit), and the walk drops it there.
    const EMPTY: WideNode = WideNode {
        lo: [[f64::INFINITY; 4]; 3],
        hi: [[f64::INFINITY; 4]; 3],
        child: [Child::None; 4],
    };
}

/// A child of a wide node: an interior node (its index), a leaf (`count`
/// items from `first`), or nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Child {
    Node(u32),
    Leaf { first: u32, count: u32 },
    None,
}

/// Children per wide node.
pub(crate) const WIDTH: usize = 4;

/// Entries of a walk's stack: three per level of the wide tree, far more
/// than any tree built here needs.
pub(crate) const STACK: usize = 96;

/// A walk's stack, kept by the caller from ray to ray: set up anew for
/// every ray, it cost a tenth of the walk.
pub(crate) type Stack = Vec<(Child, f64)>;

const BINS: usize = 12;
const MAX_LEAF: usize = 4;

impl Bvh {
    /// Build over `(item, bounds)` pairs (finite bounds only).
    pub fn build(input: &[(u32, Aabb)]) -> Bvh {
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * input.len().max(1)),
            items: Vec::new(),
            wide: Vec::new(),
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
        // The root goes first; `widen` pushes the nodes below it.
        bvh.wide.reserve(bvh.nodes.len() / 2 + 1);
        bvh.wide.push(WideNode::EMPTY);
        bvh.wide[0] = bvh.widen(0);
        bvh
    }

    /// The wide node standing for binary node `node`: its children are the
    /// binary descendants left after opening the largest interior ones
    /// until there are four. Pushes the wide nodes below it.
    fn widen(&mut self, node: usize) -> WideNode {
        let n = self.nodes[node];
        let mut kids: Vec<usize> = if n.count > 0 {
            // A leaf at the top: a single child.
            vec![node]
        } else {
            vec![n.first as usize, n.first as usize + 1]
        };
        while kids.len() < WIDTH {
            let open = kids
                .iter()
                .enumerate()
                .filter(|(_, &k)| self.nodes[k].count == 0)
                .max_by(|a, b| {
                    let (x, y) = (&self.nodes[*a.1].bounds, &self.nodes[*b.1].bounds);
                    x.area().total_cmp(&y.area())
                })
                .map(|(i, _)| i);
            let Some(i) = open else { break };
            let k = kids[i];
            let f = self.nodes[k].first as usize;
            kids[i] = f;
            kids.insert(i + 1, f + 1);
        }
        let mut w = WideNode::EMPTY;
        for (slot, &k) in kids.iter().enumerate() {
            let kn = self.nodes[k];
            for axis in 0..3 {
                w.lo[axis][slot] = kn.bounds.min[axis];
                w.hi[axis][slot] = kn.bounds.max[axis];
            }
            w.child[slot] = if kn.count > 0 {
                Child::Leaf {
                    first: kn.first,
                    count: kn.count,
                }
            } else {
                let sub = self.widen(k);
                self.wide.push(sub);
                Child::Node(self.wide.len() as u32 - 1)
            };
        }
        w
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
    /// nearer ones first; `visit` may lower `*tmax` to prune the rest.
    /// `visit` returns `true` to stop the traversal.
    #[inline]
    pub fn traverse(
        &self,
        ray: &Ray,
        tmin: f64,
        tmax: &mut f64,
        stack: &mut Stack,
        mut visit: impl FnMut(&[u32], &mut f64) -> bool,
    ) {
        if self.wide.is_empty() {
            return;
        }
        // Entries still to visit with the distance at which the ray enters
        // their box: a node is skipped when that is past `*tmax`.
        if stack.len() < STACK {
            stack.resize(STACK, (Child::None, 0.0));
        }
        let stack = &mut stack[..STACK];
        let mut sp = 0;
        stack[sp] = (Child::Node(0), tmin);
        sp += 1;
        while sp > 0 {
            sp -= 1;
            let (c, t) = stack[sp];
            if t > *tmax {
                continue;
            }
            match c {
                Child::Leaf { first, count } => {
                    if visit(&self.items[first as usize..(first + count) as usize], tmax) {
                        return;
                    }
                }
                Child::Node(i) => {
                    let n = &self.wide[i as usize];
                    let (near, hit) = slabs4(n, ray, tmin, *tmax);
                    // The children met, pushed farthest first.
                    let mut order = [(0.0f64, 0usize); WIDTH];
                    let mut m = 0;
                    for k in 0..WIDTH {
                        if hit[k] {
                            order[m] = (near[k], k);
                            m += 1;
                        }
                    }
                    // Farthest first: an insertion sort of at most four,
                    // cheaper here than the library's sort.
                    for i in 1..m {
                        let x = order[i];
                        let mut j = i;
                        while j > 0 && order[j - 1].0 < x.0 {
                            order[j] = order[j - 1];
                            j -= 1;
                        }
                        order[j] = x;
                    }
                    let order = &order[..m];
                    if sp + m > stack.len() {
                        // Deeper than any tree built here: finish by
                        // visiting what is left in turn.
                        for &(tk, k) in order.iter().rev() {
                            self.walk_from(n.child[k], tk, ray, tmin, tmax, &mut visit);
                        }
                        continue;
                    }
                    for &(tk, k) in order.iter() {
                        stack[sp] = (n.child[k], tk);
                        sp += 1;
                    }
                }
                Child::None => {}
            }
        }
    }

    /// Recursive walk below `c` (only for trees deeper than the stack).
    fn walk_from(
        &self,
        c: Child,
        t: f64,
        ray: &Ray,
        tmin: f64,
        tmax: &mut f64,
        visit: &mut impl FnMut(&[u32], &mut f64) -> bool,
    ) -> bool {
        if t > *tmax {
            return false;
        }
        match c {
            Child::Leaf { first, count } => {
                visit(&self.items[first as usize..(first + count) as usize], tmax)
            }
            Child::Node(i) => {
                let n = &self.wide[i as usize];
                let (near, hit) = slabs4(n, ray, tmin, *tmax);
                let mut order: Vec<(f64, usize)> = (0..WIDTH)
                    .filter(|&k| hit[k] && n.child[k] != Child::None)
                    .map(|k| (near[k], k))
                    .collect();
                order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
                order
                    .into_iter()
                    .any(|(tk, k)| self.walk_from(n.child[k], tk, ray, tmin, tmax, visit))
            }
            Child::None => false,
        }
    }
}

/// The slab test of a wide node's four boxes at once: entry distances and
/// which boxes the ray meets within `[tmin, tmax]` (as [`hits`]).
#[inline(always)]
fn slabs4(n: &WideNode, ray: &Ray, tmin: f64, tmax: f64) -> ([f64; WIDTH], [bool; WIDTH]) {
    let (o, inv) = (ray.origin.to_array(), ray.inv_dir.to_array());
    let mut t0 = [tmin; WIDTH];
    let mut t1 = [tmax; WIDTH];
    for axis in 0..3 {
        for k in 0..WIDTH {
            let a = (n.lo[axis][k] - o[axis]) * inv[axis];
            let b = (n.hi[axis][k] - o[axis]) * inv[axis];
            t0[k] = fmax(fmin(a, b), t0[k]);
            t1[k] = fmin(fmax(a, b), t1[k]);
        }
    }
    let mut hit = [false; WIDTH];
    for k in 0..WIDTH {
        hit[k] = t0[k] <= t1[k];
    }
    (t0, hit)
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
