//! INCLUDE: another scene, a COMGEOM deck or a FLUKA input read into the
//! scene.

use super::{merge, Clash, File, MergeError, Session};
use crate::diag::{Diagnostic, SourceFile};
use crate::text::Token;
use crate::{Format, LoadError, Loaded};
use std::path::{Path, PathBuf};
use sv_scene::Units;

/// How deep INCLUDEs may nest.
const MAX_INCLUDE_DEPTH: usize = 16;

impl Session<'_> {
    /// Read the file `name` names (relative to `src`) and merge it into
    /// `file`; problems go to the session's diagnostics.
    pub(super) fn include(&mut self, src: &SourceFile, name: &Token, file: &mut File) {
        let error = |msg: String| Diagnostic::error_in(src, name.span, msg);
        let base = Path::new(&src.name).parent().unwrap_or(Path::new(""));
        let path = base.join(name.text);
        if self.includes.len() > MAX_INCLUDE_DEPTH
            || self.includes.iter().any(|p| same_file(p, &path))
        {
            self.diags.push(
                error(format!("`{}` includes itself", name.text))
                    .with_hint("remove the circular INCLUDE"),
            );
            return;
        }
        let text = match std::fs::read(&path) {
            Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
            Err(e) => {
                self.diags
                    .push(error(format!("cannot read `{}`: {e}", path.display())));
                return;
            }
        };
        let included = SourceFile::new(path.display().to_string(), text);
        let format = Format::detect(&path, &included.text);
        let loaded = if format == Format::Native {
            match self.included_scene(path, &included, file.scene.units) {
                Some(loaded) => Ok(loaded),
                None => return,
            }
        } else {
            crate::load_source(&included, format, self.opts)
        };
        match loaded {
            Ok(loaded) => {
                self.warnings.extend(loaded.warnings);
                // A scene that has not said its units takes those of the
                // first model it includes.
                if !file.units_set && file.scene.geometry.bodies.is_empty() {
                    file.scene.units = loaded.scene.units;
                    file.units_set = true;
                }
                let tag = Path::new(name.text)
                    .file_stem()
                    .map_or(name.text.to_string(), |s| s.to_string_lossy().into_owned());
                if let Err(MergeError::Region(region)) =
                    merge(&mut file.scene, loaded.scene, &tag, Clash::Rename)
                {
                    self.diags.push(error(format!(
                        "region `{region}` is defined both here and in the included file"
                    )));
                }
            }
            Err(LoadError::Invalid(ds)) => self.diags.items.extend(ds.items),
            Err(e) => self.diags.push(error(e.to_string())),
        }
    }

    /// An included scene, read on its own to be merged (and scaled into the
    /// including scene's units) like any deck; without UNITS of its own it
    /// is in `units`. `None` when it has errors (they are reported).
    fn included_scene(
        &mut self,
        path: PathBuf,
        included: &SourceFile,
        units: Units,
    ) -> Option<Loaded> {
        let errors_before = self.diags.errors().count();
        self.includes.push(path);
        let mut inner = self.read_file(included);
        self.includes.pop();
        if !inner.units_set {
            inner.scene.units = units;
        }
        if self.diags.errors().count() > errors_before {
            return None;
        }
        Some(Loaded {
            scene: inner.scene,
            warnings: Vec::new(),
            format: crate::Format::Native,
        })
    }
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}
