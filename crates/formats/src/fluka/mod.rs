//! FLUKA free-format geometry.
use crate::{Diagnostics, LoadOptions, Loaded, SourceFile, Diagnostic};

/// Read the geometry of a FLUKA input.
pub fn read(src: &SourceFile, _opts: &LoadOptions) -> Result<Loaded, Diagnostics> {
    Err(Diagnostic::error(src, 0, 0, "FLUKA reader not written yet").into())
}
