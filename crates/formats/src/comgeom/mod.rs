//! COMGEOM / GIFT fixed-column decks.
use crate::{Diagnostic, Diagnostics, LoadOptions, Loaded, SourceFile};

/// Read a COMGEOM deck.
pub fn read(src: &SourceFile, _opts: &LoadOptions) -> Result<Loaded, Diagnostics> {
    Err(Diagnostic::error(src, 0, 0, "COMGEOM reader not written yet").into())
}
