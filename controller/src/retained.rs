//! Retained data of a run (PGCFIL OLD): restored into the first image, written by a thread of its
//! own while the scan runs (coalescing bursts), saved once more at the end.
//!
//! **Invariant:** recordings and virtual-time runs start fresh and never write the file (the
//! builder passes no path for them).

use std::path::{Path, PathBuf};
use std::sync::mpsc;

use runtime::program::ProgramMeta;
use runtime::retain::{self, Restored, RetainLayout, RetainRecord};
use runtime::scheduler::Scheduler;

/// The retain layout of a program.
pub fn layout(meta: &dyn ProgramMeta) -> RetainLayout {
    RetainLayout::new(
        &meta.written_signals(),
        meta.retain_range(),
        meta.retain_layout(),
    )
}

/// Restores the retained T bytes and RETAIN variables of `path` into `image`, saying what it did.
pub fn restore(path: &Path, meta: &dyn ProgramMeta, image: &mut [u8]) {
    match retain::load(path) {
        Ok(Some(rec)) => match layout(meta).restore(&rec, image) {
            Restored::All => {
                eprintln!("retain: restored T bytes and RETAIN variables (PGCFIL OLD)")
            }
            Restored::TOnly => {
                eprintln!("retain: restored T bytes; RETAIN layout changed, variables start at 0")
            }
            Restored::NotAllowed => {
                eprintln!("retain: MUSPE was 0 at the last shutdown; nothing restored")
            }
        },
        Ok(None) => {}
        Err(e) => eprintln!("warning: {e}; starting without retained data"),
    }
}

/// Starts the thread that writes retain snapshots (coalescing bursts) and connects it.
pub fn start_writer(path: PathBuf, sched: &mut Scheduler) -> std::thread::JoinHandle<()> {
    let (tx, rx) = mpsc::channel::<RetainRecord>();
    let start_seq = retain::load(&path).ok().flatten().map_or(0, |r| r.seq);
    let handle = std::thread::spawn(move || {
        while let Ok(first) = rx.recv() {
            let latest = rx.try_iter().last().unwrap_or(first);
            let rec = RetainRecord {
                seq: start_seq + latest.seq,
                ..latest
            };
            if let Err(e) = retain::save(&path, &rec) {
                eprintln!("warning: {e}");
            }
        }
    });
    sched.retain_to(Box::new(move |r| {
        let _ = tx.send(r);
    }));
    handle
}

/// The final save at the end of a run: the image's retained part after the writer has stopped.
pub fn save_final(path: &Path, meta: &dyn ProgramMeta, image: &[u8]) {
    let seq = retain::load(path).ok().flatten().map_or(0, |r| r.seq) + 1;
    if let Err(e) = retain::save(path, &layout(meta).snapshot(image, seq)) {
        eprintln!("warning: {e}");
    }
}
