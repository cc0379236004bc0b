//! `Film`: a director's script, its frames as `Image`s, and the film made
//! on disk as the CLI's `film` makes it (same frames, same hashes, so
//! either can resume what the other began).

use crate::errors::{bad_input, load_error, runtime, without_gil};
use crate::image::Image;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::ops::Range;
use std::path::{Path, PathBuf};
use sv_formats::script::{load_script, load_source};
use sv_formats::{LoadOptions, SourceFile};
use sv_output::film::{
    frames_hash, make_film, render_frames, FilmOptions, FilmReport, FrameResult, Mp4Status,
};
use sv_output::{to_rgb8, Encoding};
use sv_render::{Renderer, Settings};

/// A director's script (.svs) read, its scenes loaded and its timeline
/// built: `len(film)` frames, `film[i]` or `film.frame(i)` an `Image`.
#[pyclass(frozen, module = "synthavision")]
pub struct Film {
    film: sv_formats::script::Film,
}

/// Frame numbers from `frames`: None (all), a `range` of step 1, or
/// `(start, stop)`.
fn frame_range(frames: Option<&Bound<'_, PyAny>>, total: usize) -> PyResult<Range<usize>> {
    let Some(frames) = frames else {
        return Ok(0..total);
    };
    let (start, stop): (usize, usize) = match frames.extract() {
        Ok(pair) => pair,
        Err(_) => {
            if frames.getattr("step")?.extract::<isize>()? != 1 {
                return Err(bad_input("frames: a range with step 1"));
            }
            (
                frames.getattr("start")?.extract()?,
                frames.getattr("stop")?.extract()?,
            )
        }
    };
    if start >= stop || start >= total {
        return Err(bad_input(format!(
            "frames: {start}..{stop} holds no frame of this film of {total} frames"
        )));
    }
    Ok(start..stop.min(total))
}

impl Film {
    /// The raster size: asked for, the script's SIZE, the scene's, or
    /// 960×720 as the CLI.
    fn size(&self, size: Option<(u32, u32)>) -> PyResult<(u32, u32)> {
        let (width, height) = size
            .or(self.film.timeline.size())
            .or(self.film.scene.size)
            .unwrap_or((960, 720));
        if width == 0 || height == 0 || width > 65536 || height > 65536 {
            return Err(bad_input(format!(
                "size {width}x{height} is out of range (1 to 65536 each way)"
            )));
        }
        Ok((width, height))
    }

    /// The frame number of a Python index (negative from the end).
    fn frame_number(&self, index: isize) -> PyResult<usize> {
        let total = self.film.timeline.frame_count();
        let number = if index < 0 {
            total as isize + index
        } else {
            index
        };
        if number < 0 || number as usize >= total {
            return Err(pyo3::exceptions::PyIndexError::new_err(format!(
                "frame {index} of a film of {total} frames"
            )));
        }
        Ok(number as usize)
    }
}

#[pymethods]
impl Film {
    /// Read a script from a path, or from text (anything with a line
    /// break; its SCENE files are then found from `base_dir`).
    #[new]
    #[pyo3(signature = (script, base_dir=None))]
    fn new(py: Python<'_>, script: PathBuf, base_dir: Option<PathBuf>) -> PyResult<Film> {
        let text = script.to_string_lossy().into_owned();
        let loaded = without_gil(py, || {
            let opts = LoadOptions::default();
            Ok(if text.contains('\n') {
                let source = SourceFile::new("<script>", text.as_str());
                load_source(&source, &base_dir.unwrap_or_default(), &opts)
            } else {
                load_script(Path::new(&text), &opts)
            })
        })?;
        let film = loaded.map_err(|e| load_error(py, e, "no frame was rendered"))?;
        Ok(Film { film })
    }

    fn __len__(&self) -> usize {
        self.film.timeline.frame_count()
    }

    fn __getitem__(&self, py: Python<'_>, index: isize) -> PyResult<Image> {
        self.frame(py, index, None, true)
    }

    /// Frames per second.
    #[getter]
    fn fps(&self) -> f64 {
        self.film.timeline.fps()
    }

    /// The frame size the script asks for (or the default).
    #[getter]
    fn frame_size(&self) -> PyResult<(u32, u32)> {
        self.size(None)
    }

    /// Warnings met while reading the scenes.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.film
            .warnings
            .iter()
            .map(|w| w.message.clone())
            .collect()
    }

    /// Frame `index` rendered as the CLI's `film` renders it.
    #[pyo3(signature = (index, size=None, shadows=true))]
    fn frame(
        &self,
        py: Python<'_>,
        index: isize,
        size: Option<(u32, u32)>,
        shadows: bool,
    ) -> PyResult<Image> {
        let number = self.frame_number(index)?;
        let (width, height) = self.size(size)?;
        let settings = Settings {
            width,
            height,
            shadows,
            samples: 1,
            aovs: true,
        };
        let frame = without_gil(py, || {
            let scene = self.film.scene_at(number);
            let (renderer, _) =
                Renderer::new(&scene, width as f64 / height as f64).map_err(bad_input)?;
            Ok(renderer.render(&settings, &|_| {}))
        })?;
        Image::from_frame(py, frame)
    }

    /// Render frames into `out_dir` as the CLI's `film`: frames already
    /// there with the same hash are kept; the GIF, MP4 and contact sheet
    /// are made once every frame is done (unless `assemble` is False, as
    /// for a share of the frames on a cluster). Returns what was done.
    #[pyo3(signature = (out_dir, frames=None, size=None, shadows=true, srgb=false, gif=true,
                        mp4=true, assemble=true))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        out_dir: PathBuf,
        frames: Option<&Bound<'py, PyAny>>,
        size: Option<(u32, u32)>,
        shadows: bool,
        srgb: bool,
        gif: bool,
        mp4: bool,
        assemble: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let film = &self.film;
        let total = film.timeline.frame_count();
        let range = frame_range(frames, total)?;
        let (width, height) = self.size(size)?;
        let hash = frames_hash(&film.fingerprint(), width, height, shadows, srgb);
        let mut opts = FilmOptions::new(&out_dir, hash);
        opts.frames = range;
        opts.fps = film.timeline.fps();
        opts.gif = gif;
        opts.mp4 = mp4;
        let settings = Settings {
            width,
            height,
            shadows,
            samples: 1,
            aovs: false,
        };
        let encoding = if srgb {
            Encoding::Srgb
        } else {
            Encoding::Linear
        };
        let render_frame = |number: usize| -> FrameResult {
            let scene = film.scene_at(number);
            let (renderer, _) = Renderer::new(&scene, width as f64 / height as f64)?;
            let frame = renderer.render(&settings, &|_| {});
            Ok(to_rgb8(width, height, &frame.rgb, encoding))
        };
        let report = without_gil(py, || {
            if assemble {
                make_film(total, &opts, render_frame, |_, _| {}).map_err(runtime)
            } else {
                let (rendered, reused) =
                    render_frames(total, &opts, render_frame, |_, _| {}).map_err(runtime)?;
                Ok(FilmReport {
                    rendered,
                    reused,
                    missing: Vec::new(),
                    gif: None,
                    mp4: Mp4Status::NotMade,
                    contact_sheet: None,
                })
            }
        })?;
        let result = PyDict::new(py);
        result.set_item("rendered", report.rendered)?;
        result.set_item("reused", report.reused)?;
        result.set_item("missing", report.missing)?;
        result.set_item("gif", report.gif)?;
        result.set_item("contact_sheet", report.contact_sheet)?;
        result.set_item("mp4", report.mp4.to_string())?;
        Ok(result)
    }

    fn __repr__(&self) -> String {
        format!(
            "<synthavision.Film {} frames at {} fps>",
            self.film.timeline.frame_count(),
            self.film.timeline.fps()
        )
    }
}
