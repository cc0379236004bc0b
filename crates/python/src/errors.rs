//! Errors as Python exceptions: located diagnostics become `ParseError`,
//! bad options `ValueError`, failed writes `OSError`, and a panic inside
//! the engine a `RuntimeError` instead of unwinding into Python.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sv_formats::{Diagnostics, LoadError, Style};

pyo3::create_exception!(
    synthavision,
    ParseError,
    PyValueError,
    "Bad input: a scene, deck or script with errors. `file`, `line`, `column` \
     and `message` locate the first error; `diagnostics` lists them all; \
     str() is the report the command-line tool prints."
);

/// The exception for a file that could not be read or has errors; the
/// text is what the CLI prints followed by `consequence`.
pub fn load_error(py: Python<'_>, error: LoadError, consequence: &str) -> PyErr {
    match error {
        LoadError::Invalid(diagnostics) => parse_error(py, &diagnostics, consequence),
        io @ LoadError::Io { .. } => PyOSError::new_err(io.to_string()),
    }
}

/// `ParseError` carrying the location of the first error (the first
/// diagnostic when none is an error) and every diagnostic.
fn parse_error(py: Python<'_>, diagnostics: &Diagnostics, consequence: &str) -> PyErr {
    let text = diagnostics.report(Style::Graphical, Some(consequence));
    let error = ParseError::new_err(text.trim_end().to_string());
    let located: PyResult<()> = (|| {
        let value = error.value(py);
        let mut all = Vec::new();
        for item in &diagnostics.items {
            let (line, column) = item.source.line_col(item.offset);
            let entry = PyDict::new(py);
            entry.set_item("file", &item.source.name)?;
            entry.set_item("line", line)?;
            entry.set_item("column", column)?;
            entry.set_item("message", &item.message)?;
            entry.set_item("hint", &item.hint)?;
            all.push(entry);
        }
        let first = diagnostics.errors().next().or(diagnostics.items.first());
        if let Some(first) = first {
            let (line, column) = first.source.line_col(first.offset);
            value.setattr("file", &first.source.name)?;
            value.setattr("line", line)?;
            value.setattr("column", column)?;
            value.setattr("message", &first.message)?;
        }
        value.setattr("diagnostics", all)?;
        Ok(())
    })();
    match located {
        Ok(()) => error,
        Err(failure) => failure,
    }
}

/// `ParseError` for input that reads but breaks a geometry rule (a
/// negative radius): the CLI's message; the engine keeps no place in the
/// file for a body, so `line` and `column` are None.
pub fn geometry_error(py: Python<'_>, file: &str, message: impl std::fmt::Display) -> PyErr {
    let error = ParseError::new_err(format!("error: {message}"));
    let value = error.value(py);
    let set: PyResult<()> = (|| {
        value.setattr("file", file)?;
        value.setattr("line", py.None())?;
        value.setattr("column", py.None())?;
        value.setattr("message", message.to_string())?;
        value.setattr("diagnostics", Vec::<Py<PyAny>>::new())
    })();
    set.map(|()| error).unwrap_or_else(|failure| failure)
}

/// A bad option or argument.
pub fn bad_input(message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}

/// A picture or film that could not be written.
pub fn runtime(message: impl std::fmt::Display) -> PyErr {
    PyOSError::new_err(message.to_string())
}

/// Run `work` with the GIL released, turning a panic into a
/// `RuntimeError`.
pub fn without_gil<T, F>(py: Python<'_>, work: F) -> PyResult<T>
where
    F: FnOnce() -> PyResult<T> + Send,
    T: Send,
{
    py.detach(|| {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)).unwrap_or_else(|panic| {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".into());
            Err(PyRuntimeError::new_err(format!(
                "internal error in the SynthaVision engine: {what}"
            )))
        })
    })
}
