//! Shading: the paper's formula, per channel,
//!
//! `I = c ⊙ (Σ_lights I₀ · k · cosθ · f(R) · light colour + A₀)`,
//!
//! where `c` is the region's colour (white by default, giving exactly
//! `I = I₀ k cosθ + A₀`), `k` its reflectance, `f(R) = R⁻ⁿ` for a point
//! light at distance `R` with decay `n` and 1 for a parallel light; a light
//! contributes nothing where `cos θ ≤ 0` or, with shadows on, where an
//! opaque region blocks it. Values are linear.
//!
//! [`Shading::RtEyeLight`] is BRL-CAD's `rt -l1` instead: one light at the
//! eye and ambient 0.4, `I = 0.4 + 0.6 · max(0, cos θ)`, grey whatever the
//! region's colour and `k`.

use crate::Renderer;
use sv_math::{DVec3, Ray};
use sv_scene::LightKind;
use sv_trace::{Hit, Occluders, Scratch};

/// Which formula shades a hit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shading {
    /// The paper's: the scene's lights, `k`, colours and ambient.
    #[default]
    Paper,
    /// BRL-CAD's `rt -l1`: a light at the eye, `0.4 + 0.6 · cos θ`; a ray
    /// that starts inside a solid is shaded with the normal of the surface
    /// where it entered that solid behind the eye, as `rt` does (a face
    /// toward the viewer in [`Shading::Paper`]).
    RtEyeLight,
}

/// `rt`'s ambient intensity (its `AmbientIntensity`).
const RT_AMBIENT: f64 = 0.4;

/// [`Shading::RtEyeLight`]'s grey for a surface that faces its ray by
/// `facing` ([`sv_trace::Prepared::facing`]): `rt -l1` lights a hit from
/// the eye over its ambient.
#[inline(always)]
pub(crate) fn rt_grey(facing: f64) -> f64 {
    RT_AMBIENT + (1.0 - RT_AMBIENT) * facing
}

impl Renderer {
    /// Intensity (linear RGB) of the surface at `hit`.
    pub fn shade(&self, ray: &Ray, hit: &Hit, shadows: bool, s: &mut Scratch) -> [f64; 3] {
        let n = self.prepared().normal(hit, ray);
        self.intensity(ray, (0, hit), n, shadows, &mut Occluders::default(), s)
    }

    /// The paper's shading of `hit` (the tile's hit number `h`, seen along
    /// `ray`, surface normal `n`), its shadow rays asked of `occluders`.
    /// Inlined into both pixel loops of the tile: called through a function
    /// it costs some scenes a few per cent.
    #[inline(always)]
    pub(crate) fn intensity(
        &self,
        ray: &Ray,
        (h, hit): (usize, &Hit),
        n: DVec3,
        shadows: bool,
        occluders: &mut Occluders<'_>,
        s: &mut Scratch,
    ) -> [f64; 3] {
        if self.shading == Shading::RtEyeLight {
            return [rt_grey(self.prepared().facing(hit, ray, s)); 3];
        }
        let p = ray.at(hit.t);
        let (k, colour) = self.looks[hit.region as usize];
        let mut sum = [0.0; 3];
        for (li, l) in self.lights.iter().enumerate() {
            // The fall-off's exponent: none for a parallel light.
            let (to_light, dist, decay) = match l.kind {
                // Made once a render (as the light's buffer has it).
                LightKind::Parallel { dir } => (
                    occluders.toward(li).unwrap_or_else(|| -dir.normalize()),
                    f64::INFINITY,
                    None,
                ),
                LightKind::Point { pos, decay } => {
                    let d = pos - p;
                    let r = d.length();
                    (d / r, r, Some(decay))
                }
            };
            let cos = n.dot(to_light);
            if cos <= 0.0 {
                continue;
            }
            if shadows && occluders.occluded(self.prepared(), li, (h, hit), p, to_light, dist, s) {
                continue;
            }
            // Only for a surface the light reaches: the power took 8 % of a
            // crowd's time under a lamp.
            let fall = decay.map_or(1.0, |n| dist.powf(-n));
            let e = l.intensity * k * cos * fall;
            for (acc, lc) in sum.iter_mut().zip(l.colour) {
                *acc += e * lc;
            }
        }
        std::array::from_fn(|c| colour[c] * (sum[c] + self.ambient))
    }
}
