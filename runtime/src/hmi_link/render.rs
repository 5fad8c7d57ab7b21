//! The HMI's render thread: picks up the newest [`Frame`] the scan published (polling the triple
//! buffer every [`POLL`]), builds the [`Snapshot`] from it (names, strings, the per-process alarm
//! lists with acknowledge, the tool path) and puts it into the server's latest-value channel. All
//! of this runs beside the scan, never on it.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use compiler::ir::Ty;
use compiler::ir::flow::FlowMap;
use fieldbus::exchange::TripleReader;
use hmi::{ScanStats, SharedSnapshot, Snapshot};
use tokio::sync::watch;

use super::CncView;
use super::alarms::AlarmList;
use super::frame::{Frame, MAX_PROCESSES};

/// How often the render thread looks for a new frame.
pub const POLL: Duration = Duration::from_millis(2);

/// What the render thread keeps between frames.
pub struct Renderer {
    view: Box<dyn CncView>,
    tick_ms: u32,
    process_alarms: Vec<(u8, AlarmList)>,
    acks: [u64; MAX_PROCESSES],
    /// The scan times sampled at each frame (the median the page shows).
    scans: hdrhistogram::Histogram<u64>,
}

impl Renderer {
    /// A renderer over the CNC's render half `view`.
    pub fn new(view: Box<dyn CncView>, tick_ms: u32) -> Renderer {
        Renderer {
            view,
            tick_ms,
            process_alarms: Vec::new(),
            acks: [0; MAX_PROCESSES],
            scans: hdrhistogram::Histogram::new_with_bounds(1, 100_000_000_000, 3).unwrap_or_else(
                |_| hdrhistogram::Histogram::new(3).unwrap_or_else(|_| unreachable!()),
            ),
        }
    }

    /// The snapshot of frame `f`.
    pub fn render(&mut self, f: &Frame) -> Snapshot {
        let mut machine = self.view.status(f);
        if f.scan.0 > 0 {
            self.scans.saturating_record(f.scan.0);
        }
        for (p, list) in &mut self.process_alarms {
            let i = usize::from(*p).min(MAX_PROCESSES - 1);
            if f.acks[0] != self.acks[0] || f.acks[i] != self.acks[i] {
                list.acknowledge();
            }
        }
        self.acks = f.acks;
        for ps in &mut machine.processes {
            let active: Vec<String> = ps.alarms.drain(..).map(|a| a.text).collect();
            let list = match self
                .process_alarms
                .iter_mut()
                .position(|(p, _)| *p == ps.process)
            {
                Some(i) => &mut self.process_alarms[i].1,
                None => {
                    self.process_alarms.push((ps.process, AlarmList::default()));
                    let last = self.process_alarms.len() - 1;
                    &mut self.process_alarms[last].1
                }
            };
            list.sync(&active, f.tick);
            ps.alarms = list.entries().to_vec();
        }
        Snapshot {
            tick: f.tick,
            engine: f.engine.clone(),
            tick_ms: self.tick_ms,
            scan: ScanStats {
                scan_p50_us: self.scans.value_at_quantile(0.5) as f64 / 1e3,
                scan_max_us: f.scan.1 as f64 / 1e3,
                overruns: f.scan.2,
            },
            image: f.image.clone(),
            forced: f.forced.clone(),
            alarms: f.alarms.clone(),
            online: f.online.clone(),
            machine,
            tripped: f.tripped,
            flow: flow_values(&f.flow.0, f.flow.1.as_deref()),
            mdi_compiles: f
                .mdi_compiles
                .map(|(requests, scan)| hmi::MdiCompiles { requests, scan }),
            toolpaths: self.view.toolpaths(),
        }
    }
}

/// Each statement's `(line, value)` from the copied flow area `area` laid out by `map`.
pub fn flow_values(area: &[u8], map: Option<&FlowMap>) -> Vec<(u32, f64)> {
    let Some(map) = map else {
        return Vec::new();
    };
    map.slots
        .iter()
        .filter_map(|s| {
            let at = s.offset.checked_sub(map.area.0)?;
            let b = area.get(at..at + s.ty.size())?;
            let mut raw = [0u8; 8];
            raw[..b.len()].copy_from_slice(b);
            let v = match s.ty {
                Ty::Bool | Ty::Byte => f64::from(b[0]),
                Ty::Word => f64::from(u16::from_le_bytes([raw[0], raw[1]])),
                Ty::Int => f64::from(i16::from_le_bytes([raw[0], raw[1]])),
                Ty::Dword => f64::from(u32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]])),
                Ty::Dint => f64::from(i32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]])),
                Ty::Real => f64::from(f32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]])),
                Ty::Lreal => f64::from_le_bytes(raw),
            };
            Some((s.line, v))
        })
        .collect()
}

/// The running render thread; dropping it stops the thread.
pub struct RenderThread {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl RenderThread {
    /// Starts rendering the frames of `frames` into `out`.
    pub fn start(
        mut frames: TripleReader<Frame>,
        mut renderer: Renderer,
        out: watch::Sender<SharedSnapshot>,
    ) -> std::io::Result<RenderThread> {
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let thread = std::thread::Builder::new()
            .name("hmi-render".into())
            .spawn(move || {
                while !flag.load(Ordering::Relaxed) {
                    let (f, fresh) = frames.read();
                    if fresh && f.seq > 0 {
                        out.send_replace(Arc::new(renderer.render(f)));
                    }
                    std::thread::sleep(POLL);
                }
            })?;
        Ok(RenderThread {
            stop,
            thread: Some(thread),
        })
    }
}

impl Drop for RenderThread {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
