//! `Camera` and `Light`: the view of a picture, as the scene language
//! describes it.

use crate::errors::bad_input;
use pyo3::prelude::*;
use sv_math::DVec3;
use sv_scene::{Lens, LightKind};

/// Three finite numbers as a point or direction.
pub fn vec3(value: (f64, f64, f64), what: &str) -> PyResult<DVec3> {
    let point = DVec3::new(value.0, value.1, value.2);
    if point.is_finite() {
        Ok(point)
    } else {
        Err(bad_input(format!("{what} must be three finite numbers")))
    }
}

/// A camera: `Camera(eye=(x, y, z), at=(x, y, z), up=(0, 0, 1), fov=40)`,
/// or `ortho_height=H` for a parallel projection showing H model units
/// vertically.
#[pyclass(frozen, from_py_object, module = "synthavision")]
#[derive(Clone)]
pub struct Camera {
    /// The camera as the renderer takes it.
    pub camera: sv_scene::Camera,
}

#[pymethods]
impl Camera {
    #[new]
    #[pyo3(signature = (eye, at, up=(0.0, 0.0, 1.0), fov=None, ortho_height=None))]
    fn new(
        eye: (f64, f64, f64),
        at: (f64, f64, f64),
        up: (f64, f64, f64),
        fov: Option<f64>,
        ortho_height: Option<f64>,
    ) -> PyResult<Camera> {
        let (eye, at, up) = (vec3(eye, "eye")?, vec3(at, "at")?, vec3(up, "up")?);
        if eye == at {
            return Err(bad_input("eye and at are the same point"));
        }
        if up.length_squared() == 0.0 {
            return Err(bad_input("up must not be zero"));
        }
        let lens = match (fov, ortho_height) {
            (Some(_), Some(_)) => return Err(bad_input("give fov or ortho_height, not both")),
            (None, Some(height)) if height > 0.0 && height.is_finite() => Lens::Ortho { height },
            (None, Some(height)) => {
                return Err(bad_input(format!(
                    "ortho_height must be positive, found {height}"
                )))
            }
            (fov, None) => {
                let degrees = fov.unwrap_or(40.0);
                if !(degrees > 0.0 && degrees < 180.0) {
                    return Err(bad_input(format!(
                        "fov must lie between 0 and 180 degrees, found {degrees}"
                    )));
                }
                Lens::Fov {
                    vertical_deg: degrees,
                }
            }
        };
        Ok(Camera {
            camera: sv_scene::Camera::looking_at(eye, at, up, lens),
        })
    }

    /// The eye point.
    #[getter]
    fn eye(&self) -> (f64, f64, f64) {
        self.camera.eye.into()
    }

    /// The viewing direction.
    #[getter]
    fn direction(&self) -> (f64, f64, f64) {
        self.camera.dir.into()
    }

    fn __repr__(&self) -> String {
        let (eye, dir) = (self.camera.eye, self.camera.dir);
        format!(
            "Camera(eye=({}, {}, {}), direction=({}, {}, {}), lens={:?})",
            eye.x, eye.y, eye.z, dir.x, dir.y, dir.z, self.camera.lens
        )
    }
}

/// A light source: `Light.parallel(direction)` or `Light.point(position)`.
#[pyclass(frozen, from_py_object, module = "synthavision")]
#[derive(Clone)]
pub struct Light {
    /// The light as the renderer takes it.
    pub light: sv_scene::Light,
}

/// A light of `kind`, checking intensity and colour.
fn light(kind: LightKind, intensity: f64, colour: (f64, f64, f64)) -> PyResult<Light> {
    if !(intensity >= 0.0 && intensity.is_finite()) {
        return Err(bad_input(format!(
            "intensity must be zero or more, found {intensity}"
        )));
    }
    let colour = vec3(colour, "colour")?;
    Ok(Light {
        light: sv_scene::Light {
            name: "PYTHON".into(),
            kind,
            intensity,
            colour: colour.to_array(),
        },
    })
}

#[pymethods]
impl Light {
    /// Plane-parallel light travelling along `direction`.
    #[staticmethod]
    #[pyo3(signature = (direction, intensity=1.0, colour=(1.0, 1.0, 1.0)))]
    fn parallel(
        direction: (f64, f64, f64),
        intensity: f64,
        colour: (f64, f64, f64),
    ) -> PyResult<Light> {
        let dir = vec3(direction, "direction")?;
        if dir.length_squared() == 0.0 {
            return Err(bad_input("direction must not be zero"));
        }
        light(LightKind::Parallel { dir }, intensity, colour)
    }

    /// A point source at `position`; the intensity falls off as
    /// `distance ** -decay`.
    #[staticmethod]
    #[pyo3(signature = (position, intensity=1.0, colour=(1.0, 1.0, 1.0), decay=0.0))]
    fn point(
        position: (f64, f64, f64),
        intensity: f64,
        colour: (f64, f64, f64),
        decay: f64,
    ) -> PyResult<Light> {
        let pos = vec3(position, "position")?;
        if !(decay >= 0.0 && decay.is_finite()) {
            return Err(bad_input(format!(
                "decay must be zero or more, found {decay}"
            )));
        }
        light(LightKind::Point { pos, decay }, intensity, colour)
    }

    fn __repr__(&self) -> String {
        format!(
            "Light({:?}, intensity={}, colour={:?})",
            self.light.kind, self.light.intensity, self.light.colour
        )
    }
}
