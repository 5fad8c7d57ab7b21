//! The zero-offset table file `TAB0.POS` (structure-motion spec §9.2, §9.4, §9.6): the offsets of
//! the program zeros G53…G59 from machine zero, copied into the system tables at power-up.
//!
//! The manual leaves the file's layout to the operator's manual, which we do not have; ncplc reads
//! it in the shape of `TAB0.KOR`: everything before the keyword `$POS` is a comment, then one row
//! per line: the function `G53`…`G59` and `:`, then `axis=value` fields separated by blanks, the
//! axis by the machine's name (`X=`) or ordinal (`1=`..`6=`). Values are mm (degrees for a rotary
//! axis); rows and fields not written are zero. [`parse_pos`] returns the table it could read and
//! located diagnostics (codes 2070–2075); it never panics. A Fanuc program reads rows G54…G59 as
//! its work offsets (G54 is its power-up system); a MEFI program selects them with G53…G59.

use diag::Diagnostic;

use crate::codes;

/// The zero-offset table: row k = G53+k, column = machine axis ordinal − 1 (mm).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct ZeroOffsets {
    /// Rows G53..G59, six axis columns each.
    pub rows: [[f64; 6]; 7],
}

/// Reads a `TAB0.POS` text named `file` for a machine whose axes (in order) are `axes`; returns
/// the table it could read and the diagnostics (any error means the file is not usable).
pub fn parse_pos(file: &str, text: &str, axes: &[char]) -> (ZeroOffsets, Vec<Diagnostic>) {
    let mut table = ZeroOffsets::default();
    let mut diags = Vec::new();
    let mut err = |code: u32, span: std::ops::Range<usize>, msg: String, help: &str| {
        diags.push(
            Diagnostic::error(code, file.to_string(), span, msg)
                .with_hint(help)
                .locate(text),
        );
    };
    let Some(kw) = text.find("$POS") else {
        err(
            codes::POS_NO_KEYWORD,
            0..text.len().min(1),
            "no `$POS` keyword: the file holds no zero-offset table".into(),
            "the table starts after a line `$POS`; text before it is a comment",
        );
        return (table, diags);
    };
    let mut seen = [false; 7];
    let mut pos = text[kw..].find('\n').map_or(text.len(), |k| kw + k + 1);
    while pos < text.len() {
        let end = text[pos..].find('\n').map_or(text.len(), |k| pos + k);
        let line = text[pos..end].trim_end_matches('\r');
        let start = pos;
        pos = end + 1;
        let body = line.trim_start();
        if body.is_empty() {
            continue;
        }
        let at = start + (line.len() - body.len());
        let Some((head, fields)) = body.split_once(':') else {
            err(
                codes::POS_LINE,
                at..start + line.len(),
                "a row is `G5x:` followed by `axis=value` fields".into(),
                "for example `G54: X=-400 Y=-250 Z=-200`",
            );
            continue;
        };
        let row = match head.trim() {
            "G53" => 0,
            "G54" => 1,
            "G55" => 2,
            "G56" => 3,
            "G57" => 4,
            "G58" => 5,
            "G59" => 6,
            other => {
                err(
                    codes::POS_LINE,
                    at..at + head.len(),
                    format!("`{other}` is not a zero-offset function"),
                    "rows are G53 … G59",
                );
                continue;
            }
        };
        if std::mem::replace(&mut seen[row], true) {
            err(
                codes::POS_DUPLICATE,
                at..at + head.len(),
                format!("G5{} is written twice", row + 3),
                "write each row once",
            );
            continue;
        }
        let mut off = at + head.len() + 1;
        for word in fields.split([' ', '\t']) {
            let w_at = off;
            off += word.len() + 1;
            if word.is_empty() {
                continue;
            }
            let span = w_at..w_at + word.len();
            let Some((name, value)) = word.split_once('=') else {
                err(
                    codes::POS_LINE,
                    span,
                    format!("`{word}` is not `axis=value`"),
                    "write fields without blanks around `=`, e.g. `X=-400`",
                );
                continue;
            };
            let col = match name.parse::<usize>() {
                Ok(n) if (1..=6).contains(&n) && n <= axes.len() => Some(n - 1),
                Ok(_) => None,
                Err(_) => {
                    let mut c = name.chars();
                    match (c.next(), c.next()) {
                        (Some(a), None) => axes.iter().take(6).position(|x| *x == a),
                        _ => None,
                    }
                }
            };
            let Some(col) = col else {
                err(
                    codes::POS_AXIS,
                    span,
                    format!("`{name}` is not an axis of the machine"),
                    "use the axis letters of AXCFIL or the ordinals 1..6",
                );
                continue;
            };
            match value.parse::<f64>() {
                Ok(v) if v.is_finite() && v.abs() <= 99_999.999 => table.rows[row][col] = v,
                _ => err(
                    codes::POS_VALUE,
                    span,
                    format!("`{value}` is not an offset in mm"),
                    "a number of at most ±99999.999",
                ),
            }
        }
    }
    (table, diags)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_by_name_and_ordinal_the_rest_zero() {
        let text = "comment\n$POS\nG54: X=-400 Y=-250.5 3=-200\n\nG57: Z=1\n";
        let (t, d) = parse_pos("TAB0.POS", text, &['X', 'Y', 'Z']);
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(t.rows[1], [-400.0, -250.5, -200.0, 0.0, 0.0, 0.0]);
        assert_eq!(t.rows[4], [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
        assert_eq!(t.rows[0], [0.0; 6]);
    }

    #[test]
    fn bad_rows_are_located_errors() {
        let text = "$POS\nG60: X=1\nG54: Q=1 X=abc\nG54: X=1\nG55 X=1\n";
        let (t, d) = parse_pos("TAB0.POS", text, &['X', 'Z']);
        let codes: Vec<u32> = d.iter().map(|d| d.code).collect();
        assert_eq!(
            codes,
            [
                codes::POS_LINE,
                codes::POS_AXIS,
                codes::POS_VALUE,
                codes::POS_DUPLICATE,
                codes::POS_LINE
            ]
        );
        assert_eq!(t, ZeroOffsets::default());
        let (_, d) = parse_pos("TAB0.POS", "G54: X=1\n", &['X']);
        assert_eq!(d[0].code, codes::POS_NO_KEYWORD);
    }
}
