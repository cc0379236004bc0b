//! Points, vectors, rays, bounds and rigid transforms.
//!
//! All geometry is in `f64`: real decks come in large coordinates (inches,
//! millimetres) and the booleans compare distances along a ray, so the tracer
//! keeps full precision end to end. Bounding boxes used by the BVH are
//! widened outward when they are narrowed to `f32`.
//!
//! ```
//! use sv_math::{Aabb, Ray, DVec3};
//! let b = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
//! let r = Ray::new(DVec3::new(0.0, 0.0, -5.0), DVec3::Z);
//! assert_eq!(b.ray_range(&r), Some((4.0, 6.0)));
//! ```
#![warn(missing_docs)]

pub use glam::{DAffine3, DMat3, DQuat, DVec2, DVec3, Vec3A};

mod aabb;
mod frame;
pub mod lanes;
mod ray;
mod raygen;
pub mod simd;

pub use aabb::Aabb;
pub use frame::{orthonormal_basis, rotation_about_axis};
pub use ray::Ray;
pub use raygen::RayGen;
