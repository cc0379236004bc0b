//! The light buffer of a parallel light (Haines and Greenberg 1986, "The
//! light buffer: a shadow-testing accelerator"): the opaque zones binned by
//! where their bounds fall on a plane normal to the light. A point light's
//! buffer ([`PointBuffer`]) bins them by direction on the faces of a cube
//! around the light, as that paper first did.
//!
//! Every shadow ray toward a parallel light runs along the same direction,
//! so its projection on that plane is a single point: it can only meet the
//! zones whose projected bounds hold that point, which are the zones listed
//! in the point's cell. Each cell's zones are sorted by how far their
//! bounds reach toward the light, farthest first, so a shadow ray stops
//! at the first zone wholly behind its origin. Zones large beside the rest
//! (a ground under a vehicle) are kept apart in one list, so that they do
//! not stretch the grid. A shadow test then looks at a handful of zones
//! instead of walking the hierarchy.

mod binning;
mod parallel;
mod point;
#[cfg(test)]
mod tests;

pub use parallel::LightBuffer;
pub(crate) use parallel::{Grid, Place};
pub use point::PointBuffer;

use crate::hit::Scratch;
use crate::prepare::Prepared;
use sv_math::Ray;

/// The zones a shadow ray may meet, from a buffer: all of `big`, and the
/// zones of a cell while their keys (sorted) are at most `bound`.
pub struct Candidates<'a> {
    big: &'a [u32],
    cell: &'a [u32],
    keys: &'a [f64],
    bound: f64,
}

impl<'a> Candidates<'a> {
    /// Only the zones of `big`.
    fn only(big: &'a [u32]) -> Candidates<'a> {
        Candidates {
            big,
            cell: &[],
            keys: &[],
            bound: f64::NEG_INFINITY,
        }
    }

    /// Every zone listed: the large ones, then the cell's.
    pub(crate) fn all(&self) -> impl Iterator<Item = u32> + 'a {
        self.big.iter().copied().chain(self.cell())
    }

    /// The cell's zones that may be met, in order: the loop that tests
    /// them stops at the first whose key is past the bound (no search for
    /// where they end first).
    fn cell(&self) -> impl Iterator<Item = u32> + 'a {
        let bound = self.bound;
        self.cell
            .iter()
            .zip(self.keys)
            .take_while(move |(_, &k)| k <= bound)
            .map(|(&zi, _)| zi)
    }
}

/// A shadow-ray accelerator, for [`Prepared::occluded_by`]: a parallel
/// light's [`LightBuffer`] or a point light's [`PointBuffer`].
pub trait ShadowBuffer: sealed::Zones {}

impl ShadowBuffer for LightBuffer {}
impl ShadowBuffer for PointBuffer {}

/// What [`Prepared::occluded_by`] asks of a buffer, kept out of the public
/// interface.
mod sealed {
    use super::Candidates;
    use sv_math::{DVec3, Ray};

    pub trait Zones {
        /// The zones that a shadow ray from `p` may meet, or `None` to
        /// search everything.
        fn zones_at(&self, p: DVec3) -> Option<Candidates<'_>>;

        /// Check (in debug builds) that `ray` is one of the buffer's.
        fn check(&self, _ray: &Ray) {}
    }
}

impl Prepared {
    /// As [`Prepared::occluded`] for a shadow ray toward the light of
    /// `buf`: the same answer, looking only at the zones the buffer lists
    /// for the ray's origin. Toward a parallel light the ray must come
    /// from [`LightBuffer::shadow_ray`]; toward a point light `tmax` must
    /// be no farther than the light.
    ///
    /// `last` is the buffer's shadow cache: the zone that blocked the
    /// previous shadow ray (`None` if it was not blocked). Neighbouring
    /// points are mostly shadowed by the same zone, so it is tried first;
    /// the answer does not depend on it.
    #[allow(clippy::too_many_arguments)]
    pub fn occluded_by<B: ShadowBuffer>(
        &self,
        buf: &B,
        ray: &Ray,
        tmin: f64,
        tmax: f64,
        skip: Option<u32>,
        last: &mut Option<u32>,
        s: &mut Scratch,
    ) -> bool {
        buf.check(ray);
        let Some(zones) = buf.zones_at(ray.origin) else {
            // A point that is not a number: let the full search decide.
            return self.occluded(ray, tmin, tmax, skip, s);
        };
        s.new_ray();
        if let Some(z) = *last {
            if self.any_opaque([z], skip, ray, tmin, tmax, s).is_some() {
                return true;
            }
        }
        let all = self.unbounded_opaque.iter().copied().chain(zones.all());
        *last = self.any_opaque(all, skip, ray, tmin, tmax, s);
        last.is_some()
    }
}
