//! FLUKA free-format geometry.
use crate::{Diagnostic, Diagnostics, LoadOptions, Loaded, SourceFile};

/// Read the geometry of a FLUKA input.
pub fn read(src: &SourceFile, _opts: &LoadOptions) -> Result<Loaded, Diagnostics> {
    Err(Diagnostic::error(src, 0, 0, "FLUKA reader not written yet").into())
}
