//! The PLC message files: the texts of the messages the PLC program raises (docs/plc-messages.md).
//!
//! FCRSYS section 2 binds the common file to the logical name FILMS5 (`FILMS5,MESSAG/MP0`,
//! 003:571, 003:707); a process with a PGCFIL `FLC` instruction has its own file (third name,
//! `FInMSG`, 003:4763-4767), which replaces the common one for that process. The manual numbers a
//! message by its line in the file (003:665-673); ncplc writes the number on the line instead, so
//! that comments and gaps are possible: one message per line, `nnn text` (1–3 digits, 1..=64, at
//! least one blank, the text up to the end of the line, trailing blanks dropped); blank lines and
//! lines starting with `;` are skipped. Bytes are decoded as every characterization file is
//! ([`crate::decode`]: UTF-8, else CP866 or CP1251).
//!
//! **Invariants:** every line is either read or reported (946 malformed, 947 number out of range,
//! 948 number given twice); a file is read up to [`crate::reader::MAX_BYTES`] and in one pass, so
//! the work is linear in its size; nothing here panics on input.

use std::collections::BTreeMap;

use diag::{Diagnostic, Sink};
use serde::{Deserialize, Serialize};

use crate::codes;

/// The highest message number: connectors 21K and 22K carry 64 request bits.
pub const MAX_MESSAGE: u8 = 64;

/// The longest message text, in characters.
pub const MAX_TEXT: usize = 200;

/// The texts of one message file by number.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MessageFile {
    /// The file's name in diagnostics (relative to the machine directory, `MP0/MESSAG`).
    pub name: String,
    /// Message number (1..=64) → text.
    pub texts: BTreeMap<u8, String>,
}

/// The PLC message texts of a machine: the common file (FILMS5) and the processes' own (FLC).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlcMessages {
    /// The file FCRSYS binds to FILMS5, when it names one that could be read.
    pub common: Option<MessageFile>,
    /// Process number → the file its PGCFIL `FLC` names.
    pub processes: BTreeMap<u8, MessageFile>,
}

impl PlcMessages {
    /// The text of message `number` of `process`: from the process's own file when it has one,
    /// else from the common file; `None` when that file has no line for it.
    pub fn text(&self, process: u8, number: u8) -> Option<&str> {
        let file = self.processes.get(&process).or(self.common.as_ref())?;
        file.texts.get(&number).map(String::as_str)
    }

    /// The text shown for message `number` of `process`: [`PlcMessages::text`], or
    /// `PLC message n` when no file gives one.
    pub fn shown(&self, process: u8, number: u8) -> String {
        match self.text(process, number) {
            Some(t) => t.to_string(),
            None => format!("PLC message {number}"),
        }
    }
}

/// Reads one message file's decoded `text` (named `name` in diagnostics), pushing a located
/// diagnostic for every line that is not a message, a comment or blank.
pub fn parse_into(name: &str, text: &str, diags: &mut Sink) -> MessageFile {
    let mut file = MessageFile {
        name: name.to_string(),
        texts: BTreeMap::new(),
    };
    let mut first_line: BTreeMap<u8, u32> = BTreeMap::new();
    let mut start = 0usize;
    for (i, raw) in text.split_inclusive('\n').enumerate() {
        let line_no = u32::try_from(i + 1).unwrap_or(u32::MAX);
        let line = raw.trim_end_matches(['\n', '\r']);
        let at = start;
        start += raw.len();
        let trimmed = line.trim_start_matches([' ', '\t']);
        if trimmed.is_empty() || trimmed.starts_with(';') {
            continue;
        }
        let lead = line.len() - trimmed.len();
        let err = |code: u32, from: usize, len: usize, message: String, hint: &str| {
            let column = u32::try_from(line[..from].chars().count() + 1).unwrap_or(u32::MAX);
            let mut d =
                Diagnostic::error(code, name, at + from..at + from + len, message).with_hint(hint);
            d.line = line_no;
            d.column = column;
            d
        };
        let digits = trimmed.bytes().take_while(u8::is_ascii_digit).count();
        let rest = &trimmed[digits..];
        let body = rest.trim_matches([' ', '\t']);
        let bad_form = digits == 0
            || digits > 3
            || !(rest.starts_with(' ') || rest.starts_with('\t'))
            || body.is_empty();
        if bad_form {
            diags.push(err(
                codes::MESSAGE_LINE,
                lead,
                trimmed.len(),
                "not a message line: expected `nnn text` (a number 1..64, a blank, the text)"
                    .into(),
                "write e.g. `1 Lubrication level low`, or start a comment with `;`",
            ));
            continue;
        }
        if let Some(c) = body.chars().find(|c| c.is_control() && *c != '\t') {
            diags.push(err(
                codes::MESSAGE_LINE,
                lead + digits,
                rest.len(),
                format!(
                    "the message text holds the control character U+{:04X}",
                    c as u32
                ),
                "a message file is text: one message per line",
            ));
            continue;
        }
        if body.chars().count() > MAX_TEXT {
            diags.push(err(
                codes::MESSAGE_LINE,
                lead + digits,
                rest.len(),
                format!("the message text is longer than {MAX_TEXT} characters"),
                "shorten the text: the HMI shows one line per message",
            ));
            continue;
        }
        let number = trimmed[..digits]
            .parse::<u16>()
            .ok()
            .and_then(|n| u8::try_from(n).ok())
            .filter(|n| (1..=MAX_MESSAGE).contains(n));
        let Some(number) = number else {
            diags.push(err(
                codes::MESSAGE_NUMBER,
                lead,
                digits,
                format!(
                    "message number {} is outside 1..{MAX_MESSAGE}",
                    &trimmed[..digits]
                ),
                "connectors 21K and 22K carry messages 1..64 (docs/plc-messages.md)",
            ));
            continue;
        };
        if let Some(first) = first_line.get(&number) {
            diags.push(err(
                codes::MESSAGE_TWICE,
                lead,
                digits,
                format!("message {number} is given twice (first on line {first})"),
                "give each message number one line",
            ));
            continue;
        }
        first_line.insert(number, line_no);
        file.texts.insert(number, body.to_string());
    }
    file
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> (MessageFile, Vec<(u32, u32, u32)>) {
        let mut sink = Sink::unbounded();
        let f = parse_into("MP0/MESSAG", text, &mut sink);
        let (kept, _) = sink.finish();
        (f, kept.iter().map(|d| (d.code, d.line, d.column)).collect())
    }

    #[test]
    fn numbered_lines_comments_and_blanks() {
        let (f, d) = read("; lathe\n\n1 Lubrication level low  \r\n 64\tDoor open\n");
        assert_eq!(d, vec![]);
        assert_eq!(
            f.texts.get(&1).map(String::as_str),
            Some("Lubrication level low")
        );
        assert_eq!(f.texts.get(&64).map(String::as_str), Some("Door open"));
        assert_eq!(f.texts.len(), 2);
    }

    #[test]
    fn every_bad_line_is_located() {
        let text = "x text\n1\n0 zero\n65 high\n2 ok\n  2 again\n1234 long\n3\u{1}x\n";
        let (f, d) = read(text);
        assert_eq!(
            d,
            vec![
                (946, 1, 1),
                (946, 2, 1),
                (947, 3, 1),
                (947, 4, 1),
                (948, 6, 3),
                (946, 7, 1),
                (946, 8, 1),
            ]
        );
        assert_eq!(f.texts.keys().copied().collect::<Vec<_>>(), vec![2]);
    }

    proptest::proptest! {
        /// Any bytes: no panic, and every line that is neither blank nor a comment is either a
        /// message or exactly one diagnostic whose span lies inside the text.
        #[test]
        fn every_line_is_read_or_reported(bytes in proptest::collection::vec(
            proptest::prop_oneof![
                proptest::sample::select(b"0123456789 \t;\n\r".to_vec()),
                proptest::num::u8::ANY,
            ],
            0..400,
        )) {
            let text = crate::decode::decode(&bytes);
            let mut sink = Sink::unbounded();
            let f = parse_into("M", &text, &mut sink);
            let (kept, _) = sink.finish();
            let lines = text
                .split_inclusive('\n')
                .map(|l| l.trim_end_matches(['\n', '\r']).trim_start_matches([' ', '\t']))
                .filter(|l| !l.is_empty() && !l.starts_with(';'))
                .count();
            proptest::prop_assert_eq!(f.texts.len() + kept.len(), lines);
            for d in &kept {
                proptest::prop_assert!(d.span.end <= text.len() && d.line >= 1 && d.column >= 1);
            }
        }
    }

    #[test]
    fn the_process_file_replaces_the_common_one_and_a_missing_text_is_named() {
        let common = MessageFile {
            name: "MP0/MESSAG".into(),
            texts: BTreeMap::from([(1, "common".to_string())]),
        };
        let own = MessageFile {
            name: "MP0/FI2MSG".into(),
            texts: BTreeMap::from([(2, "own".to_string())]),
        };
        let m = PlcMessages {
            common: Some(common),
            processes: BTreeMap::from([(2, own)]),
        };
        assert_eq!(m.shown(1, 1), "common");
        assert_eq!(m.shown(2, 2), "own");
        assert_eq!(m.shown(2, 1), "PLC message 1");
        assert_eq!(PlcMessages::default().shown(1, 5), "PLC message 5");
    }
}
