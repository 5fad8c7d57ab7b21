//! Replaying a part-run trace: the header names the partprograms, their CRC-32 and the operator's
//! options; the replay loads the programs (a changed text is an error naming the file), builds the
//! same kernel, plant and operator as `ncplc run --program`, and re-runs them beside the logic
//! ([`runtime::replay::ReplayKernel`]).

use std::borrow::Borrow;
use std::sync::{Arc, Mutex, PoisonError};

use cnc::Cnc;

use crate::machine::Machine;
use crate::part_run::{PartRun, PartSpec, kernel_version, start_spec};
use runtime::program::Loaded;
use runtime::replay::{Replay, ReplayKernel, ReplayOptions, replay_records};
use trace::reader::Header;
use trace::{AxisId, AxisValue, OperatorCommand, PartHeader, TickRecord};

/// The kernel, plant and operator of a part run, driven by a replay.
pub struct KernelReplay {
    cnc: Arc<Mutex<Cnc>>,
    run: PartRun,
    last_out: Vec<u8>,
    /// Per drive of the header, the fault last seen (a new one raises its alarm).
    faults: Vec<Option<trace::DriveFaultRecord>>,
    /// The packet-A input bytes that came over the bus (header `bus_inputs`): the recorded
    /// inputs, never the kernel's writes.
    bus_inputs: Vec<usize>,
    kept: Vec<u8>,
}

impl KernelReplay {
    /// Builds the part run a trace header names, after checking every program's CRC-32.
    pub fn new(machine: &Machine, header: &PartHeader, tick_ms: u32) -> Result<Self, String> {
        let spec = PartSpec::from_header(header);
        let (_io, run) = start_spec(&spec, machine, tick_ms)?;
        let mut expected: Vec<(&str, &str)> = header
            .others
            .iter()
            .map(|o| (o.program.as_str(), o.crc32.as_str()))
            .collect();
        if let (Some(p), Some(c)) = (&header.program, &header.crc32) {
            expected.push((p, c));
        }
        for (name, path, now) in run.programs() {
            let Some((_, then)) = expected.iter().find(|(n, _)| *n == name) else {
                continue;
            };
            if *then != now {
                return Err(format!(
                    "error: {}: the partprogram changed since the trace was recorded (crc32 {then} in the trace, {now} now)",
                    path.display()
                ));
            }
        }
        check_files(machine, header, &run.files())?;
        if header.kernel != kernel_version() {
            eprintln!(
                "note: the trace was recorded by {}, this is {}; positions may differ",
                header.kernel,
                kernel_version()
            );
        }
        let cnc = run.cnc();
        crate::drive_io::attach(
            &mut cnc.lock().unwrap_or_else(PoisonError::into_inner),
            &header.drives,
        )?;
        Ok(KernelReplay {
            cnc,
            run,
            last_out: vec![0; packets::PACKETS_LEN],
            faults: vec![None; header.drives.len()],
            bus_inputs: header.bus_inputs.iter().map(|&b| usize::from(b)).collect(),
            kept: Vec::new(),
        })
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Cnc> {
        self.cnc.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// The files the trace's run read against what the run reads now: a changed, new or vanished
/// file is an error naming it. A trace without `files` (recorded before they were listed) checks
/// the programs only.
fn check_files(
    machine: &Machine,
    header: &PartHeader,
    now: &[(String, String)],
) -> Result<(), String> {
    if header.files.is_empty() {
        return Ok(());
    }
    let path = |f: &str| machine.dir.join(f).display().to_string();
    for then in &header.files {
        match now.iter().find(|(f, _)| *f == then.file) {
            Some((_, crc)) if *crc == then.crc32 => {}
            Some((_, crc)) => {
                return Err(format!(
                    "error: {}: changed since the trace was recorded (crc32 {} in the trace, {crc} now)",
                    path(&then.file),
                    then.crc32
                ));
            }
            None => {
                return Err(format!(
                    "error: {}: read when the trace was recorded, not now",
                    path(&then.file)
                ));
            }
        }
    }
    if let Some((f, _)) = now
        .iter()
        .find(|(f, _)| !header.files.iter().any(|h| h.file == *f))
    {
        return Err(format!(
            "error: {}: read now but not when the trace was recorded",
            path(f)
        ));
    }
    Ok(())
}

/// Every axis of `cnc` with its drive's actual position bits.
pub fn axis_positions(cnc: &Cnc, out: &mut Vec<AxisValue>) {
    for p in cnc.processes() {
        let process = p.number();
        out.extend(
            p.actual_positions()
                .map(|(axis, x)| (AxisId { process, axis }, x.to_bits())),
        );
    }
}

impl ReplayKernel for KernelReplay {
    fn written_mask(&self) -> Vec<u8> {
        let mut mask = vec![0; packets::PACKETS_LEN];
        self.lock().written_mask(&mut mask);
        for &b in &self.bus_inputs {
            if let Some(m) = mask.get_mut(b) {
                *m = 0;
            }
        }
        mask
    }

    fn latch(&mut self, t: u64, packets: &mut [u8]) {
        let cnc = Arc::clone(&self.cnc);
        let mut c = cnc.lock().unwrap_or_else(PoisonError::into_inner);
        self.kept.clear();
        self.kept.extend(
            self.bus_inputs
                .iter()
                .map(|&b| packets.get(b).copied().unwrap_or(0)),
        );
        c.step(t, &self.last_out, packets);
        // What the plant wrote there went onto the nodes' terminals; the scan read the bus.
        for (&b, &v) in self.bus_inputs.iter().zip(&self.kept) {
            if let Some(p) = packets.get_mut(b) {
                *p = v;
            }
        }
    }

    fn publish(&mut self, t: u64, packets: &[u8]) {
        let n = packets.len().min(self.last_out.len());
        self.last_out[..n].copy_from_slice(&packets[..n]);
        // As after a live tick: the operator acts (tick_count = t + 1); the run never stops here.
        self.run.each_tick(t + 1, false);
    }

    fn positions(&mut self, out: &mut Vec<AxisValue>) {
        axis_positions(&self.lock(), out);
    }

    fn command(&mut self, _t: u64, c: &OperatorCommand) -> Result<(), String> {
        crate::hmi_link::kernel_cnc::apply_command(&mut self.lock(), c.process, &c.command)
    }

    fn drives(&mut self, _t: u64, feedback: &[trace::DriveSample]) {
        let cnc = Arc::clone(&self.cnc);
        let mut c = cnc.lock().unwrap_or_else(PoisonError::into_inner);
        crate::drive_io::apply_feedback(&mut c, feedback, &mut self.faults);
    }

    fn nodes_lost(&mut self, _t: u64, lost: &[trace::NodeLoss]) {
        crate::drive_io::apply_nodes_lost(&mut self.lock(), lost);
    }
}

/// Replays the trace with `header` whose `records` arrive one at a time through `loaded`: with
/// the kernel when the header names partprograms, as a logic-only trace otherwise (where a
/// record with operator commands is an error: there is no kernel to give them to). Each record
/// the replay produces goes to `actual`.
pub fn replay_trace<R: Borrow<TickRecord>>(
    machine: &Machine,
    header: &Header,
    records: impl IntoIterator<Item = Result<R, String>>,
    loaded: Loaded,
    options: ReplayOptions,
    actual: &mut dyn FnMut(&TickRecord) -> Result<(), String>,
    progress: impl FnMut(u64),
) -> Result<Replay, String> {
    let t_init = &machine.config.t_init;
    match &header.part {
        Some(h) => {
            let mut k = KernelReplay::new(machine, h, header.tick_ms)?;
            let options = ReplayOptions {
                drives_kernel: true,
                ..options
            };
            replay_records(
                records,
                loaded,
                t_init,
                options,
                Some(&mut k),
                actual,
                progress,
            )
        }
        None => {
            let records = records.into_iter().map(|r| {
                let r = r?;
                if r.borrow().commands.is_empty() {
                    Ok(r)
                } else {
                    Err(format!(
                        "error: tick {}: the trace records operator commands but its header names no partprogram (no CNC kernel to give them to)",
                        r.borrow().t
                    ))
                }
            });
            replay_records(records, loaded, t_init, options, None, actual, progress)
        }
    }
}
