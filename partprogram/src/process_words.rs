//! The instructions of the process logic (PGCFIL) that a partprogram block may hold by mistake,
//! and the one a misspelt run of letters most likely meant.
//!
//! A block is words of one address letter and a number, so every run of letters in it is a
//! syntax error, and each gets the hint "did you mean `RPT`?" when the run is one edit from an
//! instruction. Only runs of two to four letters can be (an instruction has three letters and the
//! suggestion rule of [`diag::nearest`] allows one edit at these lengths), so the answers are
//! computed once, for every such run: a file of letter runs had one `nearest` search over the 53
//! instructions per error, a third of the time of `nc check` on it.

use std::collections::HashMap;
use std::sync::LazyLock;

/// The three-letter instructions of the process logic (PGCFIL, seed 003 table of chapter 3): a
/// partprogram block holding one was meant for the process, not for the part.
pub(crate) const PROCESS_INSTRUCTIONS: &[&str] = &[
    "CLS", "DPT", "RED", "BNC", "DIS", "SCR", "BGT", "TOF", "WRT", "BLT", "RQU", "BEQ", "RQP",
    "BNE", "UCG", "BGE", "CLG", "BLE", "DCG", "EPP", "RPT", "DEF", "ERP", "FIL", "UAO", "TGL",
    "UOT", "DFP", "UIO", "EPF", "MIR", "SPA", "URT", "SPF", "SPP", "CLP", "DLY", "CAN", "RLG",
    "DLO", "CLO", "BSP", "DSA", "CRE", "ESP", "ASC", "DER", "DSC", "INP", "CTL", "OPN", "DAM",
    "OUT",
];

/// Every run of upper-case letters one edit from an instruction (a letter deleted, inserted,
/// replaced, or two neighbours swapped), with the instruction [`diag::nearest`] suggests for it.
static NEAR: LazyLock<HashMap<String, &'static str>> = LazyLock::new(|| {
    let mut runs: Vec<String> = Vec::new();
    for word in PROCESS_INSTRUCTIONS {
        let w = word.as_bytes();
        for i in 0..w.len() {
            let mut d = w.to_vec();
            d.remove(i);
            runs.push(String::from_utf8_lossy(&d).into_owned());
            if i + 1 < w.len() {
                let mut t = w.to_vec();
                t.swap(i, i + 1);
                runs.push(String::from_utf8_lossy(&t).into_owned());
            }
        }
        for letter in b'A'..=b'Z' {
            for i in 0..=w.len() {
                let mut ins = w.to_vec();
                ins.insert(i, letter);
                runs.push(String::from_utf8_lossy(&ins).into_owned());
                if i < w.len() {
                    let mut sub = w.to_vec();
                    sub[i] = letter;
                    runs.push(String::from_utf8_lossy(&sub).into_owned());
                }
            }
        }
    }
    runs.into_iter()
        .filter_map(|run| {
            let meant = diag::nearest(&run, PROCESS_INSTRUCTIONS.iter().copied())?;
            Some((run, meant))
        })
        .collect()
});

/// The instruction `run` (upper-case letters) is, or the one it most likely meant: exactly what
/// [`diag::nearest`] over [`PROCESS_INSTRUCTIONS`] gives, looked up in constant time.
pub(crate) fn instruction_meant(run: &str) -> Option<(&'static str, bool)> {
    if let Some(known) = PROCESS_INSTRUCTIONS.iter().find(|w| **w == run) {
        return Some((known, true));
    }
    if !(2..=4).contains(&run.len()) {
        return None;
    }
    NEAR.get(run).map(|meant| (*meant, false))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every run of two and three letters, and of four letters over the instructions' own letters
    /// plus two others, gets exactly the suggestion of the search it replaces.
    #[test]
    fn the_table_agrees_with_nearest_on_every_short_run() {
        let all: Vec<u8> = (b'A'..=b'Z').collect();
        let mut four: Vec<u8> = PROCESS_INSTRUCTIONS
            .iter()
            .flat_map(|w| w.bytes())
            .chain([b'K', b'Z'])
            .collect();
        four.sort_unstable();
        four.dedup();
        let mut runs: Vec<String> = Vec::new();
        for a in &all {
            for b in &all {
                runs.push(String::from_utf8_lossy(&[*a, *b]).into_owned());
                for c in &all {
                    runs.push(String::from_utf8_lossy(&[*a, *b, *c]).into_owned());
                }
            }
        }
        for a in &four {
            for b in &four {
                for c in &four {
                    for d in &four {
                        runs.push(String::from_utf8_lossy(&[*a, *b, *c, *d]).into_owned());
                    }
                }
            }
        }
        runs.extend(["RPTT", "CLOSE", "R", "ABCDEFGH"].map(String::from));
        let mut suggested = 0;
        for run in &runs {
            let known = PROCESS_INSTRUCTIONS.iter().find(|w| **w == run).copied();
            let expected = match known {
                Some(k) => Some((k, true)),
                None => {
                    diag::nearest(run, PROCESS_INSTRUCTIONS.iter().copied()).map(|m| (m, false))
                }
            };
            assert_eq!(instruction_meant(run), expected, "{run}");
            suggested += usize::from(expected.is_some_and(|(_, known)| !known));
        }
        assert!(suggested > 5_000, "{suggested}");
        assert_eq!(instruction_meant("RPTT"), Some(("RPT", false)));
        // One edit from RPT (swapped) and from RQP (replaced): the first in the table wins.
        assert_eq!(instruction_meant("RTP"), Some(("RQP", false)));
        assert_eq!(instruction_meant("DLYY"), Some(("DLY", false)));
        assert_eq!(instruction_meant("CLOSE"), None);
    }
}
