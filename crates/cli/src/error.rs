//! What a command reports when it fails, and the exit code that goes with
//! it.

use std::process::ExitCode;
use sv_formats::{Diagnostics, LoadError, Style};

/// A command's failure.
pub enum CliError {
    /// Bad input: diagnostics already formatted. Exit 2.
    Input(String),
    /// Could not write output or another run-time failure. Exit 3.
    Runtime(String),
}

impl CliError {
    /// Print the message on stderr.
    pub fn print(&self) {
        match self {
            CliError::Input(text) | CliError::Runtime(text) => errln!("{}", text.trim_end()),
        }
    }

    /// The exit code of the failure.
    pub fn exit_code(&self) -> ExitCode {
        match self {
            CliError::Input(_) => ExitCode::from(2),
            CliError::Runtime(_) => ExitCode::from(3),
        }
    }
}

/// Bad input (exit 2), said in one line.
pub fn bad_input(message: impl Into<String>) -> CliError {
    CliError::Input(format!("error: {}", message.into()))
}

/// A run-time failure (exit 3): output that could not be written, threads
/// that could not start.
pub fn runtime(error: impl std::fmt::Display) -> CliError {
    CliError::Runtime(format!("error: {error}"))
}

/// A scene, deck or script that could not be read: its diagnostics, and
/// `consequence` (what was not done) after the count of errors.
pub fn load_failure(error: LoadError, consequence: &str) -> CliError {
    match error {
        LoadError::Invalid(diagnostics) => {
            CliError::Input(diagnostics_text(&diagnostics, consequence))
        }
        io @ LoadError::Io { .. } => bad_input(io.to_string()),
    }
}

/// Diagnostics as every command prints them: each one located (file, line,
/// column, the line, a caret, a hint), then, when any is an error, how
/// many, and `consequence` ("nothing was written").
pub fn diagnostics_text(diagnostics: &Diagnostics, consequence: &str) -> String {
    let style = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        Style::Colour
    } else {
        Style::Graphical
    };
    diagnostics.report(style, Some(consequence))
}

#[cfg(test)]
mod tests {
    use super::*;
    use sv_formats::{load_source, Format, LoadOptions, SourceFile};

    /// The diagnostics of a scene with `bad` unknown body types.
    fn errors(bad: usize) -> Diagnostics {
        let mut text = String::from("BODY a SPH (0,0,0) 1\nREGION r = +a\n");
        for line in 0..bad {
            text.push_str(&format!("BODY b{line} SHP (0,0,0) 1\n"));
        }
        let source = SourceFile::new("a.sv", text);
        match load_source(&source, Format::Native, &LoadOptions::default()) {
            Err(LoadError::Invalid(diagnostics)) => diagnostics,
            Err(other) => panic!("{other}"),
            Ok(_) => Diagnostics { items: Vec::new() },
        }
    }

    #[test]
    fn the_count_of_errors_agrees_with_its_number() {
        let one = diagnostics_text(&errors(1), "nothing was written");
        assert!(one.contains("a.sv:3:9"), "{one}");
        assert!(
            one.ends_with("\n1 error found; nothing was written\n"),
            "{one}"
        );
        let two = diagnostics_text(&errors(2), "no frame was rendered");
        assert!(two.contains("a.sv:4:9"), "{two}");
        assert!(
            two.ends_with("\n2 errors found; no frame was rendered\n"),
            "{two}"
        );
        assert_eq!(diagnostics_text(&errors(0), "nothing was written"), "");
    }
}
