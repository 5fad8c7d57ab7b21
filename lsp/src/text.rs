//! A document's text with its line starts: LSP positions (line, UTF-16 column) ↔ byte offsets,
//! and the editor's incremental edits applied to the text.
//!
//! Invariant: `line_starts` always matches `text` (rebuilt after every edit, O(text)); every
//! conversion clamps out-of-range positions to the nearest valid place instead of failing, so no
//! client input can make the server panic.

use lsp_types::{Position, Range, TextDocumentContentChangeEvent};

/// The text of an open document and its line index.
#[derive(Debug, Clone, Default)]
pub struct Text {
    text: String,
    line_starts: Vec<usize>,
}

impl Text {
    /// Indexes `text`.
    pub fn new(text: String) -> Self {
        let mut t = Text {
            text,
            line_starts: Vec::new(),
        };
        t.reindex();
        t
    }

    fn reindex(&mut self) {
        self.line_starts.clear();
        self.line_starts.push(0);
        self.line_starts.extend(
            self.text
                .bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(i, _)| i + 1),
        );
    }

    /// The text.
    pub fn as_str(&self) -> &str {
        &self.text
    }

    /// The byte offset of an LSP position (clamped into the text, on a character boundary).
    pub fn offset(&self, p: Position) -> usize {
        let Some(&start) = self.line_starts.get(p.line as usize) else {
            return self.text.len();
        };
        let end = self
            .line_starts
            .get(p.line as usize + 1)
            .map_or(self.text.len(), |&e| e);
        let line = self.text.get(start..end).unwrap_or("");
        let mut units = 0u32;
        for (i, c) in line.char_indices() {
            if units >= p.character || c == '\n' {
                return start + i;
            }
            units += c.len_utf16() as u32;
        }
        end
    }

    /// The LSP position of byte `offset` (clamped to the text and back to a character boundary).
    pub fn position(&self, offset: usize) -> Position {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.line_starts.partition_point(|&s| s <= offset) - 1;
        let start = self.line_starts[line];
        let character: usize = self.text[start..offset].chars().map(char::len_utf16).sum();
        Position::new(line as u32, character as u32)
    }

    /// The LSP range of a byte range.
    pub fn range(&self, span: std::ops::Range<usize>) -> Range {
        Range::new(self.position(span.start), self.position(span.end))
    }

    /// Applies one change of `textDocument/didChange` (a ranged edit, or the whole text).
    pub fn apply(&mut self, change: &TextDocumentContentChangeEvent) {
        match change.range {
            Some(r) => {
                let a = self.offset(r.start);
                let b = self.offset(r.end).max(a);
                self.text.replace_range(a..b, &change.text);
            }
            None => self.text = change.text.clone(),
        }
        self.reindex();
    }

    /// Number of lines (a text ending with a newline has an empty last line).
    pub fn lines(&self) -> usize {
        self.line_starts.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_utf16_units_and_clamp() {
        let t = Text::new("U4A0 = I0A0 ; ж𝄞x\nB\n".to_string());
        // `ж` is 2 bytes and 1 unit, `𝄞` 4 bytes and 2 units.
        let x = t.as_str().find('x').expect("x");
        assert_eq!(t.position(x), Position::new(0, 17));
        assert_eq!(t.offset(Position::new(0, 17)), x);
        assert_eq!(t.offset(Position::new(1, 0)), x + 2);
        assert_eq!(t.offset(Position::new(0, 99)), x + 1);
        assert_eq!(t.offset(Position::new(9, 0)), t.as_str().len());
        assert_eq!(t.position(x + 99), Position::new(2, 0));
    }

    #[test]
    fn edits_apply_at_their_range() {
        let mut t = Text::new("U4A0 = I0A0\nU4A1 = I0A1\n".to_string());
        t.apply(&TextDocumentContentChangeEvent {
            range: Some(Range::new(Position::new(1, 7), Position::new(1, 11))),
            range_length: None,
            text: "/I0A2 * I0A3".to_string(),
        });
        assert_eq!(t.as_str(), "U4A0 = I0A0\nU4A1 = /I0A2 * I0A3\n");
        assert_eq!(t.lines(), 3);
    }
}
