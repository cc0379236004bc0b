use sv_math::DVec3;

/// A light source of the paper: the sun (parallel) or a point source whose
/// intensity falls as `R⁻ⁿ`.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Name the director uses (`SUN`, `LAMP`).
    pub name: String,
    /// Parallel or point.
    pub kind: LightKind,
    /// Intensity I₀.
    pub intensity: f64,
    /// Colour (linear RGB), white by default.
    pub colour: [f64; 3],
}

/// Kind of light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Uniform plane-parallel light travelling along `dir`.
    Parallel {
        /// Direction the light travels in.
        dir: DVec3,
    },
    /// Point source at `pos`; received intensity is `I₀ · R⁻ⁿ`.
    Point {
        /// Position.
        pos: DVec3,
        /// Decay exponent n (0: no fall-off; 2: inverse square).
        decay: f64,
    },
}
