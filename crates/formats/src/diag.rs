//! Diagnostics with file, line, column, the offending text and a hint.
//!
//! Every reader reports problems as [`Diagnostic`]s and collects all of a
//! file's errors into one [`Diagnostics`] value, so a user sees every problem
//! of a deck at once. They implement [`miette::Diagnostic`].
//!
//! [`Diagnostics::report`] is the one way to show them: each diagnostic in a
//! [`Style`] (miette's graphical report, in colour or not, or the plain
//! `file:line:column` form of [`Diagnostic::render_plain`] that the golden
//! tests compare against), then the count of errors (`1 error found`,
//! `2 errors found`). [`count`] words every count of errors the readers
//! print.

use std::fmt;
use std::sync::Arc;

/// How serious a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    /// The input cannot be used.
    Error,
    /// The input is used, but something is off.
    Warning,
}

/// A source file held for diagnostics.
#[derive(Clone, Debug)]
pub struct SourceFile {
    /// Name as shown to the user (the path as given).
    pub name: String,
    /// Whole text.
    pub text: Arc<str>,
}

impl SourceFile {
    /// A source file. A carriage return that does not end a line (one
    /// not followed by a line feed) is read as a space: the readers count
    /// lines by line feeds, and so must the snippets of the diagnostics,
    /// which would otherwise break the line there.
    pub fn new(name: impl Into<String>, text: impl Into<Arc<str>>) -> SourceFile {
        let text: Arc<str> = text.into();
        let text = if text.contains('\r') {
            stray_returns_to_spaces(&text).into()
        } else {
            text
        };
        SourceFile {
            name: name.into(),
            text,
        }
    }

    /// Byte offset of 1-based (`line`, `column`) (columns count characters).
    pub fn offset(&self, line: usize, column: usize) -> usize {
        let mut off = 0;
        for (i, l) in self.text.split_inclusive('\n').enumerate() {
            if i + 1 == line {
                let col_off: usize = l
                    .chars()
                    .take(column.saturating_sub(1))
                    .map(char::len_utf8)
                    .sum();
                return off + col_off;
            }
            off += l.len();
        }
        self.text.len()
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let before = &self.text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        (line, self.text[line_start..offset].chars().count() + 1)
    }
}

/// `text` with each carriage return not followed by a line feed made a
/// space (the same length in bytes, so offsets keep their meaning).
fn stray_returns_to_spaces(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '\r' && chars.peek() != Some(&'\n') {
            out.push(' ');
        } else {
            out.push(c);
        }
    }
    out
}

/// A place on one line of a file: 1-based line and column and a length,
/// both counted in characters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Span {
    /// Line.
    pub line: usize,
    /// Column (characters).
    pub col: usize,
    /// Length (characters).
    pub len: usize,
}

/// One problem found in an input file.
#[derive(Clone, Debug)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// What is wrong.
    pub message: String,
    /// How to fix it, when there is something to say.
    pub hint: Option<String>,
    /// The file.
    pub source: SourceFile,
    /// Byte offset of the offending text.
    pub offset: usize,
    /// Byte length of the offending text (0 marks a position).
    pub len: usize,
    /// For the line that ends a report cut short (`… and 5 more errors`):
    /// how many errors it stands for, which are counted but not listed. 0
    /// for every other diagnostic.
    pub unlisted_errors: usize,
}

impl Diagnostic {
    /// An error at a byte span of `source`.
    pub fn error(
        source: &SourceFile,
        offset: usize,
        len: usize,
        message: impl Into<String>,
    ) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            message: message.into(),
            hint: None,
            source: source.clone(),
            offset,
            len,
            unlisted_errors: 0,
        }
    }

    /// An error at 1-based line and column (characters), spanning `len` characters.
    pub fn error_at(
        source: &SourceFile,
        line: usize,
        column: usize,
        len: usize,
        message: impl Into<String>,
    ) -> Diagnostic {
        let start = source.offset(line, column);
        let end = source.offset(line, column + len).max(start);
        Diagnostic::error(source, start, end - start, message)
    }

    /// An error at a [`Span`] (line and column 0 count as 1).
    pub fn error_in(source: &SourceFile, span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic::error_at(source, span.line.max(1), span.col.max(1), span.len, message)
    }

    /// The line that ends a report cut short after this diagnostic: `… and
    /// {n} more errors`, standing for the `n` errors not listed.
    pub(crate) fn unlisted(&self, n: usize) -> Diagnostic {
        let mut d = self.clone();
        d.message = format!("… and {}", count(n, "more error", "more errors"));
        d.hint = None;
        d.unlisted_errors = n;
        d
    }

    /// The same diagnostic as a warning.
    pub fn warning(mut self) -> Diagnostic {
        self.severity = Severity::Warning;
        self
    }

    /// Attach a hint.
    pub fn with_hint(mut self, hint: impl Into<String>) -> Diagnostic {
        self.hint = Some(hint.into());
        self
    }

    /// 1-based line and column.
    pub fn line_col(&self) -> (usize, usize) {
        self.source.line_col(self.offset)
    }

    /// The full report as plain text: `file:line:column`, the source line
    /// with a caret under the offending text, and the hint.
    ///
    /// ```text
    /// error: unknown body type `SHP`
    ///   --> scene.sv:3:8
    ///    |
    ///  3 | BODY 1 SHP 0 0 0 1
    ///    |        ^^^
    ///    = hint: did you mean `SPH`?
    /// ```
    pub fn render_plain(&self) -> String {
        let (line, col) = self.line_col();
        let text = self.source.text.lines().nth(line - 1).unwrap_or("");
        let width = line.to_string().len();
        let pad = " ".repeat(width);
        let span_chars = self.source.text
            [self.offset..(self.offset + self.len).min(self.source.text.len())]
            .lines()
            .next()
            .map_or(0, |s| s.chars().count());
        let kind = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        let mut s = format!(
            "{kind}: {}\n{pad}--> {}:{line}:{col}\n{pad} |\n{line} | {}\n{pad} | {}{}\n",
            self.message,
            self.source.name,
            text.trim_end(),
            " ".repeat(col - 1),
            "^".repeat(span_chars.max(1)),
        );
        if let Some(h) = &self.hint {
            s.push_str(&format!("{pad} = hint: {h}\n"));
        }
        s
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (line, col) = self.line_col();
        write!(f, "{}:{line}:{col}: {}", self.source.name, self.message)
    }
}

impl std::error::Error for Diagnostic {}

impl miette::Diagnostic for Diagnostic {
    fn severity(&self) -> Option<miette::Severity> {
        Some(match self.severity {
            Severity::Error => miette::Severity::Error,
            Severity::Warning => miette::Severity::Warning,
        })
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.hint
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        Some(self)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = miette::LabeledSpan> + '_>> {
        Some(Box::new(std::iter::once(
            miette::LabeledSpan::new_primary_with_span(None, (self.offset, self.len)),
        )))
    }
}

impl miette::SourceCode for Diagnostic {
    fn read_span<'a>(
        &'a self,
        span: &miette::SourceSpan,
        lines_before: usize,
        lines_after: usize,
    ) -> Result<Box<dyn miette::SpanContents<'a> + 'a>, miette::MietteError> {
        let inner = self
            .source
            .text
            .read_span(span, lines_before, lines_after)?;
        Ok(Box::new(miette::MietteSpanContents::new_named(
            self.source.name.clone(),
            inner.data(),
            *inner.span(),
            inner.line(),
            inner.column(),
            inner.line_count(),
        )))
    }
}

/// Every error (and warning) of one input, reported together.
#[derive(Clone, Debug, Default)]
pub struct Diagnostics {
    /// The diagnostics, in file order.
    pub items: Vec<Diagnostic>,
}

impl Diagnostics {
    /// True when there is at least one error.
    pub fn has_errors(&self) -> bool {
        self.items.iter().any(|d| d.severity == Severity::Error)
    }

    /// Add one.
    pub fn push(&mut self, d: Diagnostic) {
        self.items.push(d);
    }

    /// How many errors there are, those a cut-short report does not list
    /// included.
    pub fn error_count(&self) -> usize {
        self.errors()
            .map(|d| match d.unlisted_errors {
                0 => 1,
                n => n,
            })
            .sum()
    }

    /// Errors only.
    pub fn errors(&self) -> impl Iterator<Item = &Diagnostic> {
        self.items.iter().filter(|d| d.severity == Severity::Error)
    }

    /// Warnings only.
    pub fn warnings(&self) -> impl Iterator<Item = &Diagnostic> {
        self.items
            .iter()
            .filter(|d| d.severity == Severity::Warning)
    }

    /// All reports as plain text, one after another (no count).
    pub fn render_plain(&self) -> String {
        self.render_items(Style::Plain)
    }

    /// Every diagnostic drawn in `style`, one after another.
    fn render_items(&self, style: Style) -> String {
        let handler = match style {
            Style::Plain => {
                return self
                    .items
                    .iter()
                    .map(Diagnostic::render_plain)
                    .collect::<Vec<_>>()
                    .join("\n")
            }
            Style::Graphical => {
                miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
            }
            Style::Colour => miette::GraphicalReportHandler::new(),
        };
        let mut out = String::new();
        for d in &self.items {
            // Writing to a String cannot fail.
            let _ = handler.render_report(&mut out, d);
        }
        out
    }

    /// The report a user reads: every diagnostic drawn in `style`, then,
    /// when there are errors, their count on a line of its own (`1 error
    /// found`, `3 errors found`), followed by `; {consequence}` when one is
    /// given (`nothing was written`).
    pub fn report(&self, style: Style, consequence: Option<&str>) -> String {
        let mut out = self.render_items(style);
        let errors = self.error_count();
        if errors > 0 {
            if !out.is_empty() && !out.ends_with('\n') {
                out.push('\n');
            }
            out.push_str(&count(errors, "error", "errors"));
            out.push_str(" found");
            if let Some(c) = consequence {
                out.push_str("; ");
                out.push_str(c);
            }
            out.push('\n');
        }
        out
    }
}

/// How [`Diagnostics::report`] draws each diagnostic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// [`Diagnostic::render_plain`]: `file:line:column`, the line, a caret
    /// and the hint, in ASCII.
    Plain,
    /// miette's graphical report without colour (for logs and pipes).
    Graphical,
    /// miette's graphical report in colour (for a terminal).
    Colour,
}

/// `n` and the noun in the right number: `1 error`, `2 errors`.
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

impl From<Diagnostic> for Diagnostics {
    fn from(d: Diagnostic) -> Self {
        Diagnostics { items: vec![d] }
    }
}

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", count(self.error_count(), "error", "errors"))
    }
}

impl std::error::Error for Diagnostics {}

/// The candidate closest to `word` (Levenshtein distance, ignoring case),
/// if it is close enough to be a plausible typo.
pub fn did_you_mean<'a, I: IntoIterator<Item = &'a str>>(
    word: &str,
    candidates: I,
) -> Option<&'a str> {
    let w = word.to_ascii_uppercase();
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        let d = levenshtein(&w, &c.to_ascii_uppercase());
        if best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, c));
        }
    }
    let limit = (word.chars().count() / 3).max(1) + usize::from(word.len() > 2);
    best.filter(|(d, _)| *d <= limit).map(|(_, c)| c)
}

fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur.push(sub.min(prev[j + 1] + 1).min(cur[j] + 1));
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_rendering_points_at_the_span() {
        let src = SourceFile::new("scene.sv", "# demo\n\nBODY 1 SHP 0 0 0 1\n");
        let d = Diagnostic::error_at(&src, 3, 8, 3, "unknown body type `SHP`")
            .with_hint("did you mean `SPH`?");
        assert_eq!(
            d.render_plain(),
            "error: unknown body type `SHP`\n --> scene.sv:3:8\n  |\n3 | BODY 1 SHP 0 0 0 1\n  |        ^^^\n  = hint: did you mean `SPH`?\n"
        );
        assert_eq!(d.to_string(), "scene.sv:3:8: unknown body type `SHP`");
    }

    #[test]
    fn reports_count_their_errors() {
        let src = SourceFile::new("a.sv", "x\ny\n");
        let one = Diagnostics::from(Diagnostic::error_at(&src, 1, 1, 1, "bad x"));
        assert_eq!(
            one.report(Style::Plain, Some("nothing was written")),
            format!("{}1 error found; nothing was written\n", one.render_plain())
        );
        let mut two = one.clone();
        two.push(Diagnostic::error_at(&src, 2, 1, 1, "bad y"));
        two.push(Diagnostic::error_at(&src, 2, 1, 1, "odd y").warning());
        let graphical = two.report(Style::Graphical, None);
        assert!(graphical.ends_with("\n2 errors found\n"), "{graphical}");
        assert!(graphical.contains("bad y") && graphical.contains("odd y"));
        let warnings = Diagnostics::from(Diagnostic::error_at(&src, 1, 1, 1, "odd").warning());
        assert!(!warnings.report(Style::Plain, None).contains("found"));
        assert_eq!(one.to_string(), "1 error");
        assert_eq!(two.to_string(), "2 errors");
    }

    #[test]
    fn suggestions_are_close_matches_only() {
        assert_eq!(did_you_mean("SHP", ["SPH", "RCC", "TOR"]), Some("SPH"));
        assert_eq!(
            did_you_mean("helicoptr", ["HELICOPTER", "ROTOR"]),
            Some("HELICOPTER")
        );
        assert_eq!(did_you_mean("XYZZY", ["SPH", "RCC"]), None);
    }
}
