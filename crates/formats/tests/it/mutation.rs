//! What the readers' tests share: random edits of real inputs for the
//! property tests, and the errors of a failed read by place.

use proptest::prelude::*;
use sv_formats::Diagnostics;

/// One edit of an input's text.
#[derive(Clone, Debug)]
pub enum Edit {
    /// Insert text at a character position (taken modulo the length).
    Insert(usize, String),
    /// Delete characters from a position.
    Delete(usize, usize),
    /// Duplicate a line.
    DuplicateLine(usize),
    /// Swap two lines.
    SwapLines(usize, usize),
}

/// Edits that insert one of `snippet`'s texts, delete, duplicate or swap.
pub fn edit(snippet: impl Strategy<Value = String>) -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), snippet).prop_map(|(p, s)| Edit::Insert(p, s)),
        (any::<usize>(), 0usize..40).prop_map(|(p, n)| Edit::Delete(p, n)),
        any::<usize>().prop_map(Edit::DuplicateLine),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Edit::SwapLines(a, b)),
    ]
}

/// `text` with `edits` applied in turn.
pub fn apply(text: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for e in edits {
        match e {
            Edit::Insert(p, s) => {
                let at = p % (chars.len() + 1);
                chars.splice(at..at, s.chars());
            }
            Edit::Delete(p, n) => {
                let at = p % (chars.len() + 1);
                let end = (at + n).min(chars.len());
                chars.drain(at..end);
            }
            Edit::DuplicateLine(i) | Edit::SwapLines(i, _) => {
                let s: String = chars.iter().collect();
                let mut lines: Vec<&str> = s.split('\n').collect();
                let a = i % lines.len();
                if let Edit::SwapLines(_, j) = e {
                    let b = j % lines.len();
                    lines.swap(a, b);
                } else {
                    lines.insert(a, lines[a]);
                }
                chars = lines.join("\n").chars().collect();
            }
        }
    }
    chars.into_iter().collect()
}

/// (line, column, message) of every error.
pub fn located(d: &Diagnostics) -> Vec<(usize, usize, String)> {
    d.errors()
        .map(|e| {
            let (l, c) = e.line_col();
            (l, c, e.message.clone())
        })
        .collect()
}
