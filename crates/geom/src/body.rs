//! Bodies as written, checked and turned into their ray-casting form
//! ([`prepare`]): every rule a body's values must keep is tested here and
//! names the body and the rule broken.

use crate::model::Body;
use crate::shape::Shape;
use crate::table::BodyKind;
use std::fmt;
use sv_math::{Aabb, DVec3};

/// Something wrong with a body that was nevertheless rendered.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// Body name.
    pub body: String,
    /// Body type.
    pub kind: BodyKind,
    /// What is off and what was done about it.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} `{}`: {}", self.kind, self.body, self.message)
    }
}

/// The largest magnitude of a body's value. Beyond it the squares and
/// products of ray casting and of the model's bounds overflow, and a body
/// would vanish from the bounds without a word.
pub const MAX_MAGNITUDE: f64 = 1e50;

fn finite(b: &Body) -> Result<(), String> {
    for (i, v) in b.params.iter().enumerate() {
        if !v.is_finite() {
            return Err(format!("value {} is not a finite number", i + 1));
        }
        if v.abs() > MAX_MAGNITUDE {
            return Err(format!(
                "value {} is {v:e}, beyond ±{MAX_MAGNITUDE:e}: the model's bounds would overflow",
                i + 1
            ));
        }
    }
    Ok(())
}

pub(crate) fn nonzero(v: DVec3, what: &str) -> Result<DVec3, String> {
    if v.length_squared() == 0.0 {
        Err(format!("{what} is zero"))
    } else {
        Ok(v)
    }
}

pub(crate) fn positive(x: f64, what: &str) -> Result<f64, String> {
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("{what} must be positive (is {x})"))
    }
}

pub(crate) fn independent(a: DVec3, b: DVec3, c: DVec3, what: &str) -> Result<(), String> {
    let det = a.cross(b).dot(c).abs();
    if det <= 1e-12 * a.length() * b.length() * c.length() {
        Err(format!("{what} are coplanar (zero volume)"))
    } else {
        Ok(())
    }
}

pub(crate) fn perpendicular(a: DVec3, b: DVec3, what: &str) -> Result<(), String> {
    if a.dot(b).abs() > 1e-5 * a.length() * b.length() {
        Err(format!("{what} are not perpendicular"))
    } else {
        Ok(())
    }
}

/// The prepared shape of body `b` and its bounds, or the rule its values
/// break. Warnings (a body rendered though something is off) go to
/// `warnings`. The values' count and finiteness are checked here; each
/// body family's own rules where its shape is made (the table's
/// [`BodyType::prepare`](crate::table::BodyType)).
pub fn prepare(b: &Body, warnings: &mut Vec<Warning>) -> Result<(Shape, Aabb), String> {
    finite(b)?;
    let expect = b.kind.info().value_count();
    if b.kind == BodyKind::Ars {
        crate::shape::mesh::check_ars_counts(b)?;
    } else if b.params.len() != expect {
        return Err(format!("takes {expect} values, found {}", b.params.len()));
    }
    (b.kind.info().prepare)(b, warnings)
}

/// A shape with its own bounds, as most families return it.
pub(crate) fn with_bounds(shape: Shape) -> Result<(Shape, Aabb), String> {
    let bounds = shape.bounds();
    Ok((shape, bounds))
}

/// The signature of a body family's preparation: the shape and bounds of a
/// body whose values have the table's count and are finite.
pub type Prepare = fn(&Body, &mut Vec<Warning>) -> Result<(Shape, Aabb), String>;
