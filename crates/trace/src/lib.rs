//! Rays through a prepared Combinatorial Geometry.
//!
//! [`Prepared`] lays a [`Geometry`](sv_geom::Geometry)'s zones out in flat
//! arrays with a bounding volume hierarchy (walked four-wide); the ray
//! queries find the first opaque region hit, any hit (shadows) and every
//! region's stretches along a ray; the light buffers answer shadow rays
//! toward parallel and point lights; the packet tracer casts a tile's rays
//! eight at a time in AVX-512 lanes (four in AVX2), chosen at run time, bit
//! for bit what the scalar tracer gives.
//!
//! ```
//! use sv_geom::{Body, BodyKind, Geometry, Region};
//! use sv_math::{DVec3, Ray};
//! use sv_trace::{PrepareOptions, Prepared, Scratch};
//! let mut g = Geometry::default();
//! g.bodies.push(Body::new("1", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0]));
//! g.regions.push(Region::of_body("B", 0));
//! let (p, _warnings) = Prepared::new(&g, &PrepareOptions::default()).unwrap();
//! let mut s = Scratch::new(&p);
//! let hit = p.first_hit(&Ray::new(DVec3::new(0.0, 0.0, -5.0), DVec3::Z), 0.0, f64::INFINITY, &mut s).unwrap();
//! assert!((hit.t - 4.0).abs() < 1e-12);
//! ```
#![warn(missing_docs)]

mod build;
mod bvh;
mod fill;
mod frustum;
mod hit;
mod lightbuf;
mod occlusion;
mod packet;
mod per_thread;
mod prepare;
mod query;
mod raster;
mod zone;

pub use frustum::{Frustum, RasterExtent};
pub use hit::{
    by_entry, leave_repeats_empty, same_stretches, Crossing, Hit, Partition, Scratch, Step,
};
pub use lightbuf::{LightBuffer, PointBuffer, ShadowBuffer};
pub use occlusion::{LightAt, Occluders, ShadowBuffers};
pub use packet::{RaysShare, Tile, FACING_MISS};
pub use per_thread::PerThread;
pub use prepare::{PrepareError, PrepareOptions, Prepared};
pub use sv_geom::Warning;

/// Numbers spread evenly over `[0, 1)` for the tests, from a 64-bit linear
/// congruential generator started at `seed`: the same every run.
#[cfg(test)]
pub(crate) fn test_numbers(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The parameters of a BOX body for the tests: corner `(x, y, z)`, turned
/// about the vertical by `(a, b)`, 0.4 high.
#[cfg(test)]
pub(crate) fn turned_box([x, y, z]: [f64; 3], a: f64, b: f64) -> Vec<f64> {
    let v = [x, y, z, 2.0 * a, 2.0 * b, 0.0, -0.3 * b, 0.3 * a, 0.0];
    [&v[..], &[0.0, 0.0, 0.4]].concat()
}
