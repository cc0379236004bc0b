//! `synthavision bodies`: the body types, their parameters and meaning.

use crate::error::CliError;
use std::process::ExitCode;
use sv_geom::BODY_TYPES;

/// Run `bodies`.
pub fn bodies() -> Result<ExitCode, CliError> {
    for body_type in BODY_TYPES {
        let params: Vec<&str> = body_type.params.iter().map(|p| p.name).collect();
        let alias = if body_type.aliases.is_empty() {
            String::new()
        } else {
            format!(" (also {})", body_type.aliases.join(", "))
        };
        outln!(
            "{:<5} {:<8} {}{alias}",
            body_type.name,
            body_type.family,
            body_type.doc
        );
        if !params.is_empty() {
            outln!("      values: {}", params.join(" "));
        }
    }
    Ok(ExitCode::SUCCESS)
}
