//! The HMI's render thread: while somebody looks (a WebSocket client, or an API read in the last
//! [`hmi::demand::LINGER`]) it picks up the newest [`Frame`] the scan published (polling the
//! triple buffer every [`POLL`]); while nobody does it sleeps on [`hmi::Demand`] and does not
//! wake at all. It builds the [`Snapshot`] from it (names, strings, the per-process alarm
//! lists with acknowledge, the tool path) and puts it into the server's latest-value channel. All
//! of this runs beside the scan, never on it.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use compiler::ir::Ty;
use compiler::ir::flow::FlowMap;
use fieldbus::exchange::TripleReader;
use hmi::{Demand, ScanStats, SharedSnapshot, Snapshot};
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
            messages: f.messages.clone(),
            online: f.online.clone(),
            machine,
            tripped: f.tripped,
            flow_enabled: f.flow_enabled,
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
    demand: Arc<Demand>,
    wakeups: Arc<AtomicU64>,
    thread: Option<JoinHandle<()>>,
}

impl RenderThread {
    /// Starts rendering the frames of `frames` into `out` while `demand` says somebody looks;
    /// otherwise the thread sleeps until somebody does.
    pub fn start(
        mut frames: TripleReader<Frame>,
        mut renderer: Renderer,
        out: watch::Sender<SharedSnapshot>,
        demand: Arc<Demand>,
    ) -> std::io::Result<RenderThread> {
        let wakeups = Arc::new(AtomicU64::new(0));
        let (d, count) = (Arc::clone(&demand), Arc::clone(&wakeups));
        let thread = std::thread::Builder::new()
            .name("hmi-render".into())
            .spawn(move || {
                let mut rendered = 0;
                while let Some(requested) = d.wait() {
                    count.fetch_add(1, Ordering::Relaxed);
                    let (f, _) = frames.read();
                    if f.seq > 0 && (f.seq != rendered || requested) {
                        rendered = f.seq;
                        out.send_replace(Arc::new(renderer.render(f)));
                    }
                    std::thread::sleep(POLL);
                }
            })?;
        Ok(RenderThread {
            demand,
            wakeups,
            thread: Some(thread),
        })
    }

    /// How many times the thread has woken to look for a frame (it does not while nobody looks).
    pub fn wakeups(&self) -> u64 {
        self.wakeups.load(Ordering::Relaxed)
    }
}

impl Drop for RenderThread {
    fn drop(&mut self) {
        self.demand.stop();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fieldbus::exchange::triple;
    use hmi::MachineStatus;

    struct NoCnc;

    impl CncView for NoCnc {
        fn status(&mut self, _: &Frame) -> MachineStatus {
            MachineStatus::default()
        }
    }

    /// Waits (bounded) until the channel's snapshot is of tick `tick`.
    fn wait_for(rx: &watch::Receiver<SharedSnapshot>, tick: u64) {
        for _ in 0..5000 {
            if rx.borrow().tick == tick {
                return;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        panic!("no snapshot of tick {tick}; last {}", rx.borrow().tick);
    }

    #[test]
    fn the_render_thread_sleeps_while_nobody_looks_and_renders_when_asked() {
        let (mut frames, reader) = triple(Frame::with_image(4));
        let (tx, rx) = watch::channel(Arc::new(Snapshot::default()));
        let demand = Arc::new(Demand::new(Duration::ZERO));
        let render = RenderThread::start(
            reader,
            Renderer::new(Box::new(NoCnc), 10),
            tx,
            Arc::clone(&demand),
        )
        .expect("thread");
        let mut publish = |seq: u64, tick: u64| {
            let f = frames.buf();
            (f.seq, f.tick) = (seq, tick);
            frames.publish();
        };
        publish(1, 5);
        // Nobody looks: 25 polls' worth of time pass without a single wake-up.
        std::thread::sleep(POLL * 25);
        assert_eq!((render.wakeups(), rx.borrow().tick), (0, 0));
        // An API read wakes it once: it renders the newest frame, then sleeps again.
        assert!(demand.read(), "it was asleep");
        wait_for(&rx, 5);
        publish(2, 6);
        std::thread::sleep(POLL * 25);
        assert_eq!((render.wakeups(), rx.borrow().tick), (1, 5));
        // A WebSocket client: every new frame is rendered while it stays.
        let client = demand.connect();
        wait_for(&rx, 6);
        publish(3, 7);
        wait_for(&rx, 7);
        drop(client);
        drop(render);
    }
}
