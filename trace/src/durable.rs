//! A recording that survives a crash: the scan encodes each record into a lock-free byte ring
//! (`rtrb`), and a writer thread drains the ring into `<path>.partial` and syncs it to disk every
//! flush period. A `kill -9` loses at most what the ring held (one drain period); a power loss at
//! most one flush period plus the sync itself. The framing (one JSON line or one COBS frame per
//! record) makes a torn tail detectable: [`super::recover`] reads everything before it.
//!
//! The scan never waits on the disk: with a real clock a full ring stops the recording (the file
//! keeps every tick up to the last record that fit) and [`TraceSink::finish`] reports it; in
//! virtual time nothing is real-time, so the scan waits for room instead.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::binary::BinaryWriter;
use super::text::TextWriter;
use super::{PartHeader, TickRecord, TraceError, TraceSink};

/// How a durable recording behaves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DurableOptions {
    /// The longest time between two syncs of the file to disk (the bound on what a power loss
    /// loses); the ring is drained into the file at least every 100 ms.
    pub flush: Duration,
    /// Wait for room when the ring is full (virtual time) instead of stopping the recording.
    pub wait_when_full: bool,
    /// Ring size in bytes.
    pub ring_bytes: usize,
}

impl Default for DurableOptions {
    fn default() -> Self {
        DurableOptions {
            flush: Duration::from_secs(1),
            wait_when_full: true,
            ring_bytes: 8 << 20,
        }
    }
}

/// The record encoder of a recording, writing into a staging buffer.
enum Encoder {
    Binary(BinaryWriter<Vec<u8>>),
    Text(TextWriter<Vec<u8>>),
}

impl Encoder {
    fn record(&mut self, rec: &TickRecord) -> Result<(), TraceError> {
        match self {
            Encoder::Binary(w) => TraceSink::record(w, rec),
            Encoder::Text(w) => TraceSink::record(w, rec),
        }
    }

    fn staged(&mut self) -> &mut Vec<u8> {
        match self {
            Encoder::Binary(w) => w.get_mut(),
            Encoder::Text(w) => w.get_mut(),
        }
    }
}

/// A recording into `<target>.partial` through a ring and a writer thread, renamed over `target`
/// when finished.
pub struct DurableSink {
    encoder: Encoder,
    ring: rtrb::Producer<u8>,
    options: DurableOptions,
    stop: Arc<AtomicBool>,
    writer: Option<JoinHandle<Result<(), std::io::Error>>>,
    /// The tick of the last record that went into the ring.
    last_tick: Option<u64>,
    /// Records that did not fit (the recording stopped at the first).
    dropped: u64,
    partial: PathBuf,
    target: PathBuf,
    done: bool,
}

impl DurableSink {
    /// Creates `<target>.partial` (mode 0666 less the umask), writes the header and starts the
    /// writer thread; binary when `binary`, JSON Lines otherwise.
    pub fn create(
        target: &Path,
        partial: PathBuf,
        tick_ms: u32,
        binary: bool,
        options: DurableOptions,
    ) -> Result<DurableSink, TraceError> {
        Self::create_with_part(target, partial, tick_ms, None, binary, options)
    }

    /// [`DurableSink::create`] with a header that names the partprograms of a part run.
    pub fn create_with_part(
        target: &Path,
        partial: PathBuf,
        tick_ms: u32,
        part: Option<&PartHeader>,
        binary: bool,
        options: DurableOptions,
    ) -> Result<DurableSink, TraceError> {
        let file = File::create(&partial)?;
        let (ring, consumer) = rtrb::RingBuffer::new(options.ring_bytes.max(1024));
        let encoder = if binary {
            Encoder::Binary(BinaryWriter::with_part(
                Vec::with_capacity(4096),
                tick_ms,
                part,
            )?)
        } else {
            Encoder::Text(TextWriter::with_part(
                Vec::with_capacity(4096),
                tick_ms,
                part,
            )?)
        };
        let stop = Arc::new(AtomicBool::new(false));
        let flush = options.flush.max(Duration::from_millis(1));
        let writer = {
            let stop = stop.clone();
            std::thread::Builder::new()
                .name("ncplc-record".into())
                .spawn(move || write_loop(file, consumer, &stop, flush))?
        };
        let mut sink = DurableSink {
            encoder,
            ring,
            options,
            stop,
            writer: Some(writer),
            last_tick: None,
            dropped: 0,
            partial,
            target: target.to_path_buf(),
            done: false,
        };
        sink.push_staged();
        Ok(sink)
    }

    /// Moves the staged bytes into the ring (all or nothing, so the file only ever holds whole
    /// records). Returns false when they did not fit and the recording stopped.
    fn push_staged(&mut self) -> bool {
        let staged = std::mem::take(self.encoder.staged());
        let mut ok = self.dropped == 0;
        while ok && self.ring.push_entire_slice(&staged).is_err() {
            if self.options.wait_when_full && staged.len() <= self.ring.buffer().capacity() {
                if let Some(w) = &self.writer {
                    w.thread().unpark();
                }
                std::thread::sleep(Duration::from_micros(200));
            } else {
                ok = false;
            }
        }
        if !ok {
            self.dropped += 1;
        }
        // Give the buffer back so that the next record reuses its allocation.
        let mut staged = staged;
        staged.clear();
        *self.encoder.staged() = staged;
        ok
    }

    fn stop_writer(&mut self) -> Result<(), TraceError> {
        self.stop.store(true, Ordering::Release);
        if let Some(w) = self.writer.take() {
            w.thread().unpark();
            match w.join() {
                Ok(r) => r?,
                Err(_) => {
                    return Err(TraceError::Io(std::io::Error::other(
                        "the recording thread panicked",
                    )));
                }
            }
        }
        Ok(())
    }
}

impl TraceSink for DurableSink {
    fn record(&mut self, rec: &TickRecord) -> Result<(), TraceError> {
        if self.dropped > 0 {
            self.dropped += 1;
            return Ok(());
        }
        self.encoder.record(rec)?;
        if self.push_staged() {
            self.last_tick = Some(rec.t);
        }
        Ok(())
    }

    fn flush(&mut self) -> Result<(), TraceError> {
        // The writer thread flushes on its own schedule; wake it so that it drains now.
        if let Some(w) = &self.writer {
            w.thread().unpark();
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), TraceError> {
        if self.done {
            return Ok(());
        }
        self.stop_writer()?;
        self.done = true;
        if self.dropped > 0 {
            let upto = self
                .last_tick
                .map_or("no tick".to_string(), |t| format!("tick {t}"));
            return Err(TraceError::Io(std::io::Error::other(format!(
                "the disk did not keep up: {} records after {upto} were not recorded; {} keeps the ticks up to {upto}",
                self.dropped,
                self.partial.display()
            ))));
        }
        std::fs::rename(&self.partial, &self.target)?;
        let dir = self
            .target
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
        Ok(())
    }
}

impl Drop for DurableSink {
    fn drop(&mut self) {
        // An unfinished recording (an error ended the run): keep what was recorded in `.partial`.
        let _ = self.stop_writer();
    }
}

/// The writer thread: drains the ring into the file at least every 100 ms (or when woken) and
/// syncs the file every `flush`; on stop, drains and syncs once more.
fn write_loop(
    mut file: File,
    mut ring: rtrb::Consumer<u8>,
    stop: &AtomicBool,
    flush: Duration,
) -> Result<(), std::io::Error> {
    let drain_every = flush.min(Duration::from_millis(100));
    let mut last_sync = Instant::now();
    let mut unsynced = false;
    loop {
        let stopping = stop.load(Ordering::Acquire);
        let n = ring.slots();
        if n > 0 {
            let chunk = ring
                .read_chunk(n)
                .map_err(|e| std::io::Error::other(e.to_string()))?;
            let (a, b) = chunk.as_slices();
            file.write_all(a)?;
            file.write_all(b)?;
            chunk.commit_all();
            unsynced = true;
        }
        if unsynced && (stopping || last_sync.elapsed() >= flush) {
            file.sync_data()?;
            last_sync = Instant::now();
            unsynced = false;
        }
        if stopping {
            return Ok(());
        }
        std::thread::park_timeout(drain_every);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Trace;

    #[test]
    fn records_reach_the_partial_file_within_a_drain_period_without_finish() {
        let dir = tempfile::tempdir().expect("tempdir");
        let target = dir.path().join("run.ptrace");
        let partial = dir.path().join("run.ptrace.partial");
        let options = DurableOptions {
            flush: Duration::from_millis(20),
            ..DurableOptions::default()
        };
        let mut sink =
            DurableSink::create(&target, partial.clone(), 5, true, options).expect("sink");
        for t in [0, 3, 9] {
            sink.record(&TickRecord::at(t)).expect("record");
        }
        // Nobody calls flush or finish (the process is about to be killed): the writer thread
        // alone must bring the records to the file.
        let deadline = Instant::now() + Duration::from_secs(5);
        let mut seen = Vec::new();
        while Instant::now() < deadline {
            if let Ok(t) = Trace::load(&partial) {
                seen = t.ticks.iter().map(|r| r.t).collect();
                if seen.len() == 3 {
                    break;
                }
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        assert_eq!(seen, [0, 3, 9]);
        sink.finish().expect("finish");
        assert!(!partial.exists());
        assert_eq!(Trace::load(&target).expect("target").tick_ms, 5);
    }

    #[test]
    fn a_full_ring_in_real_time_stops_the_recording_and_finish_says_so() {
        let dir = tempfile::tempdir().expect("tempdir");
        let target = dir.path().join("run.jsonl");
        let partial = dir.path().join("run.jsonl.partial");
        let options = DurableOptions {
            flush: Duration::from_secs(3600),
            wait_when_full: false,
            ring_bytes: 1024,
        };
        let mut sink =
            DurableSink::create(&target, partial.clone(), 1, false, options).expect("sink");
        // Each line `{"t":N}\n` is 8..12 bytes; far more than 1024 bytes in one burst, faster
        // than the writer's 100 ms drain period.
        for t in 0..1000 {
            sink.record(&TickRecord::at(t)).expect("record");
        }
        let e = sink.finish().expect_err("records were dropped").to_string();
        assert!(
            e.starts_with("the disk did not keep up: "),
            "unexpected message: {e}"
        );
        assert!(!target.exists());
        // What was recorded is a clean prefix.
        let kept = Trace::load(&partial).expect("the partial file is complete");
        let ticks: Vec<u64> = kept.ticks.iter().map(|r| r.t).collect();
        assert_eq!(ticks, (0..ticks.len() as u64).collect::<Vec<_>>());
        assert!(!ticks.is_empty());
    }
}
