//! The correction table file `TAB0.KOR` (structure-motion spec §13.1, fixture F25).
//!
//! Everything before the keyword `$KOR` is a comment. Each following line is one entry: a two-digit
//! correction number `01`..`99` and `:`, then fields separated by blanks: the radius `R=`, lengths by
//! axis name (`X=`, `Y=`, `Z=`, `U=`, allowed only when the machine's axis of that ordinal carries
//! that name; a lathe writes its Z length as `2=`) or by ordinal (`1=`..`4=`), and on lathes the
//! tool-tip type `P=1`..`P=9`. Blanks around `=` are allowed; missing entries and values are zero.
//! [`parse_kor`] returns the table it could read and located diagnostics (codes 2040–2049); it never
//! panics. Choices where the manual is silent: a value without a decimal point is in mm (as a
//! coordinate word, §3.3), at most three decimals and at most ±999.999 mm (the length limit of §13.8);
//! blank lines are allowed; a second `$KOR` ends the table with an error (one table per file).

use std::collections::BTreeMap;

use diag::Diagnostic;

use crate::codes;

/// One entry of the correction table.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct KorEntry {
    /// Radius correction, then the lengths of axes 1..4 (mm).
    pub data: [f64; 5],
    /// Lathe tool-tip type `P=1..9` (None: not written, the same as P9).
    pub tip: Option<u8>,
}

/// A correction table: entries 1..99 by number; entries not written are all zero.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct CorrectionTable {
    /// The written entries by correction number (1..=99).
    pub entries: BTreeMap<u8, KorEntry>,
}

/// Number of rows of the memory table: D0 (always zero) to D99.
pub const ROWS: usize = 100;

impl CorrectionTable {
    /// The memory table: row `n` = `[radius, length axis 1, …, length axis 4]` of correction `n`,
    /// rows 0..=99 (row 0 and rows not written are zero).
    pub fn rows(&self) -> Vec<[f64; 5]> {
        let mut rows = vec![[0.0; 5]; ROWS];
        for (n, e) in &self.entries {
            if let Some(r) = rows.get_mut(usize::from(*n)) {
                *r = e.data;
            }
        }
        rows
    }

    /// The data of correction `n` (zero when not written).
    pub fn data(&self, n: u8) -> [f64; 5] {
        self.entries.get(&n).map_or([0.0; 5], |e| e.data)
    }

    /// The tool-tip type of correction `n`, when written.
    pub fn tip(&self, n: u8) -> Option<u8> {
        self.entries.get(&n).and_then(|e| e.tip)
    }
}

/// The axis names the field letters stand for, by ordinal (X = axis 1, …, U = axis 4).
const NAMES: [char; 4] = ['X', 'Y', 'Z', 'U'];

struct Reader<'a> {
    file: &'a str,
    text: &'a str,
    axes: &'a [char],
    diags: Vec<Diagnostic>,
}

impl Reader<'_> {
    fn error(&mut self, code: u32, span: std::ops::Range<usize>, msg: String, hint: &str) {
        let d = Diagnostic::error(code, self.file, span, msg)
            .with_hint(hint)
            .locate(self.text);
        self.diags.push(d);
    }

    /// Reads one entry line starting at byte `base`; returns the entry number and entry.
    fn line(&mut self, base: usize, line: &str) -> Option<(u8, KorEntry)> {
        let b = line.as_bytes();
        let mut i = skip_blank(b, 0);
        let start = i;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        let digits = &line[start..i];
        let number = digits.parse::<u8>().ok().filter(|n| (1..=99).contains(n));
        let j = skip_blank(b, i);
        let (Some(n), 2, Some(b':')) = (number, digits.len(), b.get(j).copied()) else {
            self.error(
                codes::KOR_LINE,
                base + start..base + line.len(),
                "expected a two-digit correction number 01..99 followed by `:`".into(),
                "an entry line looks like `01: R=10.0 X=20.0 Y=30.0 Z=40.0`",
            );
            return None;
        };
        let mut entry = KorEntry::default();
        let mut seen = [false; 6];
        i = j + 1;
        loop {
            i = skip_blank(b, i);
            let Some(&k) = b.get(i) else { break };
            let key_at = i;
            let slot = match k {
                b'R' => 0,
                b'1'..=b'4' => usize::from(k - b'0'),
                b'P' => 5,
                b'X' | b'Y' | b'Z' | b'U' => {
                    let c = char::from(k);
                    let ord = NAMES.iter().position(|n| *n == c).unwrap_or(0);
                    if self.axes.get(ord) != Some(&c) {
                        let hint = match self.axes.iter().position(|a| *a == c) {
                            Some(p) if p < 4 => format!("write the axis ordinal `{}=`", p + 1),
                            _ => "write lengths by axis ordinal `1=`..`4=`".to_string(),
                        };
                        self.error(
                            codes::KOR_AXIS_NAME,
                            base + i..base + i + 1,
                            format!(
                                "`{c}=` means axis {} and may be used only when that axis is named {c}",
                                ord + 1
                            ),
                            &hint,
                        );
                        return None;
                    }
                    ord + 1
                }
                _ => {
                    let end = next_blank(line, i);
                    self.error(
                        codes::KOR_UNKNOWN_FIELD,
                        base + i..base + end,
                        format!("unknown field `{}`", &line[i..end]),
                        "fields: R=, X=, Y=, Z=, U=, 1= .. 4=, P=",
                    );
                    return None;
                }
            };
            i = skip_blank(b, i + 1);
            if b.get(i) != Some(&b'=') {
                self.error(
                    codes::KOR_SYNTAX,
                    base + key_at..base + key_at + 1,
                    format!("expected `=` after `{}`", char::from(k)),
                    "write `X=20.0` or `X = 20.0`",
                );
                return None;
            }
            i = skip_blank(b, i + 1);
            let vstart = i;
            let vend = next_blank(line, i);
            let text = &line[vstart..vend];
            let Some(num) = number_of(text) else {
                self.error(
                    codes::KOR_SYNTAX,
                    base + vstart..base + vend,
                    if text.is_empty() {
                        format!("expected a value after `{}=`", char::from(k))
                    } else {
                        format!("`{text}` is not a number")
                    },
                    "a value looks like `20.0`, `-5.0` or `12.55`",
                );
                return None;
            };
            let span = base + vstart..base + vend;
            if seen[slot] {
                self.error(
                    codes::KOR_DUPLICATE_FIELD,
                    base + key_at..base + vend,
                    format!("{} is written twice in entry {n:02}", datum_name(slot)),
                    "write each datum once (an axis name and its ordinal are the same datum)",
                );
                return None;
            }
            seen[slot] = true;
            if slot == 5 {
                match (num.point, num.sign, num.milli / 1000) {
                    (false, false, p @ 1..=9) if num.milli % 1000 == 0 => {
                        entry.tip = u8::try_from(p).ok();
                    }
                    _ => {
                        self.error(
                            codes::KOR_VALUE,
                            span,
                            format!("tool-tip type `P={text}` is not allowed"),
                            "P takes a single digit 1..9",
                        );
                        return None;
                    }
                }
            } else {
                if num.decimals > 3 || num.milli.abs() > 999_999 {
                    self.error(
                        codes::KOR_VALUE,
                        span,
                        format!("correction value `{text}` out of format"),
                        "mm with at most 3 decimals, within ±999.999",
                    );
                    return None;
                }
                entry.data[slot] = num.milli as f64 / 1000.0;
            }
            i = vend;
        }
        Some((n, entry))
    }
}

fn datum_name(slot: usize) -> String {
    match slot {
        0 => "the radius R".into(),
        5 => "the tool-tip type P".into(),
        k => format!("the length of axis {k}"),
    }
}

fn skip_blank(b: &[u8], mut i: usize) -> usize {
    while i < b.len() && (b[i] == b' ' || b[i] == b'\t') {
        i += 1;
    }
    i
}

/// End of the run of non-blank characters starting at `i` (a char boundary).
fn next_blank(line: &str, i: usize) -> usize {
    line.get(i..)
        .and_then(|rest| rest.find([' ', '\t']))
        .map_or(line.len(), |k| i + k)
}

struct Num {
    milli: i64,
    point: bool,
    sign: bool,
    decimals: usize,
}

/// `[+-]digits[.digits]` with at least one digit, as thousandths (more decimals are counted, not kept).
fn number_of(text: &str) -> Option<Num> {
    let (sign, neg, body) = match text.as_bytes().first() {
        Some(b'-') => (true, true, &text[1..]),
        Some(b'+') => (true, false, &text[1..]),
        _ => (false, false, text),
    };
    let (int, frac, point) = match body.split_once('.') {
        Some((a, b)) => (a, b, true),
        None => (body, "", false),
    };
    let digits = |s: &str| s.bytes().all(|c| c.is_ascii_digit());
    if (int.is_empty() && frac.is_empty()) || !digits(int) || !digits(frac) {
        return None;
    }
    let int_v: i64 = match int.len() {
        0 => 0,
        1..=12 => int.parse().ok()?,
        _ => i64::MAX / 2000,
    };
    let mut f3 = 0i64;
    for (k, c) in frac.bytes().take(3).enumerate() {
        f3 += i64::from(c - b'0') * 10i64.pow(2 - k as u32);
    }
    let milli = int_v.saturating_mul(1000).saturating_add(f3);
    Some(Num {
        milli: if neg { -milli } else { milli },
        point,
        sign,
        decimals: frac.len(),
    })
}

/// Reads a `TAB*.KOR` text named `file` for a machine whose axes (in order) are `axes`; returns the
/// table it could read and the diagnostics (any error means the file is not usable).
pub fn parse_kor(file: &str, text: &str, axes: &[char]) -> (CorrectionTable, Vec<Diagnostic>) {
    // Diagnostics are located one by one: index the text once for all of them.
    let _lines = diag::Indexed::new(text);
    let mut r = Reader {
        file,
        text,
        axes,
        diags: Vec::new(),
    };
    let mut table = CorrectionTable::default();
    let Some(kw) = text.find("$KOR") else {
        r.error(
            codes::KOR_NO_KEYWORD,
            0..text.len().min(1),
            "no `$KOR` keyword: the file holds no correction table".into(),
            "the table starts after a line `$KOR`; text before it is a comment",
        );
        return (table, r.diags);
    };
    let after = kw + 4;
    let eol = text[after..].find('\n').map_or(text.len(), |k| after + k);
    let rest = text[after..eol].trim_end_matches('\r');
    if !rest.trim().is_empty() {
        let s = after + (rest.len() - rest.trim_start().len());
        r.error(
            codes::KOR_LINE,
            s..after + rest.len(),
            "text after `$KOR` on its line".into(),
            "entries start on the line after `$KOR`",
        );
    }
    let mut pos = (eol + 1).min(text.len());
    let mut where_defined: BTreeMap<u8, usize> = BTreeMap::new();
    while pos < text.len() {
        let end = text[pos..].find('\n').map_or(text.len(), |k| pos + k);
        let line = text[pos..end].trim_end_matches('\r');
        let trimmed = line.trim_start_matches([' ', '\t']);
        if trimmed.starts_with("$KOR") {
            let at = pos + (line.len() - trimmed.len());
            r.error(
                codes::KOR_SECOND_TABLE,
                at..at + 4,
                "a second `$KOR`: a file holds one table".into(),
                "keep one table per file; the lines after this one are not read",
            );
            break;
        }
        if !trimmed.trim_end().is_empty()
            && let Some((n, e)) = r.line(pos, line)
        {
            if let Some(first) = where_defined.get(&n) {
                let (l, _) = diag::line_column(text, *first);
                r.error(
                    codes::KOR_DUPLICATE_ENTRY,
                    pos..pos + line.len(),
                    format!("correction {n:02} is defined twice (first on line {l})"),
                    "each correction number once per file",
                );
            } else {
                where_defined.insert(n, pos);
                table.entries.insert(n, e);
            }
        }
        pos = end + 1;
    }
    (table, r.diags)
}
