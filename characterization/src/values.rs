//! Typed parameter values and located diagnostics.
//!
//! [`Ctx`] says where a check happens (file, section, process); it builds located diagnostics.
//! The value parsers turn one [`Param`] into a typed value with the lexical rules and codes of the
//! manual's Table 7.1:
//!
//! | parser | accepts | errors |
//! |---|---|---|
//! | [`integer`] | `[+-]digits`, −32768…32767 | 13, 14 |
//! | [`word`] | `digits`, 0…65535 | 15, 16 |
//! | [`real`] | `[+-]digits[.digits]`, `[+-].digits` (no exponent) | 20 |
//! | [`hex`] | hex digits with an optional `H`/`h` suffix, at most `max_digits` digits | 21, 22 |
//! | [`boolean`] | `0` or `1` | 901 |
//! | [`ascii`] | up to 10 ASCII characters | 23, 900 |
//! | [`plc_variable`] | `I`/`U` + connector + packet `K N A T` + contact | 17, 18, 19 |
//!
//! Every parser returns `Ok(None)` for an empty parameter, so the caller applies the manual's
//! default (or reports the parameter as missing). Range checks beyond the type use [`in_range`] with
//! the instruction's own code. Parsers never panic.

use std::ops::{Range, RangeInclusive};

use diag::Diagnostic;
use packets::{Dir, Packet, Signal};

use crate::codes;
use crate::reader::{Param, ParsedFile, Record};

/// `hint` prefixed with "did you mean `X`? " when one of the upper-case instruction names listed in
/// `allowed` (a hint text such as "section 1 allows NBP, TIM, PRO") is one edit or so from `key`.
pub fn suggest_key(key: &str, allowed: &str, hint: &str) -> String {
    let names = allowed
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|t| {
            !t.is_empty()
                && t.bytes()
                    .all(|b| b.is_ascii_uppercase() || b.is_ascii_digit())
        })
        .filter(|t| t.bytes().any(|b| b.is_ascii_uppercase()));
    match diag::did_you_mean(key, names) {
        Some(s) => format!("{s} {hint}"),
        None => hint.to_string(),
    }
}

/// Where a check happens: the file (for its name and text), the section and the process.
#[derive(Debug, Clone, Copy)]
pub struct Ctx<'a> {
    /// The file being checked.
    pub file: &'a ParsedFile,
    /// Section number, when known.
    pub section: Option<u32>,
    /// Process number, when known.
    pub process: Option<u32>,
}

impl<'a> Ctx<'a> {
    /// A context for the whole file (no section, no process).
    pub fn new(file: &'a ParsedFile) -> Self {
        Ctx {
            file,
            section: None,
            process: None,
        }
    }

    /// The same context in section `n`.
    pub fn in_section(self, n: u32) -> Self {
        Ctx {
            section: Some(n),
            ..self
        }
    }

    /// The same context in process `p` (`None` outside a process subsection).
    pub fn in_process(self, p: Option<u32>) -> Self {
        Ctx { process: p, ..self }
    }

    /// A located error with `code` at `span`, with its hint.
    pub fn error(
        &self,
        code: u32,
        span: Range<usize>,
        message: impl Into<String>,
        hint: impl Into<String>,
    ) -> Diagnostic {
        self.place(Diagnostic::error(code, self.file.name.as_str(), span, message).with_hint(hint))
    }

    /// A located warning with `code` at `span`, with its hint.
    pub fn warning(
        &self,
        code: u32,
        span: Range<usize>,
        message: impl Into<String>,
        hint: impl Into<String>,
    ) -> Diagnostic {
        self.place(
            Diagnostic::warning(code, self.file.name.as_str(), span, message).with_hint(hint),
        )
    }

    fn place(&self, mut d: Diagnostic) -> Diagnostic {
        d.section = self.section;
        d.process = self.process;
        self.file.locate(d)
    }

    /// Checks that `record` has between `min` and `max` parameters (errors 10 and 11).
    ///
    /// A record with fewer parameters gets error 10 at its end; one with more gets error 11 at the
    /// first extra parameter.
    pub fn arity(&self, record: &Record, min: usize, max: usize) -> Result<(), Diagnostic> {
        let n = record.params.len();
        let expected = if min == max {
            format!("{min}")
        } else {
            format!("{min} to {max}")
        };
        if n < min {
            let hint = format!(
                "{} takes {expected} parameters; write an empty parameter as just its `,`",
                record.key
            );
            return Err(self.error(
                codes::TOO_FEW_PARAMS,
                record.end_span(),
                format!("{} has {n} parameter(s), {expected} expected", record.key),
                hint,
            ));
        }
        if n > max {
            let extra = record.params[max].span.start.saturating_sub(1);
            let span = extra..record.span.end;
            return Err(self.error(
                codes::TOO_MANY_PARAMS,
                span,
                format!("{} has {n} parameters, {expected} expected", record.key),
                format!("remove the parameters after the {max}th"),
            ));
        }
        Ok(())
    }
}

fn none_if_empty(p: &Param) -> bool {
    p.text.is_empty()
}

/// An `integer` parameter (−32768…32767); `Ok(None)` when empty. Errors 13, 14.
pub fn integer(ctx: &Ctx, p: &Param) -> Result<Option<i32>, Diagnostic> {
    if none_if_empty(p) {
        return Ok(None);
    }
    let t = p.text.as_str();
    let digits = t.strip_prefix(['+', '-']).unwrap_or(t);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err(ctx.error(
            codes::INTEGER_SYNTAX,
            p.span.clone(),
            format!("`{t}` is not an integer"),
            "an integer is decimal digits with an optional sign, e.g. -105",
        ));
    }
    match t.parse::<i64>() {
        Ok(v) if (-32768..=32767).contains(&v) => Ok(Some(v as i32)),
        _ => Err(ctx.error(
            codes::INTEGER_OVERFLOW,
            p.span.clone(),
            format!("integer `{t}` overflows"),
            "an integer is between -32768 and 32767",
        )),
    }
}

/// A `word` parameter (0…65535); `Ok(None)` when empty. Errors 15, 16.
pub fn word(ctx: &Ctx, p: &Param) -> Result<Option<u32>, Diagnostic> {
    if none_if_empty(p) {
        return Ok(None);
    }
    let t = p.text.as_str();
    let digits = t.strip_prefix('+').unwrap_or(t);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err(ctx.error(
            codes::WORD_SYNTAX,
            p.span.clone(),
            format!("`{t}` is not a word (unsigned whole number)"),
            "a word is decimal digits only, 0 to 65535",
        ));
    }
    match digits.parse::<u64>() {
        Ok(v) if v <= 65535 => Ok(Some(v as u32)),
        _ => Err(ctx.error(
            codes::WORD_OVERFLOW,
            p.span.clone(),
            format!("word `{t}` overflows"),
            "a word is between 0 and 65535",
        )),
    }
}

/// A `real` parameter; `Ok(None)` when empty. Error 20.
pub fn real(ctx: &Ctx, p: &Param) -> Result<Option<f64>, Diagnostic> {
    if none_if_empty(p) {
        return Ok(None);
    }
    let t = p.text.as_str();
    let body = t.strip_prefix(['+', '-']).unwrap_or(t);
    let (int, frac) = body.split_once('.').unwrap_or((body, ""));
    let ok = !(int.is_empty() && frac.is_empty())
        && int.bytes().all(|b| b.is_ascii_digit())
        && frac.bytes().all(|b| b.is_ascii_digit());
    let value = if ok {
        t.parse::<f64>().ok().filter(|v| v.is_finite())
    } else {
        None
    };
    match value {
        Some(v) => Ok(Some(v)),
        None => Err(ctx.error(
            codes::REAL_SYNTAX,
            p.span.clone(),
            format!("`{t}` is not a real number"),
            "a real is digits with an optional sign and decimal point, e.g. 12000, -.05, 7.5",
        )),
    }
}

/// A `hexadecimal (max_digits digits)` parameter, with an optional `H`/`h` suffix; `Ok(None)`
/// when empty. Errors 21, 22.
pub fn hex(ctx: &Ctx, p: &Param, max_digits: usize) -> Result<Option<u32>, Diagnostic> {
    if none_if_empty(p) {
        return Ok(None);
    }
    let t = p.text.as_str();
    let digits = t.strip_suffix(['H', 'h']).unwrap_or(t);
    if let Some((i, c)) = digits.char_indices().find(|(_, c)| !c.is_ascii_hexdigit()) {
        let at = p.span.start + i;
        return Err(ctx.error(
            codes::HEX_SYNTAX,
            at..at + c.len_utf8(),
            format!("`{c}` in the hexadecimal parameter `{t}`"),
            "a hexadecimal parameter is digits 0-9 and letters A-F, optionally followed by H",
        ));
    }
    if digits.is_empty() {
        return Err(ctx.error(
            codes::HEX_SYNTAX,
            p.span.clone(),
            format!("`{t}` has no hexadecimal digits"),
            "write hexadecimal digits, e.g. 41 or 820",
        ));
    }
    if digits.len() > max_digits {
        return Err(ctx.error(
            codes::HEX_DIGITS,
            p.span.clone(),
            format!(
                "hexadecimal `{t}` has {} digits, at most {max_digits} allowed",
                digits.len()
            ),
            format!("write at most {max_digits} hexadecimal digits"),
        ));
    }
    match u32::from_str_radix(digits, 16) {
        Ok(v) => Ok(Some(v)),
        Err(_) => Err(ctx.error(
            codes::HEX_DIGITS,
            p.span.clone(),
            format!("hexadecimal `{t}` does not fit 32 bits"),
            "write at most 8 hexadecimal digits",
        )),
    }
}

/// A `boolean` parameter, `0` or `1` (leading zeros allowed: MCZ writes "2 digits"); `Ok(None)` when empty. Error 901.
pub fn boolean(ctx: &Ctx, p: &Param) -> Result<Option<bool>, Diagnostic> {
    if none_if_empty(p) {
        return Ok(None);
    }
    let t = p.text.trim_start_matches('0');
    match t {
        "" => Ok(Some(false)),
        "1" => Ok(Some(true)),
        _ => Err(ctx.error(
            codes::BOOLEAN,
            p.span.clone(),
            format!("`{}` is not a boolean", p.text),
            "a boolean is 0 or 1",
        )),
    }
}

/// An `ASCII string` parameter of at most 10 characters; `Ok(None)` when empty. Errors 23, 900.
pub fn ascii(ctx: &Ctx, p: &Param) -> Result<Option<String>, Diagnostic> {
    if none_if_empty(p) {
        return Ok(None);
    }
    if let Some((i, c)) = p.text.char_indices().find(|(_, c)| !c.is_ascii()) {
        let at = p.span.start + i;
        let hint = match crate::reader::homoglyph(c) {
            Some(l) => format!("`{c}` is Cyrillic; write the Latin letter `{l}`"),
            None => "ASCII strings may contain ASCII characters only".to_string(),
        };
        return Err(ctx.error(
            codes::NON_ASCII,
            at..at + c.len_utf8(),
            format!("non-ASCII character `{c}` in `{}`", p.text),
            hint,
        ));
    }
    if p.text.len() > 10 {
        return Err(ctx.error(
            codes::ASCII_TOO_LONG,
            p.span.clone(),
            format!(
                "`{}` has {} characters, at most 10 allowed",
                p.text,
                p.text.len()
            ),
            "an ASCII parameter has at most 10 characters",
        ));
    }
    Ok(Some(p.text.clone()))
}

/// A `PLC variable` parameter: a bit signal `I…`/`U…` of packet K, N, A or T; `Ok(None)` when
/// empty. Errors 17 (prefix), 18 (connector or contact), 19 (packet letter).
pub fn plc_variable(ctx: &Ctx, p: &Param) -> Result<Option<Signal>, Diagnostic> {
    if none_if_empty(p) {
        return Ok(None);
    }
    let t = p.text.as_str();
    let bytes = t.as_bytes();
    let dir = match bytes.first().map(u8::to_ascii_uppercase) {
        Some(b'I') => Dir::In,
        Some(b'U') => Dir::Out,
        _ => return Err(ctx.error(
            codes::SIGNAL_PREFIX,
            p.span.clone(),
            format!("`{t}` is not a PLC signal: it must start with I or U"),
            "write a PLC signal as I or U, connector, packet letter, contact, e.g. U10K5 or I1A4",
        )),
    };
    let conn_len = bytes[1..].iter().take_while(|b| b.is_ascii_digit()).count();
    let conn_text = &t[1..1 + conn_len];
    let rest = &t[1 + conn_len..];
    let letter = rest.chars().next();
    let packet = letter.and_then(|c| Packet::from_letter(c.to_ascii_uppercase()));
    let Some(packet) = packet else {
        let at = p.span.start + 1 + conn_len;
        let span = match letter {
            Some(c) => at..at + c.len_utf8(),
            None => p.span.clone(),
        };
        return Err(ctx.error(
            codes::SIGNAL_PACKET,
            span,
            format!("`{t}` has no packet letter K, N, A or T"),
            "the packet letter is K (packet K), N (packet N), A (packet A) or T (packet T)",
        ));
    };
    let contact_text = &rest[1..];
    let limit = packet.connectors() - 1;
    let connector = conn_text
        .parse::<u32>()
        .ok()
        .filter(|&c| c <= u32::from(limit));
    let contact = if contact_text.bytes().all(|b| b.is_ascii_digit()) {
        contact_text.parse::<u32>().ok().filter(|&c| c <= 31)
    } else {
        None
    };
    match (connector, contact) {
        (Some(connector), Some(contact)) => Ok(Some(Signal::Bit {
            dir,
            packet,
            connector: connector as u16,
            contact: contact as u8,
        })),
        (None, _) => Err(ctx.error(
            codes::SIGNAL_NUMBER,
            p.span.clone(),
            format!(
                "`{t}`: connector `{conn_text}` is not 0…{limit} for packet {}",
                packet.letter()
            ),
            format!(
                "packet {} has connectors 0 to {limit}; e.g. {}",
                packet.letter(),
                example(packet)
            ),
        )),
        (_, None) => Err(ctx.error(
            codes::SIGNAL_NUMBER,
            p.span.clone(),
            format!("`{t}`: contact `{contact_text}` is not 0…31"),
            "a contact number is 0 to 31",
        )),
    }
}

fn example(packet: Packet) -> &'static str {
    match packet {
        Packet::A => "I1A4",
        Packet::K => "U10K5",
        Packet::N => "U10N1",
        Packet::T => "I0T0",
    }
}

/// Checks `value` against `range`, reporting `code` at the parameter with a hint naming the range.
pub fn in_range<T: PartialOrd + std::fmt::Display + Copy>(
    ctx: &Ctx,
    p: &Param,
    value: T,
    range: RangeInclusive<T>,
    code: u32,
    what: &str,
) -> Result<T, Diagnostic> {
    if range.contains(&value) {
        Ok(value)
    } else {
        Err(ctx.error(
            code,
            p.span.clone(),
            format!("{what} {value} is out of range"),
            format!("{what} must be {} to {}", range.start(), range.end()),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reader::read;

    fn file() -> ParsedFile {
        read("T", b"*1\nX=1\n").0
    }

    fn param(text: &str) -> Param {
        Param {
            text: text.to_string(),
            span: 5..5 + text.len(),
        }
    }

    #[test]
    fn integers_words_and_reals() {
        let f = file();
        let c = Ctx::new(&f);
        assert_eq!(integer(&c, &param("-201")), Ok(Some(-201)));
        assert_eq!(integer(&c, &param("")), Ok(None));
        assert_eq!(integer(&c, &param("1x")).map_err(|d| d.code), Err(13));
        assert_eq!(integer(&c, &param("40000")).map_err(|d| d.code), Err(14));
        assert_eq!(word(&c, &param("65535")), Ok(Some(65535)));
        assert_eq!(word(&c, &param("-1")).map_err(|d| d.code), Err(15));
        assert_eq!(word(&c, &param("65536")).map_err(|d| d.code), Err(16));
        assert_eq!(real(&c, &param("-.05")), Ok(Some(-0.05)));
        assert_eq!(real(&c, &param("+5")), Ok(Some(5.0)));
        assert_eq!(real(&c, &param("1500.")), Ok(Some(1500.0)));
        assert_eq!(real(&c, &param("1e3")).map_err(|d| d.code), Err(20));
        assert_eq!(real(&c, &param(".")).map_err(|d| d.code), Err(20));
    }

    #[test]
    fn hex_with_and_without_suffix() {
        let f = file();
        let c = Ctx::new(&f);
        assert_eq!(hex(&c, &param("ECDF"), 4), Ok(Some(0xECDF)));
        assert_eq!(hex(&c, &param("820H"), 8), Ok(Some(0x820)));
        assert_eq!(hex(&c, &param("0d"), 8), Ok(Some(0xD)));
        assert_eq!(
            hex(&c, &param("1G"), 8).map_err(|d| (d.code, d.span)),
            Err((21, 6..7))
        );
        assert_eq!(hex(&c, &param("12345"), 4).map_err(|d| d.code), Err(22));
    }

    #[test]
    fn signals_report_the_manual_codes() {
        let f = file();
        let c = Ctx::new(&f);
        assert_eq!(
            plc_variable(&c, &param("U10K5"))
                .ok()
                .flatten()
                .map(|s| s.to_string()),
            Some("U10K5".to_string())
        );
        assert_eq!(
            plc_variable(&c, &param("I00A0"))
                .ok()
                .flatten()
                .map(|s| s.to_string()),
            Some("I0A0".to_string())
        );
        for (bad, code) in [
            ("X1K1", 17),
            ("W3K0", 17),
            ("U256K20", 18),
            ("U200K32", 18),
            ("I32A1", 18),
            ("I32A32", 18),
            ("I16T0", 18),
            ("U1B1", 19),
            ("U10", 19),
            ("U10K", 18),
        ] {
            assert_eq!(
                plc_variable(&c, &param(bad)).map_err(|d| d.code),
                Err(code),
                "{bad}"
            );
        }
    }

    #[test]
    fn ascii_and_boolean() {
        let f = file();
        let c = Ctx::new(&f);
        assert_eq!(ascii(&c, &param("XYZBS")), Ok(Some("XYZBS".into())));
        assert_eq!(
            ascii(&c, &param("ABCDEFGHIJK")).map_err(|d| d.code),
            Err(23)
        );
        assert_eq!(ascii(&c, &param("В")).map_err(|d| d.code), Err(900));
        assert_eq!(boolean(&c, &param("01")), Ok(Some(true)));
        assert_eq!(boolean(&c, &param("0")), Ok(Some(false)));
        assert_eq!(boolean(&c, &param("2")).map_err(|d| d.code), Err(901));
    }
}
