//! Primary rays: a tile's rays traced in packets through its sorted list
//! of zones, or through the hierarchy when the tile is crowded.

use super::{lane_rays, NearestHit, RaysShare};
use crate::bvh::{Child, WideNode, STACK, WIDTH};
use crate::hit::{Hit, Scratch};
use crate::prepare::Prepared;
use std::mem::MaybeUninit;
use sv_math::lanes::{dot, slab_lanes, splat3, Lanes, MAX_LANES};
use sv_math::simd::Simd;
use sv_math::{DVec3, Ray, RayGen};

/// A tile of a raster: the pixels of columns `x0..x1` and rows `y0..y1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// First column.
    pub x0: usize,
    /// Past the last column.
    pub x1: usize,
    /// First row.
    pub y0: usize,
    /// Past the last row.
    pub y1: usize,
}

impl Tile {
    /// Its pixels.
    pub fn len(&self) -> usize {
        (self.x1 - self.x0) * (self.y1 - self.y0)
    }

    /// True when it has no pixel.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Its pixels' columns and rows, row by row.
    pub fn pixels(&self) -> impl Iterator<Item = (usize, usize)> {
        let (x0, x1) = (self.x0, self.x1);
        (self.y0..self.y1).flat_map(move |y| (x0..x1).map(move |x| (x, y)))
    }
}

/// Where [`Prepared::tile_facing`] puts a pixel whose ray meets nothing.
pub const FACING_MISS: f64 = -1.0;

/// What a packet's hits are written as.
pub(crate) enum PacketOut<'a> {
    /// The hits at the first places, in lane order, with their lanes'
    /// indices ([`NearestHit::emit`](super::NearestHit)), and when given,
    /// their rays and normals at the same places.
    Hits(
        &'a mut [(u32, Hit)],
        Option<(&'a mut [Ray], &'a mut [DVec3])>,
    ),
    /// How squarely each hit faces its ray, at its lane's index
    /// ([`Prepared::tile_facing`]).
    Facing(&'a mut [f64]),
}

impl PacketOut<'_> {
    /// The places left after `found` hits.
    #[inline(always)]
    fn past(&mut self, found: usize) -> PacketOut<'_> {
        match self {
            PacketOut::Hits(hits, None) => PacketOut::Hits(&mut hits[found..], None),
            PacketOut::Hits(hits, Some((rays, normals))) => PacketOut::Hits(
                &mut hits[found..],
                Some((&mut rays[found..], &mut normals[found..])),
            ),
            // Written by index, not packed.
            PacketOut::Facing(facing) => PacketOut::Facing(facing),
        }
    }
}

impl Prepared {
    /// [`Prepared::first_hit_in`] for each of `rays` (a tile's, in the
    /// order they are given), several rays at once where the processor has
    /// vector instructions for it. The hits go to the first places of
    /// `out`, with the index of their ray, in the order of the rays; the
    /// number of hits is returned. `out` is only ever grown: its places
    /// past the hits are kept for the next call.
    pub fn first_hits_in(
        &self,
        zones: &[(f64, u32)],
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut Vec<(u32, Hit)>,
    ) -> usize {
        grow(out, rays.len(), (0, Hit::NONE));
        if let Some(n) = rays_any(self, Some(zones), rays, tmin, tmax, s, out) {
            return n;
        }
        self.hits_one_by_one(zones, rays, tmin, tmax, s, out)
    }

    /// Ask the processor to bring the records of a tile list's zones
    /// into its caches, and return at once: a hint, with no effect on any
    /// answer. Of 100,000 small zones, each is met by a few tiles a frame,
    /// and its first reading there waited for memory. Issued a tile or two
    /// before the list is walked, the fetches of its zones overlap one
    /// another and the work in between. Then
    /// [`Prepared::prefetch_bodies`], once they have arrived.
    pub fn prefetch_zones(&self, zones: &[(f64, u32)]) {
        for &(_, zi) in zones {
            prefetch(&self.zones[zi as usize]);
        }
    }

    /// As [`Prepared::prefetch_zones`], for the first `+` body of each
    /// zone that has one: it reads the zones' records, so these should be
    /// fetched already.
    pub fn prefetch_bodies(&self, zones: &[(f64, u32)]) {
        for &(_, zi) in zones {
            let z = &self.zones[zi as usize];
            if z.plus > 0 {
                prefetch(&self.shapes[self.terms[z.first as usize] as usize]);
            }
        }
    }

    /// [`Prepared::first_hits_in`] ray by ray.
    pub(crate) fn hits_one_by_one(
        &self,
        zones: &[(f64, u32)],
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut [(u32, Hit)],
    ) -> usize {
        let mut found = 0;
        for (k, ray) in rays.iter().enumerate() {
            let slot = &mut out[found];
            if self.first_hit_in(zones, ray, tmin, tmax, s, &mut slot.1) {
                slot.0 = k as u32;
                found += 1;
            }
        }
        found
    }

    /// [`Prepared::first_hit`] for each of `rays`, several rays at once
    /// where the processor has vector instructions for it: a packet walks
    /// the hierarchy together, each lane into the boxes its ray meets
    /// before its best hit. Output as [`Prepared::first_hits_in`].
    pub fn first_hits(
        &self,
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut Vec<(u32, Hit)>,
    ) -> usize {
        grow(out, rays.len(), (0, Hit::NONE));
        if let Some(n) = rays_any(self, None, rays, tmin, tmax, s, out) {
            return n;
        }
        self.walk_one_by_one(rays, tmin, tmax, s, out)
    }

    /// [`Prepared::first_hits`] ray by ray.
    pub(crate) fn walk_one_by_one(
        &self,
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut [(u32, Hit)],
    ) -> usize {
        let mut found = 0;
        for (k, ray) in rays.iter().enumerate() {
            if let Some(h) = self.first_hit(ray, tmin, tmax, s) {
                out[found] = (k as u32, h);
                found += 1;
            }
        }
        found
    }

    /// The first hits of the rays through the centres of `tile`'s pixels,
    /// one ray each, as `gen` makes it ([`RayGen::ray`]), found among
    /// `zones` (the tile's list, as for [`Prepared::first_hits_in`]) or,
    /// given none, by walking the hierarchy. Several rays at once where the
    /// processor has vector instructions for it, made in the vector lanes
    /// by the same operations as `gen.ray`: no ray is made but for a hit.
    ///
    /// The hits go to the first places of `hits`, with their pixel's index
    /// in the tile (row by row), their rays to the same places of `rays`,
    /// and the surface normals there ([`Prepared::normal`]) to those of
    /// `normals`, computed in the lanes too for the bodies several rays of
    /// a packet hit; the number of hits is returned. The hits come in no
    /// particular order (a packet's rays are a block of the tile), and only
    /// the rays of hits are written out. All three buffers are only ever
    /// grown.
    #[allow(clippy::too_many_arguments)]
    pub fn tile_hits(
        &self,
        gen: &RayGen,
        tile: Tile,
        zones: Option<&[(f64, u32)]>,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        hits: &mut Vec<(u32, Hit)>,
        rays: &mut Vec<Ray>,
        normals: &mut Vec<DVec3>,
    ) -> usize {
        if tile.is_empty() {
            return 0;
        }
        grow(hits, tile.len(), (0, Hit::NONE));
        grow(rays, tile.len(), gen.along);
        grow(normals, tile.len(), DVec3::ZERO);
        let out = PacketOut::Hits(hits, Some((rays, normals)));
        if let Some(n) = tile_any(self, gen, tile, zones, tmin, tmax, s, out) {
            return n;
        }
        self.tile_one_by_one(gen, tile, zones, tmin, tmax, s, hits, rays, normals)
    }

    /// How squarely each pixel of `tile` faces the ray through its centre
    /// ([`Prepared::facing`] of its first hit, as [`Prepared::tile_hits`]
    /// finds it, from 0 to 1), or −1 where that ray meets nothing: into
    /// the first `tile.len()` places of `facing`, row by row, which is
    /// only ever grown. The number of hits is returned.
    ///
    /// Everything BRL-CAD's `rt -l1` shades a pixel with, found without
    /// writing out the hits, their rays and normals: in the lanes, a
    /// packet's normals go straight into its cosines.
    #[allow(clippy::too_many_arguments)]
    pub fn tile_facing(
        &self,
        gen: &RayGen,
        tile: Tile,
        zones: Option<&[(f64, u32)]>,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        facing: &mut Vec<f64>,
    ) -> usize {
        grow(facing, tile.len(), FACING_MISS);
        facing[..tile.len()].fill(FACING_MISS);
        if tile.is_empty() {
            return 0;
        }
        let out = PacketOut::Facing(&mut facing[..]);
        if let Some(n) = tile_any(self, gen, tile, zones, tmin, tmax, s, out) {
            return n;
        }
        let mut found = 0;
        for (k, (x, y)) in tile.pixels().enumerate() {
            let ray = gen.ray(x as f64 + 0.5, y as f64 + 0.5);
            if let Some(h) = self.hit_among(zones, &ray, tmin, tmax, s) {
                facing[k] = self.facing(&h, &ray, s);
                found += 1;
            }
        }
        found
    }

    /// [`Prepared::first_hit_in`] `zones` or, given none,
    /// [`Prepared::first_hit`].
    fn hit_among(
        &self,
        zones: Option<&[(f64, u32)]>,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
    ) -> Option<Hit> {
        match zones {
            Some(zones) => {
                let mut h = Hit::NONE;
                self.first_hit_in(zones, ray, tmin, tmax, s, &mut h)
                    .then_some(h)
            }
            None => self.first_hit(ray, tmin, tmax, s),
        }
    }

    /// [`Prepared::tile_hits`] ray by ray.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn tile_one_by_one(
        &self,
        gen: &RayGen,
        tile: Tile,
        zones: Option<&[(f64, u32)]>,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        hits: &mut [(u32, Hit)],
        rays: &mut [Ray],
        normals: &mut [DVec3],
    ) -> usize {
        let mut found = 0;
        for (k, (x, y)) in tile.pixels().enumerate() {
            let ray = gen.ray(x as f64 + 0.5, y as f64 + 0.5);
            if let Some(h) = self.hit_among(zones, &ray, tmin, tmax, s) {
                hits[found] = (k as u32, h);
                rays[found] = ray;
                normals[found] = self.normal(&h, &ray);
                found += 1;
            }
        }
        found
    }

    /// [`Prepared::first_hits_in`] (given `zones`) or
    /// [`Prepared::first_hits`] in packets of `S::LANES` rays.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn rays_in_packets<S: Simd>(
        &self,
        s: S,
        zones: Option<&[(f64, u32)]>,
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        sc: &mut Scratch,
        out: &mut [(u32, Hit)],
    ) -> usize {
        let mut found = 0;
        for (p, chunk) in rays.chunks(S::LANES).enumerate() {
            let lanes = lanes_of(s, chunk, RaysShare::Unknown);
            let active = (1u32 << chunk.len()) - 1;
            let index = std::array::from_fn(|j| (p * S::LANES + j) as u32);
            found += self.packet(
                s,
                zones,
                &lanes,
                active,
                tmin,
                tmax,
                sc,
                &index,
                PacketOut::Hits(&mut out[found..], None),
            );
        }
        found
    }

    /// [`Prepared::tile_hits`] or [`Prepared::tile_facing`] (as `out`
    /// asks) in packets of `S::LANES` rays, each the rays of a block of
    /// pixels two rows high.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn tile_in_packets<S: Simd>(
        &self,
        s: S,
        gen: &RayGen,
        tile: Tile,
        zones: Option<&[(f64, u32)]>,
        tmin: f64,
        tmax: f64,
        sc: &mut Scratch,
        mut out: PacketOut<'_>,
    ) -> usize {
        let cols = S::LANES / 2;
        let width = tile.x1 - tile.x0;
        // Each lane's place in its block, made once.
        let (mut dx, mut dy) = ([0.0; MAX_LANES], [0.0; MAX_LANES]);
        for j in 0..S::LANES {
            dx[j] = (j % cols) as f64;
            dy[j] = (j / cols) as f64;
        }
        let (dx, dy) = (s.load(&dx), s.load(&dy));
        // Lanes past the tile repeat its last column or row, inactive.
        let last_x = s.splat((tile.x1 - 1) as f64 + 0.5);
        let last_y = s.splat((tile.y1 - 1) as f64 + 0.5);
        let mut found = 0;
        for y in (tile.y0..tile.y1).step_by(2) {
            for x in (tile.x0..tile.x1).step_by(cols) {
                let mut index = [0u32; MAX_LANES];
                let mut active = 0;
                for (j, at) in index.iter_mut().enumerate().take(S::LANES) {
                    let (px, py) = (x + j % cols, y + j / cols);
                    let (cx, cy) = (px.min(tile.x1 - 1), py.min(tile.y1 - 1));
                    *at = ((cy - tile.y0) * width + cx - tile.x0) as u32;
                    if px < tile.x1 && py < tile.y1 {
                        active |= 1 << j;
                    }
                }
                // Pixel centres: whole numbers and a half, exact.
                let px = s.min(s.add(s.splat(x as f64 + 0.5), dx), last_x);
                let py = s.min(s.add(s.splat(y as f64 + 0.5), dy), last_y);
                let r = raster_lanes(s, gen, px, py);
                found += self.packet(
                    s,
                    zones,
                    &r,
                    active,
                    tmin,
                    tmax,
                    sc,
                    &index,
                    out.past(found),
                );
            }
        }
        found
    }

    /// One packet (the lanes of `active`): its best hits among the sorted
    /// `zones` or, given none, by walking the hierarchy, written as `out`
    /// asks; the number of hits.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn packet<S: Simd>(
        &self,
        s: S,
        zones: Option<&[(f64, u32)]>,
        r: &Lanes<S>,
        active: u32,
        tmin: f64,
        tmax: f64,
        sc: &mut Scratch,
        index: &[u32; MAX_LANES],
        out: PacketOut<'_>,
    ) -> usize {
        let best = match zones {
            Some(zones) => Some(self.list_best(s, zones, r, active, tmin, tmax, sc)),
            None => self.walk_best(s, r, active, tmin, tmax, sc),
        };
        if let Some(b) = best {
            return match out {
                PacketOut::Hits(hits, rays) => b.emit(
                    self,
                    s,
                    index,
                    hits,
                    rays.map(|(rays, normals)| (r, rays, normals)),
                ),
                PacketOut::Facing(facing) => {
                    let hit = b.hits(s);
                    b.facing(self, s, r, hit, index, facing, sc);
                    hit.count_ones() as usize
                }
            };
        }
        // A tree deeper than the walk's stack: ray by ray.
        let lanes = lane_rays(s, r);
        let mut out = out;
        let mut n = 0;
        for (j, ray) in lanes.iter().enumerate().take(S::LANES) {
            if active & (1 << j) == 0 {
                continue;
            }
            let Some(h) = self.first_hit(ray, tmin, tmax, sc) else {
                continue;
            };
            match &mut out {
                PacketOut::Hits(hits, rays) => {
                    hits[n] = (index[j], h);
                    if let Some((rays, normals)) = rays {
                        rays[n] = *ray;
                        normals[n] = self.normal(&h, ray);
                    }
                }
                PacketOut::Facing(facing) => facing[index[j] as usize] = self.facing(&h, ray, sc),
            }
            n += 1;
        }
        n
    }

    /// The best hits of one packet's rays (the lanes of `active`) among the
    /// sorted `zones`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn list_best<S: Simd>(
        &self,
        s: S,
        zones: &[(f64, u32)],
        r: &Lanes<S>,
        active: u32,
        tmin: f64,
        tmax: f64,
        sc: &mut Scratch,
    ) -> NearestHit<S> {
        let mut b = NearestHit::new(s, tmin, tmax);
        let mut alive = s.mask(active);
        for &(near, zi) in zones {
            // A lane stops at the first zone that cannot come nearer than
            // its best hit, as the ray alone would.
            alive = s.andnot(alive, s.gt(s.splat(near), b.limit));
            if !s.any(alive) {
                break;
            }
            self.consider_lanes(s, zi, r, alive, &mut b, sc);
        }
        b
    }

    /// The best hits of one packet's rays (the lanes of `active`): the
    /// unbounded zones, then the hierarchy's, walked together, nearer boxes
    /// first; `None` for a tree deeper than the walk's stack.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn walk_best<S: Simd>(
        &self,
        s: S,
        r: &Lanes<S>,
        active: u32,
        tmin: f64,
        tmax: f64,
        sc: &mut Scratch,
    ) -> Option<NearestHit<S>> {
        let mut b = NearestHit::new(s, tmin, tmax);
        let act = s.mask(active);
        for &zi in &self.unbounded_opaque {
            self.consider_lanes(s, zi, r, act, &mut b, sc);
        }
        let bvh = &self.bvh_opaque;
        if bvh.wide.is_empty() {
            return Some(b);
        }
        // Entries to visit, with each lane's entry into their box: not a
        // number for a lane that misses it, which no limit lets through
        // (infinity would pass an infinite limit).
        let (miss, inf) = (s.splat(f64::NAN), s.splat(f64::INFINITY));
        // Not filled beforehand: a packet of a crowded tile would spend a
        // tenth of its walk on it. Only the entries below `sp` are read.
        let mut stack = [const { MaybeUninit::<(Child, S::F)>::uninit() }; STACK];
        stack[0].write((Child::Node(0), s.select(act, b.tmin, miss)));
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            // SAFETY: every entry below `sp` was written before `sp` passed
            // it.
            let (c, near) = unsafe { stack[sp].assume_init() };
            let m = s.le(near, b.limit);
            if !s.any(m) {
                continue;
            }
            match c {
                Child::Leaf { first, count } => {
                    for &zi in &bvh.items[first as usize..(first + count) as usize] {
                        self.consider_lanes(s, zi, r, m, &mut b, sc);
                    }
                }
                Child::Node(i) => {
                    let n = &bvh.wide[i as usize];
                    // The children met, pushed farthest first (by the
                    // nearest entry of any lane).
                    let mut order = [(0.0f64, 0usize, miss); WIDTH];
                    let mut k_met = 0;
                    for k in 0..WIDTH {
                        if n.child[k] == Child::None {
                            continue;
                        }
                        let (t0, hit) = child_lanes(s, n, k, r, b.tmin, b.limit);
                        let hit = s.and(hit, m);
                        if !s.any(hit) {
                            continue;
                        }
                        let first = s.min_lane(s.select(hit, t0, inf));
                        let t0 = s.select(hit, t0, miss);
                        let mut j = k_met;
                        while j > 0 && order[j - 1].0 < first {
                            order[j] = order[j - 1];
                            j -= 1;
                        }
                        order[j] = (first, k, t0);
                        k_met += 1;
                    }
                    if sp + k_met > STACK {
                        return None;
                    }
                    for &(_, k, t0) in &order[..k_met] {
                        stack[sp].write((n.child[k], t0));
                        sp += 1;
                    }
                }
                Child::None => {}
            }
        }
        Some(b)
    }
}

/// Ask for the cache line of `v`'s start (nothing where there is no
/// instruction for it).
#[inline(always)]
fn prefetch<T>(v: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing and never faults; `v` is a
    // reference anyway. SSE is part of x86-64.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>((v as *const T).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = v;
}

/// `v` grown to `n` places, never shrunk.
fn grow<T: Clone>(v: &mut Vec<T>, n: usize, fill: T) {
    if v.len() < n {
        v.resize(n, fill);
    }
}

/// The rays through raster points `(x, y)` in lanes: [`RayGen::ray`],
/// operation for operation (and glam's `normalize` and `recip` within it).
#[inline(always)]
fn raster_lanes<S: Simd>(s: S, g: &RayGen, x: S::F, y: S::F) -> Lanes<S> {
    let (one, two) = (s.splat(1.0), s.splat(2.0));
    let sx = s.sub(s.mul(s.mul(two, x), s.splat(g.inv_w)), one);
    let sy = s.sub(one, s.mul(s.mul(two, y), s.splat(g.inv_h)));
    if g.ortho {
        return Lanes {
            o: plane(s, g, g.eye, sx, sy),
            d: splat3(s, g.along.dir),
            inv: splat3(s, g.along.inv_dir),
        };
    }
    let d = plane(s, g, g.forward, sx, sy);
    let r = s.div(one, s.sqrt(dot(s, d, d)));
    let d = [s.mul(d[0], r), s.mul(d[1], r), s.mul(d[2], r)];
    Lanes {
        o: splat3(s, g.eye),
        d,
        inv: [s.div(one, d[0]), s.div(one, d[1]), s.div(one, d[2])],
    }
}

/// `base + right sx + up sy` in every lane, coordinate by coordinate, left
/// to right, as glam adds and scales vectors.
#[inline(always)]
fn plane<S: Simd>(s: S, g: &RayGen, base: DVec3, sx: S::F, sy: S::F) -> [S::F; 3] {
    [
        affine(s, base.x, g.right.x, g.up.x, sx, sy),
        affine(s, base.y, g.right.y, g.up.y, sx, sy),
        affine(s, base.z, g.right.z, g.up.z, sx, sy),
    ]
}

/// `(b + r sx) + u sy` in every lane.
#[inline(always)]
fn affine<S: Simd>(s: S, b: f64, r: f64, u: f64, sx: S::F, sy: S::F) -> S::F {
    s.add(
        s.add(s.splat(b), s.mul(s.splat(r), sx)),
        s.mul(s.splat(u), sy),
    )
}

/// A packet of rays in lanes. A short packet repeats its last ray in the
/// lanes left. What the caller says the rays share (see [`RaysShare`]) is
/// copied from the first ray to every lane unread.
#[inline(always)]
pub(super) fn lanes_of<S: Simd>(s: S, rays: &[Ray], share: RaysShare) -> Lanes<S> {
    if rays.len() < S::LANES {
        let mut full = [rays[rays.len() - 1]; MAX_LANES];
        full[..rays.len()].copy_from_slice(rays);
        return gather_lanes(s, Ray::coordinates(&full[..S::LANES]), share);
    }
    gather_lanes(s, Ray::coordinates(&rays[..S::LANES]), share)
}

/// The rays of [`Ray::coordinates`] `v` in lanes, each coordinate read
/// across the rays at once. (Written lane by lane into arrays first, they
/// were loaded back whole before the writes could be forwarded, which
/// stalled every packet.) Where the rays share their direction, as a
/// grid's and an orthographic view's do, the first ray's is copied to
/// every lane instead: a gather reads one value at a time, and six of them
/// cost more than comparing the rays. What `share` says the rays share is
/// copied without comparing.
#[inline(always)]
fn gather_lanes<S: Simd>(s: S, v: &[f64], share: RaysShare) -> Lanes<S> {
    let origin = |a: usize| match share {
        RaysShare::AllBut(varying) if a != varying => s.splat(v[a]),
        _ => s.gather(v, a, 9),
    };
    let o = [origin(0), origin(1), origin(2)];
    let first = &v[3..9];
    let shared = share != RaysShare::Unknown
        || v.chunks_exact(9).skip(1).all(|ray| {
            ray[3..9]
                .iter()
                .zip(first)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        });
    if shared {
        return Lanes {
            o,
            d: [s.splat(v[3]), s.splat(v[4]), s.splat(v[5])],
            inv: [s.splat(v[6]), s.splat(v[7]), s.splat(v[8])],
        };
    }
    Lanes {
        o,
        d: [s.gather(v, 3, 9), s.gather(v, 4, 9), s.gather(v, 5, 9)],
        inv: [s.gather(v, 6, 9), s.gather(v, 7, 9), s.gather(v, 8, 9)],
    }
}

/// The entry of each lane's ray into child `k` of wide node `n`, and the
/// lanes that meet it within `[tmin, tmax]`: [`crate::bvh`]'s slab test of
/// a wide node's child.
#[inline(always)]
fn child_lanes<S: Simd>(
    s: S,
    n: &WideNode,
    k: usize,
    r: &Lanes<S>,
    tmin: S::F,
    tmax: S::F,
) -> (S::F, S::M) {
    let lo = [n.lo[0][k], n.lo[1][k], n.lo[2][k]];
    let hi = [n.hi[0][k], n.hi[1][k], n.hi[2][k]];
    slab_lanes(s, lo, hi, r, tmin, tmax)
}

compiled_for_each! {
    fn rays_avx512, rays_avx2, rays_any => rays_in_packets(
        zones: Option<&[(f64, u32)]>,
        rays: &[Ray],
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: &mut [(u32, Hit)],
    ) -> usize
}

compiled_for_each! {
    fn tile_avx512, tile_avx2, tile_any => tile_in_packets(
        gen: &RayGen,
        tile: Tile,
        zones: Option<&[(f64, u32)]>,
        tmin: f64,
        tmax: f64,
        s: &mut Scratch,
        out: PacketOut<'_>,
    ) -> usize
}
