//! `load` and `Model`: a scene, deck or transport input read by the
//! formats crate, its regions, and the pictures and numbers made of it.

use crate::analysis;
use crate::errors::{bad_input, geometry_error, load_error, without_gil};
use crate::image::Image;
use crate::view::{Camera, Light};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::path::{Path, PathBuf};
use sv_formats::{Format, LoadOptions, Loaded, SourceFile};
use sv_render::{default_camera, default_lights, Renderer, Settings, UpAxis, ViewSpec};
use sv_scene::Scene;

/// A box as its lower and upper corners.
pub type Corners = ((f64, f64, f64), (f64, f64, f64));

/// One region: its name, description, material and bounds.
#[pyclass(frozen, module = "synthavision", get_all)]
pub struct Region {
    /// Index in `Model.regions` (the numbers of `Image.region`).
    pub index: usize,
    /// Name or number as the input gives it.
    pub name: String,
    /// Free-text description (a deck's comment column).
    pub description: String,
    /// The material's name (`m12`, `WATER`), or a COMGEOM material code;
    /// `None` without one.
    pub material: Option<String>,
    /// Index into `Model.materials`, or `None`.
    pub material_index: Option<usize>,
    /// Air code (non-zero marks air).
    pub air: i64,
    /// Beyond the model (a black hole, an importance-zero cell).
    pub outside: bool,
    /// `(lower_left, upper_right)` of the region, clipped to the model's
    /// box; `None` when empty.
    pub bounds: Option<Corners>,
}

#[pymethods]
impl Region {
    fn __repr__(&self) -> String {
        format!(
            "Region({}, name={:?}, material={:?})",
            self.index, self.name, self.material
        )
    }
}

/// What `load` was given, to load the same model again in another process
/// (pickling for Dask workers).
#[derive(Clone)]
struct Origin {
    path_or_text: String,
    format: Option<String>,
    deck_version: Option<String>,
}

/// A model read from a scene, COMGEOM deck, FLUKA, MCNP or OpenMC input.
#[pyclass(frozen, module = "synthavision")]
pub struct Model {
    /// The scene as read (air shown when nothing else would be).
    pub scene: Scene,
    /// Its format.
    pub format: Format,
    origin: Origin,
    regions: Vec<Py<Region>>,
    materials: Vec<String>,
    bounds: Option<Corners>,
    warnings: Vec<String>,
}

/// The format named by `name`.
fn format_named(name: &str) -> PyResult<Format> {
    Ok(match name.to_ascii_lowercase().as_str() {
        "sv" | "native" | "scene" => Format::Native,
        "comgeom" | "cg" | "gift" => Format::Comgeom,
        "fluka" => Format::Fluka,
        "mcnp" => Format::Mcnp,
        "openmc" => Format::OpenMc,
        other => {
            return Err(bad_input(format!(
                "unknown format `{other}`; use sv, comgeom, fluka, mcnp or openmc"
            )))
        }
    })
}

/// `deck_version=`: v1, v4 or v5.
fn deck_version(text: Option<&str>) -> PyResult<Option<sv_formats::DeckVersion>> {
    let Some(text) = text else {
        return Ok(None);
    };
    sv_formats::DeckVersion::named(text)
        .map(Some)
        .ok_or_else(|| bad_input(format!("unknown deck version `{text}`; use v1, v4 or v5")))
}

/// Read `path_or_text`: text when it holds a line break, else a path.
fn read(origin: &Origin) -> Result<Loaded, sv_formats::LoadError> {
    let opts = LoadOptions {
        deck_version: deck_version(origin.deck_version.as_deref()).unwrap_or(None),
    };
    let format = origin.format.as_deref().map(|name| format_named(name).ok());
    let text_given = origin.path_or_text.contains('\n');
    let path = Path::new(&origin.path_or_text);
    match (text_given, format.flatten()) {
        (false, None) => sv_formats::load_file(path, &opts),
        (false, Some(format)) if !path.is_dir() => {
            let text = std::fs::read(path).map_err(|source| sv_formats::LoadError::Io {
                path: path.to_owned(),
                source,
            })?;
            let source =
                SourceFile::new(path.display().to_string(), String::from_utf8_lossy(&text));
            sv_formats::load_source(&source, format, &opts)
        }
        (false, Some(_)) => sv_formats::load_file(path, &opts),
        (true, format) => {
            let source = SourceFile::new("<text>", origin.path_or_text.as_str());
            let format = format.unwrap_or_else(|| Format::detect(Path::new(""), &source.text));
            sv_formats::load_source(&source, format, &opts)
        }
    }
}

/// The material label of every region and the list of distinct labels.
fn materials(scene: &Scene) -> (Vec<Option<String>>, Vec<String>) {
    let mut names: Vec<String> = Vec::new();
    let labels = scene
        .regions
        .iter()
        .map(|props| {
            let label = props
                .material_name
                .clone()
                .or_else(|| (props.material != 0).then(|| props.material.to_string()))?;
            if !names.contains(&label) {
                names.push(label.clone());
            }
            Some(label)
        })
        .collect();
    (labels, names)
}

/// A box as two corners, `None` when empty or infinite.
fn corners(bounds: sv_math::Aabb) -> Option<Corners> {
    (!bounds.is_empty() && bounds.is_finite()).then(|| (bounds.min.into(), bounds.max.into()))
}

impl Model {
    fn new(py: Python<'_>, origin: Origin, loaded: Loaded) -> PyResult<Model> {
        let Loaded {
            mut scene,
            warnings,
            format,
        } = loaded;
        scene.show_air_if_nothing_else();
        let file = if origin.path_or_text.contains('\n') {
            "<text>"
        } else {
            origin.path_or_text.as_str()
        };
        let (check_model, _) = sv_check::Model::new(&scene, &sv_check::UniverseChoice::None)
            .map_err(|e| geometry_error(py, file, e))?;
        let (labels, material_names) = materials(&scene);
        let mut regions = Vec::new();
        for (index, (region, props)) in scene
            .geometry
            .regions
            .iter()
            .zip(&scene.regions)
            .enumerate()
        {
            let material = labels[index].clone();
            let material_index = material
                .as_ref()
                .and_then(|m| material_names.iter().position(|n| n == m));
            let region = Region {
                index,
                name: region.name.clone(),
                description: props.description.clone(),
                material,
                material_index,
                air: props.air,
                outside: props.outside,
                bounds: corners(check_model.region_bounds(index)),
            };
            regions.push(Py::new(py, region)?);
        }
        let mut notes: Vec<String> = warnings.iter().map(|w| w.message.clone()).collect();
        notes.extend(scene.notes.iter().cloned());
        Ok(Model {
            bounds: corners(check_model.bounds()),
            scene,
            format,
            origin,
            regions,
            materials: material_names,
            warnings: notes,
        })
    }

    /// Whether every overlap counts (FLUKA, MCNP and OpenMC have no rule
    /// that air gives way), as the CLI decides.
    pub fn strict_air(&self) -> bool {
        matches!(self.format, Format::Fluka | Format::Mcnp | Format::OpenMc)
    }

    /// The region labels of `Model.materials` per region.
    pub fn material_indices(&self, py: Python<'_>) -> Vec<Option<usize>> {
        self.regions
            .iter()
            .map(|r| r.bind(py).get().material_index)
            .collect()
    }

    /// The scene with `transparent` regions made so and coloured as
    /// `color_by` asks.
    fn scene_for(&self, transparent: &[String], color_by: Option<&str>) -> PyResult<Scene> {
        let mut scene = self.scene.clone();
        for name in transparent {
            let index = analysis::region_named(&scene, name)?;
            scene.regions[index].transparent = true;
        }
        let (labels, _) = materials(&scene);
        for (index, props) in scene.regions.iter_mut().enumerate() {
            let key = match color_by {
                None => continue,
                Some("region") => Some(scene.geometry.regions[index].name.as_str()),
                Some("material") => labels[index].as_deref(),
                Some(other) => {
                    return Err(bad_input(format!(
                        "color_by: expected \"region\" or \"material\", found \"{other}\""
                    )))
                }
            };
            if let Some(key) = key {
                props.colour = Some(sv_check::region_colour(key).map(f64::from));
            }
        }
        Ok(scene)
    }
}

/// Read a scene (.sv), COMGEOM deck, FLUKA, MCNP or OpenMC input (a folder
/// or XML file) from a path, or from text (anything with a line break).
/// `format` forces a reader: "sv", "comgeom", "fluka", "mcnp", "openmc".
/// Raises `ParseError` on bad input.
#[pyfunction]
#[pyo3(signature = (path_or_text, format=None, deck_version=None))]
pub fn load(
    py: Python<'_>,
    path_or_text: PathBuf,
    format: Option<String>,
    deck_version: Option<String>,
) -> PyResult<Model> {
    if let Some(name) = &format {
        format_named(name)?;
    }
    self::deck_version(deck_version.as_deref())?;
    let origin = Origin {
        path_or_text: path_or_text.to_string_lossy().into_owned(),
        format,
        deck_version,
    };
    let loaded = without_gil(py, || Ok(read(&origin)))?
        .map_err(|e| load_error(py, e, "nothing was loaded"))?;
    Model::new(py, origin, loaded)
}

#[pymethods]
impl Model {
    /// The regions, in the input's order.
    #[getter]
    fn regions(&self, py: Python<'_>) -> Vec<Py<Region>> {
        self.regions.iter().map(|r| r.clone_ref(py)).collect()
    }

    /// The materials the regions name, in order of first use.
    #[getter]
    fn materials(&self) -> Vec<String> {
        self.materials.clone()
    }

    /// `(lower_left, upper_right)` of the model, `None` when unbounded.
    #[getter]
    fn bounding_box(&self) -> Option<Corners> {
        self.bounds
    }

    /// The title of the input.
    #[getter]
    fn title(&self) -> String {
        self.scene.title.clone()
    }

    /// Length unit (`in`, `cm`, …).
    #[getter]
    fn unit(&self) -> &'static str {
        self.scene.units.abbrev()
    }

    /// The format read: sv, comgeom, fluka, mcnp or openmc.
    #[getter]
    fn format(&self) -> &'static str {
        match self.format {
            Format::Native => "sv",
            Format::Comgeom => "comgeom",
            Format::Fluka => "fluka",
            Format::Mcnp => "mcnp",
            Format::OpenMc => "openmc",
        }
    }

    /// Warnings and notes met while reading.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// Render a picture with its region, depth and normal images, on all
    /// cores with the GIL released. `camera` (default: the scene's, or a
    /// view from `az`/`el` degrees), `size=(w, h)`, `lights` (default: the
    /// scene's), `transparent` region names, `color_by` "region" or
    /// "material" (default: the scene's colours), `samples` per side;
    /// `aovs=False` leaves the region, depth and normal images out.
    #[pyo3(signature = (camera=None, size=None, lights=None, shadows=None, transparent=None,
                        color_by=None, samples=1, az=None, el=None, aovs=true))]
    #[allow(clippy::too_many_arguments)]
    fn render(
        &self,
        py: Python<'_>,
        camera: Option<Camera>,
        size: Option<(u32, u32)>,
        lights: Option<Vec<Light>>,
        shadows: Option<bool>,
        transparent: Option<Vec<String>>,
        color_by: Option<String>,
        samples: u32,
        az: Option<f64>,
        el: Option<f64>,
        aovs: bool,
    ) -> PyResult<Image> {
        let scene = self.scene_for(&transparent.unwrap_or_default(), color_by.as_deref())?;
        let (width, height) = size.or(scene.size).unwrap_or((960, 720));
        if width == 0 || height == 0 || width > 65536 || height > 65536 {
            return Err(bad_input(format!(
                "size {width}x{height} is out of range (1 to 65536 each way)"
            )));
        }
        if samples == 0 || samples > 16 {
            return Err(bad_input("samples must lie between 1 and 16"));
        }
        let view = View {
            camera: camera.map(|c| c.camera),
            lights: lights.map(|l| l.into_iter().map(|l| l.light).collect()),
            az,
            el,
        };
        let settings = Settings {
            width,
            height,
            shadows: shadows.unwrap_or(scene.shadows),
            samples,
            aovs,
        };
        let frame = without_gil(py, || {
            let renderer = view.renderer(&scene, width as f64 / height as f64)?;
            Ok(renderer.render(&settings, &|_| {}))
        })?;
        Image::from_frame(py, frame)
    }

    /// Region and material index of each pixel of a section, as OpenMC's
    /// `id_map`: an int32 array (pixels[1], pixels[0], 2); −1 where there is
    /// no region, −3 in overlaps. `basis` "xy", "xz" or "yz"; `origin` is
    /// the picture's centre, `width` its size in model units.
    #[pyo3(signature = (origin, width, pixels, basis="xy", strict_air=None))]
    fn id_map<'py>(
        &self,
        py: Python<'py>,
        origin: (f64, f64, f64),
        width: (f64, f64),
        pixels: (u32, u32),
        basis: &str,
        strict_air: Option<bool>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let centre = crate::view::vec3(origin, "origin")?;
        let opts = sv_check::SliceOptions {
            plane: analysis::basis_plane(centre, basis)?,
            extent: Some(width),
            size: Some(pixels),
            centre: Some(centre),
            tolerance: None,
            strict_air: strict_air.unwrap_or(false) || self.strict_air(),
        };
        analysis::id_map(py, self, &opts)
    }

    /// A section view with its legend, as the CLI's `slice`: `plane`
    /// "z=0" (or x=, y=), or `origin` with `normal`; `extent` (w, h),
    /// `size` (w, h), `legend` draws the legend strip.
    #[pyo3(signature = (plane=None, origin=None, normal=None, extent=None, size=None,
                        legend=true, strict_air=None, tolerance=None, universe=None))]
    #[allow(clippy::too_many_arguments)]
    fn slice(
        &self,
        py: Python<'_>,
        plane: Option<&str>,
        origin: Option<(f64, f64, f64)>,
        normal: Option<(f64, f64, f64)>,
        extent: Option<(f64, f64)>,
        size: Option<(u32, u32)>,
        legend: bool,
        strict_air: Option<bool>,
        tolerance: Option<f64>,
        universe: Option<bool>,
    ) -> PyResult<analysis::Section> {
        let plane = analysis::plane(plane, origin, normal)?;
        let opts = sv_check::SliceOptions {
            plane,
            extent,
            size,
            centre: None,
            tolerance,
            strict_air: strict_air.unwrap_or(false) || self.strict_air(),
        };
        analysis::section(py, self, opts, legend, universe.unwrap_or(true))
    }

    /// The section as a matplotlib picture with a legend (matplotlib is
    /// imported here, not before); keyword arguments go to `slice`.
    #[pyo3(signature = (ax=None, **kwargs))]
    fn plot<'py>(
        slf: &Bound<'py, Self>,
        ax: Option<Bound<'py, PyAny>>,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        py.import("synthavision._plot")?
            .getattr("plot")?
            .call((slf, ax), kwargs)
    }

    /// Every surface crossing along one ray, as the CLI's `shoot` prints
    /// them: a dict with "start" (regions holding the origin) and
    /// "crossings" (t, event, body, type, regions after).
    fn shoot<'py>(
        &self,
        py: Python<'py>,
        origin: (f64, f64, f64),
        direction: (f64, f64, f64),
    ) -> PyResult<Bound<'py, PyDict>> {
        analysis::shoot(py, &self.scene, origin, direction)
    }

    /// Overlaps and voids, as the CLI's `check --json`: a dict. Options:
    /// `spacing`, `random` (0), `refine` (halvings of the spacing between
    /// neighbouring rays that see different regions, 4; 0 for none) or
    /// `refine_to` (a length), `box_` ((x0, y0, z0), (x1, y1, z1)),
    /// `seed` (1971), `strict_air`, `tolerance`, `universe` (None looks
    /// for one, False uses none, a name names it).
    #[pyo3(signature = (**options))]
    fn check<'py>(
        &self,
        py: Python<'py>,
        options: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        analysis::check(py, self, options)
    }

    /// How many chunks of rays `check(**options)` fires (for splitting a
    /// check across processes: `check_part`, `check_merge`).
    #[pyo3(signature = (**options))]
    fn check_chunks(&self, py: Python<'_>, options: Option<&Bound<'_, PyDict>>) -> PyResult<u64> {
        analysis::check_chunks(py, self, options)
    }

    /// The findings of chunks `start..stop` of `check(**options)`, as JSON
    /// text for `check_merge`.
    #[pyo3(signature = (chunks, **options))]
    fn check_part(
        &self,
        py: Python<'_>,
        chunks: (u64, u64),
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<String> {
        analysis::check_part(py, self, chunks, options)
    }

    /// The report of `check(**options)` from parts covering every chunk:
    /// the same dict as `check` but for the time taken.
    #[pyo3(signature = (parts, **options))]
    fn check_merge<'py>(
        &self,
        py: Python<'py>,
        parts: Vec<String>,
        options: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        analysis::check_merge(py, self, parts, options)
    }

    /// Volume, centroid and mass of every region, as the CLI's `volume
    /// --json`: a dict.
    #[pyo3(signature = (rel_error=0.001, max_rays=20_000_000, seed=1971))]
    fn volume<'py>(
        &self,
        py: Python<'py>,
        rel_error: f64,
        max_rays: u64,
        seed: u64,
    ) -> PyResult<Bound<'py, PyAny>> {
        analysis::volume(py, self, rel_error, max_rays, seed)
    }

    /// Pickled as what `load` was given (a path or the text), so a Dask
    /// worker reads the model itself.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let load = py.import("synthavision")?.getattr("load")?;
        let origin = &self.origin;
        let args = (
            origin.path_or_text.clone(),
            origin.format.clone(),
            origin.deck_version.clone(),
        );
        PyTuple::new(py, [load, args.into_pyobject(py)?.into_any()])
    }

    fn __repr__(&self) -> String {
        format!(
            "<synthavision.Model {:?}: {} regions, {}>",
            self.scene.title,
            self.regions.len(),
            self.format()
        )
    }
}

/// The view options of `render`.
struct View {
    camera: Option<sv_scene::Camera>,
    lights: Option<Vec<sv_scene::Light>>,
    az: Option<f64>,
    el: Option<f64>,
}

impl View {
    /// The renderer with the view applied as the CLI applies `--eye`,
    /// `--az`/`--el`: a new camera brings the default lights when the scene
    /// has none.
    fn renderer(&self, scene: &Scene, aspect: f64) -> PyResult<Renderer> {
        let (mut renderer, _) = Renderer::new(scene, aspect).map_err(bad_input)?;
        let camera = match (self.camera, self.az.is_some() || self.el.is_some()) {
            (Some(_), true) => return Err(bad_input("give camera or az/el, not both")),
            (Some(camera), false) => Some(camera),
            (None, true) => {
                let spec = ViewSpec {
                    az: self.az.unwrap_or(35.0),
                    el: self.el.unwrap_or(25.0),
                    up: UpAxis::Z,
                    ortho: false,
                    view_size: None,
                };
                Some(default_camera(renderer.prepared(), aspect, &spec))
            }
            (None, false) => None,
        };
        if let Some(camera) = camera {
            renderer.camera = camera;
            if scene.lights.is_empty() {
                renderer.lights = default_lights(&camera);
            }
        }
        if let Some(lights) = &self.lights {
            renderer.lights = lights.clone();
        }
        Ok(renderer)
    }
}
