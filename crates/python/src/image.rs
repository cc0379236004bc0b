//! `Image`: a rendered picture and its auxiliary images as numpy arrays,
//! handed over without copying the renderer's buffers.

use crate::errors::{bad_input, runtime};
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::path::PathBuf;
use sv_output::{to_rgb8, write_image, Encoding, ImageFormat, Pixels, WriteOptions};
use sv_render::Frame;

/// A rendered picture. `rgb` (float32, H×W×3, linear), `alpha` (H×W, the
/// share of each pixel covered), `region` (int32 H×W, the region index
/// at the pixel's centre, −1 for background), `depth` (float32, inf for
/// background) and `normal` (float32 H×W×3); the last three are None
/// when rendered with `aovs=False`. Shown inline in Jupyter.
#[pyclass(frozen, module = "synthavision")]
pub struct Image {
    /// Linear colour.
    #[pyo3(get)]
    rgb: Py<PyArray3<f32>>,
    /// Coverage.
    #[pyo3(get)]
    alpha: Py<PyArray2<f32>>,
    /// Region index, −1 for background.
    #[pyo3(get)]
    region: Option<Py<PyArray2<i32>>>,
    /// Distance from the eye.
    #[pyo3(get)]
    depth: Option<Py<PyArray2<f32>>>,
    /// World-space unit normal.
    #[pyo3(get)]
    normal: Option<Py<PyArray3<f32>>>,
    /// Width in pixels.
    #[pyo3(get)]
    width: u32,
    /// Height in pixels.
    #[pyo3(get)]
    height: u32,
}

impl Image {
    /// The arrays of a frame; the buffers move into numpy (the region ids
    /// are rewritten in place). A frame without auxiliary images has
    /// None for them.
    pub fn from_frame(py: Python<'_>, frame: Frame) -> PyResult<Image> {
        let (width, height) = (frame.width, frame.height);
        let (rows, columns) = (height as usize, width as usize);
        let plane = [rows, columns];
        let colour = [rows, columns, 3];
        let (region, depth, normal) = if frame.region.is_empty() {
            (None, None, None)
        } else {
            let region: Vec<i32> = frame.region.into_iter().map(|id| id as i32 - 1).collect();
            let normal = frame.normal.into_flattened();
            (
                Some(PyArray1::from_vec(py, region).reshape(plane)?.unbind()),
                Some(PyArray1::from_vec(py, frame.depth).reshape(plane)?.unbind()),
                Some(PyArray1::from_vec(py, normal).reshape(colour)?.unbind()),
            )
        };
        Ok(Image {
            rgb: PyArray1::from_vec(py, frame.rgb.into_flattened())
                .reshape(colour)?
                .unbind(),
            alpha: PyArray1::from_vec(py, frame.alpha).reshape(plane)?.unbind(),
            region,
            depth,
            normal,
            width,
            height,
        })
    }

    /// The linear colours as the writers take them.
    fn pixels(&self, py: Python<'_>) -> PyResult<(Vec<[f32; 3]>, Vec<f32>)> {
        let rgb = self.rgb.bind(py).readonly();
        let alpha = self.alpha.bind(py).readonly();
        let rgb = rgb
            .as_slice()
            .map_err(bad_input)?
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        Ok((rgb, alpha.as_slice().map_err(bad_input)?.to_vec()))
    }
}

/// 8-bit PNG bytes of linear colours, for Jupyter.
pub fn png_bytes<'py>(
    py: Python<'py>,
    width: u32,
    height: u32,
    rgb: &[[f32; 3]],
) -> PyResult<Bound<'py, PyBytes>> {
    let picture = to_rgb8(width, height, rgb, Encoding::Linear);
    let mut bytes = Vec::new();
    picture
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .map_err(runtime)?;
    Ok(PyBytes::new(py, &bytes))
}

#[pymethods]
impl Image {
    /// Write the picture as the command-line tool does (.png, .pgm/.ppm,
    /// .pfm; linear values unless `srgb`, 8 bits unless `sixteen_bit`,
    /// an alpha channel with `alpha`).
    #[pyo3(signature = (path, srgb=false, sixteen_bit=false, alpha=false))]
    fn save(
        &self,
        py: Python<'_>,
        path: PathBuf,
        srgb: bool,
        sixteen_bit: bool,
        alpha: bool,
    ) -> PyResult<()> {
        let format = ImageFormat::from_path(&path).ok_or_else(|| {
            bad_input(format!(
                "cannot tell the picture format of `{}`: use .png, .pgm, .ppm or .pfm",
                path.display()
            ))
        })?;
        let (rgb, coverage) = self.pixels(py)?;
        let opts = WriteOptions {
            sixteen_bit,
            alpha,
            encoding: if srgb {
                Encoding::Srgb
            } else {
                Encoding::Linear
            },
            ..Default::default()
        };
        let pixels = Pixels {
            width: self.width,
            height: self.height,
            rgb: &rgb,
            alpha: Some(&coverage),
        };
        write_image(&path, format, &pixels, &opts).map_err(runtime)
    }

    /// The picture as PNG bytes (8-bit, linear values as the CLI writes).
    fn png<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let (rgb, _) = self.pixels(py)?;
        png_bytes(py, self.width, self.height, &rgb)
    }

    /// Jupyter's inline picture.
    fn _repr_png_<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        self.png(py)
    }

    fn __repr__(&self) -> String {
        format!("<synthavision.Image {}x{}>", self.width, self.height)
    }
}
