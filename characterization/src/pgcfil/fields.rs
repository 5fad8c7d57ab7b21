//! Typed access to the parameters of PGCFIL and IOCFIL records, with located diagnostics.
//!
//! [`Emit`] carries the file, the current section and process and collects diagnostics; its
//! value methods call the common parsers of [`crate::values`] (Table 7.1 codes 13–23) and keep
//! going after an error, so one run reports every problem. An empty parameter is `None` without
//! an error: the manual writes an omitted parameter as an empty field.

use std::ops::Range;

use diag::{Diagnostic, Sink};
use packets::Signal;

use crate::reader::{Param, ParsedFile, Record};
use crate::values::{self, Ctx};

/// Pushes the diagnostics of one file into its sink while its records are decoded (a capped sink
/// stores the first `--max-errors` of them and counts the rest: issue 23).
pub(crate) struct Emit<'f> {
    /// The file being decoded.
    pub file: &'f ParsedFile,
    /// Section of the record being decoded (0 before the first section).
    pub section: u32,
    /// Process of the record being decoded, when the section is per process.
    pub process: Option<u32>,
    /// Where the diagnostics go.
    pub diags: &'f mut Sink,
}

impl<'f> Emit<'f> {
    /// An emitter for `file` pushing into `diags`.
    pub fn new(file: &'f ParsedFile, diags: &'f mut Sink) -> Self {
        Emit {
            file,
            section: 0,
            process: None,
            diags,
        }
    }

    fn finish(&self, mut d: Diagnostic, hint: &str) -> Diagnostic {
        if !hint.is_empty() {
            d = d.with_hint(hint);
        }
        if self.section != 0 {
            d = d.with_section(self.section);
        }
        if let Some(p) = self.process {
            d = d.with_process(p);
        }
        self.file.locate(d)
    }

    /// Reports error `code` at `span`.
    pub fn error(&mut self, code: u32, span: Range<usize>, message: impl Into<String>, hint: &str) {
        let d = Diagnostic::error(code, self.file.name.clone(), span, message);
        let d = self.finish(d, hint);
        self.diags.push(d);
    }

    /// Reports warning `code` at `span`.
    pub fn warning(
        &mut self,
        code: u32,
        span: Range<usize>,
        message: impl Into<String>,
        hint: &str,
    ) {
        let d = Diagnostic::warning(code, self.file.name.clone(), span, message);
        let d = self.finish(d, hint);
        self.diags.push(d);
    }

    /// Checks the parameter count of `rec` (errors 10 and 11); true when it is within `min..=max`.
    pub fn count(&mut self, rec: &Record, min: usize, max: usize) -> bool {
        let r = self.ctx().arity(rec, min, max);
        match r {
            Ok(()) => true,
            Err(d) => {
                self.diags.push(d);
                false
            }
        }
    }

    fn ctx(&self) -> Ctx<'f> {
        Ctx {
            file: self.file,
            section: (self.section != 0).then_some(self.section),
            process: self.process,
        }
    }

    fn take<T>(&mut self, r: Result<Option<T>, Diagnostic>) -> Option<T> {
        match r {
            Ok(v) => v,
            Err(d) => {
                self.diags.push(d);
                None
            }
        }
    }

    /// An "integer" parameter (−32768…32767): errors 13 and 14; `None` when empty or wrong.
    pub fn integer(&mut self, p: &Param) -> Option<i32> {
        let r = values::integer(&self.ctx(), p);
        self.take(r)
    }

    /// A "word" parameter (0…65535): errors 15 and 16.
    pub fn word(&mut self, p: &Param) -> Option<u32> {
        let r = values::word(&self.ctx(), p);
        self.take(r)
    }

    /// A "boolean" parameter, 0 or 1: error 901.
    pub fn boolean(&mut self, p: &Param) -> Option<bool> {
        let r = values::boolean(&self.ctx(), p);
        self.take(r)
    }

    /// A "real" parameter: error 20.
    pub fn real(&mut self, p: &Param) -> Option<f64> {
        let r = values::real(&self.ctx(), p);
        self.take(r)
    }

    /// A "hexadecimal (N digits)" parameter: errors 21 and 22.
    pub fn hex(&mut self, p: &Param, digits: usize) -> Option<u16> {
        let r = values::hex(&self.ctx(), p, digits);
        self.take(r).and_then(|v| u16::try_from(v).ok())
    }

    /// An "ASCII string" parameter (at most 10 characters): errors 23 and 900.
    pub fn ascii(&mut self, p: &Param) -> Option<String> {
        let r = values::ascii(&self.ctx(), p);
        self.take(r)
    }

    /// A "PLC variable" parameter: errors 17, 18 and 19.
    pub fn plc_variable(&mut self, p: &Param) -> Option<Signal> {
        let r = values::plc_variable(&self.ctx(), p);
        self.take(r)
    }

    /// A one-character name of `what` (interpolator names may be digits), reporting `code` otherwise.
    pub fn axis_name_like(&mut self, p: &Param, code: u32, what: &str) -> Option<char> {
        let t = self.ascii(p)?;
        let mut chars = t.chars();
        match (chars.next(), chars.next()) {
            (Some(c), None) if c.is_ascii_alphanumeric() => Some(c.to_ascii_uppercase()),
            _ => {
                self.error(
                    code,
                    p.span.clone(),
                    format!("{what} name '{t}' must be one character"),
                    &format!("an {what} name is one letter or digit"),
                );
                None
            }
        }
    }

    /// A one-character axis name, reporting `code` when the text is longer.
    pub fn axis_name(&mut self, p: &Param, code: u32) -> Option<char> {
        let t = self.ascii(p)?;
        let mut chars = t.chars();
        match (chars.next(), chars.next()) {
            (Some(c), None) if c.is_ascii_alphabetic() => Some(c.to_ascii_uppercase()),
            _ => {
                self.error(
                    code,
                    p.span.clone(),
                    format!("axis name '{t}' must be one letter"),
                    "an axis name is a single letter such as X",
                );
                None
            }
        }
    }
}
