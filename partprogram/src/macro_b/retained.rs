//! The retained Macro B variables `#500`–`#999`: a Fanuc control keeps them across programs and
//! power cycles. ncplc keeps them in the machine's file `nc/MACROVARS` (the runtime reads and
//! writes it; this module is its format and the table it holds).
//!
//! The file is text, one variable per line, `#<n> = <value>` with `n` in 500..=999 and the value a
//! finite decimal number (an exponent `1.5e-7` is allowed); a variable not written is null (`#0`);
//! blank lines and `( … )` comments are ignored. [`format_retained`] writes every non-null variable
//! in number order with the shortest text that reads back as the same `f64` bits, so a file written
//! and read again gives the same plan. [`parse_retained`] returns the values it could read and
//! located diagnostics (2076–2079); any error makes the file unusable: never a value silently
//! dropped.

use std::collections::BTreeMap;

use diag::Diagnostic;

use crate::codes;

/// The first retained variable.
pub const FIRST: u32 = 500;
/// The last retained variable.
pub const LAST: u32 = 999;

/// The values of the retained variables that are not null, by number.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Retained {
    /// Variable number (500..=999) → value (finite).
    pub values: BTreeMap<u32, f64>,
}

impl Retained {
    /// The retained part of a plan's variable table (slot n is #n; NaN is null).
    pub fn from_slots(slots: &[f64]) -> Retained {
        let values = (FIRST..=LAST)
            .filter_map(|n| {
                let v = *slots.get(n as usize)?;
                v.is_finite().then_some((n, v))
            })
            .collect();
        Retained { values }
    }

    /// Writes these values into a variable table (the others stay null).
    pub fn load_into(&self, slots: &mut [f64]) {
        for (n, v) in &self.values {
            if let Some(s) = slots.get_mut(*n as usize) {
                *s = *v;
            }
        }
    }

    /// The variables a plan changed: every number whose value in `after` differs (in bits, null
    /// included) from `before`, written over `self` (null in `after` removes it).
    pub fn apply_changes(&mut self, before: &Retained, after: &Retained) {
        for n in FIRST..=LAST {
            let (b, a) = (before.values.get(&n), after.values.get(&n));
            if b.map(|x| x.to_bits()) == a.map(|x| x.to_bits()) {
                continue;
            }
            match a {
                Some(v) => self.values.insert(n, *v),
                None => self.values.remove(&n),
            };
        }
    }
}

/// The file text of `r` (see the module doc).
pub fn format_retained(r: &Retained) -> String {
    let mut s =
        String::from("(ncplc retained macro variables #500-#999; null ones are not listed)\n");
    for (n, v) in &r.values {
        let a = v.abs();
        if a != 0.0 && !(1e-5..1e16).contains(&a) {
            s.push_str(&format!("#{n} = {v:e}\n"));
        } else {
            s.push_str(&format!("#{n} = {v}\n"));
        }
    }
    s
}

/// Reads a retained-variables text named `file`; returns the values it could read and the
/// diagnostics (any error means the file is not usable).
pub fn parse_retained(file: &str, text: &str) -> (Retained, Vec<Diagnostic>) {
    let mut out = Retained::default();
    let mut diags = Vec::new();
    let mut err = |code: u32, span: std::ops::Range<usize>, msg: String, help: &str| {
        diags.push(
            Diagnostic::error(code, file.to_string(), span, msg)
                .with_hint(help)
                .locate(text),
        );
    };
    let mut pos = 0;
    while pos < text.len() {
        let end = text[pos..].find('\n').map_or(text.len(), |k| pos + k);
        let raw = text[pos..end].trim_end_matches('\r');
        let start = pos;
        pos = end + 1;
        // A comment runs from `(` to the end of the line.
        let line = raw.split('(').next().unwrap_or("");
        let body = line.trim();
        if body.is_empty() {
            continue;
        }
        let at = start + (line.len() - line.trim_start().len());
        let span = at..at + body.len();
        let Some((var, value)) = body.strip_prefix('#').and_then(|rest| rest.split_once('='))
        else {
            err(
                codes::VARS_LINE,
                span,
                format!("`{body}` is not `#<n> = <value>`"),
                "one retained variable per line, for example `#500 = 1.25`",
            );
            continue;
        };
        let var_t = var.trim();
        let Some(n) = var_t
            .parse::<u32>()
            .ok()
            .filter(|_| var_t.bytes().all(|c| c.is_ascii_digit()))
            .filter(|n| (FIRST..=LAST).contains(n))
        else {
            err(
                codes::VARS_NUMBER,
                span,
                format!("`#{var_t}` is not a retained variable"),
                "the file holds #500 … #999 only",
            );
            continue;
        };
        let value_t = value.trim();
        let numeric = !value_t.is_empty()
            && value_t
                .bytes()
                .all(|c| c.is_ascii_digit() || matches!(c, b'+' | b'-' | b'.' | b'e' | b'E'));
        let Some(v) = value_t
            .parse::<f64>()
            .ok()
            .filter(|v| numeric && v.is_finite())
        else {
            err(
                codes::VARS_VALUE,
                span,
                format!("#{n}: `{value_t}` is not a finite number"),
                "a decimal number such as `-12.5` or `1.5e-7`; leave a null variable out",
            );
            continue;
        };
        if out.values.insert(n, v).is_some() {
            err(
                codes::VARS_DUPLICATE,
                span,
                format!("#{n} is written twice"),
                "keep one line per variable",
            );
        }
    }
    (out, diags)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn retained_round_trip_keeps_bits() {
        let mut r = Retained::default();
        for (n, v) in [
            (500, 1.25),
            (501, -0.1),
            (502, 1e300),
            (503, 3e-9),
            (999, 0.0),
        ] {
            r.values.insert(n, v);
        }
        let text = format_retained(&r);
        assert!(text.contains("#500 = 1.25\n#501 = -0.1\n#502 = 1e300\n#503 = 3e-9\n#999 = 0\n"));
        let (back, diags) = parse_retained("nc/MACROVARS", &text);
        assert!(diags.is_empty(), "{diags:?}");
        assert_eq!(back, r);
    }

    #[test]
    fn retained_errors_are_located() {
        let text = "#500 = 1\n#100 = 2\n#501 = abc (why)\n#500 = 3\nX\n#502 = inf\n";
        let (_, d) = parse_retained("V", text);
        let got: Vec<(u32, u32)> = d.iter().map(|d| (d.code, d.line)).collect();
        assert_eq!(
            got,
            vec![
                (codes::VARS_NUMBER, 2),
                (codes::VARS_VALUE, 3),
                (codes::VARS_DUPLICATE, 4),
                (codes::VARS_LINE, 5),
                (codes::VARS_VALUE, 6)
            ]
        );
    }

    #[test]
    fn retained_changes_merge_in_order() {
        let mut base = Retained::default();
        base.values.insert(500, 1.0);
        base.values.insert(501, 2.0);
        let before = base.clone();
        let mut after = base.clone();
        after.values.insert(502, 7.0);
        after.values.remove(&501);
        let mut persisted = base.clone();
        persisted.values.insert(500, 9.0); // an earlier run changed #500
        persisted.apply_changes(&before, &after);
        assert_eq!(
            persisted.values.into_iter().collect::<Vec<_>>(),
            vec![(500, 9.0), (502, 7.0)]
        );
    }
}
