//! A part run on CiA 402 drives (`ncplc run --io canopen --program …` with `[[canopen.drive]]`):
//! the CANopen master (I/O nodes and drives) and the CNC kernel behind one [`PacketIo`].
//!
//! Per tick, in `latch_inputs(t)`: the master's inputs (packet A from the I/O nodes; in
//! lock-step mode it first waits for the drives' answers to tick t−1's SYNCs), then the drives'
//! answers become the kernel's feedback ([`apply_feedback`], shared with the replay: new faults
//! raise their alarms), then the kernel steps behind `sim.toml`'s part script, and its set points
//! of the tick's interpolation ticks become the drives' orders, which `publish_outputs(t)` hands
//! to the master with the outputs: one SYNC per interpolation tick, set point n in the RPDO before
//! SYNC n. The feedback the kernel took is kept for the recording ([`DriveIo::samples`]): the
//! answers, the statusword, the fault, and for homing the home switch (`60FDh`) and the touch
//! probe (status and latched position); the orders arm the touch probe while the MCZ cycle
//! waits for a reference mark.
//!
//! **The simulated I/O nodes carry the script and the plant** (the `virtual` transport, whose
//! nodes' terminals are wired to packet A: `fieldbus::canopen::sim_wiring`): the kernel steps on
//! a scratch image whose wired input bytes are the nodes' input terminals; what the script and the
//! plant leave there goes onto the terminals, and the scan reads it from the TPDOs of the tick's
//! SYNCs at its next latch — one tick later, as on real wiring. The outputs the kernel and the
//! script read (`publish_outputs(t)`, handed over at latch t+1) have their wired bytes from the
//! nodes' output terminals, which the RPDOs of tick t set. On another transport the script's
//! inputs are written over the nodes' inputs, as in a simulated part run.
//!
//! Invariant: the kernel sees only what the recording keeps (the samples; the wired inputs come
//! from the recorded inputs, `PartHeader::bus_inputs`), so a replay that feeds the recorded samples
//! re-runs it exactly without the bus.

use std::sync::{Arc, Mutex, PoisonError};

use cnc::Cnc;
use fieldbus::canopen::drive::{DriveAnswers, DriveFault, FaultCause};
use fieldbus::canopen::master::CanopenIo;
use fieldbus::health::Fault;
use packets::{IoAlarm, PacketIo};
use trace::{AxisId, DriveFaultRecord, DriveSample, HeaderDrive, NodeLoss};

/// The samples the kernel took at the last latch, for the recording.
pub type Samples = Arc<Mutex<Vec<DriveSample>>>;

/// The I/O nodes newly lost at the last latch, for the recording.
pub type NodesLost = Arc<Mutex<Vec<NodeLoss>>>;

/// The master and the kernel behind one [`PacketIo`].
pub struct DriveIo {
    canopen: CanopenIo,
    kernel: Box<dyn PacketIo>,
    cnc: Arc<Mutex<Cnc>>,
    drives: Vec<HeaderDrive>,
    faults: Vec<Option<DriveFaultRecord>>,
    samples: Samples,
    /// Per packet byte: true where a simulated node's input terminal is wired.
    wired: Vec<bool>,
    /// The kernel's image of a tick on wired nodes.
    scratch: Vec<u8>,
    /// The scan's last published outputs, handed to the kernel at the next latch (wired nodes).
    published: Option<Vec<u8>>,
    /// The I/O nodes lost at the last latch (node ids).
    nodes_lost: Vec<u8>,
    /// The nodes newly lost at the last latch (shared with the recording).
    newly_lost: NodesLost,
}

impl DriveIo {
    /// Puts the kernel's axes on the master's drives (each drive's axis must be a coordinated
    /// axis or the spindle of its process).
    pub fn new(
        mut canopen: CanopenIo,
        kernel: Box<dyn PacketIo>,
        cnc: Arc<Mutex<Cnc>>,
    ) -> Result<DriveIo, String> {
        let drives: Vec<HeaderDrive> = canopen
            .drives()
            .map(|d| {
                d.drives()
                    .iter()
                    .map(|c| HeaderDrive {
                        axis: AxisId {
                            process: c.process as u8,
                            axis: c.axis,
                        },
                        node: c.node_id,
                    })
                    .collect()
            })
            .unwrap_or_default();
        attach(&mut lock(&cnc), &drives)?;
        let mut wired = Vec::new();
        if let Some(w) = canopen.sim_wiring() {
            wired = vec![false; packets::PACKETS_LEN];
            for r in w.input_bytes() {
                if let Some(b) = wired.get_mut(r.start) {
                    *b = true;
                }
            }
        }
        Ok(DriveIo {
            wired,
            scratch: Vec::new(),
            published: None,
            nodes_lost: Vec::new(),
            newly_lost: NodesLost::default(),
            canopen,
            kernel,
            cnc,
            faults: vec![None; drives.len()],
            drives,
            samples: Arc::new(Mutex::new(Vec::new())),
        })
    }

    /// The drives, as the trace header names them.
    pub fn drives(&self) -> &[HeaderDrive] {
        &self.drives
    }

    /// Takes packet-A bytes out of the bus path: the handwheels' counters, which the kernel reads
    /// in the tick they turn (the CNC's own encoder inputs), go into the scan's image directly.
    pub fn unwire(&mut self, bytes: impl IntoIterator<Item = usize>) {
        for b in bytes {
            if let Some(w) = self.wired.get_mut(b) {
                *w = false;
            }
        }
    }

    /// The packet-A input bytes the simulated I/O nodes carry (empty off the virtual transport).
    pub fn bus_inputs(&self) -> Vec<u16> {
        (0..self.wired.len())
            .filter(|&i| self.wired[i])
            .map(|i| i as u16)
            .collect()
    }

    /// The feedback the kernel took at the last latch (shared with the recording).
    pub fn samples(&self) -> Samples {
        Arc::clone(&self.samples)
    }

    /// The I/O nodes newly lost at the last latch (shared with the recording).
    pub fn nodes_lost(&self) -> NodesLost {
        Arc::clone(&self.newly_lost)
    }
}

fn lock(cnc: &Mutex<Cnc>) -> std::sync::MutexGuard<'_, Cnc> {
    cnc.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Puts each drive's axis of `drives` on the bus of its process.
pub fn attach(cnc: &mut Cnc, drives: &[HeaderDrive]) -> Result<(), String> {
    for n in 1..=5u8 {
        let on: Vec<char> = drives
            .iter()
            .filter(|d| d.axis.process == n)
            .map(|d| d.axis.axis)
            .collect();
        if on.is_empty() {
            continue;
        }
        let p = cnc
            .process_mut(n)
            .map_err(|_| format!("drives on process {n}, which the machine does not have"))?;
        let spindle = on.contains(&'S') && p.axis_index('S').is_none();
        let axes: Vec<char> = on.into_iter().filter(|&a| !(spindle && a == 'S')).collect();
        p.attach_bus(&axes, spindle)?;
    }
    Ok(())
}

/// The master's answers as trace samples, in drive order; `published` is the number of orders
/// the scan has published (the answers to the last ones are 1 tick old).
fn samples_of(
    answers: &DriveAnswers,
    published: u64,
    drives: &[HeaderDrive],
    out: &mut Vec<DriveSample>,
) {
    out.clear();
    let age = u32::try_from((published + 1).saturating_sub(answers.seq)).unwrap_or(u32::MAX);
    for (d, a) in drives.iter().zip(&answers.drives) {
        out.push(DriveSample {
            axis: d.axis,
            values: a.values.iter().map(|v| v.map(f64::to_bits)).collect(),
            statusword: a.statusword,
            age,
            fault: a.fault.map(fault_record),
            inputs: a.inputs,
            probe_status: a.probe_status,
            probe: a.probe.map(f64::to_bits),
        });
    }
}

fn fault_record(f: DriveFault) -> DriveFaultRecord {
    let cause = match f.cause {
        FaultCause::Drive => "drive",
        FaultCause::HeartbeatLost => "heartbeat",
        FaultCause::NotOperational => "nmt",
        FaultCause::EnableRefused => "enable",
    };
    DriveFaultRecord {
        node: f.node,
        code: f.code,
        cause: cause.into(),
    }
}

/// Why a node is lost, as the alarm and the trace say it.
fn lost_why(fault: Fault) -> &'static str {
    match fault {
        Fault::None => "no answer",
        f => f.text(),
    }
}

/// The alarm text of a lost I/O node.
pub fn node_lost_message(name: &str, node: u8, why: &str) -> String {
    format!(
        "I/O node {name} (node {node}) lost ({why}): its inputs read their fail values and its outputs are safe; machine off"
    )
}

impl DriveIo {
    /// A newly lost I/O node (the master's heartbeat consumer, as the fieldbus alarm says) is a
    /// stopping alarm on every process, as a lost drive is on its own: the inputs the machine
    /// runs on are gone.
    fn watch_nodes(&mut self) {
        let lost: Vec<(String, u8, Fault)> = self
            .canopen
            .lost_nodes()
            .map(|(n, id, f)| (n.to_string(), id, f))
            .collect();
        let mut newly = self
            .newly_lost
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        newly.clear();
        for (name, id, fault) in &lost {
            if !self.nodes_lost.contains(id) {
                newly.push(NodeLoss {
                    name: name.clone(),
                    node: *id,
                    why: lost_why(*fault).to_string(),
                });
            }
        }
        apply_nodes_lost(&mut lock(&self.cnc), &newly);
        self.nodes_lost = lost.iter().map(|(_, id, _)| *id).collect();
    }
}

/// Raises the stopping alarm of each newly lost I/O node on every process (live, and in a replay
/// from the recorded losses).
pub fn apply_nodes_lost(cnc: &mut Cnc, lost: &[NodeLoss]) {
    for l in lost {
        let message = node_lost_message(&l.name, l.node, &l.why);
        for n in 1..=5u8 {
            if let Ok(p) = cnc.process_mut(n) {
                p.drive_alarm(message.clone());
            }
        }
    }
}

/// The alarm text of a drive fault on `axis`.
pub fn fault_message(axis: char, f: &DriveFaultRecord) -> String {
    let (node, code) = (f.node, f.code);
    match f.cause.as_str() {
        "drive" => {
            format!("drive fault on axis {axis} (node {node}): error code {code:04X}h (603Fh)")
        }
        "heartbeat" => format!(
            "drive of axis {axis} (node {node}) lost: no heartbeat within the consumer time ({code:04X}h); quick stop, machine off"
        ),
        "nmt" => format!("drive of axis {axis} (node {node}) left NMT operational ({code:04X}h)"),
        "enable" => format!(
            "drive of axis {axis} (node {node}) did not reach Operation enabled within {} SYNCs ({code:04X}h): the machine does not enable",
            fieldbus::canopen::drive::set::ENABLE_TICKS
        ),
        other => format!("drive of axis {axis} (node {node}): fault {other} ({code:04X}h)"),
    }
}

/// Gives the kernel the drives' feedback of `samples` for its next step; a fault that is new
/// since `faults` (per drive, the last one seen) raises its stopping alarm on the process.
pub fn apply_feedback(
    cnc: &mut Cnc,
    samples: &[DriveSample],
    faults: &mut [Option<DriveFaultRecord>],
) {
    let mut values = Vec::new();
    for (s, last) in samples.iter().zip(faults.iter_mut()) {
        let Ok(p) = cnc.process_mut(s.axis.process) else {
            continue;
        };
        values.clear();
        values.extend(s.values.iter().map(|v| v.map(f64::from_bits)));
        p.bus_feedback(s.axis.axis, &values, s.age as usize);
        let switch = s.inputs & fieldbus::canopen::drive::set::INPUT_HOME_SWITCH != 0;
        p.bus_home(s.axis.axis, switch, s.probe.map(f64::from_bits));
        let new = match (&s.fault, &*last) {
            (Some(f), Some(l)) => f.cause != l.cause,
            (Some(_), None) => true,
            _ => false,
        };
        if new && let Some(f) = &s.fault {
            p.drive_alarm(fault_message(s.axis.axis, f));
        }
        last.clone_from(&s.fault);
    }
}

impl PacketIo for DriveIo {
    fn name(&self) -> &str {
        "canopen+cnc"
    }

    fn latch_inputs(&mut self, tick: u64, packets: &mut [u8]) {
        self.canopen.latch_inputs(tick, packets);
        self.watch_nodes();
        let mut samples = self.samples.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(d) = self.canopen.drives() {
            let published = d.published();
            samples_of(d.answers(), published, &self.drives, &mut samples);
        }
        apply_feedback(&mut lock(&self.cnc), &samples, &mut self.faults);
        drop(samples);
        match self.canopen.sim_wiring() {
            Some(w) => {
                if let Some(mut out) = self.published.take() {
                    w.get_outputs(&mut out);
                    self.kernel.publish_outputs(tick.saturating_sub(1), &out);
                }
                self.scratch.clear();
                self.scratch.extend_from_slice(packets);
                w.get_inputs(&mut self.scratch);
                self.kernel.latch_inputs(tick, &mut self.scratch);
                w.put_inputs(&self.scratch);
                for (i, (dst, src)) in packets.iter_mut().zip(&self.scratch).enumerate() {
                    if !self.wired.get(i).copied().unwrap_or(false) {
                        *dst = *src;
                    }
                }
            }
            None => self.kernel.latch_inputs(tick, packets),
        }
        let cnc = lock(&self.cnc);
        let Some(d) = self.canopen.drives() else {
            return;
        };
        for (order, drive) in d.orders().iter_mut().zip(&self.drives) {
            let Some(p) = cnc
                .processes()
                .iter()
                .find(|p| p.number() == drive.axis.process)
            else {
                continue;
            };
            let c = p.bus_command();
            order.enable = c.enable;
            order.quick_stop = c.quick_stop;
            order.fault_reset = c.fault_reset;
            order.probe = p.bus_probe(drive.axis.axis);
            order.set_points.clear();
            if let Some(sp) = p.bus_set_points(drive.axis.axis) {
                order.set_points.extend_from_slice(sp);
            }
        }
    }

    fn publish_outputs(&mut self, tick: u64, packets: &[u8]) {
        if self.canopen.sim_wiring().is_some() {
            let out = self.published.get_or_insert_with(Vec::new);
            out.clear();
            out.extend_from_slice(packets);
        } else {
            self.kernel.publish_outputs(tick, packets);
        }
        self.canopen.publish_outputs(tick, packets);
    }

    fn safe_state(&mut self) {
        self.kernel.safe_state();
        self.canopen.safe_state();
    }

    fn take_alarms(&mut self) -> Vec<IoAlarm> {
        let mut v = self.canopen.take_alarms();
        v.append(&mut self.kernel.take_alarms());
        v
    }
}
