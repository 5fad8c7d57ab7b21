//! Reading a trace record by record: the header first, then one [`TickRecord`] at a time, so that
//! a replay of a trace of any length holds one record (and one line or frame) at a time.
//!
//! The form is chosen by the first byte that is not white space (`{`: text, see [`crate::text`];
//! anything else: binary, see [`crate::binary`]). Errors are located exactly as when the whole
//! file is parsed at once; after an error the reader yields nothing more. A line or frame longer
//! than [`MAX_RECORD_BYTES`] is an error, so no input makes the reader hold more than that.

use std::io::{BufRead, Chain, Cursor, Read};
use std::path::Path;

use crate::binary::{self, Decoded, Decoder};
use crate::{PartHeader, TickRecord, Trace, TraceError, text};

/// The longest line (text) or frame (binary) read: far beyond any record the recorder writes.
pub const MAX_RECORD_BYTES: usize = 16 << 20;

/// What a trace says before its first record.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Header {
    /// The logic tick the trace was recorded with, in ms.
    pub tick_ms: u32,
    /// The partprograms a part run recorded with (None: a logic-only trace).
    pub part: Option<PartHeader>,
    /// True for the text form (JSON Lines), false for the binary one.
    pub text: bool,
}

/// The input: the white space read to find the form, then the rest.
type Input<R> = Chain<Cursor<Vec<u8>>, R>;

/// A trace's records, read one at a time from `R`.
pub struct Reader<R: BufRead> {
    input: Input<R>,
    header: Header,
    /// The binary form's pending lists (None for text).
    decoder: Option<Decoder>,
    /// The 0-based number of the next line (text) or frame (binary).
    next: usize,
    /// A record read with the header (a binary trace's frame 1 when it is no part header), or
    /// the error reading it, and where it ends.
    first: Option<(Result<TickRecord, TraceError>, u64)>,
    /// Bytes up to the end of the last complete record (of the header before the first).
    complete: u64,
    /// Reading what a crash left: a last line without its line end is torn, not a record.
    whole_lines: bool,
    /// The previous record's tick (text: each must follow it).
    prev_t: Option<u64>,
    buf: Vec<u8>,
    bytes: u64,
    done: bool,
}

impl Reader<std::io::BufReader<std::fs::File>> {
    /// Opens the trace file at `path` and reads its header.
    pub fn open(path: &Path) -> Result<Self, TraceError> {
        Reader::new(std::io::BufReader::with_capacity(
            1 << 16,
            std::fs::File::open(path)?,
        ))
    }
}

impl<R: BufRead> Reader<R> {
    /// Reads the header of the trace `input` holds, in the form its first byte names.
    pub fn new(input: R) -> Result<Self, TraceError> {
        Reader::with_form(input, None)
    }

    /// [`Reader::new`] of a trace in the given form (true: text) or, with None, the form its first
    /// byte that is not white space names.
    pub(crate) fn with_form(input: R, text: Option<bool>) -> Result<Self, TraceError> {
        Reader::start(input, text, false)
    }

    /// Reads the header of what a crashed recording left (`<file>.partial`): the records come
    /// while they are complete — a line that ends in a line end and parses, a frame that ends
    /// in `0x00` and decodes — and [`Reader::complete_bytes`] says where the last one ends. An
    /// incomplete header is an error.
    pub fn recovering(input: R) -> Result<Self, TraceError> {
        Reader::start(input, None, true)
    }

    fn start(mut input: R, text: Option<bool>, whole_lines: bool) -> Result<Self, TraceError> {
        let (prefix, first_byte) = leading_white_space(&mut input)?;
        let text = text.unwrap_or(first_byte == Some(b'{'));
        let mut reader = Reader {
            input: Cursor::new(prefix).chain(input),
            header: Header {
                tick_ms: 0,
                part: None,
                text,
            },
            decoder: (!text).then(Decoder::default),
            next: 0,
            first: None,
            complete: 0,
            whole_lines,
            prev_t: None,
            buf: Vec::new(),
            bytes: 0,
            done: false,
        };
        if text {
            reader.text_header()?;
        } else {
            reader.binary_header()?;
        }
        Ok(reader)
    }

    /// The header.
    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Bytes of the input read so far (for progress).
    pub fn bytes_read(&self) -> u64 {
        self.bytes
    }

    /// Bytes of the input up to the end of the last record read (of the header, or a blank line
    /// after it, before the first): where the complete part of a torn file ends.
    pub fn complete_bytes(&self) -> u64 {
        self.complete
    }

    /// Reads every record into a whole [`Trace`].
    pub fn collect_trace(self) -> Result<Trace, TraceError> {
        let tick_ms = self.header.tick_ms;
        let part = self.header.part.clone();
        let ticks = self.collect::<Result<Vec<_>, _>>()?;
        Ok(Trace {
            tick_ms,
            ticks,
            part,
        })
    }

    /// Reads the next line or frame (ending in `sep`) into `buf`; false at the end of the input.
    fn read_unit(&mut self, sep: u8) -> Result<bool, TraceError> {
        self.buf.clear();
        let limit = MAX_RECORD_BYTES as u64 + 1;
        let n = (&mut self.input)
            .take(limit)
            .read_until(sep, &mut self.buf)?;
        self.bytes += n as u64;
        if self.buf.len() > MAX_RECORD_BYTES {
            let what = if sep == b'\n' { "line" } else { "frame" };
            let message = format!("longer than {MAX_RECORD_BYTES} bytes: no {what} of a trace");
            return Err(self.located(message));
        }
        if n > 0 && self.whole_lines && sep == b'\n' && self.buf.last() != Some(&b'\n') {
            return Err(self.located("torn: the last line has no line end".into()));
        }
        Ok(n > 0)
    }

    /// An error of the line or frame just read.
    fn located(&self, message: String) -> TraceError {
        if self.header.text {
            TraceError::Text {
                line: self.next + 1,
                message,
            }
        } else {
            TraceError::Binary {
                frame: self.next,
                message,
            }
        }
    }

    /// The line just read as text (without its line end).
    fn line(&self) -> Result<&str, TraceError> {
        let raw = self.buf.strip_suffix(b"\n").unwrap_or(&self.buf);
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        std::str::from_utf8(raw).map_err(|e| self.located(e.to_string()))
    }

    /// Reads the next line that is not blank; false at the end of the input.
    fn next_line(&mut self) -> Result<bool, TraceError> {
        loop {
            if !self.read_unit(b'\n')? {
                return Ok(false);
            }
            if !self.line()?.trim().is_empty() {
                return Ok(true);
            }
            self.next += 1;
            if self.header.tick_ms > 0 {
                self.complete = self.bytes;
            }
        }
    }

    fn text_header(&mut self) -> Result<(), TraceError> {
        if !self.next_line()? {
            return Err(TraceError::Text {
                line: 1,
                message: "empty trace: the header line is missing".into(),
            });
        }
        let (tick_ms, part) = text::parse_header(self.next, self.line()?)?;
        self.header.tick_ms = tick_ms;
        self.header.part = part;
        self.next += 1;
        self.complete = self.bytes;
        Ok(())
    }

    fn binary_header(&mut self) -> Result<(), TraceError> {
        let read = self.read_unit(0).map_err(|e| match e {
            // A first "frame" that long: most likely not a trace at all.
            TraceError::Binary { frame, message } => TraceError::Binary {
                frame,
                message: format!(
                    "not an ncplc trace: neither a text trace (a JSON header line first) nor a binary one ({message})"
                ),
            },
            other => other,
        })?;
        if !read {
            return Err(TraceError::Binary {
                frame: 0,
                message: "empty file".into(),
            });
        }
        self.header.tick_ms = binary::decode_header(0, &mut self.buf)?;
        self.next = 1;
        self.complete = self.bytes;
        // Frame 1 may be the part-run header: read on to the first record (whose error, if
        // any, is the iterator's first item).
        let complete = self.complete;
        match self.binary_record() {
            Ok(Some(r)) => self.first = Some((Ok(r), self.bytes)),
            Ok(None) => {}
            Err(e) => self.first = Some((Err(e), self.bytes)),
        }
        // The record read ahead is not yet handed out (a part header is complete at once).
        if self.header.part.is_none() {
            self.complete = complete;
        }
        Ok(())
    }

    /// The next record of a binary trace (None at its end).
    fn binary_record(&mut self) -> Result<Option<TickRecord>, TraceError> {
        loop {
            let read = self.read_unit(0)?;
            let Some(decoder) = self.decoder.as_mut() else {
                return Ok(None);
            };
            if !read {
                decoder.finish()?;
                return Ok(None);
            }
            let i = self.next;
            self.next += 1;
            match decoder.frame(i, &mut self.buf)? {
                Decoded::Record(r) => return Ok(Some(r)),
                Decoded::Part(p) => {
                    self.header.part = Some(p);
                    self.complete = self.bytes;
                }
                Decoded::Nothing => {}
            }
        }
    }

    /// The next record of a text trace (None at its end).
    fn text_record(&mut self) -> Result<Option<TickRecord>, TraceError> {
        if !self.next_line()? {
            return Ok(None);
        }
        let r = text::parse_tick(self.next, self.line()?, self.prev_t)?;
        self.next += 1;
        self.prev_t = Some(r.t);
        Ok(Some(r))
    }
}

impl<R: BufRead> Iterator for Reader<R> {
    type Item = Result<TickRecord, TraceError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        if let Some((r, end)) = self.first.take() {
            match &r {
                Ok(_) => self.complete = end,
                Err(_) => self.done = true,
            }
            return Some(r);
        }
        let r = if self.header.text {
            self.text_record()
        } else {
            self.binary_record()
        };
        match r {
            Ok(Some(r)) => {
                self.complete = self.bytes;
                Some(Ok(r))
            }
            Ok(None) => {
                self.done = true;
                None
            }
            Err(e) => {
                self.done = true;
                Some(Err(e))
            }
        }
    }
}

/// Reads the white space at the start of `input` (kept: it belongs to the first line or frame)
/// and peeks at the byte after it (None: the input is all white space).
fn leading_white_space(input: &mut impl BufRead) -> Result<(Vec<u8>, Option<u8>), TraceError> {
    let mut prefix = Vec::new();
    loop {
        let avail = input.fill_buf()?;
        if avail.is_empty() {
            return Ok((prefix, None));
        }
        match avail.iter().position(|b| !b.is_ascii_whitespace()) {
            Some(p) => {
                let first = avail[p];
                prefix.extend_from_slice(&avail[..p]);
                input.consume(p);
                return Ok((prefix, Some(first)));
            }
            None => {
                let n = avail.len();
                if prefix.len() + n > MAX_RECORD_BYTES {
                    return Err(TraceError::Binary {
                        frame: 0,
                        message: format!(
                            "not an ncplc trace: it starts with more than {MAX_RECORD_BYTES} bytes of white space"
                        ),
                    });
                }
                prefix.extend_from_slice(avail);
                input.consume(n);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{AxisId, binary};

    fn trace() -> Trace {
        let sig = |s: &str| s.parse().expect("signal");
        let part = PartHeader {
            kernel: "cnc 0.1 r1".into(),
            process: 1,
            program: Some("P1.nc".into()),
            crc32: Some("0badf00d".into()),
            ..PartHeader::default()
        };
        Trace {
            part: Some(part),
            tick_ms: 4,
            ticks: vec![
                TickRecord {
                    t: 0,
                    inputs: vec![(sig("I0A5"), 1), (sig("W3K0"), 145)],
                    outputs: vec![(sig("U4A0"), 1)],
                    positions: vec![(
                        AxisId {
                            process: 1,
                            axis: 'X',
                        },
                        1.5f64.to_bits(),
                    )],
                    ..TickRecord::default()
                },
                TickRecord {
                    t: 7,
                    outputs: vec![(sig("U4A0"), 0)],
                    forced: vec![(sig("U4A1"), 1)],
                    ..TickRecord::default()
                },
                TickRecord {
                    t: 9,
                    ..TickRecord::default()
                },
            ],
        }
    }

    fn both_forms() -> [Vec<u8>; 2] {
        let mut text = Vec::new();
        trace().write_text(&mut text).expect("text");
        [text, binary::encode(&trace()).expect("binary")]
    }

    /// What reading `bytes` through a buffer of `capacity` bytes gives, errors as text.
    fn read(bytes: &[u8], capacity: usize) -> Result<Trace, String> {
        Reader::new(std::io::BufReader::with_capacity(capacity, bytes))
            .and_then(Reader::collect_trace)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn a_reader_through_a_one_byte_buffer_reads_what_a_whole_read_reads_at_every_cut() {
        for bytes in both_forms() {
            assert_eq!(read(&bytes, 1), Ok(trace()));
            // Every prefix (a torn file), with blank lines and white space in front.
            for cut in 0..=bytes.len() {
                for lead in [&b""[..], b"\n \r\n"] {
                    let input = [lead, &bytes[..cut]].concat();
                    let whole = Trace::from_bytes(&input).map_err(|e| e.to_string());
                    assert_eq!(read(&input, 1), whole, "cut {cut}, lead {lead:?}");
                    assert_eq!(read(&input, 3), whole, "cut {cut}, lead {lead:?}");
                }
            }
        }
    }

    #[test]
    fn the_header_is_read_before_the_records_and_records_one_at_a_time() {
        for (bytes, text) in both_forms().into_iter().zip([true, false]) {
            let mut r = Reader::new(&bytes[..]).expect("header");
            assert_eq!(
                r.header(),
                &Header {
                    tick_ms: 4,
                    part: trace().part,
                    text
                }
            );
            let ticks: Vec<u64> = r.by_ref().map(|x| x.expect("record").t).collect();
            assert_eq!(ticks, [0, 7, 9]);
            assert_eq!(r.bytes_read(), bytes.len() as u64);
            assert!(r.next().is_none());
        }
    }

    #[test]
    fn an_error_ends_the_records_and_names_its_line() {
        let mut text = both_forms()[0].clone();
        text.extend_from_slice(b"{\"t\":12,\"out\":{\"U4A0\":\xff}}\n{\"t\":13}\n");
        let mut r = Reader::new(&text[..]).expect("header");
        assert_eq!(r.by_ref().take(3).filter(Result::is_ok).count(), 3);
        assert_eq!(
            r.next().map(|e| e.map_err(|e| e.to_string())),
            Some(Err(
                "line 5: invalid utf-8 sequence of 1 bytes from index 22".into()
            ))
        );
        assert!(r.next().is_none(), "nothing after an error");
    }

    #[test]
    fn a_line_or_frame_longer_than_the_limit_is_refused_without_reading_it_whole() {
        let mut text = both_forms()[0].clone();
        let long = MAX_RECORD_BYTES + 10;
        text.extend(std::iter::repeat_n(b' ', long));
        let mut r = Reader::new(&text[..]).expect("header");
        assert_eq!(r.by_ref().filter(Result::is_ok).count(), 3);
        let e = read(&text, 1 << 16).expect_err("too long");
        assert_eq!(
            e,
            format!("line 5: longer than {MAX_RECORD_BYTES} bytes: no line of a trace")
        );
        // Past the limit the reader stops reading: it held at most the limit and a buffer.
        let mut r = Reader::new(&text[..]).expect("header");
        while r.next().is_some() {}
        assert!(r.bytes_read() <= (both_forms()[0].len() + MAX_RECORD_BYTES + 1) as u64);
        let mut bin = both_forms()[1].clone();
        bin.extend(std::iter::repeat_n(7u8, long));
        assert_eq!(
            read(&bin, 1 << 16).expect_err("too long"),
            format!("frame 7: longer than {MAX_RECORD_BYTES} bytes: no frame of a trace")
        );
    }
}
