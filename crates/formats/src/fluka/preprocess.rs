//! The FLUKA preprocessor: `#define`, `#undef`, `#if`/`#ifdef`/`#ifndef`,
//! `#elif`, `#else`, `#endif` and `#include`, and `$name` substitution.
//!
//! FLUKA's conditions only ask whether a name is defined (`#if NAME` is true
//! when `#define NAME` came before, whatever its value). A defined name's
//! value replaces `$name` wherever it stands on an active line (`-$name`
//! in a region, a body parameter, a WHAT of a card); `$` words that name
//! nothing defined (`$start_transform`) are left alone. The output is the
//! list of active lines, each remembering its file and line number, and
//! where substitutions moved its columns, so later diagnostics point into
//! the right file at the right place.

use crate::{did_you_mean, Diagnostic, SourceFile};
use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};

/// How deep `#include`s may nest (a deeper one is an error).
pub const MAX_INCLUDE_DEPTH: usize = 16;
/// Largest file `#include` reads, and largest total text after expansion.
pub(crate) const MAX_TEXT_BYTES: usize = 64 << 20;

/// One active input line.
#[derive(Clone, Debug)]
pub(crate) struct Line {
    /// Index of the file in [`Output::files`].
    pub file: usize,
    /// 1-based line number in that file.
    pub line: usize,
    /// The text, without the line break, `$name`s substituted.
    pub text: String,
    /// The substitutions made in `text`, left to right.
    pub subs: Vec<Substitution>,
}

/// One `$name` replaced by its value on a line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Substitution {
    /// 1-based column of the value in the substituted text.
    pub col: usize,
    /// Length of the value, in characters.
    pub len: usize,
    /// Length of `$name` as written, in characters.
    pub written: usize,
}

impl Line {
    /// The span as written of `len` characters at column `col` of the
    /// substituted text: columns after a substitution move back by what
    /// it added, and a span inside a value covers the `$name` written.
    pub fn written_span(&self, col: usize, len: usize) -> (usize, usize) {
        let mut shift: isize = 0;
        for s in &self.subs {
            if col < s.col {
                break;
            }
            if col < s.col + s.len.max(1) {
                let start = s.col as isize - shift;
                return (start.max(1) as usize, s.written);
            }
            shift += s.len as isize - s.written as isize;
        }
        ((col as isize - shift).max(1) as usize, len)
    }
}

/// The preprocessed input.
#[derive(Debug, Default)]
pub(crate) struct Output {
    /// Every file read: the input first, then included files.
    pub files: Vec<SourceFile>,
    /// The active lines, in order.
    pub lines: Vec<Line>,
    /// Errors.
    pub errors: Vec<Diagnostic>,
    /// Errors past [`super::MAX_ERRORS`], counted only.
    pub suppressed: usize,
    /// Byte offset of each line start, per file (see [`Output::error`]).
    pub starts: Vec<Vec<usize>>,
    /// The names `#define`d at the end of the input, with their values.
    pub defines: HashMap<String, String>,
    /// Bytes of text read so far.
    bytes: usize,
}

impl Output {
    fn push_file(&mut self, f: SourceFile) {
        let starts = std::iter::once(0)
            .chain(f.text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        self.starts.push(starts);
        self.files.push(f);
    }

    /// An error at 1-based `line` and character `col` of file `file`,
    /// `len` characters long; found through the line table, so reporting
    /// costs no more than the length of the line.
    pub fn error(
        &self,
        file: usize,
        line: usize,
        col: usize,
        len: usize,
        msg: impl Into<String>,
    ) -> Diagnostic {
        let src = &self.files[file];
        let starts = &self.starts[file];
        let start = starts
            .get(line.saturating_sub(1))
            .copied()
            .unwrap_or(src.text.len());
        let stop = starts.get(line).copied().unwrap_or(src.text.len());
        let text = &src.text[start..stop];
        let at = |c: usize| {
            text.char_indices()
                .nth(c.saturating_sub(1))
                .map_or(text.len(), |(b, _)| b)
        };
        let (a, b) = (at(col), at(col + len));
        Diagnostic::error(src, start + a, b.max(a) - a, msg)
    }
}

const DIRECTIVES: [&str; 9] = [
    "define", "undef", "if", "ifdef", "ifndef", "elif", "else", "endif", "include",
];

struct Frame {
    /// Whether the enclosing text is active.
    parent: bool,
    /// Whether the current branch is active.
    taking: bool,
    /// Whether some branch was already taken.
    taken: bool,
    seen_else: bool,
    line: usize,
    col: usize,
}

/// Where a directive stands, and whether the text around it is read.
#[derive(Clone, Copy)]
struct Here {
    file: usize,
    line: usize,
    active: bool,
}

/// A line starting (after blanks) with `#`, split into its parts.
struct DirectiveLine<'a> {
    /// 1-based column of the `#`.
    col: usize,
    /// The directive's name, lower case, without `#`.
    word: String,
    /// Its length in characters.
    word_len: usize,
    /// The text after the name, trimmed.
    rest: &'a str,
    /// The first word after the name, and its column.
    arg: Option<&'a str>,
    arg_col: Option<usize>,
    /// The directive as written (`#word`), for messages.
    shown: &'a str,
}

impl<'a> DirectiveLine<'a> {
    /// The directive on `raw`, or `None` when it is an ordinary line.
    fn parse(raw: &'a str) -> Option<DirectiveLine<'a>> {
        let trimmed = raw.trim_start();
        let body = trimmed.strip_prefix('#')?;
        let col = raw.chars().count() - trimmed.chars().count() + 1;
        let word_len = body.chars().take_while(|c| c.is_ascii_alphabetic()).count();
        let after = &body[word_len..];
        let rest = after.trim();
        let arg = rest.split_whitespace().next();
        let arg_col = arg
            .map(|a| col + 1 + word_len + after.find(a).map_or(0, |b| after[..b].chars().count()));
        Some(DirectiveLine {
            col,
            word: body[..word_len].to_ascii_lowercase(),
            word_len,
            rest,
            arg,
            arg_col,
            shown: trimmed.split_whitespace().next().unwrap_or("#"),
        })
    }
}

struct Pre {
    out: Output,
    too_large: bool,
}

/// Run the preprocessor over `src`, reading `#include`d files relative to the
/// file that includes them.
pub(crate) fn run(src: &SourceFile) -> Output {
    let mut p = Pre {
        out: Output::default(),
        too_large: false,
    };
    p.out.push_file(src.clone());
    let mut chain = Vec::new();
    if let Ok(c) = std::fs::canonicalize(&src.name) {
        chain.push(c);
    }
    p.file(0, 0, &mut chain);
    p.out
}

impl Output {
    /// Read the file `name` (relative to file `from`'s folder) named at
    /// `line`, `col` (`len` characters) of file `from`, as an `#include`
    /// there would, with the names defined at the end of the input; its
    /// lines are appended to [`Output::lines`]. The range of lines it
    /// added, or `None` when it could not be read (an error is recorded).
    pub fn read_file(
        &mut self,
        from: usize,
        at: (usize, usize, usize),
        name: &str,
    ) -> Option<std::ops::Range<usize>> {
        let (line, col, len) = at;
        let path = Path::new(&self.files[from].name)
            .parent()
            .map(|dir| dir.join(name))
            .unwrap_or_else(|| PathBuf::from(name));
        if let Err(e) = std::fs::metadata(&path) {
            let d = self.error(
                from,
                line,
                col,
                len,
                format!("cannot read the geometry file `{}`: {e}", path.display()),
            );
            self.errors.push(d.with_hint(
                "GEOBEGIN WHAT(3) names a logical unit: the geometry is read from the file \
                 named on the next card, beside the input",
            ));
            return None;
        }
        let mut p = Pre {
            out: std::mem::take(self),
            too_large: false,
        };
        let first = p.out.lines.len();
        let files = p.out.files.len();
        let here = Here {
            file: from,
            line,
            active: true,
        };
        p.include(here, col, len, name, 0, &mut Vec::new());
        *self = p.out;
        (self.files.len() > files).then_some(first..self.lines.len())
    }
}

impl Pre {
    /// Record an error; `None` once [`super::MAX_ERRORS`] are kept (it is
    /// then only counted).
    fn err(
        &mut self,
        file: usize,
        line: usize,
        col: usize,
        len: usize,
        msg: impl Into<String>,
    ) -> Option<&mut Diagnostic> {
        if self.out.errors.len() >= super::MAX_ERRORS {
            self.out.suppressed += 1;
            return None;
        }
        let d = self.out.error(file, line, col, len, msg);
        self.out.errors.push(d);
        self.out.errors.last_mut()
    }

    fn file(&mut self, file: usize, depth: usize, chain: &mut Vec<PathBuf>) {
        let text = self.out.files[file].text.clone();
        self.out.bytes += text.len();
        if self.out.bytes > MAX_TEXT_BYTES {
            if !self.too_large {
                self.too_large = true;
                self.err(
                    file,
                    1,
                    1,
                    0,
                    format!(
                        "the input is larger than {} MiB after #include expansion",
                        MAX_TEXT_BYTES >> 20
                    ),
                );
            }
            return;
        }
        let mut stack: Vec<Frame> = Vec::new();
        for (i, raw) in text.split('\n').enumerate() {
            let line = i + 1;
            let raw = raw.strip_suffix('\r').unwrap_or(raw);
            let active = stack.last().is_none_or(|f| f.parent && f.taking);
            match DirectiveLine::parse(raw) {
                None => {
                    if active {
                        let (text, subs) = substitute(raw, &self.out.defines);
                        self.out.lines.push(Line {
                            file,
                            line,
                            text,
                            subs,
                        });
                    }
                }
                Some(d) => {
                    let here = Here { file, line, active };
                    match d.word.as_str() {
                        "if" | "ifdef" | "ifndef" | "elif" | "else" | "endif" => {
                            self.conditional(here, &d, &mut stack)
                        }
                        _ => self.directive(here, &d, depth, chain),
                    }
                }
            }
        }
        for f in stack {
            self.err(file, f.line, f.col, 3, "`#if` is never closed by `#endif`");
        }
    }

    /// `#define`, `#undef`, `#include` and unknown directives.
    fn directive(&mut self, here: Here, d: &DirectiveLine, depth: usize, chain: &mut Vec<PathBuf>) {
        let Here { file, line, active } = here;
        if !active {
            return;
        }
        let word = d.word.as_str();
        match word {
            "define" | "undef" => match d.arg {
                Some(name) => {
                    if word == "define" {
                        let value = d.rest[name.len()..].trim().to_string();
                        self.out.defines.insert(name.to_string(), value);
                    } else {
                        self.out.defines.remove(name);
                    }
                }
                None => {
                    self.err(
                        file,
                        line,
                        d.col,
                        d.word_len + 1,
                        format!("`#{word}` needs a name"),
                    );
                }
            },
            "include" => {
                let name = d
                    .rest
                    .trim_matches(|c| c == '"' || c == '\'' || c == '<' || c == '>')
                    .trim();
                if name.is_empty() {
                    self.err(file, line, d.col, 8, "`#include` needs a file name");
                } else {
                    let col = d.arg_col.unwrap_or(d.col);
                    self.include(here, col, d.rest.chars().count(), name, depth, chain);
                }
            }
            _ => {
                let shown = d.shown;
                let e = self.err(
                    file,
                    line,
                    d.col,
                    shown.chars().count(),
                    format!("unknown preprocessor directive `{shown}`"),
                );
                if let (Some(e), Some(s)) = (e, did_you_mean(word, DIRECTIVES)) {
                    e.hint = Some(format!("did you mean `#{s}`?"));
                }
            }
        }
    }

    /// `#if`, `#ifdef`, `#ifndef`, `#elif`, `#else` and `#endif`: they are
    /// followed even in inactive text, to find the matching `#endif`.
    fn conditional(&mut self, here: Here, d: &DirectiveLine, stack: &mut Vec<Frame>) {
        let Here { file, line, active } = here;
        let col = d.col;
        match d.word.as_str() {
            "if" | "ifdef" | "ifndef" => {
                let cond = match d.arg {
                    Some(name) => self.out.defines.contains_key(name) != (d.word == "ifndef"),
                    None => {
                        if active {
                            self.err(
                                file,
                                line,
                                col,
                                d.word_len + 1,
                                format!("`#{}` needs a name", d.word),
                            );
                        }
                        false
                    }
                };
                stack.push(Frame {
                    parent: active,
                    taking: cond,
                    taken: cond,
                    seen_else: false,
                    line,
                    col,
                });
            }
            "elif" => {
                let defined = d.arg.is_some_and(|n| self.out.defines.contains_key(n));
                match stack.last_mut() {
                    None => {
                        self.err(file, line, col, 5, "`#elif` without `#if`");
                    }
                    Some(f) if f.seen_else => {
                        self.err(file, line, col, 5, "`#elif` after `#else`");
                    }
                    Some(f) => {
                        let parent = f.parent;
                        f.taking = !f.taken && defined;
                        f.taken |= f.taking;
                        if d.arg.is_none() && parent {
                            self.err(file, line, col, 5, "`#elif` needs a name");
                        }
                    }
                }
            }
            "else" => match stack.last_mut() {
                None => {
                    self.err(file, line, col, 5, "`#else` without `#if`");
                }
                Some(f) if f.seen_else => {
                    let hint = format!("the `#if` is on line {}", f.line);
                    if let Some(e) =
                        self.err(file, line, col, 5, "second `#else` for the same `#if`")
                    {
                        e.hint = Some(hint);
                    }
                }
                Some(f) => {
                    f.taking = !f.taken;
                    f.taken = true;
                    f.seen_else = true;
                }
            },
            _ => {
                // #endif
                if stack.pop().is_none() {
                    self.err(file, line, col, 6, "`#endif` without `#if`");
                }
            }
        }
    }

    /// `#include name`, at column `col` (`len` characters) of a line.
    fn include(
        &mut self,
        here: Here,
        col: usize,
        len: usize,
        name: &str,
        depth: usize,
        chain: &mut Vec<PathBuf>,
    ) {
        let Here { file, line, .. } = here;
        if depth + 1 > MAX_INCLUDE_DEPTH {
            self.err(
                file,
                line,
                col,
                len,
                format!("`#include` nested more than {MAX_INCLUDE_DEPTH} levels deep"),
            );
            return;
        }
        let base = Path::new(&self.out.files[file].name)
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let path = base.join(name);
        let canon = match std::fs::canonicalize(&path) {
            Ok(c) => c,
            Err(e) => {
                self.err(
                    file,
                    line,
                    col,
                    len,
                    format!("cannot include `{}`: {e}", path.display()),
                );
                return;
            }
        };
        if chain.contains(&canon) {
            self.err(
                file,
                line,
                col,
                len,
                format!("`{}` includes itself (recursive #include)", path.display()),
            );
            return;
        }
        let text = match read_limited(&canon) {
            Ok(t) => t,
            Err(e) => {
                self.err(
                    file,
                    line,
                    col,
                    len,
                    format!("cannot include `{}`: {e}", path.display()),
                );
                return;
            }
        };
        self.out
            .push_file(SourceFile::new(path.display().to_string(), text));
        let idx = self.out.files.len() - 1;
        chain.push(canon);
        self.file(idx, depth + 1, chain);
        chain.pop();
    }
}

/// `raw` with every `$name` of a defined name replaced by its value, and
/// where the values went.
fn substitute(raw: &str, defines: &HashMap<String, String>) -> (String, Vec<Substitution>) {
    if defines.is_empty() || !raw.contains('$') {
        return (raw.to_string(), Vec::new());
    }
    let chars: Vec<char> = raw.chars().collect();
    let mut text = String::with_capacity(raw.len());
    let mut subs = Vec::new();
    let mut col = 1;
    let mut k = 0;
    while k < chars.len() {
        let name_len = if chars[k] == '$' {
            chars[k + 1..]
                .iter()
                .take_while(|c| c.is_ascii_alphanumeric() || **c == '_')
                .count()
        } else {
            0
        };
        let name: String = chars[(k + 1).min(chars.len())..k + 1 + name_len]
            .iter()
            .collect();
        match defines.get(&name).filter(|_| name_len > 0) {
            Some(value) => {
                let len = value.chars().count();
                subs.push(Substitution {
                    col,
                    len,
                    written: name_len + 1,
                });
                text.push_str(value);
                col += len;
                k += name_len + 1;
            }
            None => {
                text.push(chars[k]);
                col += 1;
                k += 1;
            }
        }
    }
    (text, subs)
}

/// Read a regular file of at most [`MAX_TEXT_BYTES`] bytes (never a device
/// or a pipe, which could block).
fn read_limited(path: &Path) -> std::io::Result<String> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(std::io::Error::other("not a regular file"));
    }
    if meta.len() > MAX_TEXT_BYTES as u64 {
        return Err(std::io::Error::other(format!(
            "larger than {} MiB",
            MAX_TEXT_BYTES >> 20
        )));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(MAX_TEXT_BYTES as u64)
        .read_to_end(&mut bytes)?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}
