//! Script text to syntax tree, with syntax errors: the header (SCENE, FPS,
//! SIZE, CAMERA, OBJECT, AXIS) and the blocks of the film.

use super::ast::{
    AxisAst, Block, CameraAst, Cmd, CmdKind, Name, ObjectAst, ScriptAst, Span, KEYWORDS,
};
use super::command::{command, count, read_name, timing, triple};
use crate::camera_light::{self, above_zero};
use crate::diag::{did_you_mean, Diagnostic, Diagnostics, SourceFile};
use crate::text::{Cursor, Kind, Token, SCRIPT};

type PResult<T> = Result<T, Diagnostic>;

/// A REPEAT or TOGETHER block not yet closed by its END.
struct Open {
    kind: &'static str,
    span: Span,
    count: usize,
    blocks: Vec<Block>,
    cmds: Vec<Cmd>,
}

impl Open {
    fn new(kind: &'static str, span: Span, count: usize) -> Open {
        Open {
            kind,
            span,
            count,
            blocks: Vec::new(),
            cmds: Vec::new(),
        }
    }

    /// The block it makes once closed.
    fn close(self) -> Block {
        match self.kind {
            "TOGETHER" => Block::Together(self.cmds, self.span),
            _ => Block::Repeat(self.count, self.blocks, self.span),
        }
    }
}

/// The script read so far: its header, the blocks closed at the top and
/// the blocks still open.
#[derive(Default)]
struct Parser {
    ast: ScriptAst,
    open: Vec<Open>,
    top: Vec<Block>,
}

impl Parser {
    /// Add a finished block to the innermost open block, or to the top.
    fn push(&mut self, block: Block) {
        match self.open.last_mut() {
            Some(o) => o.blocks.push(block),
            None => self.top.push(block),
        }
    }
}

/// Parse a script; statements with errors are left out and every error is
/// reported.
pub fn parse(src: &SourceFile) -> (ScriptAst, Diagnostics) {
    let mut parser = Parser::default();
    let mut diags = Diagnostics::default();
    for (i, text) in src.text.lines().enumerate() {
        let mut line = Cursor::new(src, i + 1, text, &SCRIPT);
        if let Some(t) = line
            .tokens()
            .iter()
            .find(|t| t.kind == Kind::Quoted { closed: false })
        {
            diags.push(
                line.error(t, "unterminated string")
                    .with_hint("close it with `\"`"),
            );
            continue;
        }
        if line.is_blank() {
            continue;
        }
        if let Err(d) = parser.statement(&mut line) {
            diags.push(d);
        }
    }
    while let Some(open) = parser.open.pop() {
        diags.push(
            Diagnostic::error_in(src, open.span, format!("{} without END", open.kind))
                .with_hint("close the block with `END`"),
        );
        // Keep what the block held so that its names are still checked.
        let block = open.close();
        parser.push(block);
    }
    let mut ast = parser.ast;
    if ast.scenes.is_empty() {
        diags.push(
            Diagnostic::error_at(src, 1, 1, 0, "the script names no scene")
                .with_hint("start the script with `SCENE \"file.sv\"`"),
        );
    }
    ast.blocks = parser.top;
    diags.items.sort_by_key(|d| d.offset);
    (ast, diags)
}

/// Statements that belong to the header or open and shoot blocks: none of
/// them may stand inside TOGETHER.
const NOT_IN_TOGETHER: &[&str] = &[
    "SCENE", "FPS", "SIZE", "CAMERA", "OBJECT", "AXIS", "SHOOT", "FRAME", "HOLD", "REPEAT",
    "TOGETHER",
];

impl Parser {
    fn statement(&mut self, line: &mut Cursor) -> PResult<()> {
        let keyword = line.any("a command")?;
        let Some(word) = keyword.word().map(str::to_ascii_uppercase) else {
            return Err(line.expected(&keyword, "a command"));
        };
        let in_together = self.open.last().is_some_and(|o| o.kind == "TOGETHER");
        if in_together && NOT_IN_TOGETHER.contains(&word.as_str()) {
            return Err(line
                .error(&keyword, format!("{word} cannot be used inside TOGETHER"))
                .with_hint("TOGETHER holds changes that run over the same frames; put this before or after the block"));
        }
        match word.as_str() {
            "SCENE" => self.scene(line),
            "FPS" => self.fps(line, &keyword),
            "SIZE" => self.size(line, &keyword),
            "CAMERA" => self.camera(line, &keyword),
            "OBJECT" => self.object(line),
            "AXIS" => self.axis(line),
            "SHOOT" | "FRAME" | "HOLD" => self.shoot(line, &keyword, &word),
            "REPEAT" => self.repeat(line, &keyword),
            "TOGETHER" => {
                self.open.push(Open::new("TOGETHER", keyword.span, 1));
                line.finish()
            }
            "END" => self.end(line, &keyword),
            "MOVE" | "TURN" | "SPIN" | "STOP" | "AIM" | "TRACK" | "ZOOM" | "INTENSITY" => {
                self.change(line, &keyword, &word)
            }
            _ => {
                let mut d = line.error(&keyword, format!("unknown command `{}`", keyword.shown()));
                if let Some(s) = did_you_mean(&word, KEYWORDS.iter().copied()) {
                    d = d.with_hint(format!("did you mean `{s}`?"));
                }
                Err(d)
            }
        }
    }

    /// `SCENE "file"`.
    fn scene(&mut self, line: &mut Cursor) -> PResult<()> {
        let t = line.any("a quoted file name")?;
        if !matches!(t.kind, Kind::Quoted { .. }) {
            return Err(line.expected(&t, "a quoted file name"));
        }
        self.ast.scenes.push((t.text.to_string(), t.span));
        line.finish()
    }

    /// `FPS rate`.
    fn fps(&mut self, line: &mut Cursor, keyword: &Token) -> PResult<()> {
        let rate = above_zero(line, "a frame rate")?;
        if let Some((_, at)) = self.ast.fps {
            return Err(line.error(keyword, format!("FPS is already set on line {}", at.line)));
        }
        self.ast.fps = Some((rate, keyword.span));
        line.finish()
    }

    /// `SIZE width height`.
    fn size(&mut self, line: &mut Cursor, keyword: &Token) -> PResult<()> {
        let width = count(line, "a width in pixels", 1 << 16)?;
        let height = count(line, "a height in pixels", 1 << 16)?;
        if let Some((_, at)) = self.ast.size {
            return Err(line.error(keyword, format!("SIZE is already set on line {}", at.line)));
        }
        self.ast.size = Some(((width as u32, height as u32), keyword.span));
        line.finish()
    }

    /// `CAMERA …`, the grammar scenes use too.
    fn camera(&mut self, line: &mut Cursor, keyword: &Token) -> PResult<()> {
        let camera = camera_light::camera(line)?;
        if let Some(c) = &self.ast.camera {
            return Err(line.error(
                keyword,
                format!("CAMERA is already set on line {}", c.span.line),
            ));
        }
        self.ast.camera = Some(CameraAst {
            camera,
            span: keyword.span,
        });
        line.finish()
    }

    /// `OBJECT name [REGIONS] region… [CONTAINS object…]`.
    fn object(&mut self, line: &mut Cursor) -> PResult<()> {
        let name = read_name(line, "an object name")?;
        // Until the line is read through, uses of the name are not reported.
        self.ast.broken.push(name.text.to_ascii_uppercase());
        if !line.eat("REGIONS") {
            line.eat("REGION");
        }
        let mut regions = Vec::new();
        let mut contains = Vec::new();
        let mut in_contains = false;
        while let Some(t) = line.advance() {
            if t.is("CONTAINS") && !in_contains {
                in_contains = true;
                continue;
            }
            line.eat_punct(',');
            let listed = match t.kind {
                Kind::Word => Name::of(&t),
                Kind::Punct(',') => continue,
                _ => {
                    let what = if in_contains {
                        "an object name"
                    } else {
                        "a region name"
                    };
                    return Err(line.expected(&t, what));
                }
            };
            if in_contains {
                contains.push(listed);
            } else {
                regions.push(listed);
            }
        }
        if in_contains && contains.is_empty() {
            return Err(line.missing("an object name"));
        }
        self.ast.broken.pop();
        self.ast.objects.push(ObjectAst {
            name,
            regions,
            contains,
        });
        Ok(())
    }

    /// `AXIS name POINT (x,y,z) DIR (x,y,z) [ON object]`.
    fn axis(&mut self, line: &mut Cursor) -> PResult<()> {
        let name = read_name(line, "an axis name")?;
        self.ast.broken.push(name.text.to_ascii_uppercase());
        line.expect("POINT")?;
        let point = triple(line)?;
        let dir_keyword = line.expect("DIR")?;
        let dir = triple(line)?;
        if dir.length_squared() == 0.0 {
            return Err(line.error(&dir_keyword, "the axis direction must not be zero"));
        }
        let on = if line.eat("ON") {
            Some(read_name(line, "an object name")?)
        } else {
            None
        };
        line.finish()?;
        self.ast.broken.pop();
        self.ast.axes.push(AxisAst {
            name,
            point,
            dir,
            on,
        });
        Ok(())
    }

    /// `SHOOT [n]`, `FRAME [n]`, `HOLD n`.
    fn shoot(&mut self, line: &mut Cursor, keyword: &Token, word: &str) -> PResult<()> {
        let frames = if word == "HOLD" || line.peek().is_some() {
            count(line, "a whole number of frames", sv_director::MAX_FRAMES)?
        } else {
            1
        };
        line.finish()?;
        self.push(Block::Shoot(frames, keyword.span));
        Ok(())
    }

    /// `REPEAT n [TIMES]` opens a block.
    fn repeat(&mut self, line: &mut Cursor, keyword: &Token) -> PResult<()> {
        // The block is opened even when the count is wrong, so that its
        // END is not reported as well.
        let times = count(line, "a repeat count", sv_director::MAX_FRAMES);
        let _ = line.eat("TIMES");
        let rest = line.finish();
        self.open.push(Open::new(
            "REPEAT",
            keyword.span,
            *times.as_ref().unwrap_or(&0),
        ));
        times?;
        rest
    }

    /// `END [REPEAT|TOGETHER]` closes the innermost block.
    fn end(&mut self, line: &mut Cursor, keyword: &Token) -> PResult<()> {
        let _ = line.eat("REPEAT") || line.eat("TOGETHER");
        line.finish()?;
        let Some(open) = self.open.pop() else {
            return Err(line.error(keyword, "END without REPEAT or TOGETHER"));
        };
        let block = open.close();
        self.push(block);
        Ok(())
    }

    /// A change command with its timing.
    fn change(&mut self, line: &mut Cursor, keyword: &Token, word: &str) -> PResult<()> {
        let kind = command(line, word)?;
        let untimed = matches!(
            kind,
            CmdKind::Spin(..) | CmdKind::Stop(_) | CmdKind::StopTrack | CmdKind::Track(_)
        );
        let over = if untimed { None } else { timing(line)? };
        line.finish()?;
        let cmd = Cmd {
            kind,
            over,
            span: keyword.span,
        };
        match self.open.last_mut() {
            Some(o) if o.kind == "TOGETHER" => o.cmds.push(cmd),
            _ => self.push(Block::Cmd(cmd)),
        }
        Ok(())
    }
}
