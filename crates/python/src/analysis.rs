//! What `Model` computes besides pictures: section views and id maps,
//! crossings along a ray, overlap checks and volumes, each through the
//! check and trace crates as the CLI's commands drive them.

use crate::errors::{bad_input, runtime, without_gil};
use crate::model::Model;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;
use sv_check::{Plane, Slice, SliceOptions, UniverseChoice};
use sv_math::Ray;
use sv_output::{write_image, ImageFormat, Pixels, WriteOptions};
use sv_scene::Scene;

/// The index of the region `name`, or a `ValueError` with a suggestion.
pub fn region_named(scene: &Scene, name: &str) -> PyResult<usize> {
    scene.geometry.region_index(name).ok_or_else(|| {
        let hint =
            sv_formats::did_you_mean(name, scene.geometry.regions.iter().map(|r| r.name.as_str()))
                .map(|s| format!("; did you mean `{s}`?"))
                .unwrap_or_default();
        bad_input(format!("no region `{name}`{hint}"))
    })
}

/// The cutting plane: `plane` "x=V" (y, z), or `origin` with `normal`.
pub fn plane(
    axis_plane: Option<&str>,
    origin: Option<(f64, f64, f64)>,
    normal: Option<(f64, f64, f64)>,
) -> PyResult<Plane> {
    match (axis_plane, origin, normal) {
        (Some(text), None, None) => Plane::parse(text).ok_or_else(|| {
            bad_input(format!(
                "plane: expected \"x=VALUE\", \"y=VALUE\" or \"z=VALUE\", found \"{text}\""
            ))
        }),
        (None, Some(origin), Some(normal)) => {
            let origin = crate::view::vec3(origin, "origin")?;
            let normal = crate::view::vec3(normal, "normal")?;
            Plane::new(origin, normal).ok_or_else(|| bad_input("normal must not be zero"))
        }
        (None, None, None) => Err(bad_input(
            "give the plane: plane=\"z=0\" (or x=, y=), or origin=(x, y, z) with normal=(x, y, z)",
        )),
        (Some(_), _, _) => Err(bad_input("plane cannot be combined with origin/normal")),
        _ => Err(bad_input("origin and normal go together")),
    }
}

/// The check crate's model of `model`, looking for a universe unless told
/// not to (`universe=False`) or told its name.
fn check_model(model: &Model, universe: UniverseChoice) -> PyResult<sv_check::Model> {
    let (check_model, _) = sv_check::Model::new(&model.scene, &universe).map_err(bad_input)?;
    Ok(check_model)
}

/// The section of `opts`, on all cores with the GIL released.
fn cut(model: &Model, opts: &SliceOptions, universe: UniverseChoice) -> PyResult<Slice> {
    let check_model = check_model(model, universe)?;
    sv_check::slice(&check_model, opts).map_err(bad_input)
}

/// Region ids of a section: −1 nothing or void, −3 overlap, else the
/// region index.
fn region_ids(section: &Slice) -> Vec<i32> {
    section
        .class
        .iter()
        .map(|&class| match class {
            0 | Slice::VOID => -1,
            Slice::OVERLAP => -3,
            region => region as i32 - 1,
        })
        .collect()
}

/// The plane of OpenMC's `basis` ("xy", "xz" or "yz") through `centre`.
pub fn basis_plane(centre: sv_math::DVec3, basis: &str) -> PyResult<Plane> {
    let axis = match basis.to_ascii_lowercase().as_str() {
        "xy" => 2,
        "xz" => 1,
        "yz" => 0,
        other => {
            return Err(bad_input(format!(
                "basis: expected \"xy\", \"xz\" or \"yz\", found \"{other}\""
            )))
        }
    };
    Ok(Plane::axis(axis, centre[axis]))
}

/// `Model.id_map`: region and material index per pixel of the section.
pub fn id_map<'py>(
    py: Python<'py>,
    model: &Model,
    opts: &SliceOptions,
) -> PyResult<Bound<'py, PyAny>> {
    let materials = model.material_indices(py);
    let (ids, columns, rows) = without_gil(py, || {
        let section = cut(model, opts, UniverseChoice::Auto)?;
        let regions = region_ids(&section);
        let mut both = Vec::with_capacity(regions.len() * 2);
        for region in regions {
            let material = match region {
                region if region >= 0 => materials[region as usize].map_or(-1, |m| m as i32),
                special => special,
            };
            both.extend([region, material]);
        }
        Ok((both, section.width, section.height))
    })?;
    let shape = [rows as usize, columns as usize, 2];
    Ok(PyArray1::from_vec(py, ids).reshape(shape)?.into_any())
}

/// A section view: the picture (with the legend strip unless left off),
/// the region id of each pixel of the section, and the legend.
#[pyclass(frozen, module = "synthavision")]
pub struct Section {
    /// Display colours 0…1, float32 (height, width, 3), legend included.
    #[pyo3(get)]
    rgb: Py<PyAny>,
    /// Region index per pixel of the section (−1 nothing, −3 overlap).
    #[pyo3(get)]
    region: Py<PyAny>,
    /// Regions in the picture, largest area first: dicts of label,
    /// description, colour, pixels and area.
    #[pyo3(get)]
    legend: Py<PyAny>,
    /// Overlapping pairs in the picture.
    #[pyo3(get)]
    overlaps: Py<PyAny>,
    /// Void in the picture, or None.
    #[pyo3(get)]
    void: Py<PyAny>,
    /// Width and height of the view in model units.
    #[pyo3(get)]
    extent: (f64, f64),
    /// Centre of the view.
    #[pyo3(get)]
    centre: (f64, f64, f64),
    /// The plane's right and up directions.
    #[pyo3(get)]
    axes: ((f64, f64, f64), (f64, f64, f64)),
    width: u32,
    height: u32,
    colours: Vec<[f32; 3]>,
}

/// `Model.slice`.
pub fn section(
    py: Python<'_>,
    model: &Model,
    opts: SliceOptions,
    legend: bool,
    universe: bool,
) -> PyResult<Section> {
    let choice = if universe {
        UniverseChoice::Auto
    } else {
        UniverseChoice::None
    };
    let (section, (width, height, colours)) = without_gil(py, || {
        let section = cut(model, &opts, choice)?;
        let picture = if legend {
            sv_check::with_legend(&section)
        } else {
            (section.width, section.height, section.rgb.clone())
        };
        Ok((section, picture))
    })?;
    let json = py.import("json")?;
    let as_python = |value: String| -> PyResult<Py<PyAny>> {
        Ok(json.call_method1("loads", (value,))?.unbind())
    };
    let flat: Vec<f32> = colours.iter().flatten().copied().collect();
    let rgb = PyArray1::from_vec(py, flat).reshape([height as usize, width as usize, 3])?;
    let shape = [section.height as usize, section.width as usize];
    let region = PyArray1::from_vec(py, region_ids(&section)).reshape(shape)?;
    Ok(Section {
        rgb: rgb.into_any().unbind(),
        region: region.into_any().unbind(),
        legend: as_python(to_json(&section.legend))?,
        overlaps: as_python(to_json(&section.overlaps))?,
        void: as_python(to_json(&section.void))?,
        extent: section.extent,
        centre: section.centre.into(),
        axes: (section.plane.u.into(), section.plane.v.into()),
        width,
        height,
        colours,
    })
}

/// A legend's entries as JSON.
fn to_json<T: serde::Serialize>(value: &T) -> String {
    serde_json::to_string(value).expect("legend entries serialise")
}

#[pymethods]
impl Section {
    /// Write the picture as the CLI's `slice` does (.png or .ppm).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        let format = match ImageFormat::from_path(&path) {
            Some(format @ (ImageFormat::Png | ImageFormat::Pnm)) => format,
            _ => {
                return Err(bad_input(format!(
                    "cannot tell the picture format of `{}`: use .png or .ppm",
                    path.display()
                )))
            }
        };
        let pixels = Pixels {
            width: self.width,
            height: self.height,
            rgb: &self.colours,
            alpha: None,
        };
        write_image(&path, format, &pixels, &WriteOptions::default()).map_err(runtime)
    }

    /// Jupyter's inline picture.
    fn _repr_png_<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        crate::image::png_bytes(py, self.width, self.height, &self.colours)
    }
}

/// `Model.shoot`: the regions holding the origin and every crossing.
pub fn shoot<'py>(
    py: Python<'py>,
    scene: &Scene,
    origin: (f64, f64, f64),
    direction: (f64, f64, f64),
) -> PyResult<Bound<'py, PyDict>> {
    let from = crate::view::vec3(origin, "origin")?;
    let dir = crate::view::vec3(direction, "direction")?;
    if dir.length_squared() == 0.0 {
        return Err(bad_input("direction must not be zero"));
    }
    let geometry = &scene.geometry;
    let (prepared, _) =
        sv_trace::Prepared::new(geometry, &Default::default()).map_err(bad_input)?;
    let name = |region: usize| geometry.regions[region].name.clone();
    let start: Vec<String> = (0..geometry.regions.len())
        .filter(|&region| prepared.region_contains(region, from))
        .map(name)
        .collect();
    let mut scratch = sv_trace::Scratch::new(&prepared);
    let crossings = pyo3::types::PyList::empty(py);
    for step in prepared.walk(&Ray::new(from, dir), 0.0, &mut scratch) {
        let body = &geometry.bodies[step.body as usize];
        let crossing = PyDict::new(py);
        crossing.set_item("t", step.t)?;
        crossing.set_item("event", if step.entering { "enters" } else { "leaves" })?;
        crossing.set_item("body", &body.name)?;
        crossing.set_item("type", body.kind.name())?;
        let after: Vec<String> = step
            .regions_after
            .iter()
            .map(|r| name(*r as usize))
            .collect();
        crossing.set_item("overlap", after.len() > 1)?;
        crossing.set_item("regions_after", after)?;
        crossings.append(crossing)?;
    }
    let result = PyDict::new(py);
    result.set_item("start", start)?;
    result.set_item("crossings", crossings)?;
    Ok(result)
}

/// `universe=`: None looks for one, False none, a string names it.
fn universe_choice(universe: Option<&Bound<'_, PyAny>>) -> PyResult<UniverseChoice> {
    let Some(value) = universe else {
        return Ok(UniverseChoice::Auto);
    };
    if let Ok(name) = value.extract::<String>() {
        return Ok(UniverseChoice::Named(name));
    }
    match value.extract::<bool>() {
        Ok(true) => Ok(UniverseChoice::Auto),
        Ok(false) => Ok(UniverseChoice::None),
        Err(_) => Err(bad_input(
            "universe: None or True looks for one, False uses none, a name names it",
        )),
    }
}

/// The check's options from `Model.check`'s keyword arguments.
fn check_options(
    model: &Model,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<(sv_check::CheckOptions, UniverseChoice)> {
    let mut opts = sv_check::CheckOptions::default();
    let mut universe = UniverseChoice::Auto;
    let mut strict_air = model.strict_air();
    for (key, value) in options.into_iter().flatten() {
        let key: String = key.extract()?;
        if value.is_none() && key != "universe" {
            continue;
        }
        match key.as_str() {
            "spacing" => {
                let spacing: f64 = value.extract()?;
                if !(spacing > 0.0 && spacing.is_finite()) {
                    return Err(bad_input(format!(
                        "spacing must be positive, found {spacing}"
                    )));
                }
                opts.spacing = Some(spacing);
            }
            "random" => opts.random = value.extract()?,
            "refine" => opts.refine = value.extract()?,
            "refine_to" => opts.refine_to = Some(value.extract()?),
            "seed" => opts.seed = value.extract()?,
            "tolerance" => opts.tolerance = Some(value.extract()?),
            "strict_air" => strict_air |= value.extract::<bool>()?,
            "box_" | "box" => {
                let (lo, hi): ((f64, f64, f64), (f64, f64, f64)) = value.extract()?;
                opts.bounds = Some(sv_math::Aabb::new(lo.into(), hi.into()));
            }
            "universe" => universe = universe_choice(Some(&value))?,
            other => {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "check: unexpected option `{other}`; use spacing, random, refine, \
                     refine_to, box_, seed, strict_air, tolerance or universe"
                )))
            }
        }
    }
    opts.strict_air = strict_air;
    Ok((opts, universe))
}

/// `Model.check`: the report as the CLI's JSON, read back as a dict.
pub fn check<'py>(
    py: Python<'py>,
    model: &Model,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let (opts, choice) = check_options(model, options)?;
    let json = without_gil(py, || {
        let check_model = check_model(model, choice)?;
        let report = sv_check::check(&check_model, &opts).map_err(bad_input)?;
        Ok(report.to_json())
    })?;
    py.import("json")?.call_method1("loads", (json,))
}

/// `Model.check_chunks`.
pub fn check_chunks(
    py: Python<'_>,
    model: &Model,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<u64> {
    let (opts, choice) = check_options(model, options)?;
    without_gil(py, || {
        sv_check::check_chunks(&check_model(model, choice)?, &opts).map_err(bad_input)
    })
}

/// `Model.check_part`: the share as JSON text.
pub fn check_part(
    py: Python<'_>,
    model: &Model,
    chunks: (u64, u64),
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<String> {
    let (opts, choice) = check_options(model, options)?;
    without_gil(py, || {
        let check_model = check_model(model, choice)?;
        let part =
            sv_check::check_part(&check_model, &opts, chunks.0..chunks.1).map_err(bad_input)?;
        serde_json::to_string(&part).map_err(runtime)
    })
}

/// `Model.check_merge`: the report of the parts, as a dict.
pub fn check_merge<'py>(
    py: Python<'py>,
    model: &Model,
    parts: Vec<String>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let (opts, choice) = check_options(model, options)?;
    let json = without_gil(py, || {
        let parts = parts
            .iter()
            .map(|text| serde_json::from_str::<sv_check::CheckPart>(text))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| bad_input(format!("not a part of a check: {e}")))?;
        let check_model = check_model(model, choice)?;
        let report = sv_check::check_merge(&check_model, &opts, &parts).map_err(bad_input)?;
        Ok(report.to_json())
    })?;
    py.import("json")?.call_method1("loads", (json,))
}

/// `Model.volume`: the report as the CLI's JSON, read back as a dict.
pub fn volume<'py>(
    py: Python<'py>,
    model: &Model,
    rel_error: f64,
    max_rays: u64,
    seed: u64,
) -> PyResult<Bound<'py, PyAny>> {
    if !(rel_error > 0.0 && rel_error < 1.0) {
        return Err(bad_input(format!(
            "rel_error must lie between 0 and 1, found {rel_error}"
        )));
    }
    let opts = sv_check::VolumeOptions {
        rel_error,
        max_rays,
        seed,
        ..Default::default()
    };
    let json = without_gil(py, || {
        let check_model = check_model(model, UniverseChoice::None)?;
        let report = sv_check::volumes(&check_model, &opts).map_err(bad_input)?;
        Ok(report.to_json())
    })?;
    py.import("json")?.call_method1("loads", (json,))
}
