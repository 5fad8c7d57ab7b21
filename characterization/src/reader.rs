//! The common grammar of the characterization files: bytes → sections → records → parameters.
//!
//! Every characterization file is a sequence of lines. A line is a comment (first non-blank
//! character `;`), a section marker (`*n`, alone on its line), or an instruction
//! `KEY = p1, p2, …, pN`. A `;` after an instruction starts a comment that runs to the end of the
//! line (the manual's examples write `GRA=I0A8,12 ;`). Empty parameters are kept as parameters
//! with empty text (`IN0=0,1,,,,,,` has eight parameters), so the typed layer can count them.
//!
//! FCRSYS has its own record forms (see [`Grammar::fcrsys`]): `MP0=C:\CNC32\MP0` keeps the whole
//! path as one parameter, section-2 records `AXCONF, AXCFIL/MP0` have no `=` (the first field is the
//! key), sections may be omitted, and the file ends with a lone `*`.
//!
//! Files are read as bytes, not as UTF-8 text: comments of real files contain CP866 or CP1251
//! Cyrillic. [`decode`] turns the bytes into a `String` (valid UTF-8 is kept as it is; otherwise the
//! code page is guessed from the byte statistics and every byte ≥ 0x80 becomes one character), and
//! all spans index that decoded text, which is also what [`diag::Sources`] gets, so rendered
//! diagnostics mark the right characters. Non-ASCII characters outside comments are reported as
//! error 900.
//!
//! The reader reports the errors of the manual's Table 7.1 that depend only on the grammar:
//! 2 (bad first character), 3 (no `*1` first), 4 (section out of order), 5 (text after a section
//! marker), 7 (instruction name longer than 5), 8 (no `=`), 9 (bad character in the name). Errors
//! 1 and 24 (too few / too many sections) depend on the file kind: see [`check_section_count`].

use std::ops::Range;

use diag::{Diagnostic, LineIndex, Sink};
use serde::{Deserialize, Serialize};

use crate::codes;
pub use crate::decode::{decode, homoglyph};

/// One positional parameter of a record; its `text` is trimmed and `""` for an empty parameter.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Param {
    /// The parameter text without surrounding blanks (`""` when empty).
    pub text: String,
    /// Byte span of `text` in the decoded file text (empty span at the parameter's place when empty).
    pub span: Range<usize>,
}

impl Param {
    /// True when the parameter was left empty (`TPA=41,` has an empty second parameter).
    pub fn is_empty(&self) -> bool {
        self.text.is_empty()
    }
}

/// One instruction line: `KEY=p1,p2,…` (or an FCRSYS `log_name, file/MPx` line).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Record {
    /// The instruction name, upper-cased (`NAS`, `IN1`, `GM0`, `AXCONF`).
    pub key: String,
    /// Byte span of the key as written.
    pub key_span: Range<usize>,
    /// The parameters in order; a record `KEY=` has one empty parameter.
    pub params: Vec<Param>,
    /// Byte span of the whole instruction, from the key to the last parameter character.
    pub span: Range<usize>,
}

impl Record {
    /// Parameter `i` (0-based), if written.
    pub fn param(&self, i: usize) -> Option<&Param> {
        self.params.get(i)
    }

    /// Parameter `i` when written and not empty.
    pub fn value(&self, i: usize) -> Option<&Param> {
        self.params.get(i).filter(|p| !p.is_empty())
    }

    /// Empty span just after the record, where a missing parameter would go.
    pub fn end_span(&self) -> Range<usize> {
        self.span.end..self.span.end
    }
}

/// One section `*n` with its records in file order.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Section {
    /// The section number as written after `*`.
    pub number: u32,
    /// Byte span of the `*n` marker.
    pub span: Range<usize>,
    /// The instructions of the section.
    pub records: Vec<Record>,
}

/// A whole file after reading: its decoded text and its sections.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ParsedFile {
    /// The file name used in diagnostics (e.g. `MP0/AXCFIL`).
    pub name: String,
    /// The decoded text; every span indexes it.
    pub text: String,
    /// The sections in file order.
    pub sections: Vec<Section>,
    /// Header word before `*1` when the grammar allows one (PGCFIL's `NEW` / `OLD`).
    pub header: Option<Param>,
    /// Span of the lone `*` that ends an FCRSYS file, when present.
    pub end_marker: Option<Range<usize>>,
    /// Line index of `text`, so that locating a diagnostic does not rescan the file.
    #[serde(skip)]
    pub lines: LineIndex,
    /// The reader gave up on the file (error 970 or 971): it is not validated further, since every
    /// further diagnostic would be a follow-on of it not being a characterization file.
    #[serde(default)]
    pub abandoned: bool,
}

impl ParsedFile {
    /// The first section numbered `n`, if any.
    pub fn section(&self, n: u32) -> Option<&Section> {
        self.sections.iter().find(|s| s.number == n)
    }

    /// Fills line and column of `d` (a diagnostic about this file) from its span.
    pub fn locate(&self, d: Diagnostic) -> Diagnostic {
        d.locate_in(&self.text, &self.lines)
    }

    /// Empty span at the end of the text, for "missing …" diagnostics about the whole file.
    pub fn end_span(&self) -> Range<usize> {
        self.text.len()..self.text.len()
    }
}

/// Variations of the grammar between file kinds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Grammar {
    /// The file may start with a header word before `*1` (PGCFIL's `NEW`/`OLD`, checked by its validator).
    pub header: bool,
    /// FCRSYS record forms: `log_name, file/MPx` without `=`, whole-path values, section gaps,
    /// long names, and the lone `*` terminator.
    pub fcrsys: bool,
}

impl Grammar {
    /// The grammar of AXCFIL, PGCFIL (with [`Grammar::header`]) and IOCFIL.
    pub const FUNCTIONAL: Grammar = Grammar {
        header: false,
        fcrsys: false,
    };
    /// The grammar of PGCFIL: functional, with the `NEW`/`OLD` header.
    pub const PGCFIL: Grammar = Grammar {
        header: true,
        fcrsys: false,
    };
    /// The grammar of FCRSYS.
    pub const FCRSYS: Grammar = Grammar {
        header: false,
        fcrsys: true,
    };
}

/// Reads a functional-level file (AXCFIL, IOCFIL) with [`Grammar::FUNCTIONAL`].
pub fn read(name: &str, bytes: &[u8]) -> (ParsedFile, Vec<Diagnostic>) {
    read_with(name, bytes, Grammar::FUNCTIONAL)
}

/// Consecutive lines with an error (blank and comment lines do not count either way) after which
/// the reader decides the file is not a characterization file and stops (error 971): random text
/// or a file of another kind then costs a few dozen diagnostics, not one per line.
pub const MAX_BAD_LINES: usize = 50;

/// Records a file may hold: at the next one the reader stops (error 973, the file is not
/// validated), so the records kept of any file are bounded whatever its size (issue 23).
pub const MAX_RECORDS: usize = 250_000;

/// Reads a file with the given grammar; never panics, whatever the bytes. A file with a NUL byte
/// (error 970), with [`MAX_BAD_LINES`] bad lines in a row (error 971) or with more than
/// [`MAX_RECORDS`] records (error 973) is read no further (its text kept up to the line reading
/// stopped at) and comes back [`ParsedFile::abandoned`], as does an empty or comment-only file (error 972, one
/// error instead of the missing sections and every cross-file rule that follows from them).
pub fn read_with(name: &str, bytes: &[u8], grammar: Grammar) -> (ParsedFile, Vec<Diagnostic>) {
    let nul = bytes.iter().position(|&b| b == 0);
    let text = decode(&bytes[..nul.unwrap_or(bytes.len())]);
    let mut diags = Sink::unbounded();
    let file = read_text(name, text, nul, grammar, &mut diags);
    (file, diags.into_vec())
}

/// [`read_with`] of bytes the caller gives up (valid UTF-8 becomes the text without a copy), its
/// diagnostics pushed into `diags`, a sink that may store only the first of them.
pub fn read_into(name: &str, mut bytes: Vec<u8>, grammar: Grammar, diags: &mut Sink) -> ParsedFile {
    let nul = bytes.iter().position(|&b| b == 0);
    bytes.truncate(nul.unwrap_or(bytes.len()));
    let text = match String::from_utf8(bytes) {
        Ok(text) => text,
        Err(e) => decode(e.as_bytes()),
    };
    read_text(name, text, nul, grammar, diags)
}

/// Bytes of a file the reader reads at most: the rest is not read (error 974), so a file of any
/// size costs at most this much text. No valid characterization file comes near it.
pub const MAX_BYTES: usize = 16 << 20;

/// Reads the file at `path` as [`read_into`] does, but at most [`MAX_BYTES`] of it (up to the
/// last line end within them): a longer file is read that far and then abandoned with error 974,
/// unless the reader stopped before (970, 971, 973).
pub fn read_path(
    path: &std::path::Path,
    name: &str,
    grammar: Grammar,
    diags: &mut Sink,
) -> std::io::Result<ParsedFile> {
    use std::io::Read as _;
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(MAX_BYTES as u64 + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() <= MAX_BYTES {
        return Ok(read_into(name, bytes, grammar, diags));
    }
    let cut = bytes[..MAX_BYTES]
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    bytes.truncate(cut);
    let mut file = read_into(name, bytes, grammar, diags);
    if !file.abandoned {
        let end = file.text.len();
        diags.push(
            Diagnostic::error(
                codes::TOO_LARGE,
                name,
                end..end,
                format!("{name} is larger than {} MiB; reading stopped here", MAX_BYTES >> 20),
            )
            .with_hint("no characterization file of a valid machine comes near this size; is this the right file?")
            .locate_in(&file.text, &file.lines),
        );
        file.abandoned = true;
    }
    Ok(file)
}

fn read_text(
    name: &str,
    text: String,
    nul: Option<usize>,
    grammar: Grammar,
    diags: &mut Sink,
) -> ParsedFile {
    let lines = LineIndex::new(&text);
    let mut reader = Reader {
        name,
        text: &text,
        lines: &lines,
        grammar,
        diags,
        sections: Vec::new(),
        records: 0,
        header: None,
        end_marker: None,
        stray_reported: false,
        abandoned: false,
        stop: None,
    };
    reader.run();
    let blank = |l: &str| {
        let t = l.trim();
        t.is_empty() || t.starts_with(';')
    };
    if nul.is_none() && reader.diags.is_empty() && text.lines().all(blank) {
        let what = if text.trim().is_empty() {
            "is empty"
        } else {
            "holds only comments"
        };
        reader.error(
            codes::EMPTY_FILE,
            0..0,
            format!("{name} {what}"),
            "a characterization file starts with its section marker `*1`, followed by its records `NAME=p1,p2,…`; the machines in plc-programs/ are complete examples",
        );
        reader.abandoned = true;
    }
    if let Some(at) = nul
        && !reader.abandoned
    {
        // The decoded text ends at the NUL: the error points just past the last text read.
        let end = text.len();
        reader.error(
            codes::NOT_TEXT,
            end..end,
            format!("NUL byte at byte {at}: {name} is not a text file"),
            "characterization files are plain text; check that the right file is named",
        );
        reader.abandoned = true;
    }
    let Reader {
        sections,
        header,
        end_marker,
        abandoned,
        stop,
        ..
    } = reader;
    let (mut text, mut lines) = (text, lines);
    if let Some(end) = stop {
        // Nothing after the line reading stopped at is reported: keeping it would only hold the
        // memory of a file of any size (issue 23).
        text.truncate(end);
        text.shrink_to_fit();
        lines = LineIndex::new(&text);
    }
    ParsedFile {
        name: name.to_string(),
        text,
        sections,
        header,
        end_marker,
        lines,
        abandoned,
    }
}

struct Reader<'a> {
    name: &'a str,
    text: &'a str,
    lines: &'a LineIndex,
    grammar: Grammar,
    diags: &'a mut Sink,
    sections: Vec<Section>,
    /// Records stored so far (at most [`MAX_RECORDS`]).
    records: usize,
    header: Option<Param>,
    end_marker: Option<Range<usize>>,
    stray_reported: bool,
    abandoned: bool,
    /// The end of the line reading stopped at (971, 973).
    stop: Option<usize>,
}

impl Reader<'_> {
    fn error(&mut self, code: u32, span: Range<usize>, message: String, hint: &str) {
        let mut d = Diagnostic::error(code, self.name, span, message)
            .with_hint(hint)
            .locate_in(self.text, self.lines);
        if let Some(s) = self.sections.last() {
            d = d.with_section(s.number);
        }
        self.diags.push(d);
    }

    fn run(&mut self) {
        let text = self.text;
        let mut start = 0;
        let mut bad_run = 0;
        while start < text.len() {
            let end = text[start..].find('\n').map_or(text.len(), |i| start + i);
            let before = self.diags.len();
            let neutral = self.line(start, end);
            if self.abandoned {
                self.stop = Some((end + 1).min(text.len()));
                return;
            }
            if self.diags.len() > before {
                bad_run += 1;
            } else if !neutral {
                bad_run = 0;
            }
            if bad_run >= MAX_BAD_LINES {
                self.error(
                    codes::GAVE_UP,
                    start..start,
                    format!(
                        "{MAX_BAD_LINES} lines in a row are not valid records; reading of {} stopped here",
                        self.name
                    ),
                    "is this the right file? A characterization file is `*<n>` section markers, `NAME=p1,p2,…` records and `;` comments",
                );
                self.abandoned = true;
                self.stop = Some((end + 1).min(text.len()));
                return;
            }
            start = end + 1;
        }
    }

    /// Handles the line `text[start..end]` (without its `\n`); returns true for a blank or
    /// comment-only line, which says nothing about whether the file is a characterization file.
    fn line(&mut self, start: usize, end: usize) -> bool {
        let line = &self.text[start..end];
        let content = line.strip_suffix('\r').unwrap_or(line);
        let lead = content.len() - content.trim_start().len();
        let body = &content[lead..];
        let at = start + lead;
        let Some(first) = body.chars().next() else {
            return true;
        };
        match first {
            ';' => return true,
            '*' => self.section_marker(at, body),
            c if c.is_ascii_alphabetic() => self.instruction(at, body),
            c => {
                let span = at..at + c.len_utf8();
                if c.is_ascii() {
                    self.error(codes::LINE_START, span, format!("a line cannot start with `{c}`"), "start the line with `*` (section), a letter (instruction) or `;` (comment)");
                } else {
                    self.non_ascii(span, c);
                }
            }
        }
        false
    }

    fn non_ascii(&mut self, span: Range<usize>, c: char) {
        let hint = match homoglyph(c) {
            Some(latin) => format!(
                "`{c}` (U+{:04X}) looks like the Latin letter `{latin}`; write `{latin}`",
                u32::from(c)
            ),
            None => {
                "only ASCII is allowed outside comments; Cyrillic text may only appear after `;`"
                    .to_string()
            }
        };
        self.error(
            codes::NON_ASCII,
            span,
            format!("non-ASCII character `{c}` outside a comment"),
            &hint,
        );
    }

    fn section_marker(&mut self, at: usize, body: &str) {
        // `body` starts with `*`; the number follows directly.
        let comment = if self.grammar.fcrsys {
            body.len()
        } else {
            body.find(';').unwrap_or(body.len())
        };
        let marker = body[..comment].trim_end();
        let digits = marker[1..].bytes().take_while(u8::is_ascii_digit).count();
        let num_span = at..at + 1 + digits;
        if digits == 0 {
            if marker.len() == 1 {
                if self.grammar.fcrsys {
                    self.end_marker = Some(at..at + 1);
                } else {
                    self.error(
                        codes::SECTION_ORDER,
                        at..at + 1,
                        "section marker `*` without a number".into(),
                        "write the section number after `*`, e.g. `*1`",
                    );
                }
            } else {
                self.error(
                    codes::SECTION_CR,
                    at..at + marker.len(),
                    format!("`{marker}` is not a section marker"),
                    "a section marker is `*` followed by its number, alone on its line",
                );
            }
            return;
        }
        let number: u32 = marker[1..1 + digits].parse().unwrap_or(u32::MAX);
        if marker.len() > 1 + digits || comment < body.len() {
            let rest = at + 1 + digits..at + body.len();
            self.error(
                codes::SECTION_CR,
                rest,
                format!("text after the section marker `*{number}`"),
                "the section marker must be alone on its line",
            );
        }
        if self.end_marker.is_some() {
            self.error(
                codes::SECTION_ORDER,
                num_span.clone(),
                format!("section `*{number}` after the closing `*`"),
                "the lone `*` ends FCRSYS; put it after the last section",
            );
        }
        let expected = self
            .sections
            .last()
            .map_or(1, |s| s.number.saturating_add(1));
        if self.sections.is_empty() && number != 1 && !self.grammar.fcrsys {
            self.error(
                codes::NO_SECTION,
                num_span.clone(),
                format!("the file starts with section `*{number}` instead of `*1`"),
                "the first section of the file is `*1`",
            );
        } else if self.grammar.fcrsys {
            if number < expected || number == 0 {
                self.error(
                    codes::SECTION_ORDER,
                    num_span.clone(),
                    format!("section `*{number}` is out of order"),
                    "FCRSYS sections come in increasing order (sections may be omitted)",
                );
            }
        } else if number != expected {
            self.error(
                codes::SECTION_ORDER,
                num_span.clone(),
                format!("section `*{number}` where section `*{expected}` is expected"),
                &format!("write section `*{expected}` next (an empty section is just its marker)"),
            );
        }
        self.sections.push(Section {
            number,
            span: num_span,
            records: Vec::new(),
        });
    }

    fn instruction(&mut self, at: usize, body: &str) {
        // Drop an end-of-line comment and trailing blanks.
        let code_len = body.find(';').unwrap_or(body.len());
        let code = body[..code_len].trim_end();
        if let Some((i, c)) = code.char_indices().find(|(_, c)| !c.is_ascii()) {
            self.non_ascii(at + i..at + i + c.len_utf8(), c);
        }
        if self.sections.is_empty() {
            if self.grammar.header
                && self.header.is_none()
                && !code.contains('=')
                && !code.contains(',')
            {
                self.header = Some(Param {
                    text: code.to_string(),
                    span: at..at + code.len(),
                });
                return;
            }
            if !self.stray_reported {
                self.stray_reported = true;
                self.error(
                    codes::NO_SECTION,
                    at..at + code.len(),
                    "instruction before the first section marker".into(),
                    "start the file with the section marker `*1`",
                );
            }
            return;
        }
        let record = if self.grammar.fcrsys {
            self.fcrsys_record(at, code)
        } else {
            self.functional_record(at, code)
        };
        if let (Some(mut record), Some(_)) = (record, self.sections.last()) {
            if self.records == MAX_RECORDS {
                self.error(
                    codes::TOO_MANY_RECORDS,
                    at..at + code.len(),
                    format!(
                        "{} has more than {MAX_RECORDS} records; reading stopped here",
                        self.name
                    ),
                    "no characterization file of a valid machine comes near this size (5 processes of 16 axes with two 1000-point compensation tables each are 160,000 records); is this the right file?",
                );
                self.abandoned = true;
                return;
            }
            self.records += 1;
            record.params.shrink_to_fit();
            if let Some(section) = self.sections.last_mut() {
                section.records.push(record);
            }
        }
    }

    fn functional_record(&mut self, at: usize, code: &str) -> Option<Record> {
        let Some(eq) = code.find('=') else {
            let word = code.split([' ', '\t', ',']).next().unwrap_or(code);
            self.error(
                codes::NO_EQUALS,
                at..at + code.len(),
                format!("instruction `{word}` is not followed by `=`"),
                "write the instruction as `NAME=p1,p2,…`",
            );
            return None;
        };
        let key_raw = code[..eq].trim_end();
        let key_span = at..at + key_raw.len();
        if let Some((i, c)) = key_raw
            .char_indices()
            .find(|(_, c)| !c.is_ascii_alphanumeric())
        {
            if c.is_ascii() {
                let what = if c == ' ' || c == '\t' {
                    "a blank".to_string()
                } else {
                    format!("`{c}`")
                };
                self.error(
                    codes::BAD_NAME_CHAR,
                    at + i..at + i + c.len_utf8(),
                    format!("{what} in the instruction name `{key_raw}`"),
                    "an instruction name is letters and digits without blanks, followed by `=`",
                );
            }
            return None;
        }
        if key_raw.len() > 5 {
            self.error(
                codes::NAME_TOO_LONG,
                key_span,
                format!("instruction name `{key_raw}` is longer than 5 characters"),
                "instruction names have at most 5 characters",
            );
            return None;
        }
        let params = split_params(code, at, eq + 1);
        Some(Record {
            key: key_raw.to_ascii_uppercase(),
            key_span,
            params,
            span: at..at + code.len(),
        })
    }

    fn fcrsys_record(&mut self, at: usize, code: &str) -> Option<Record> {
        let sep = match (code.find('='), code.find(',')) {
            (Some(e), Some(c)) => e.min(c),
            (Some(e), None) => e,
            (None, Some(c)) => c,
            (None, None) => {
                self.error(
                    codes::NO_EQUALS,
                    at..at + code.len(),
                    format!("`{code}` is neither `NAME=value` nor `log_name, file/MPx`"),
                    "write `MPx=path`, `log_name, file_name/MPx`, `HDD=…` or `FLP=…`",
                );
                return None;
            }
        };
        let key_raw = code[..sep].trim_end();
        let key_span = at..at + key_raw.len();
        if let Some((i, c)) = key_raw
            .char_indices()
            .find(|(_, c)| !c.is_ascii_alphanumeric())
        {
            if c.is_ascii() {
                self.error(
                    codes::BAD_NAME_CHAR,
                    at + i..at + i + 1,
                    format!("`{c}` in the name `{key_raw}`"),
                    "a name is letters and digits without blanks",
                );
            }
            return None;
        }
        // `MPx=path` keeps the whole path (it may contain `\`, `:`, but no commas in practice).
        let params = split_params(code, at, sep + 1);
        Some(Record {
            key: key_raw.to_ascii_uppercase(),
            key_span,
            params,
            span: at..at + code.len(),
        })
    }
}

/// Splits `code[from..]` at commas into trimmed parameters with spans relative to `at`.
fn split_params(code: &str, at: usize, from: usize) -> Vec<Param> {
    let mut params = Vec::new();
    let mut start = from;
    loop {
        let end = code[start..].find(',').map_or(code.len(), |i| start + i);
        let field = &code[start..end];
        let lead = field.len() - field.trim_start().len();
        let trimmed = field.trim();
        let s = at + start + lead;
        let span = if trimmed.is_empty() {
            at + start..at + start
        } else {
            s..s + trimmed.len()
        };
        params.push(Param {
            text: trimmed.to_string(),
            span,
        });
        if end >= code.len() {
            break;
        }
        start = end + 1;
    }
    params
}

/// Reports errors 1 (not enough sections) and 24 (too many) for a file that must have sections
/// `1..=expected`; `required` is how many of them must be present (FCRSYS may omit sections).
pub fn check_section_count(file: &ParsedFile, required: u32, max: u32) -> Vec<Diagnostic> {
    let mut diags = Vec::new();
    for s in file.sections.iter().filter(|s| s.number > max) {
        diags.push(
            Diagnostic::error(
                codes::TOO_MANY_SECTIONS,
                file.name.as_str(),
                s.span.clone(),
                format!(
                    "section `*{}` is one too many: {} has {max} sections",
                    s.number, file.name
                ),
            )
            .with_hint(format!(
                "remove the section or merge its instructions into sections *1..*{max}"
            ))
            .with_section(s.number)
            .locate_in(&file.text, &file.lines),
        );
    }
    let present = file
        .sections
        .iter()
        .map(|s| s.number)
        .filter(|&n| n >= 1 && n <= required)
        .collect::<std::collections::BTreeSet<_>>();
    let missing: Vec<String> = (1..=required)
        .filter(|n| !present.contains(n))
        .map(|n| format!("*{n}"))
        .collect();
    if !missing.is_empty() {
        diags.push(
            Diagnostic::error(codes::MISSING_SECTIONS, file.name.as_str(), file.end_span(), format!("{} lacks section(s) {}", file.name, missing.join(", ")))
                .with_hint(format!("the file needs sections *1..*{required}; an unused section is written as its marker alone"))
                .locate_in(&file.text, &file.lines),
        );
    }
    diags
}

#[cfg(test)]
mod tests {
    use super::*;

    fn codes_of(d: &[Diagnostic]) -> Vec<(u32, u32, u32)> {
        d.iter().map(|d| (d.code, d.line, d.column)).collect()
    }

    #[test]
    fn records_params_and_spans() {
        let src = "; comment\n*1\nIN0 = 0, 1,,,,,,\r\nGRA=I0A8,12 ; trailing\n*2\nTPA=41,\n";
        let (f, d) = read("AXCFIL", src.as_bytes());
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(f.sections.len(), 2);
        let r = &f.sections[0].records[0];
        assert_eq!(r.key, "IN0");
        assert_eq!(r.params.len(), 8);
        assert_eq!(&f.text[r.params[1].span.clone()], "1");
        assert!(r.params[2].is_empty());
        let gra = &f.sections[0].records[1];
        assert_eq!(
            gra.params
                .iter()
                .map(|p| p.text.as_str())
                .collect::<Vec<_>>(),
            ["I0A8", "12"]
        );
        assert_eq!(&f.text[gra.span.clone()], "GRA=I0A8,12");
        let tpa = &f.sections[1].records[0];
        assert_eq!(tpa.params.len(), 2);
        assert_eq!(f.sections[1].number, 2);
    }

    #[test]
    fn grammar_errors_have_the_manual_codes() {
        let (_, d) = read(
            "F",
            b"NAS=X\n*1\n1A=2\n*1 x\nNA S=1\nLONGKEY=1\nNOEQ 5\n*3\n",
        );
        assert_eq!(
            codes_of(&d),
            [
                (3, 1, 1),
                (2, 3, 1),
                (5, 4, 3),
                (4, 4, 1),
                (9, 5, 3),
                (7, 6, 1),
                (8, 7, 1),
                (4, 8, 1)
            ]
        );
    }

    #[test]
    fn cyrillic_bytes_in_comments_load_and_elsewhere_fail() {
        // CP866 "процесс" in a comment and CP866 "В" (0x82) as an axis name.
        let mut bytes = b"*1\n; ".to_vec();
        bytes.extend([0xAF, 0xE0, 0xAE, 0xE6, 0xA5, 0xE1, 0xE1]);
        bytes.extend(b"\nNAS=");
        bytes.push(0x82);
        bytes.extend(b"\n");
        let (f, d) = read("AXCFIL", &bytes);
        assert!(f.text.contains("; процесс"), "{}", f.text);
        assert_eq!(codes_of(&d), [(900, 3, 5)]);
        assert_eq!(f.sections[0].records[0].params[0].text, "В");
    }

    #[test]
    fn fcrsys_forms() {
        let src = "*1\nMP0=C:\\CNC32\\MP0\n*2\nAXCONF, AXCFIL/MP0\n*4\nUSB=CRD,CRD,,\n*\n";
        let (f, d) = read_with("FCRSYS", src.as_bytes(), Grammar::FCRSYS);
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(
            f.sections.iter().map(|s| s.number).collect::<Vec<_>>(),
            [1, 2, 4]
        );
        assert_eq!(f.sections[0].records[0].params[0].text, "C:\\CNC32\\MP0");
        let ax = &f.sections[1].records[0];
        assert_eq!(
            (ax.key.as_str(), ax.params[0].text.as_str()),
            ("AXCONF", "AXCFIL/MP0")
        );
        assert!(f.end_marker.is_some());
    }

    #[test]
    fn pgcfil_header_and_section_counts() {
        let (f, d) = read_with("PGCFIL", b"NEW\n*1\n*2\n", Grammar::PGCFIL);
        assert!(d.is_empty());
        assert_eq!(f.header.as_ref().map(|h| h.text.as_str()), Some("NEW"));
        let d = check_section_count(&f, 3, 3);
        assert_eq!(codes_of(&d), [(1, 4, 1)]);
        let (f, _) = read("AXCFIL", b"*1\n*2\n*3\n*4\n");
        assert_eq!(codes_of(&check_section_count(&f, 3, 3)), [(24, 4, 1)]);
    }
}
