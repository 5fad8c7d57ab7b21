//! A part run on CiA 402 drives (`ncplc run --io canopen --program …` with `[[canopen.drive]]`):
//! the CANopen master (I/O nodes and drives) and the CNC kernel behind one [`PacketIo`].
//!
//! Per tick, in `latch_inputs(t)`: the master's inputs (packet A from the I/O nodes; in
//! lock-step mode it first waits for the drives' answers to tick t−1's SYNCs), then the drives'
//! answers become the kernel's feedback ([`apply_feedback`], shared with the replay: new faults
//! raise their alarms), then the kernel steps behind `sim.toml`'s part script (panel and machine
//! contacts written over the I/O nodes' inputs, as in a simulated part run), and its set points of
//! the tick's interpolation ticks become the drives' orders, which `publish_outputs(t)` hands to
//! the master with the outputs: one SYNC per interpolation tick, set point n in the RPDO before
//! SYNC n. The feedback the kernel took is kept for the recording ([`DriveIo::samples`]): the
//! answers, the statusword, the fault, and for homing the home switch (`60FDh`) and the touch
//! probe (status and latched position); the orders arm the touch probe while the MCZ cycle
//! waits for a reference mark.
//!
//! Invariant: the kernel sees only what the recording keeps (the samples), so a replay that
//! feeds the recorded samples re-runs it exactly without the bus.

use std::sync::{Arc, Mutex, PoisonError};

use cnc::Cnc;
use fieldbus::canopen::drive::{DriveAnswers, DriveFault, FaultCause};
use fieldbus::canopen::master::CanopenIo;
use packets::{IoAlarm, PacketIo};
use trace::{AxisId, DriveFaultRecord, DriveSample, HeaderDrive};

/// The samples the kernel took at the last latch, for the recording.
pub type Samples = Arc<Mutex<Vec<DriveSample>>>;

/// The master and the kernel behind one [`PacketIo`].
pub struct DriveIo {
    canopen: CanopenIo,
    kernel: Box<dyn PacketIo>,
    cnc: Arc<Mutex<Cnc>>,
    drives: Vec<HeaderDrive>,
    faults: Vec<Option<DriveFaultRecord>>,
    samples: Samples,
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
        Ok(DriveIo {
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

    /// The feedback the kernel took at the last latch (shared with the recording).
    pub fn samples(&self) -> Samples {
        Arc::clone(&self.samples)
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
        let mut samples = self.samples.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(d) = self.canopen.drives() {
            let published = d.published();
            samples_of(d.answers(), published, &self.drives, &mut samples);
        }
        apply_feedback(&mut lock(&self.cnc), &samples, &mut self.faults);
        drop(samples);
        self.kernel.latch_inputs(tick, packets);
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
        self.kernel.publish_outputs(tick, packets);
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
