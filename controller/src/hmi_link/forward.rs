//! The HMI's request thread, between the server's request channel and the scan: every request
//! passes through it in order, and an MDI line is compiled and planned here, beside the scan,
//! not on it. The thread reads the process's set points under a brief lock of the kernel, runs
//! the kernel's shared MDI compiler ([`cnc::Cnc::mdi_compiler_at`]) from them and hands the scan
//! the planned blocks with the start position they assume ([`PlannedMdi`]); the scan loads them
//! when the set points are still that position ([`cnc::Cnc::mdi_planned`]), else compiles inline
//! (the axes moved between the two: rare, MDI needs an idle interpreter). A line that does not
//! compile is answered from here; the scan never sees it.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError, mpsc};

use hmi::{Command, Envelope, Request};
use partprogram::canon::Canon;

/// A request on its way to the scan, with the planned MDI blocks of an MDI command.
#[derive(Debug)]
pub struct Forwarded {
    /// The server's request and its reply channel.
    pub env: Envelope,
    /// The planned blocks of an MDI command (None: any other request, or no shared compiler).
    pub mdi: Option<PlannedMdi>,
}

/// MDI blocks planned off the scan, and the start position they were planned from.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedMdi {
    /// Each axis letter of the process with the set point the plan starts at.
    pub at: Vec<(char, f64)>,
    /// The planned blocks.
    pub blocks: Vec<Canon>,
}

/// Compiles MDI lines for the scan from the kernel's current set points.
#[derive(Clone)]
pub struct MdiPlanner {
    cnc: Arc<Mutex<cnc::Cnc>>,
    compiles: Arc<AtomicU64>,
}

impl MdiPlanner {
    /// A planner over `cnc` that counts its compiles in `compiles`.
    pub fn new(cnc: Arc<Mutex<cnc::Cnc>>, compiles: Arc<AtomicU64>) -> MdiPlanner {
        MdiPlanner { cnc, compiles }
    }

    /// Plans MDI text `line` of `process` from where its axes stand now; None when the kernel
    /// has no shared compiler (the scan then compiles as before). The error is the kernel's
    /// text for a refused MDI command.
    pub fn plan(&self, process: u8, line: &str) -> Result<Option<PlannedMdi>, String> {
        let (compiler, at) = {
            let c = self.cnc.lock().unwrap_or_else(PoisonError::into_inner);
            (c.mdi_compiler_at(), c.mdi_start(process))
        };
        let Some(compile) = compiler else {
            return Ok(None);
        };
        let at = at.map_err(|e| e.to_string())?;
        self.compiles.fetch_add(1, Ordering::Relaxed);
        let blocks =
            compile(process, line, &at).map_err(|e| cnc::CommandError::Mdi(e).to_string())?;
        Ok(Some(PlannedMdi { at, blocks }))
    }
}

/// Starts the request thread: reads `requests` until the server drops its sender and forwards
/// each to `scan`, planning MDI lines with `planner` on the way.
pub fn start(
    requests: mpsc::Receiver<Envelope>,
    scan: mpsc::Sender<Forwarded>,
    planner: Option<MdiPlanner>,
) -> std::io::Result<()> {
    std::thread::Builder::new()
        .name("hmi-requests".into())
        .spawn(move || {
            for env in requests {
                let planned = match (&env.request, &planner) {
                    (
                        Request::Command {
                            process,
                            command: Command::Mdi { line },
                        },
                        Some(p),
                    ) => p.plan(*process, line),
                    _ => Ok(None),
                };
                match planned {
                    Ok(mdi) => {
                        if scan.send(Forwarded { env, mdi }).is_err() {
                            return;
                        }
                    }
                    Err(e) => {
                        let _ = env.reply.send(Err(e));
                    }
                }
            }
        })?;
    Ok(())
}
