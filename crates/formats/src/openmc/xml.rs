//! OpenMC's XML as the reader needs it: every value found either as an
//! attribute or as a child element (OpenMC accepts both spellings, `<surface
//! id="1" …/>` and `<surface><id>1</id>…</surface>`), with the byte offset it
//! is written at, so that a diagnostic points at the value, or at the word
//! inside it, that is wrong.

use crate::diag::count;
use crate::{Diagnostic, Diagnostics, SourceFile};
use roxmltree::{Document, Node, ParsingOptions};

/// At most this many errors and warnings are kept per read; the rest are
/// counted in a last line.
const MAX_DIAGNOSTICS: usize = 200;

/// At most this many XML nodes are parsed: bounds the memory a hostile file
/// can take (the largest real models have a few thousand).
const MAX_NODES: u32 = 4_000_000;

/// A value as written in the file.
#[derive(Clone, Copy, Debug)]
pub(super) struct Value<'a> {
    /// The text (entities resolved).
    pub text: &'a str,
    /// Byte offset in the file of the text, or of the element or attribute
    /// that holds it when the text is not written verbatim.
    pub offset: usize,
    /// Bytes to underline when pointing at the whole value.
    pub len: usize,
    /// Whether `text` stands in the file as is from `offset` on (no entity or
    /// character references), so that a word inside it can be pointed at.
    pub verbatim: bool,
}

impl<'a> Value<'a> {
    /// Offset and length of `part`, a slice of `text`; the whole value when
    /// the text is not written verbatim.
    pub fn span(&self, part: &str) -> (usize, usize) {
        let start = (part.as_ptr() as usize).wrapping_sub(self.text.as_ptr() as usize);
        if self.verbatim && start <= self.text.len() {
            (self.offset + start, part.len())
        } else {
            (self.offset, self.len)
        }
    }

    /// The whitespace-separated words of the value.
    pub fn words(&self) -> impl Iterator<Item = &'a str> {
        self.text.split_ascii_whitespace()
    }

    /// The value trimmed, as OpenMC compares keywords.
    pub fn trimmed(&self) -> &'a str {
        self.text.trim()
    }
}

/// A parsed XML file and the diagnostics met while reading it.
pub(super) struct Xml<'s> {
    /// The file.
    pub src: &'s SourceFile,
}

impl<'s> Xml<'s> {
    /// The value `name` of `node`: its attribute, else the text of its first
    /// child element of that name.
    pub fn value<'a>(&self, node: Node<'a, '_>, name: &str) -> Option<Value<'a>> {
        if let Some(attr) = node.attribute_node(name) {
            let text = attr.value();
            let range = attr.range_value();
            let verbatim = self.src.text.get(range.clone()) == Some(text);
            let whole = attr.range();
            return Some(if verbatim {
                Value {
                    text,
                    offset: range.start,
                    len: text.len(),
                    verbatim,
                }
            } else {
                Value {
                    text,
                    offset: whole.start,
                    len: whole.len(),
                    verbatim,
                }
            });
        }
        let child = node
            .children()
            .find(|c| c.is_element() && c.has_tag_name(name))?;
        Some(self.text_of(child))
    }

    /// The text of an element, where it is written.
    pub fn text_of<'a>(&self, element: Node<'a, '_>) -> Value<'a> {
        let text = element.text().unwrap_or("");
        match element.first_child().filter(|c| c.is_text()) {
            Some(t) if self.src.text.get(t.range()) == Some(text) => Value {
                text,
                offset: t.range().start,
                len: text.len(),
                verbatim: true,
            },
            _ => {
                let (offset, len) = self.tag(element);
                Value {
                    text,
                    offset,
                    len,
                    verbatim: false,
                }
            }
        }
    }

    /// Offset and length of an element's start tag name (`<cell`).
    pub fn tag(&self, element: Node) -> (usize, usize) {
        (element.range().start, 1 + element.tag_name().name().len())
    }

    /// An error at `part` of `value`.
    pub fn error_at(&self, value: &Value, part: &str, msg: impl Into<String>) -> Diagnostic {
        let (offset, len) = value.span(part);
        Diagnostic::error(self.src, offset, len, msg)
    }

    /// An error at a whole value.
    pub fn error(&self, value: &Value, msg: impl Into<String>) -> Diagnostic {
        Diagnostic::error(self.src, value.offset, value.len, msg)
    }

    /// An error at an element's start tag.
    pub fn error_tag(&self, element: Node, msg: impl Into<String>) -> Diagnostic {
        let (offset, len) = self.tag(element);
        Diagnostic::error(self.src, offset, len, msg)
    }
}

/// Parse `src` as XML, or the diagnostic saying where it is not.
pub(super) fn parse(src: &SourceFile) -> Result<Document<'_>, Diagnostic> {
    let opts = ParsingOptions {
        allow_dtd: false,
        nodes_limit: MAX_NODES,
        ..ParsingOptions::default()
    };
    Document::parse_with_options(&src.text, opts).map_err(|e| {
        let pos = e.pos();
        let offset = src.offset(pos.row as usize, pos.col as usize);
        Diagnostic::error(src, offset, 0, format!("not well-formed XML: {e}"))
            .with_hint("OpenMC reads geometry.xml, materials.xml and model.xml as XML documents")
    })
}

/// The elements `name` directly under `node`.
pub(super) fn children<'a, 'i>(
    node: Node<'a, 'i>,
    name: &'static str,
) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children()
        .filter(move |c| c.is_element() && c.has_tag_name(name))
}

/// Errors and warnings of one read, kept in bounds.
#[derive(Default)]
pub(super) struct Sink {
    /// Errors, in the order found.
    pub errors: Vec<Diagnostic>,
    /// Warnings.
    pub warnings: Vec<Diagnostic>,
    /// Diagnostics not kept beyond [`MAX_DIAGNOSTICS`].
    suppressed: usize,
    /// How many of them are errors.
    suppressed_errors: usize,
}

impl Sink {
    fn full(&mut self) -> bool {
        let full = self.errors.len() + self.warnings.len() >= MAX_DIAGNOSTICS;
        if full {
            self.suppressed += 1;
        }
        full
    }

    /// Record an error.
    pub fn error(&mut self, d: Diagnostic) {
        if self.full() {
            self.suppressed_errors += 1;
        } else {
            self.errors.push(d);
        }
    }

    /// Record a warning.
    pub fn warn(&mut self, d: Diagnostic) {
        if !self.full() {
            self.warnings.push(d.warning());
        }
    }

    /// True when an error was recorded.
    pub fn failed(&self) -> bool {
        !self.errors.is_empty() || self.suppressed_errors > 0
    }

    /// Every error and warning, the errors first, with a last line for
    /// those not kept.
    pub fn into_diagnostics(mut self) -> Diagnostics {
        // File by file (in the order their first diagnostic came), in file
        // order within each.
        let mut files: Vec<String> = Vec::new();
        for d in self.errors.iter().chain(&self.warnings) {
            if !files.contains(&d.source.name) {
                files.push(d.source.name.clone());
            }
        }
        let rank = |d: &Diagnostic| files.iter().position(|f| *f == d.source.name);
        self.errors.sort_by_key(|d| (rank(d), d.offset));
        self.warnings.sort_by_key(|d| (rank(d), d.offset));
        if self.suppressed > 0 {
            if let Some(last) = self.errors.last().cloned() {
                self.errors.push(Diagnostic {
                    message: format!(
                        "… and {} not shown",
                        count(
                            self.suppressed,
                            "more error or warning",
                            "more errors and warnings"
                        )
                    ),
                    hint: None,
                    unlisted_errors: self.suppressed_errors,
                    ..last
                });
            }
        }
        let mut items = self.errors;
        items.append(&mut self.warnings);
        Diagnostics { items }
    }
}

/// An integer as OpenMC reads ids (a 32-bit signed integer).
pub(super) fn integer(word: &str) -> Option<i64> {
    let digits = word.strip_prefix(['+', '-']).unwrap_or(word);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    word.parse::<i32>().ok().map(i64::from)
}

/// A finite real number.
pub(super) fn real(word: &str) -> Option<f64> {
    word.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The numbers of a value, or the errors naming the words that are not.
pub(super) fn reals(xml: &Xml, sink: &mut Sink, value: &Value, what: &str) -> Option<Vec<f64>> {
    let mut out = Vec::new();
    let mut ok = true;
    for word in value.words() {
        match real(word) {
            Some(v) => out.push(v),
            None => {
                ok = false;
                sink.error(xml.error_at(
                    value,
                    word,
                    format!("`{word}` in {what} is not a number"),
                ));
            }
        }
    }
    ok.then_some(out)
}

/// Exactly `n` numbers (one of `allowed` counts), or an error.
pub(super) fn reals_n(
    xml: &Xml,
    sink: &mut Sink,
    value: &Value,
    what: &str,
    allowed: &[usize],
) -> Option<Vec<f64>> {
    let v = reals(xml, sink, value, what)?;
    if allowed.contains(&v.len()) {
        return Some(v);
    }
    let want: Vec<String> = allowed.iter().map(|n| n.to_string()).collect();
    sink.error(xml.error(
        value,
        format!(
            "{what} takes {} numbers, found {}",
            want.join(" or "),
            v.len()
        ),
    ));
    None
}

/// One integer id, or an error.
pub(super) fn id_of(xml: &Xml, sink: &mut Sink, value: &Value, what: &str) -> Option<i64> {
    let mut words = value.words();
    match (words.next(), words.next()) {
        (Some(w), None) => match integer(w) {
            Some(i) => Some(i),
            None => {
                sink.error(xml.error_at(value, w, format!("{what} `{w}` is not an integer")));
                None
            }
        },
        _ => {
            sink.error(xml.error(value, format!("{what} must be one integer")));
            None
        }
    }
}
