//! The CANopen master: packet-A bytes ↔ PDOs of CiA 401 digital I/O modules.
//!
//! At start the master task performs each node's SDO expedited writes from the map (a node whose
//! configuration fails is not started and reports [`Fault::Sdo`]), then sends NMT *start remote
//! node* to every configured node. Each tick, when the scan publishes its outputs, the task sends the
//! RPDOs (only after the scan published at least once, so a node never gets a value the logic did
//! not command) followed by one SYNC; the nodes answer with their TPDOs, whose mapped bytes go into
//! the input frame. The heartbeat consumer declares a node lost when no heartbeat arrived within its
//! heartbeat time (checked at least every quarter of it), or when it reports a state other than
//! operational once it has had that time to start; a node that boots again is started again.
//! While a node is lost the scan reads its inputs' fail values and the master sends it its
//! outputs' safe values instead of the scan's; the scan's again once it answers.
//! [`CanopenIo`] returns once the nodes are configured and started, so the first scan finds them
//! operational.
//!
//! Lock-step mode (virtual time on the virtual bus, [`DriveTiming::lockstep`]): the master's clock
//! is its SYNC count (each SYNC one period; the heartbeat consumer counts SYNCs, so a loaded machine
//! cannot make a heartbeat late), and after each tick's SYNCs it waits for every node that is not
//! lost to answer an SDO read of `1000h` — a node answers in order, so its TPDOs to those SYNCs
//! have arrived before — and only then is the tick served: the scan's next latch waits for that,
//! so the inputs it reads are the answers to the previous tick's last SYNC, every run alike.
//!
//! The scan side ([`CanopenIo`]) only touches lock-free buffers, exactly like the Modbus driver.

use std::future::Future;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use packets::{IoAlarm, PacketIo};
use tokio::sync::Notify;
use tokio::time::Instant;

use super::drive::link::{DriveTiming, MasterDrives, ScanDrives, link};
use super::drive::{DriveSet, startup};
use super::transport::CanBus;
use super::{CanMsg, cob, nmt, sdo};
use crate::exchange::{OutFrame, TripleReader, TripleWriter, triple};
use crate::health::{Fault, Health};
use crate::map::{CanNode, CanopenConfig};
use crate::tick_io::{A_LEN, latch_device, queue_alarm, safe_image, take_changed_outputs};

/// Device profile number of CiA 401 (low 16 bits of object `1000h`).
const CIA_401: u32 = 401;
/// Ticks without any sign of life from the master task before the scan declares a node lost (a
/// backstop: the heartbeat consumer normally decides much earlier).
const STALE_TICKS: u32 = 1000;

/// Per-node status the master task reports.
#[derive(Debug, Clone, Copy, Default)]
struct NodeStatus {
    seq: u64,
    fault: Fault,
}

#[derive(Debug, Clone)]
struct CanIn {
    nodes: Vec<NodeStatus>,
    data: [u8; A_LEN],
}

struct NodeSide {
    cfg: CanNode,
    health: Health,
    /// The fault of the last latch.
    fault: Fault,
}

/// The CANopen master driver (implements [`PacketIo`]).
pub struct CanopenIo {
    runtime: Option<tokio::runtime::Runtime>,
    threads: crate::rt::IoThreads,
    nodes: Vec<NodeSide>,
    inputs: TripleReader<CanIn>,
    outputs: TripleWriter<OutFrame>,
    wake: Arc<Notify>,
    acked: Arc<AtomicU64>,
    out_seq: u64,
    last_out: [u8; A_LEN],
    alarms: Vec<IoAlarm>,
    drives: Option<ScanDrives>,
    /// Lock-step: ticks requested by the scan, and ticks the master has served.
    lockstep: Option<(Arc<AtomicU64>, Arc<AtomicU64>)>,
    /// The simulated nodes' terminals (the `virtual` transport).
    wiring: Option<super::sim_wiring::SimWiring>,
}

impl CanopenIo {
    /// Starts a private runtime, connects the bus with `connect` (run inside that runtime, so it may
    /// spawn tasks such as simulated nodes) and starts the master task. Callable from any thread,
    /// inside another tokio runtime too.
    pub fn start<B, F>(
        cfg: &CanopenConfig,
        connect: impl FnOnce() -> F + Send + 'static,
    ) -> std::io::Result<CanopenIo>
    where
        B: CanBus,
        F: Future<Output = std::io::Result<B>> + Send + 'static,
    {
        CanopenIo::start_pinned(cfg, &[], connect)
    }

    /// As [`CanopenIo::start_pinned`], without CiA 402 drives (`cfg.drives` are not started).
    pub fn start_pinned<B, F>(
        cfg: &CanopenConfig,
        io_cpus: &[usize],
        connect: impl FnOnce() -> F + Send + 'static,
    ) -> std::io::Result<CanopenIo>
    where
        B: CanBus,
        F: Future<Output = std::io::Result<B>> + Send + 'static,
    {
        let mut cfg = cfg.clone();
        cfg.drives.clear();
        CanopenIo::start_with_drives(&cfg, io_cpus, None, connect)
    }

    /// As [`CanopenIo::start`], the runtime's threads pinned to `io_cpus` (empty = unpinned; a
    /// refusal by the kernel is warned about once and ignored), and the CiA 402 drives of
    /// `cfg.drives` configured and started before the I/O nodes (all or none: a start-up
    /// failure is the error, naming node, object and abort code), clocked by `timing` (default:
    /// one SYNC per tick of 10 ms, not lock-step).
    pub fn start_with_drives<B, F>(
        cfg: &CanopenConfig,
        io_cpus: &[usize],
        timing: Option<DriveTiming>,
        connect: impl FnOnce() -> F + Send + 'static,
    ) -> std::io::Result<CanopenIo>
    where
        B: CanBus,
        F: Future<Output = std::io::Result<B>> + Send + 'static,
    {
        let threads = crate::rt::IoThreads::pinned(io_cpus);
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .thread_name("ncplc-canopen")
            .on_thread_start(threads.on_start())
            .on_thread_stop(threads.on_stop())
            .enable_all()
            .build()?;
        // Not `block_on`: that panics when the caller is itself inside a tokio runtime.
        let (tx, rx) = std::sync::mpsc::channel();
        let timing = timing.unwrap_or(DriveTiming {
            int_tick: Duration::from_millis(10),
            syncs: 1,
            lockstep: false,
        });
        let drive_cfg = cfg.drives.clone();
        let sdo_timeout = cfg.sdo_timeout;
        runtime.spawn(async move {
            let _ = tx.send(connect_drives(connect, drive_cfg, timing, sdo_timeout).await);
        });
        let (bus, set) = rx
            .recv()
            .map_err(|_| std::io::Error::other("the CAN connect task ended"))??;
        let (master_drives, scan_drives) = match set {
            Some(set) => {
                let (m, s) = link(set, &cfg.drives, timing);
                (Some(m), Some(s))
            }
            None => (None, None),
        };
        // Validation guarantees these; a hand-built config must not make the scan panic.
        let mut cfg = cfg.clone();
        for n in &mut cfg.nodes {
            let fits = |m: &crate::map::PdoMapping| {
                m.range.len > 0
                    && m.range.end() <= A_LEN
                    && usize::from(m.offset) + m.range.len <= 8
            };
            n.inputs.retain(fits);
            n.outputs.retain(fits);
        }
        let cfg = &cfg;
        let n = cfg.nodes.len();
        let (in_tx, in_rx) = triple(CanIn {
            nodes: vec![NodeStatus::default(); n],
            data: [0; A_LEN],
        });
        let (out_tx, out_rx) = triple(OutFrame {
            seq: 0,
            data: [0; A_LEN],
        });
        let wake = Arc::new(Notify::new());
        let acked = Arc::new(AtomicU64::new(0));
        let requested = Arc::new(AtomicU64::new(0));
        let served = Arc::new(AtomicU64::new(0));
        let (ready_tx, ready_rx) = std::sync::mpsc::channel();
        let master = Master {
            cfg: cfg.clone(),
            bus,
            inputs: in_tx,
            outputs: out_rx,
            wake: wake.clone(),
            acked: acked.clone(),
            status: vec![NodeRt::default(); n],
            data: [0; A_LEN],
            pending: Vec::new(),
            configured: false,
            drives: master_drives,
            timing,
            base: Instant::now(),
            syncs_sent: 0,
            requested: requested.clone(),
            served: served.clone(),
            ready: Some(ready_tx),
        };
        runtime.spawn(master.run());
        // The nodes are configured and started before the first scan (bounded by the SDO
        // timeouts of their transfers).
        let writes = cfg.nodes.iter().map(|n| n.sdo.len() + 1).sum::<usize>();
        let limit = cfg
            .sdo_timeout
            .saturating_mul(u32::try_from(writes).unwrap_or(u32::MAX))
            .saturating_add(Duration::from_secs(1));
        let _ = ready_rx.recv_timeout(limit);
        let nodes = cfg
            .nodes
            .iter()
            .map(|c| NodeSide {
                cfg: c.clone(),
                health: Health::new(&c.name, STALE_TICKS),
                fault: Fault::None,
            })
            .collect();
        Ok(CanopenIo {
            runtime: Some(runtime),
            threads,
            nodes,
            inputs: in_rx,
            outputs: out_tx,
            wake,
            acked,
            out_seq: 0,
            last_out: [0; A_LEN],
            alarms: Vec::new(),
            drives: scan_drives,
            lockstep: timing.lockstep.then_some((requested, served)),
            wiring: None,
        })
    }

    /// Wires the simulated nodes' terminals (the `virtual` transport does).
    pub fn set_sim_wiring(&mut self, wiring: super::sim_wiring::SimWiring) {
        self.wiring = Some(wiring);
    }

    /// The simulated nodes' terminals, on the `virtual` transport.
    pub fn sim_wiring(&self) -> Option<&super::sim_wiring::SimWiring> {
        self.wiring.as_ref()
    }

    /// The CiA 402 drives' scan side (orders for the next publish, the latest answers).
    pub fn drives(&mut self) -> Option<&mut ScanDrives> {
        self.drives.as_mut()
    }

    /// The I/O nodes lost as of the last latch: name, node id and the fault (`Fault::None` when
    /// the scan found no fresh answer for too long).
    pub fn lost_nodes(&self) -> impl Iterator<Item = (&str, u8, Fault)> + '_ {
        self.nodes
            .iter()
            .filter(|n| n.health.lost())
            .map(|n| (n.cfg.name.as_str(), n.cfg.node_id, n.fault))
    }

    /// True while node `name` is operational and its heartbeat arrives (as of the last latch).
    pub fn is_healthy(&self, name: &str) -> bool {
        self.nodes
            .iter()
            .any(|n| n.cfg.name == name && n.health.healthy())
    }

    /// In lock-step mode, waits (at most `limit`) until the master served every tick the scan
    /// requested; false when it did not in time.
    fn wait_served(&self, limit: Duration) -> bool {
        let Some((requested, served)) = &self.lockstep else {
            return true;
        };
        let want = requested.load(Ordering::Acquire);
        let deadline = std::time::Instant::now() + limit;
        while served.load(Ordering::Acquire) < want {
            if std::time::Instant::now() > deadline {
                return false;
            }
            std::thread::sleep(Duration::from_micros(20));
        }
        true
    }

    fn hand_over(&mut self, packets: &[u8], force: bool) {
        let mut changed = force || self.out_seq == 0;
        for n in &self.nodes {
            let ranges = n.cfg.outputs.iter().map(|m| m.range);
            changed |= take_changed_outputs(ranges, packets, &mut self.last_out);
        }
        if changed {
            self.out_seq += 1;
            let buf = self.outputs.buf();
            buf.seq = self.out_seq;
            buf.data = self.last_out;
            self.outputs.publish();
        }
        // One SYNC per tick, whether or not the outputs changed.
        if let Some((requested, _)) = &self.lockstep {
            requested.fetch_add(1, Ordering::AcqRel);
        }
        self.wake.notify_one();
    }
}

impl Drop for CanopenIo {
    fn drop(&mut self) {
        if let Some(rt) = self.runtime.take() {
            rt.shutdown_background();
        }
    }
}

impl PacketIo for CanopenIo {
    fn name(&self) -> &str {
        "canopen"
    }

    fn latch_inputs(&mut self, _tick: u64, packets: &mut [u8]) {
        self.threads.follow_scan();
        let drives_ok = self.drives.as_ref().is_none_or(|d| d.wait(LOCKSTEP_LIMIT));
        if !(drives_ok && self.wait_served(LOCKSTEP_LIMIT)) {
            queue_alarm(
                &mut self.alarms,
                Some(IoAlarm {
                    device: "canopen".into(),
                    message: "the bus's answers did not come within 5 s (lock-step)".into(),
                    cleared: false,
                }),
            );
        }
        let (superseded, last) = self
            .drives
            .as_mut()
            .map_or((0, 0), ScanDrives::take_superseded);
        if superseded > 0 {
            queue_alarm(
                &mut self.alarms,
                Some(IoAlarm {
                    device: "canopen".into(),
                    message: format!(
                        "the master fell behind: the drives' set points of {superseded} logic tick(s) (the last tick {last}) were superseded before they were sent"
                    ),
                    cleared: false,
                }),
            );
        }
        let (frame, _) = self.inputs.read();
        for (i, n) in self.nodes.iter_mut().enumerate() {
            let st = frame.nodes.get(i).copied().unwrap_or_default();
            n.fault = st.fault;
            let inputs = n.cfg.inputs.iter().map(|m| (m.range, m.fail));
            let alarm = latch_device(
                &mut n.health,
                st.seq,
                st.fault,
                &frame.data,
                inputs,
                n.cfg.healthy,
                packets,
            );
            queue_alarm(&mut self.alarms, alarm);
        }
    }

    fn publish_outputs(&mut self, _tick: u64, packets: &[u8]) {
        if let Some(d) = self.drives.as_mut() {
            d.publish();
        }
        self.hand_over(packets, false);
    }

    fn take_alarms(&mut self) -> Vec<IoAlarm> {
        std::mem::take(&mut self.alarms)
    }

    /// Commands every output mapping's `safe` value and waits (at most 100 ms) until the master
    /// has sent it.
    fn safe_state(&mut self) {
        let outputs = self
            .nodes
            .iter()
            .flat_map(|n| n.cfg.outputs.iter().map(|m| (m.range, m.fail)));
        let image = safe_image(outputs);
        self.hand_over(&image, true);
        let deadline = std::time::Instant::now() + Duration::from_millis(100);
        while std::time::Instant::now() < deadline
            && self.acked.load(Ordering::Acquire) < self.out_seq
        {
            std::thread::sleep(Duration::from_micros(200));
        }
    }
}

#[derive(Debug, Clone, Copy, Default)]
struct NodeRt {
    last_hb: Option<Instant>,
    state: u8,
    started: Option<Instant>,
    sdo_failed: bool,
    seq: u64,
}

struct Master<B> {
    cfg: CanopenConfig,
    bus: B,
    inputs: TripleWriter<CanIn>,
    outputs: TripleReader<OutFrame>,
    wake: Arc<Notify>,
    acked: Arc<AtomicU64>,
    status: Vec<NodeRt>,
    data: [u8; A_LEN],
    /// Frames to send that frame handling decided on (NMT restarts).
    pending: Vec<CanMsg>,
    /// False while the SDO configuration runs (boot-ups then must not start a node).
    configured: bool,
    /// The CiA 402 drives, when io.toml has any.
    drives: Option<MasterDrives>,
    /// The SYNC period and count, and lock-step mode.
    timing: DriveTiming,
    /// Lock-step: the clock's origin; it advances one SYNC period per SYNC sent.
    base: Instant,
    syncs_sent: u32,
    /// Ticks the scan requested (read when a tick starts) and the master served.
    requested: Arc<AtomicU64>,
    served: Arc<AtomicU64>,
    /// Told once the nodes are configured and started.
    ready: Option<std::sync::mpsc::Sender<()>>,
}

/// The time between two SYNCs: the interpolation tick with drives, else one logic tick.
pub fn sync_period(timing: &DriveTiming, drives: bool) -> Duration {
    if drives {
        timing.int_tick
    } else {
        timing.int_tick * timing.syncs.max(1) as u32
    }
}

/// How long a lock-step scan waits for the drives' answers before it goes on with an alarm.
const LOCKSTEP_LIMIT: Duration = Duration::from_secs(5);

/// Connects the bus and starts the drives on it (all or none).
async fn connect_drives<B, F>(
    connect: impl FnOnce() -> F,
    drives: Vec<crate::map::CanDrive>,
    timing: DriveTiming,
    sdo_timeout: Duration,
) -> std::io::Result<(B, Option<DriveSet>)>
where
    B: CanBus,
    F: Future<Output = std::io::Result<B>>,
{
    let mut bus = connect().await?;
    if drives.is_empty() {
        return Ok((bus, None));
    }
    let mut seen = Vec::new();
    let statuswords = startup::start(
        &mut bus,
        &drives,
        timing.int_tick,
        sdo_timeout,
        &mut |m: &CanMsg| {
            seen.push(*m);
        },
    )
    .await
    .map_err(std::io::Error::other)?;
    let mut set = DriveSet::new(&drives, timing.int_tick);
    let now = Instant::now();
    for m in &seen {
        set.on_frame(m, now);
    }
    set.started(now, &statuswords);
    Ok((bus, Some(set)))
}

impl<B: CanBus> Master<B> {
    async fn run(mut self) {
        self.configure().await;
        self.configured = true;
        for i in 0..self.cfg.nodes.len() {
            if !self.status[i].sdo_failed {
                self.start_node(i).await;
            }
        }
        self.publish();
        if let Some(r) = self.ready.take() {
            let _ = r.send(());
        }
        let check = self
            .cfg
            .nodes
            .iter()
            .map(|n| n.heartbeat / 4)
            .min()
            .unwrap_or(Duration::from_millis(20))
            .clamp(Duration::from_millis(1), Duration::from_millis(20));
        loop {
            tokio::select! {
                r = self.bus.recv() => match r {
                    Ok(m) => self.on_frame(&m),
                    // A broken bus: the heartbeat check below turns silence into alarms.
                    Err(_) => tokio::time::sleep(check).await,
                },
                () = self.wake.notified() => self.on_tick().await,
                () = tokio::time::sleep(check) => {}
            }
            for m in std::mem::take(&mut self.pending) {
                let _ = self.bus.send(&m).await;
            }
            self.publish();
        }
    }

    /// Reads each node's device type (`1000h`, must be CiA 401) and performs its SDO writes; a
    /// node where either fails is marked [`Fault::Sdo`] and is not started.
    async fn configure(&mut self) {
        let timeout = self.cfg.sdo_timeout;
        for i in 0..self.cfg.nodes.len() {
            let node = self.cfg.nodes[i].clone();
            let mut seen = Vec::new();
            let device_type = sdo::upload(
                &mut self.bus,
                node.node_id,
                0x1000,
                0,
                timeout,
                &mut |m: &CanMsg| seen.push(*m),
            )
            .await;
            let mut ok = matches!(device_type, Ok((v, _)) if v & 0xFFFF == CIA_401);
            for w in &node.sdo {
                if !ok {
                    break;
                }
                let r = sdo::download(
                    &mut self.bus,
                    node.node_id,
                    w,
                    timeout,
                    &mut |m: &CanMsg| seen.push(*m),
                )
                .await;
                ok = r.is_ok();
            }
            for m in &seen {
                self.on_frame(m);
            }
            self.status[i].sdo_failed = !ok;
        }
    }

    async fn start_node(&mut self, i: usize) {
        let id = self.cfg.nodes[i].node_id;
        let _ = self
            .bus
            .send(&CanMsg::new(cob::NMT, &[nmt::CMD_START, id]))
            .await;
        self.status[i].started = Some(self.now());
    }

    /// The master's clock: the wall clock, or in lock-step mode the SYNC count.
    fn now(&self) -> Instant {
        if self.timing.lockstep {
            self.base + self.sync_period() * self.syncs_sent
        } else {
            Instant::now()
        }
    }

    /// The time between two SYNCs: the interpolation tick with drives, else one logic tick.
    fn sync_period(&self) -> Duration {
        sync_period(&self.timing, self.drives.is_some())
    }

    fn on_frame(&mut self, m: &CanMsg) {
        if m.extended || m.rtr {
            return;
        }
        if let Some(d) = self.drives.as_mut() {
            self.pending.extend(d.on_frame(m));
        }
        let id = m.id as u16;
        for (i, node) in self.cfg.nodes.iter().enumerate() {
            let nid = node.node_id;
            if id == cob::HEARTBEAT + u16::from(nid) {
                let Some(&state) = m.payload().first() else {
                    continue;
                };
                let now = self.now();
                let st = &mut self.status[i];
                st.last_hb = Some(now);
                st.state = state;
                if (state == nmt::BOOTUP || state == nmt::PRE_OPERATIONAL)
                    && !st.sdo_failed
                    && self.configured
                {
                    // The node (re)booted: start it again.
                    self.pending
                        .push(CanMsg::new(cob::NMT, &[nmt::CMD_START, nid]));
                    st.started = Some(now);
                }
            }
            for map in &node.inputs {
                if id == cob::tpdo(map.pdo, nid) {
                    let src = m.payload();
                    let (o, n) = (usize::from(map.offset), map.range.len);
                    if let Some(bytes) = src.get(o..o + n) {
                        self.data[map.range.start..map.range.end()].copy_from_slice(bytes);
                    }
                }
            }
        }
    }

    async fn on_tick(&mut self) {
        let requested = self.requested.load(Ordering::Acquire);
        let (out, _) = self.outputs.read();
        let (seq, data) = (out.seq, out.data);
        if seq > 0 {
            let now = self.now();
            let lost: Vec<bool> = (0..self.cfg.nodes.len())
                .map(|i| self.fault(i, now) != Fault::None)
                .collect();
            for (node, lost) in self.cfg.nodes.iter().zip(lost) {
                for pdo in 1..=4u8 {
                    let maps: Vec<_> = node.outputs.iter().filter(|m| m.pdo == pdo).collect();
                    if maps.is_empty() {
                        continue;
                    }
                    let mut payload = [0u8; 8];
                    let mut len = 0;
                    for m in maps {
                        let o = usize::from(m.offset);
                        // A lost node gets its outputs' safe values (as the safe state).
                        match lost {
                            true => payload[o..o + m.range.len].fill(m.fail),
                            false => payload[o..o + m.range.len]
                                .copy_from_slice(&data[m.range.start..m.range.end()]),
                        }
                        len = len.max(o + m.range.len);
                    }
                    let _ = self
                        .bus
                        .send(&CanMsg::new(cob::rpdo(pdo, node.node_id), &payload[..len]))
                        .await;
                }
            }
            self.acked.store(seq, Ordering::Release);
        }
        match self.drives.take() {
            Some(mut d) => {
                let mut other = Vec::new();
                // A broken bus shows as missing answers (unhealthy feedback, then heartbeats).
                let _ = d.tick(&mut self.bus, &mut other).await;
                self.drives = Some(d);
                let n = self.timing.syncs.max(1);
                self.syncs_sent = self.syncs_sent.saturating_add(n as u32);
                for m in &other {
                    self.on_frame(m);
                }
            }
            None => {
                let _ = self.bus.send(&CanMsg::new(cob::SYNC, &[])).await;
                self.syncs_sent = self.syncs_sent.saturating_add(1);
            }
        }
        if self.timing.lockstep {
            self.barrier().await;
        }
        self.publish();
        self.served.store(requested, Ordering::Release);
    }

    /// Lock-step: waits until every node without a fault (not lost, operational or still
    /// starting, configured) has answered the tick's SYNCs (an SDO read of `1000h`, answered after
    /// them), handling the frames that come meanwhile.
    async fn barrier(&mut self) {
        let now = self.now();
        for i in 0..self.cfg.nodes.len() {
            if self.fault(i, now) != Fault::None {
                continue;
            }
            let mut seen = Vec::new();
            let id = self.cfg.nodes[i].node_id;
            let timeout = self.cfg.sdo_timeout;
            let _ = sdo::upload(&mut self.bus, id, 0x1000, 0, timeout, &mut |m: &CanMsg| {
                seen.push(*m)
            })
            .await;
            for m in &seen {
                self.on_frame(m);
            }
        }
    }

    fn fault(&self, i: usize, now: Instant) -> Fault {
        let st = &self.status[i];
        let hb = self.cfg.nodes[i].heartbeat;
        if st.sdo_failed {
            return Fault::Sdo;
        }
        let settled = st.started.is_some_and(|t| now.duration_since(t) > hb);
        match st.last_hb {
            Some(t) if now.duration_since(t) > hb => Fault::HeartbeatLost,
            None if settled => Fault::HeartbeatLost,
            Some(_) if st.state != nmt::OPERATIONAL && settled => Fault::NotOperational,
            _ => Fault::None,
        }
    }

    fn publish(&mut self) {
        let now = self.now();
        let faults: Vec<Fault> = (0..self.cfg.nodes.len())
            .map(|i| self.fault(i, now))
            .collect();
        let buf = self.inputs.buf();
        for (i, f) in faults.into_iter().enumerate() {
            let st = &mut self.status[i];
            let alive = f == Fault::None && st.last_hb.is_some() && st.state == nmt::OPERATIONAL;
            if alive {
                st.seq += 1;
            }
            if let Some(slot) = buf.nodes.get_mut(i) {
                *slot = NodeStatus {
                    seq: st.seq,
                    fault: f,
                };
            }
        }
        buf.data = self.data;
        self.inputs.publish();
    }
}
