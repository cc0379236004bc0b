//! Combinatorial Geometry: bodies, regions and ray/region intervals.
#![warn(missing_docs)]

mod model;
pub mod table;

pub use model::{cyl_axes, quadric_matrix, Body, Geometry, Op, Region, Term, TransformError, Zone};
pub use table::{BodyKind, BodyType, Param, ParamKind, BODY_TYPES};
