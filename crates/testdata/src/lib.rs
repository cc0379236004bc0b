//! Where the tests find the real inputs kept beside the repository, in
//! `../shared/decks` (COMGEOM decks, FLUKA inputs, MCNP and OpenMC models).
//!
//! A test that reads them must not pass without them: when a folder is
//! missing, [`shared_decks`] panics with a message naming it, so the test
//! fails. Only an explicit `SV_SKIP_SHARED=1` in the environment turns that
//! into a skip (the test is then told `None` and says so on stderr); CI
//! never sets it.
#![warn(missing_docs)]

use std::path::{Path, PathBuf};

/// The environment variable that, set to `1`, lets tests skip what needs
/// the shared decks.
pub const SKIP_VAR: &str = "SV_SKIP_SHARED";

/// The folder holding the shared decks: `../shared/decks` beside the
/// repository (this crate lives in `crates/testdata`).
pub fn decks_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/decks")
}

/// The folder `sub` of the shared decks (`"comgeom"`,
/// `"fluka/pyg4ometry-testdata"`, …), or `None` when it is missing and
/// `SV_SKIP_SHARED=1` is set.
///
/// # Panics
/// When the folder is missing and the skip is not asked for, naming the
/// folder: a test that needs the decks must fail without them.
pub fn shared_decks(sub: &str) -> Option<PathBuf> {
    let dir = decks_root().join(sub);
    if dir.is_dir() {
        return Some(dir);
    }
    if std::env::var(SKIP_VAR).as_deref() == Ok("1") {
        eprintln!(
            "skipped: {} is missing and {SKIP_VAR}=1 is set",
            dir.display()
        );
        return None;
    }
    panic!(
        "the shared test decks are missing: {} does not exist. The tests read \
         real inputs from ../shared/decks beside the repository; put them there, \
         or set {SKIP_VAR}=1 to skip these tests knowingly",
        dir.display()
    );
}

/// The files directly in the shared folder `sub` whose names end with one
/// of `endings` (any case), sorted; `None` as for [`shared_decks`].
///
/// # Panics
/// As [`shared_decks`], and when the folder holds no such file.
pub fn shared_files(sub: &str, endings: &[&str]) -> Option<Vec<PathBuf>> {
    let dir = shared_decks(sub)?;
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let name = p
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or("")
                .to_ascii_lowercase();
            p.is_file() && endings.iter().any(|e| name.ends_with(e))
        })
        .collect();
    files.sort();
    assert!(
        !files.is_empty(),
        "{} holds no file ending in {endings:?}",
        dir.display()
    );
    Some(files)
}
