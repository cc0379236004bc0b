//! Combinatorial Geometry: what a body and a region are.
//!
//! The one table of body types ([`table`]), bodies and regions as written
//! ([`Body`], [`Region`]), each body checked and turned into the form a ray
//! is cast against ([`prepare`], [`shape`]: one file per body family, with
//! its validation, intersection, normal, bounds and lane form), and the
//! booleans of regions as a separate pass over a ray's segments
//! ([`boolean`]). Tracing whole scenes (hierarchies, packets, shadows) is
//! sv-trace's.
//!
//! ```
//! use sv_geom::{prepare, Body, BodyKind};
//! use sv_math::{DVec3, Ray};
//! let body = Body::new("1", BodyKind::Sph, vec![0.0, 0.0, 0.0, 1.0]);
//! let (shape, bounds) = prepare(&body, &mut Vec::new()).unwrap();
//! let mut segs = Vec::new();
//! shape.shoot(&Ray::new(DVec3::new(0.0, 0.0, -5.0), DVec3::Z), &mut segs);
//! assert_eq!((segs[0].t0, segs[0].t1), (4.0, 6.0));
//! assert_eq!(bounds.max, DVec3::ONE);
//! ```
#![warn(missing_docs)]

mod body;
pub mod boolean;
mod model;
mod region;
pub mod shape;
pub mod table;

pub use body::{prepare, Prepare, Warning, MAX_MAGNITUDE};
pub use model::{cyl_axes, quadric_matrix, Body, Geometry, TransformError};
pub use region::{Fill, Group, Lattice, LatticeKind, Op, Region, Term, Universe, Zone};
pub use shape::{arb_points, ars_triangles};
pub use table::{BodyKind, BodyType, Param, ParamKind, BODY_TYPES};
