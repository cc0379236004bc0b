//! The card layer of an MCNP input: lines become cards and cards fall into
//! the three blocks, as MCNP reads them.
//!
//! * An optional message block (`MESSAGE:` up to a blank line), then the
//!   title card (the first line, whatever it holds).
//! * Blocks end at a blank line: cells, surfaces, data; what follows the
//!   data block's blank line is not read.
//! * Tabs stop every 8 columns. Columns past 128 (MCNP6.2 on) are ignored
//!   with a warning; MCNP5 and MCNP6.1 stop at column 80, which a note
//!   reports when data stands past it.
//! * A comment card has a `c` in columns 1–5 followed by a blank (or by
//!   nothing); `$` ends a line's data. Comment cards may stand between a
//!   card's lines.
//! * A line whose columns 1–5 are blank continues the card before it, and
//!   so does the line after one ending in `&`.
//! * `READ FILE=name` puts the lines of another file in its place (nested
//!   to [`MAX_READ_DEPTH`]; the name is relative to the reading file's
//!   folder).

use super::{Loc, Log};
use crate::SourceFile;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Columns MCNP6.2 and later read.
pub(crate) const MAX_COLUMNS: usize = 128;
/// Columns MCNP5 and MCNP6.1 read.
pub(crate) const OLD_COLUMNS: usize = 80;
/// How deep `READ` cards may nest.
pub const MAX_READ_DEPTH: usize = 16;
/// Most text read through `READ` cards, all files together.
const MAX_TEXT_BYTES: usize = 64 << 20;
/// Tab stops every this many columns.
const TAB: usize = 8;

/// One word of a card (no blank inside) and where it stands.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Word {
    /// The word as written.
    pub text: String,
    /// Where.
    pub at: Loc,
}

impl Word {
    /// The characters `from..from + len` of the word, with their place.
    pub fn part(&self, from: usize, len: usize) -> Word {
        Word {
            text: self.text.chars().skip(from).take(len).collect(),
            at: self.at.part(from, len),
        }
    }

    /// True when the word is `keyword`, ignoring case.
    pub fn is(&self, keyword: &str) -> bool {
        self.text.eq_ignore_ascii_case(keyword)
    }
}

/// A card: the words of all its lines, and the first `$` comment on them.
#[derive(Clone, Debug, Default)]
pub(crate) struct Card {
    /// Its words, in order.
    pub words: Vec<Word>,
    /// The first `$` comment of its lines, trimmed.
    pub comment: Option<String>,
}

/// An input split into its title and blocks.
#[derive(Debug, Default)]
pub(crate) struct Deck {
    /// The title card.
    pub title: String,
    /// Cell cards, surface cards, data cards.
    pub blocks: [Vec<Card>; 3],
    /// How many lines hold data past column 80.
    pub past_old_columns: usize,
}

/// A line of a file, tabs expanded.
struct Line {
    file: u32,
    number: u32,
    start: u32,
    /// The text with tabs expanded to blanks.
    text: String,
    /// The original column of each character of `text`, when tabs moved
    /// them.
    columns: Option<Vec<u32>>,
}

impl Line {
    /// The place of characters `from..from + len` of `text` (0-based).
    fn at(&self, from: usize, len: usize) -> Loc {
        let col = |i: usize| match &self.columns {
            Some(map) => map.get(i).copied().unwrap_or(i as u32 + 1),
            None => i as u32 + 1,
        };
        let first = col(from);
        let last = col((from + len).max(1) - 1);
        Loc {
            file: self.file,
            line: self.number,
            line_start: self.start,
            col: first,
            len: (last + 1).saturating_sub(first).max(1),
        }
    }

    fn is_blank(&self) -> bool {
        self.text.trim().is_empty()
    }

    /// A `c` in columns 1–5 followed by a blank or by the end of the line.
    fn is_comment_card(&self) -> bool {
        let mut chars = self.text.chars().enumerate().skip_while(|(_, c)| *c == ' ');
        match chars.next() {
            Some((i, 'c' | 'C')) if i < 5 => chars.next().is_none_or(|(_, c)| c == ' '),
            _ => false,
        }
    }

    /// Whether columns 1–5 are blank.
    fn continues(&self) -> bool {
        self.text.chars().take(5).filter(|c| *c == ' ').count() == 5
    }
}

fn expand_tabs(text: &str) -> (String, Option<Vec<u32>>) {
    if !text.contains('\t') {
        return (text.to_string(), None);
    }
    let mut out = String::with_capacity(text.len() + 8);
    let mut map = Vec::with_capacity(text.len() + 8);
    for (i, c) in text.chars().enumerate() {
        if c == '\t' {
            let n = TAB - map.len() % TAB;
            out.extend(std::iter::repeat_n(' ', n));
            map.extend(std::iter::repeat_n(i as u32 + 1, n));
        } else {
            out.push(c);
            map.push(i as u32 + 1);
        }
    }
    (out, Some(map))
}

/// A line's data split off its comment.
struct Split {
    words: Vec<Word>,
    comment: Option<String>,
    /// The line ended with `&`.
    ampersand: bool,
}

/// Where lines come from: the input and the files `READ` cards open.
struct Sources<'l> {
    log: &'l mut Log,
    /// Open files: index in `log.files`, their text, the next byte and line.
    stack: Vec<(u32, Arc<str>, usize, u32)>,
    /// Canonical paths of the open files (a file may not read itself).
    paths: Vec<Option<PathBuf>>,
    bytes: usize,
}

impl Sources<'_> {
    fn next_line(&mut self) -> Option<Line> {
        loop {
            let (file, text, pos, number) = self.stack.last_mut()?;
            if *pos >= text.len() {
                self.stack.pop();
                self.paths.pop();
                continue;
            }
            let start = *pos;
            let end = text[start..].find('\n').map_or(text.len(), |i| start + i);
            *pos = end + 1;
            *number += 1;
            let raw = text[start..end]
                .strip_suffix('\r')
                .unwrap_or(&text[start..end]);
            let (expanded, columns) = expand_tabs(raw);
            return Some(Line {
                file: *file,
                number: *number,
                start: start as u32,
                text: expanded,
                columns,
            });
        }
    }

    /// Split a line into words, warning about data past column 128.
    fn split(&mut self, line: &Line, past_old: &mut usize) -> Split {
        let chars: Vec<char> = line.text.chars().collect();
        let dollar = chars.iter().position(|c| *c == '$').unwrap_or(chars.len());
        let end = dollar.min(MAX_COLUMNS);
        if chars[end..dollar].iter().any(|c| !c.is_whitespace()) {
            self.log
                .warn(
                    line.at(MAX_COLUMNS, 1),
                    format!("columns past {MAX_COLUMNS} are not read, as MCNP does not read them"),
                )
                .hint = Some("continue the card on the next line (end this one with `&` or start the next with five blanks)".into());
        }
        if chars[OLD_COLUMNS.min(end)..end]
            .iter()
            .any(|c| !c.is_whitespace())
        {
            *past_old += 1;
        }
        let comment = (dollar < chars.len())
            .then(|| {
                chars[dollar + 1..]
                    .iter()
                    .collect::<String>()
                    .trim()
                    .to_string()
            })
            .filter(|c| !c.is_empty());
        let mut words = Vec::new();
        let mut i = 0;
        while i < end {
            if chars[i].is_whitespace() {
                i += 1;
                continue;
            }
            let from = i;
            while i < end && !chars[i].is_whitespace() {
                i += 1;
            }
            words.push(Word {
                text: chars[from..i].iter().collect(),
                at: line.at(from, i - from),
            });
        }
        let mut ampersand = false;
        if let Some(last) = words.last_mut() {
            if let Some(rest) = last.text.strip_suffix('&') {
                ampersand = true;
                if rest.is_empty() {
                    words.pop();
                } else {
                    let n = rest.chars().count();
                    *last = last.part(0, n);
                }
            }
        }
        Split {
            words,
            comment,
            ampersand,
        }
    }

    /// Open the file a `READ` card names.
    fn read_card(&mut self, card: &Card) {
        let words = &card.words;
        let mut name: Option<&Word> = None;
        let mut named: Option<Word> = None;
        for (i, w) in words.iter().enumerate().skip(1) {
            let lower = w.text.to_ascii_lowercase();
            if let Some(rest) = lower.strip_prefix("file") {
                let rest = rest.strip_prefix('=').unwrap_or(rest);
                if !rest.is_empty() {
                    let skip = w.text.chars().count() - rest.chars().count();
                    named = Some(w.part(skip, rest.chars().count()));
                } else {
                    name = words[i + 1..].iter().find(|w| w.text != "=");
                    if let Some(n) = name {
                        if let Some(stripped) = n.text.strip_prefix('=') {
                            named = Some(n.part(1, stripped.chars().count()));
                        }
                    }
                }
                break;
            }
        }
        let Some(name) = named.as_ref().or(name) else {
            self.log
                .error(words[0].at, "READ card without `FILE=`")
                .hint = Some("write `READ FILE=name`".into());
            return;
        };
        if self.stack.len() > MAX_READ_DEPTH {
            self.log.error(
                name.at,
                format!("READ cards nest more than {MAX_READ_DEPTH} deep"),
            );
            return;
        }
        let reading = &self.log.files[name.at.file as usize].name;
        let dir = Path::new(reading).parent().unwrap_or(Path::new(""));
        let path = dir.join(&name.text);
        let canonical = path.canonicalize().ok();
        if canonical.is_some() && self.paths.contains(&canonical) {
            self.log.error(
                name.at,
                format!("`{}` reads itself through READ cards", name.text),
            );
            return;
        }
        let bytes = match std::fs::read(&path) {
            Ok(b) => b,
            Err(e) => {
                self.log
                    .error(name.at, format!("cannot read `{}`: {e}", path.display()));
                return;
            }
        };
        self.bytes += bytes.len();
        if self.bytes > MAX_TEXT_BYTES {
            self.log.error(
                name.at,
                format!("READ cards bring in more than {} MB", MAX_TEXT_BYTES >> 20),
            );
            return;
        }
        let text: Arc<str> = String::from_utf8_lossy(&bytes).into();
        let index = self.log.files.len() as u32;
        self.log
            .files
            .push(SourceFile::new(path.display().to_string(), text.clone()));
        self.stack.push((index, text, 0, 0));
        self.paths.push(canonical);
    }
}

/// The title and blocks of the input `log.files[0]`.
pub(crate) fn read(log: &mut Log) -> Deck {
    let text = log.files[0].text.clone();
    let canonical = Path::new(&log.files[0].name).canonicalize().ok();
    let mut src = Sources {
        log,
        stack: vec![(0, text, 0, 0)],
        paths: vec![canonical],
        bytes: 0,
    };
    let mut deck = Deck::default();
    let Some(mut first) = src.next_line() else {
        return deck;
    };
    if first
        .text
        .trim_start()
        .to_ascii_lowercase()
        .starts_with("message:")
    {
        while !first.is_blank() {
            match src.next_line() {
                Some(l) => first = l,
                None => return deck,
            }
        }
        match src.next_line() {
            Some(l) => first = l,
            None => return deck,
        }
    }
    deck.title = first.text.trim().to_string();
    let mut block = 0;
    let mut current: Option<Card> = None;
    let mut continued = false;
    while let Some(line) = src.next_line() {
        if line.is_blank() {
            deck.blocks[block].extend(current.take());
            continued = false;
            block += 1;
            if block == 3 {
                break;
            }
            continue;
        }
        if line.is_comment_card() {
            continue;
        }
        let split = src.split(&line, &mut deck.past_old_columns);
        let continues = continued || line.continues();
        continued = split.ampersand || (continued && split.words.is_empty());
        if split.words.is_empty() {
            continue;
        }
        match current.as_mut() {
            Some(card) if continues => {
                card.words.extend(split.words);
                if card.comment.is_none() {
                    card.comment = split.comment;
                }
                continue;
            }
            None if continues => {
                src.log
                    .error(
                        split.words[0].at,
                        "a continuation line with no card before it",
                    )
                    .hint = Some(
                    "a card starts in columns 1–5; blanks there continue the card above".into(),
                );
            }
            _ => {}
        }
        deck.blocks[block].extend(current.take());
        let card = Card {
            words: split.words,
            comment: split.comment,
        };
        if card.words[0].is("read") {
            src.read_card(&card);
        } else {
            current = Some(card);
        }
    }
    if block < 3 {
        deck.blocks[block].extend(current);
    }
    deck
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tabs_stop_every_eight_columns() {
        let (t, map) = expand_tabs("1\t2");
        assert_eq!(t, "1       2");
        assert_eq!(map.unwrap()[8], 3);
    }
}
