//! Byte offset → 1-based line and column, in time independent of where the offset is.
//!
//! [`crate::line_column`] scans the text from its start, so locating one diagnostic per record of a
//! large file is quadratic (the issue-12 measurement: 8.6 MB of random text, 21,012 errors, 15 s).
//! A [`LineIndex`] is built once per text in one pass; each lookup is then a binary search over the
//! line starts plus a count of at most [`CHUNK`] bytes, whatever the length of the line.

/// Bytes between two character-count checkpoints.
pub const CHUNK: usize = 256;

/// Line starts and character-count checkpoints of one text, for fast line/column lookups.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LineIndex {
    /// Byte offset of the start of every line (the first is 0), for texts below 4 GiB: half
    /// the memory of `usize` offsets (a 50 MB file of short lines has millions of lines).
    starts: Vec<u32>,
    /// The same for a text of 4 GiB or more (then `starts` is empty).
    wide: Vec<usize>,
    /// Number of characters before byte `i * CHUNK`, for every `i`.
    chars: Vec<usize>,
}

/// True for the bytes that start a UTF-8 character (every byte but `0b10xx_xxxx`).
fn starts_char(b: u8) -> bool {
    (b as i8) >= -0x40
}

impl LineIndex {
    /// Indexes `text` in one pass.
    pub fn new(text: &str) -> Self {
        let bytes = text.as_bytes();
        // Counted first, so that the line starts take exactly their size (no doubling slack).
        let lines = 1 + bytes.iter().filter(|&&b| b == b'\n').count();
        let (mut starts, mut wide) = (Vec::new(), Vec::new());
        match u32::try_from(bytes.len()) {
            Ok(_) => {
                starts.reserve_exact(lines);
                starts.push(0);
                starts.extend(memchr_newlines(bytes).map(|i| i as u32));
            }
            Err(_) => {
                wide.reserve_exact(lines);
                wide.push(0);
                wide.extend(memchr_newlines(bytes));
            }
        }
        let mut chars = Vec::with_capacity(bytes.len() / CHUNK + 1);
        let mut count = 0;
        for chunk in bytes.chunks(CHUNK) {
            chars.push(count);
            count += chunk.iter().filter(|&&b| starts_char(b)).count();
        }
        chars.push(count);
        LineIndex {
            starts,
            wide,
            chars,
        }
    }

    /// Number of lines of the indexed text (a text without `\n` has one).
    pub fn lines(&self) -> usize {
        self.starts.len().max(self.wide.len())
    }

    /// Characters of `text` before byte `offset` (`offset <= text.len()`).
    fn chars_before(&self, text: &str, offset: usize) -> usize {
        let i = offset / CHUNK;
        let base = self.chars.get(i).copied().unwrap_or(0);
        let from = (i * CHUNK).min(offset);
        base + text.as_bytes()[from..offset]
            .iter()
            .filter(|&&b| starts_char(b))
            .count()
    }

    /// 1-based line and column (in characters) of byte `offset` of `text` (the text this index was
    /// built from), exactly as [`crate::line_column`] gives them.
    pub fn line_column(&self, text: &str, offset: usize) -> (u32, u32) {
        if self.lines() == 0 {
            // A default (never built) index: fall back to scanning.
            return crate::scan_line_column(text, offset);
        }
        let mut offset = offset.min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let (line, start) = if self.wide.is_empty() {
            let line = self
                .starts
                .partition_point(|&s| s as usize <= offset)
                .max(1);
            (line, self.starts[line - 1] as usize)
        } else {
            let line = self.wide.partition_point(|&s| s <= offset).max(1);
            (line, self.wide[line - 1])
        };
        let start = start.min(offset);
        let column = self.chars_before(text, offset) - self.chars_before(text, start) + 1;
        (
            u32::try_from(line).unwrap_or(u32::MAX),
            u32::try_from(column).unwrap_or(u32::MAX),
        )
    }
}

thread_local! {
    /// Indexes of the texts borrowed by live [`Indexed`] guards: (address, length, index).
    static ACTIVE: std::cell::RefCell<Vec<(usize, usize, std::rc::Rc<LineIndex>)>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// While alive, makes [`crate::line_column`] and [`crate::Diagnostic::locate`] on exactly this
/// text (same address and length) use a prebuilt [`LineIndex`] instead of scanning: front ends that
/// locate diagnostics one by one wrap their work in a guard and become linear without threading an
/// index through every function. Sound because the guard borrows the text: it can be neither
/// changed nor freed while the index is registered.
#[derive(Debug)]
pub struct Indexed<'a> {
    text: &'a str,
}

impl<'a> Indexed<'a> {
    /// Indexes `text` and registers the index for this thread until the guard is dropped.
    pub fn new(text: &'a str) -> Self {
        let index = std::rc::Rc::new(LineIndex::new(text));
        ACTIVE.with(|a| {
            a.borrow_mut()
                .push((text.as_ptr() as usize, text.len(), index))
        });
        Indexed { text }
    }
}

impl Drop for Indexed<'_> {
    fn drop(&mut self) {
        let key = (self.text.as_ptr() as usize, self.text.len());
        ACTIVE.with(|a| {
            let mut a = a.borrow_mut();
            if let Some(i) = a.iter().rposition(|(p, l, _)| (*p, *l) == key) {
                a.remove(i);
            }
        });
    }
}

/// The registered index of `text`, if a live [`Indexed`] guard holds this very text.
pub(crate) fn active(text: &str) -> Option<std::rc::Rc<LineIndex>> {
    let key = (text.as_ptr() as usize, text.len());
    ACTIVE.with(|a| {
        a.borrow()
            .iter()
            .rev()
            .find(|(p, l, _)| (*p, *l) == key)
            .map(|(_, _, i)| i.clone())
    })
}

/// 1-based line and column of every offset of `offsets` in `text`, exactly as
/// [`crate::line_column`] gives them, in one walk over the text: time linear in the text plus
/// `k log k` for `k` offsets, memory for the `k` answers only (no index of the text's lines: a
/// reader that keeps a few diagnostics of a huge file locates them without per-line storage).
pub fn line_columns(text: &str, offsets: &[usize]) -> Vec<(u32, u32)> {
    let mut order: Vec<usize> = (0..offsets.len()).collect();
    order.sort_by_key(|&i| offsets[i]);
    let bytes = text.as_bytes();
    let mut out = vec![(0, 0); offsets.len()];
    // Walk state: the line of byte `at` and the characters from that line's start to `at`.
    let (mut at, mut line, mut column) = (0usize, 1usize, 0usize);
    for i in order {
        let mut offset = offsets[i].min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        for &b in &bytes[at..offset] {
            if b == b'\n' {
                line += 1;
                column = 0;
            } else if starts_char(b) {
                column += 1;
            }
        }
        at = offset;
        out[i] = (
            u32::try_from(line).unwrap_or(u32::MAX),
            u32::try_from(column + 1).unwrap_or(u32::MAX),
        );
    }
    out
}

/// Offsets just after every `\n` of `bytes`.
fn memchr_newlines(bytes: &[u8]) -> impl Iterator<Item = usize> + '_ {
    bytes
        .iter()
        .enumerate()
        .filter(|&(_, &b)| b == b'\n')
        .map(|(i, _)| i + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_agrees_with_the_scanning_lookup_at_every_offset() {
        // Long Cyrillic line crossing several checkpoints, short lines, a trailing newline.
        let mut text = String::from("abc\n");
        text.push_str(&"дж".repeat(300));
        text.push_str("x\n\nлюбой\nend\n");
        let index = LineIndex::new(&text);
        for offset in 0..=text.len() + 3 {
            assert_eq!(
                index.line_column(&text, offset),
                crate::scan_line_column(&text, offset),
                "offset {offset}"
            );
        }
        assert_eq!(index.lines(), 6);
    }

    #[test]
    fn one_walk_locates_offsets_in_any_order_as_the_scanning_lookup() {
        let mut text = String::from("abc\n");
        text.push_str(&"дж".repeat(300));
        text.push_str("x\n\nлюбой\nend\n");
        // Every offset, in a scrambled order with repeats.
        let offsets: Vec<usize> = (0..=text.len() + 3)
            .map(|i| (i * 7919) % (text.len() + 4))
            .chain([5, 5, 0])
            .collect();
        let got = line_columns(&text, &offsets);
        for (o, lc) in offsets.iter().zip(got) {
            assert_eq!(lc, crate::scan_line_column(&text, *o), "offset {o}");
        }
        assert_eq!(line_columns(&text, &[]), []);
    }

    #[test]
    fn a_live_guard_serves_lookups_of_its_text_only() {
        let text = String::from("a\nbc\nd");
        let other = text.clone();
        {
            let _g = Indexed::new(&text);
            assert!(active(&text).is_some());
            assert!(active(&other).is_none());
            assert!(active(&text[1..]).is_none());
            assert_eq!(crate::line_column(&text, 4), (2, 3));
        }
        assert!(active(&text).is_none());
    }

    #[test]
    fn column_on_a_long_line_counts_characters() {
        let text = format!("{}z", "ё".repeat(1000));
        let index = LineIndex::new(&text);
        // 1000 two-byte characters, then `z` at byte 2000, the 1001st character.
        assert_eq!(index.line_column(&text, 2000), (1, 1001));
        assert_eq!(LineIndex::new("").line_column("", 5), (1, 1));
    }
}
