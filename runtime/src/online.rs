//! Online change: watch the PLC source, compile a change in the background, hand the new program
//! to the scheduler (which swaps it in at a tick boundary, see [`crate::scheduler::Swap`]).
//!
//! The directory is watched rather than the file, because editors save by writing a temporary
//! file and renaming it. Bursts of events are coalesced and an unchanged content is ignored. A
//! source that fails to compile never replaces the running program: its diagnostics are reported.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use notify::{RecommendedWatcher, RecursiveMode, Watcher};

use crate::compiled::LoadError;
use crate::program::Loaded;
use crate::scheduler::Swap;

/// Compiles PLC source text into a runnable program, or returns the rendered diagnostics.
pub type CompileFn = Arc<dyn Fn(&[u8]) -> Result<Loaded, LoadError> + Send + Sync>;

/// What the watcher tells the operator.
#[derive(Debug, Clone, PartialEq)]
pub enum Note {
    /// A change was compiled and handed to the scheduler.
    Compiled {
        /// Time spent compiling.
        compile: Duration,
    },
    /// The change did not compile; the running program stays.
    Rejected {
        /// Rendered diagnostics.
        diagnostics: String,
    },
    /// The file could not be read or watched.
    Error(String),
}

/// A running watcher; dropping it stops watching.
pub struct OnlineChange {
    _watcher: RecommendedWatcher,
    _thread: JoinHandle<()>,
}

/// How long a burst of file events is allowed to settle before compiling.
const SETTLE: Duration = Duration::from_millis(5);

/// Watches `source`; every changed content is compiled with `compile` and, if it compiles, sent
/// on `swaps`; what happens is reported on `notes`. `initial` is the content already running.
pub fn watch(
    source: &Path,
    initial: Vec<u8>,
    compile: CompileFn,
    swaps: Sender<Swap>,
    notes: Sender<Note>,
) -> Result<OnlineChange, notify::Error> {
    let source = std::fs::canonicalize(source).unwrap_or_else(|_| source.to_path_buf());
    let dir = source
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    let (ev_tx, ev_rx) = mpsc::channel::<Instant>();
    let name = source.file_name().map(|n| n.to_os_string());
    let mut watcher = notify::recommended_watcher(move |res: notify::Result<notify::Event>| {
        if let Ok(ev) = res
            && ev
                .paths
                .iter()
                .any(|p| p.file_name().map(|n| n.to_os_string()) == name)
            && !matches!(ev.kind, notify::EventKind::Access(_))
        {
            let _ = ev_tx.send(Instant::now());
        }
    })?;
    watcher.watch(&dir, RecursiveMode::NonRecursive)?;
    let thread = std::thread::Builder::new()
        .name("ncplc-online".into())
        .spawn(move || compile_loop(&source, initial, &compile, &ev_rx, &swaps, &notes))
        .map_err(|e| notify::Error::generic(&e.to_string()))?;
    Ok(OnlineChange {
        _watcher: watcher,
        _thread: thread,
    })
}

fn compile_loop(
    source: &Path,
    mut current: Vec<u8>,
    compile: &CompileFn,
    events: &Receiver<Instant>,
    swaps: &Sender<Swap>,
    notes: &Sender<Note>,
) {
    while let Ok(noticed) = events.recv() {
        // Let the burst settle (write + rename + metadata events).
        loop {
            match events.recv_timeout(SETTLE) {
                Ok(_) => continue,
                Err(RecvTimeoutError::Timeout) => break,
                Err(RecvTimeoutError::Disconnected) => return,
            }
        }
        let bytes = match compiler::read_source(source) {
            Ok(b) => b,
            Err(e) => {
                let _ = notes.send(Note::Error(format!("{}: {e}", source.display())));
                continue;
            }
        };
        if bytes == current {
            continue;
        }
        let modified = std::fs::metadata(source).and_then(|m| m.modified()).ok();
        let start = Instant::now();
        match compile(&bytes) {
            Ok(loaded) => {
                let _ = notes.send(Note::Compiled {
                    compile: start.elapsed(),
                });
                if swaps
                    .send(Swap {
                        loaded,
                        noticed,
                        modified,
                    })
                    .is_err()
                {
                    return;
                }
            }
            Err(e) => {
                let _ = notes.send(Note::Rejected {
                    diagnostics: e.to_string(),
                });
            }
        }
        current = bytes;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit::{FixedMeta, loaded, sig};

    fn compile_fn() -> CompileFn {
        // A toy language: the file is `ok <n>` (U4A0 := byte n) or anything else (an error).
        Arc::new(|src: &[u8]| {
            let text = String::from_utf8_lossy(src);
            let n: u8 = text
                .trim()
                .strip_prefix("ok ")
                .and_then(|n| n.parse().ok())
                .ok_or_else(|| LoadError::Diagnostics {
                    diagnostics: Vec::new(),
                    rendered: "error: bad program".into(),
                })?;
            let meta = FixedMeta {
                image_len: packets::PACKETS_LEN,
                written: vec![sig("W4A0")],
                retain: 0..0,
                layout: 0,
            };
            Ok(loaded(
                move |img: &mut [u8]| sig("W4A0").write(img, n),
                meta,
            ))
        })
    }

    #[test]
    fn edits_compile_and_failures_are_reported() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("PLCPRG");
        std::fs::write(&path, "ok 1").expect("write");
        let (stx, srx) = mpsc::channel();
        let (ntx, nrx) = mpsc::channel();
        let _w = watch(&path, b"ok 1".to_vec(), compile_fn(), stx, ntx).expect("watch");
        std::thread::sleep(Duration::from_millis(20));
        std::fs::write(&path, "nonsense").expect("write");
        let note = nrx.recv_timeout(Duration::from_secs(5)).expect("note");
        assert_eq!(
            note,
            Note::Rejected {
                diagnostics: "error: bad program".into()
            }
        );
        // Editor-style save: temporary file renamed over the source.
        let tmp = dir.path().join("PLCPRG.swp");
        std::fs::write(&tmp, "ok 7").expect("write");
        std::fs::rename(&tmp, &path).expect("rename");
        let swap = srx.recv_timeout(Duration::from_secs(5)).expect("swap");
        let mut swap_loaded = swap.loaded;
        let mut img = vec![0u8; packets::PACKETS_LEN];
        swap_loaded.logic.tick(&mut img);
        assert_eq!(sig("W4A0").read(&img), 7);
        assert!(matches!(
            nrx.recv_timeout(Duration::from_secs(5)),
            Ok(Note::Compiled { .. })
        ));
    }
}
