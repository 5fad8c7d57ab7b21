//! Bounded work on hostile input (issue 12), counted, not timed: whatever the length of a file of
//! lines that are not records, the reader reports at most 51 diagnostics and stops; and every
//! diagnostic's line and column, found through the line index, are those a scan of the text gives.

use characterization::reader::read;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// `n` lines each starting with a digit (error 2): `n` errors below 50, else 50 and error 971.
    #[test]
    fn bad_lines_cost_at_most_fifty_one_diagnostics(
        lines in prop::collection::vec("[0-9][ -~]{0,40}", 1..400)
    ) {
        let text = lines.join("\n");
        let (f, d) = read("AXCFIL", text.as_bytes());
        let n = lines.len();
        if n < 50 {
            prop_assert_eq!(d.len(), n);
            prop_assert!(d.iter().all(|d| d.code == 2));
            prop_assert!(!f.abandoned);
        } else {
            prop_assert_eq!(d.len(), 51);
            prop_assert_eq!(d[50].code, 971);
            prop_assert_eq!(d[50].line, 50);
            prop_assert!(f.abandoned);
        }
        for x in &d {
            prop_assert_eq!((x.line, x.column), diag::line_column(&f.text, x.span.start));
        }
    }

    /// Random printable text (with Cyrillic) never yields more than two reader diagnostics per
    /// line (a non-ASCII character, 900, and the grammar error of the same line, e.g. 8), plus two
    /// for the whole file (work per diagnostic is bounded, so is the total).
    #[test]
    fn diagnostics_never_outnumber_lines(text in "[ -~\n\u{0410}-\u{044F}]{0,3000}") {
        let (_, d) = read("AXCFIL", text.as_bytes());
        // The input's lines: the file's text is kept only up to where reading stopped (971).
        let lines = text.lines().count().max(1);
        prop_assert!(d.len() <= 2 * lines + 2, "{} diagnostics for {} lines", d.len(), lines);
    }
}
