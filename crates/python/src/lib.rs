//! SynthaVision for Python: the `synthavision._native` extension module
//! behind the `synthavision` package (python/synthavision). Every reader,
//! renderer and check is the workspace's own; this crate only converts
//! arguments, errors and arrays.
#![warn(missing_docs)]

mod analysis;
mod errors;
mod film;
mod image;
mod model;
mod view;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = module.py();
    module.add_function(wrap_pyfunction!(model::load, module)?)?;
    module.add_class::<model::Model>()?;
    module.add_class::<model::Region>()?;
    module.add_class::<image::Image>()?;
    module.add_class::<analysis::Section>()?;
    module.add_class::<view::Camera>()?;
    module.add_class::<view::Light>()?;
    module.add_class::<film::Film>()?;
    module.add("ParseError", py.get_type::<errors::ParseError>())?;
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
