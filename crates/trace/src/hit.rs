//! What ray queries give back (hits, partitions, crossings, steps), and
//! the per-thread working memory they reuse from ray to ray.

use crate::bvh::Stack;
use crate::packet::LaneCasts;
use crate::prepare::Prepared;
use sv_geom::boolean::{Bound, Span};
use sv_geom::shape::Seg;

/// Per-thread working memory. Reused from ray to ray, so tracing allocates
/// nothing once it has warmed up.
#[derive(Clone, Debug)]
pub struct Scratch {
    pub(crate) ray_id: u32,
    /// Per body: the ray it was last cast along and its segments' range in
    /// `segs` for that ray, side by side so that one look-up finds all
    /// three.
    pub(crate) cache: Vec<[u32; 3]>,
    pub(crate) segs: Vec<Seg>,
    pub(crate) cur: Vec<Span>,
    pub(crate) tmp: Vec<Span>,
    pub(crate) stack: Stack,
    /// Per zone, the packet of shadow rays that last tested it, so that a
    /// packet tests each zone its rays' cells list once.
    pub(crate) tested: Vec<u32>,
    pub(crate) packet: u32,
    /// Span lists to lend the evaluation of groups, one per level of
    /// nesting under way.
    pub(crate) spares: Vec<Vec<Span>>,
    /// The working memory of each sub-universe (filled regions), made on
    /// first use.
    pub(crate) subs: Vec<Option<Box<Scratch>>>,
    /// The bodies cast in the lanes for the packet of rays under way.
    pub(crate) lane_casts: LaneCasts,
}

impl Scratch {
    /// Working memory for `p`.
    pub fn new(p: &Prepared) -> Scratch {
        Scratch {
            ray_id: 0,
            cache: vec![[0; 3]; p.shapes.len()],
            segs: Vec::with_capacity(64),
            cur: Vec::with_capacity(16),
            tmp: Vec::with_capacity(16),
            stack: Stack::new(),
            tested: vec![0; p.zones.len()],
            packet: 0,
            spares: Vec::new(),
            subs: Vec::new(),
            lane_casts: LaneCasts::new(p),
        }
    }

    /// A lent copy of the spans in `cur`.
    pub(crate) fn spare_copy(&mut self) -> Vec<Span> {
        let mut copy = self.spare();
        copy.extend_from_slice(&self.cur);
        copy
    }

    /// The working memory of sub-universe `k` (prepared as `p`), lent until
    /// [`Scratch::put_sub`].
    pub(crate) fn take_sub(&mut self, k: usize, p: &Prepared) -> Box<Scratch> {
        if self.subs.len() <= k {
            self.subs.resize_with(k + 1, || None);
        }
        self.subs[k]
            .take()
            .unwrap_or_else(|| Box::new(Scratch::new(p)))
    }

    /// Working memory back from [`Scratch::take_sub`].
    pub(crate) fn put_sub(&mut self, k: usize, s: Box<Scratch>) {
        self.subs[k] = Some(s);
    }

    /// An empty span list, lent until [`Scratch::give_back`].
    pub(crate) fn spare(&mut self) -> Vec<Span> {
        self.spares.pop().unwrap_or_default()
    }

    /// A span list back, emptied, for the next [`Scratch::spare`].
    pub(crate) fn give_back(&mut self, mut spans: Vec<Span>) {
        spans.clear();
        self.spares.push(spans);
    }

    /// Begin a packet of shadow rays: no zone is yet tested for it.
    pub(crate) fn new_packet(&mut self) {
        self.packet = self.packet.wrapping_add(1);
        if self.packet == 0 {
            self.tested.iter_mut().for_each(|t| *t = 0);
            self.packet = 1;
        }
    }

    /// Forget the previous ray's cached body segments.
    pub(crate) fn new_ray(&mut self) {
        self.ray_id = self.ray_id.wrapping_add(1);
        if self.ray_id == 0 {
            self.cache.iter_mut().for_each(|c| c[0] = 0);
            self.ray_id = 1;
        }
        self.segs.clear();
    }
}

/// The first visible surface along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f64,
    /// Region entered.
    pub region: u32,
    /// Surface crossed: body (prepared number, see
    /// [`Prepared::body_index`]), face and whether it was subtracted.
    pub bound: Bound,
    /// True when the ray started inside the region (no surface crossed).
    pub inside: bool,
    /// The zone of the region that was hit.
    pub zone: u32,
}

impl Hit {
    /// No hit: any hit found is better (region `u32::MAX` marks it).
    pub const NONE: Hit = Hit {
        t: f64::INFINITY,
        region: u32::MAX,
        bound: Bound::new(f64::INFINITY, u32::MAX, 0),
        inside: false,
        zone: u32::MAX,
    };

    /// False for [`Hit::NONE`].
    pub fn is_some(&self) -> bool {
        self.region != u32::MAX
    }
}

/// A stretch of the ray inside one region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Partition {
    /// Region.
    pub region: u32,
    /// Entry and exit.
    pub span: Span,
}

/// Whether `a` and `b` hold the same regions over the same distances, to
/// the bit (the stretches of a check; bodies and faces are not read).
pub fn same_stretches(a: &[Partition], b: &[Partition]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(a, b)| {
            a.region == b.region
                && a.span.a.t.to_bits() == b.span.a.t.to_bits()
                && a.span.b.t.to_bits() == b.span.b.t.to_bits()
        })
}

/// Leave empty each list of `parts` after the first whose stretches are
/// the list before's ([`same_stretches`]), as the lanes of
/// [`Prepared::stretches_of_rays_in`] leave them; the lists so left (bit
/// `k` for list `k`, of the first 64).
pub fn leave_repeats_empty(parts: &mut [Vec<Partition>]) -> u64 {
    (1..parts.len().min(64)).fold(0, |repeats, k| leave_empty_if_repeat(parts, k, repeats))
}

/// `repeats` (lists of `parts` left empty as the list before's, bit `k`
/// for list `k`; never the first), with list `k` (`1..64`) left empty
/// too if its stretches are those of the last list before it that is
/// not ([`same_stretches`]).
pub(crate) fn leave_empty_if_repeat(parts: &mut [Vec<Partition>], k: usize, repeats: u64) -> u64 {
    let kept_before = !repeats & ((1 << k) - 1);
    let kept = 63 - kept_before.leading_zeros() as usize;
    let (before, this) = parts.split_at_mut(k);
    if !same_stretches(&before[kept], &this[0]) {
        return repeats;
    }
    this[0].clear();
    repeats | 1 << k
}

/// One surface crossing along a ray (for `shoot`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Distance along the ray.
    pub t: f64,
    /// Entering (true) or leaving the region.
    pub entering: bool,
    /// Region entered or left.
    pub region: u32,
    /// Body whose surface is crossed.
    pub body: u32,
    /// Face of that body.
    pub face: u32,
}

/// The order of [`Prepared::by_distance`]: by entry bound, then by zone.
pub fn by_entry(a: &(f64, u32), b: &(f64, u32)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}

/// One body-surface crossing along a ray, with the regions the ray is in
/// just after it (for `shoot`, the paper's Figure 3 walk-through).
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// Distance along the ray.
    pub t: f64,
    /// Body crossed.
    pub body: u32,
    /// Face of the body.
    pub face: u32,
    /// True when the ray enters the body here.
    pub entering: bool,
    /// Regions containing the ray just past this point (empty: outside
    /// the geometry; more than one: an overlap).
    pub regions_after: Vec<u32>,
}
