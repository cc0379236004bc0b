//! A worker's memory, made once per worker and render and reused from tile
//! to tile.

use crate::tiles::BandLists;
use sv_math::{DVec3, Ray};
use sv_trace::{Hit, LightAt, Occluders, PerThread, Prepared, Scratch, ShadowBuffers};

/// A worker's memory, reused from tile to tile.
pub(crate) struct Workspace<'a> {
    /// Ray scratch.
    pub(crate) scratch: Scratch,
    /// The zones of the band's tiles.
    pub(crate) lists: BandLists,
    /// The tile's zones with their entry bounds, sorted.
    pub(crate) sorted: Vec<(f64, u32)>,
    /// The raster positions of the tile's primary rays, and the rays.
    pub(crate) pts: Vec<[f64; 2]>,
    pub(crate) rays: Vec<Ray>,
    /// The rays of the tile's hits, in the order of `hits`.
    pub(crate) hit_rays: Vec<Ray>,
    /// The tile's primary rays that hit: their sample number in the tile
    /// (an index into `rays`) and the hit, in as many first entries as
    /// there are hits. Rays that miss are not kept; the entries past the
    /// hits are slots kept for the next tile.
    pub(crate) hits: Vec<(u32, Hit)>,
    /// The surface normal at each hit, in the order of `hits`.
    pub(crate) normals: Vec<DVec3>,
    /// Under rt's shading, in place of the three above: how squarely each
    /// pixel of the tile faces its ray, or `FACING_MISS`
    /// ([`sv_trace::Prepared::tile_facing`]).
    pub(crate) facing: Vec<f64>,
    /// The same for each tile of the band, left to right, with its number
    /// of hits.
    pub(crate) band_facing: Vec<(usize, Vec<f64>)>,
    /// Where the tile's shadow rays look for occluders.
    pub(crate) occluders: Occluders<'a>,
}

impl<'a> Workspace<'a> {
    /// A worker's memory for `p`, its shadow rays toward `lights` asked of
    /// `buffers` (none: the whole hierarchy).
    pub(crate) fn new(
        p: &Prepared,
        lights: &[LightAt],
        buffers: Option<&'a ShadowBuffers>,
    ) -> Workspace<'a> {
        Workspace {
            scratch: Scratch::new(p),
            lists: BandLists::default(),
            sorted: Vec::new(),
            pts: Vec::new(),
            rays: Vec::new(),
            hits: Vec::new(),
            hit_rays: Vec::new(),
            normals: Vec::new(),
            facing: Vec::new(),
            band_facing: Vec::new(),
            occluders: Occluders::new(lights, buffers),
        }
    }
}

/// One [`Workspace`] per worker thread, made once a render.
pub(crate) type Workers<'a> = PerThread<Workspace<'a>>;
