//! Integration tests of the `synthavision` binary and of the real decks
//! rendered through the library, in one test binary.

mod check;
mod cli;
mod deck_determinism;
mod export;
mod film;
mod fluka_cases;
mod fluka_render;
mod options;
mod rt;
mod trust;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The built binary, ready for arguments.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_synthavision"))
}

/// Run a command to the end.
pub fn run(command: &mut Command) -> Output {
    command.output().expect("run synthavision")
}

/// Run the binary with `args`.
pub fn sv(args: &[&str]) -> Output {
    run(bin().args(args))
}

/// The bundled examples.
pub fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// An empty folder of the test target's temporary space, `name` for one
/// test alone.
pub fn fresh_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Write `text` to the file `name` in `dir`.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}
