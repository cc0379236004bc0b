//! Ray casting, shading and tiles: a [`Renderer`] holds a prepared scene
//! with its camera, lights and looks, and renders [`Frame`]s.
//!
//! The rooms: [`Settings`] (what a picture is asked to be), the renderer
//! and its named steps (`renderer`), the paper's shading formula in one
//! function (`shading`), the tiles and bands of the raster (`tiles`), a
//! worker's memory (`workspace`), default views and lights (`view`).
//!
//! Every pixel is computed independently from its own rays, so a picture is
//! bit-for-bit the same whatever the number of threads.
#![warn(missing_docs)]

mod frame;
mod renderer;
mod settings;
mod shading;
mod tiles;
mod view;
mod workspace;

pub use frame::Frame;
pub use renderer::Renderer;
pub use settings::Settings;
pub use shading::Shading;
pub use view::{default_camera, default_lights, frame_bounds, rt_camera, UpAxis, ViewSpec};

use sv_math::DVec3;

/// A unit vector from azimuth and elevation in degrees (BRL-CAD's
/// convention: azimuth from +x toward +y, elevation above the xy plane).
pub fn az_el(az: f64, el: f64) -> DVec3 {
    let (a, e) = (az.to_radians(), el.to_radians());
    DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin())
}

#[cfg(test)]
mod tests;
