//! The cost per logic tick of the CNC kernel with its axes on CiA 402 drives (issue 21 target:
//! p99 ≤ 20 µs for 4 axes and a spindle): the mill (X, Y, Z and the spindle S of process 1 on
//! drives, the magazine axis T of process 2 on the plant) running ten minutes of squares, the
//! PLC in the loop. Timed per tick, without any bus or thread: the drives' feedback given to the
//! kernel (`drive_io::apply_feedback`), the kernel's step (`KernelIo::latch_inputs`: the part
//! script, 5 interpolation ticks), and for each of the tick's 5 SYNCs the master's drive logic
//! (`DriveSet`: commands → RPDOs, the TPDOs → feedback, the after-SYNC checks) with an ideal
//! drive answering in place (its state machine and an echo of the target). Printed as
//! p50/p99/max beside criterion's mean of the whole run.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

mod common;

use controller::Quiet;
use controller::drive_io::{apply_feedback, attach};
use criterion::{Criterion, criterion_group, criterion_main};
use fieldbus::canopen::drive::cia402::{self, State};
use fieldbus::canopen::drive::{AxisId, DriveCommand, DriveSet};
use fieldbus::canopen::{CanMsg, cob};
use fieldbus::map::{CanDrive, DriveMode};
use packets::PacketIo;
use trace::{DriveFaultRecord, DriveSample};

const SYNCS: usize = 5;

/// One simulated drive answering in place.
struct Echo {
    state: State,
    last: u16,
}

/// The kernel I/O with its axes on an in-process `DriveSet`, every latch timed.
struct OnDrives {
    inner: Box<dyn PacketIo>,
    cnc: Arc<Mutex<cnc::Cnc>>,
    set: DriveSet,
    cfg: Vec<CanDrive>,
    echo: Vec<Echo>,
    samples: Vec<DriveSample>,
    faults: Vec<Option<DriveFaultRecord>>,
    times: Arc<Mutex<Vec<u64>>>,
}

impl OnDrives {
    fn new(
        inner: Box<dyn PacketIo>,
        cnc: Arc<Mutex<cnc::Cnc>>,
        times: Arc<Mutex<Vec<u64>>>,
    ) -> OnDrives {
        let cfg: Vec<CanDrive> = [('X', 4), ('Y', 5), ('Z', 6), ('S', 7)]
            .iter()
            .map(|&(axis, node_id)| CanDrive {
                process: 1,
                axis,
                node_id,
                counts_per_unit: if axis == 'S' { 4096.0 } else { 10_000.0 },
                mode: if axis == 'S' {
                    DriveMode::Csv
                } else {
                    DriveMode::Csp
                },
                heartbeat: Duration::from_secs(3600),
                sdo: Vec::new(),
                simulate: Default::default(),
                span: 0..0,
                homing: true,
            })
            .collect();
        let header: Vec<trace::HeaderDrive> = cfg
            .iter()
            .map(|d| trace::HeaderDrive {
                axis: trace::AxisId {
                    process: 1,
                    axis: d.axis,
                },
                node: d.node_id,
            })
            .collect();
        attach(&mut cnc.lock().unwrap_or_else(|e| panic!("{e}")), &header)
            .unwrap_or_else(|e| panic!("{e}"));
        let mut set = DriveSet::new(&cfg, Duration::from_millis(2));
        let sw: Vec<u16> = cfg
            .iter()
            .map(|_| State::SwitchOnDisabled.statusword())
            .collect();
        set.started(tokio::time::Instant::now(), &sw);
        let echo = cfg
            .iter()
            .map(|_| Echo {
                state: State::SwitchOnDisabled,
                last: 0,
            })
            .collect();
        OnDrives {
            inner,
            cnc,
            faults: vec![None; cfg.len()],
            samples: header
                .iter()
                .map(|h| DriveSample {
                    axis: h.axis,
                    values: Vec::new(),
                    statusword: 0,
                    age: 1,
                    fault: None,
                    inputs: 0,
                    probe_status: 0,
                    probe: None,
                })
                .collect(),
            set,
            cfg,
            echo,
            times,
        }
    }

    /// The tick's SYNCs: orders from the kernel, RPDOs, the drives' answers, the feedback.
    fn syncs(&mut self) {
        let cnc = self.cnc.lock().unwrap_or_else(|e| panic!("{e}"));
        let p = &cnc.processes()[0];
        let c = p.bus_command();
        for s in &mut self.samples {
            s.values.clear();
        }
        for k in 0..SYNCS {
            for d in &self.cfg {
                let sp = p
                    .bus_set_points(d.axis)
                    .and_then(|v| v.get(k).copied())
                    .unwrap_or(0.0);
                self.set.command(
                    AxisId::new(d.axis),
                    DriveCommand {
                        set_point: sp,
                        enable: c.enable,
                        quick_stop: c.quick_stop,
                        fault_reset: c.fault_reset,
                        probe: false,
                    },
                );
            }
            let now = tokio::time::Instant::now();
            for m in self.set.rpdos(now) {
                let Some(j) = self
                    .cfg
                    .iter()
                    .position(|d| u32::from(cob::rpdo(1, d.node_id)) == m.id)
                else {
                    // RPDO2 (the touch probe function): the drive answers with TPDO2 and TPDO3.
                    if let Some(d) = self
                        .cfg
                        .iter()
                        .find(|d| u32::from(cob::rpdo(2, d.node_id)) == m.id)
                    {
                        self.set
                            .on_frame(&CanMsg::new(cob::tpdo(2, d.node_id), &[0; 6]), now);
                        self.set
                            .on_frame(&CanMsg::new(cob::tpdo(3, d.node_id), &[0; 4]), now);
                    }
                    continue;
                };
                let d = m.payload();
                let word = u16::from_le_bytes([d[0], d[1]]);
                let e = &mut self.echo[j];
                e.state = cia402::transition(e.state, word, e.last, false);
                e.last = word;
                let target = if e.state == State::OperationEnabled {
                    [d[2], d[3], d[4], d[5]]
                } else {
                    [0; 4]
                };
                let sw = e.state.statusword().to_le_bytes();
                let tpdo = [sw[0], sw[1], target[0], target[1], target[2], target[3]];
                self.set
                    .on_frame(&CanMsg::new(cob::tpdo(1, self.cfg[j].node_id), &tpdo), now);
            }
            self.set.after_sync(now);
            for (s, d) in self.samples.iter_mut().zip(&self.cfg) {
                let f = self.set.feedback(AxisId::new(d.axis));
                let v = f.map(|f| match d.mode {
                    DriveMode::Csp => f.position,
                    DriveMode::Csv => f.velocity,
                });
                s.values
                    .push(f.filter(|f| f.healthy).and(v).map(f64::to_bits));
                s.statusword = f.map_or(0, |f| f.state.statusword());
            }
        }
    }
}

impl PacketIo for OnDrives {
    fn name(&self) -> &str {
        "bench-drives"
    }
    fn latch_inputs(&mut self, tick: u64, packets: &mut [u8]) {
        let t = Instant::now();
        apply_feedback(
            &mut self.cnc.lock().unwrap_or_else(|e| panic!("{e}")),
            &self.samples,
            &mut self.faults,
        );
        self.inner.latch_inputs(tick, packets);
        self.syncs();
        let ns = t.elapsed().as_nanos() as u64;
        if let Ok(mut v) = self.times.lock() {
            v.push(ns);
        }
    }
    fn publish_outputs(&mut self, tick: u64, packets: &[u8]) {
        self.inner.publish_outputs(tick, packets);
    }
    fn take_alarms(&mut self) -> Vec<packets::IoAlarm> {
        self.inner.take_alarms()
    }
    fn safe_state(&mut self) {
        self.inner.safe_state();
    }
}

fn ended(cnc: &Mutex<cnc::Cnc>) -> bool {
    cnc.lock()
        .map(|c| c.processes()[0].counters().ended >= 1)
        .unwrap_or(true)
}

/// Runs `program` of the machine in `dir` to its end (built as `ncplc run DIR --program PROGRAM
/// --until-end --virtual-time` builds it) with the kernel's axes on in-process drives.
fn run(
    dir: &std::path::Path,
    program: &str,
    times: Arc<Mutex<Vec<u64>>>,
) -> (u64, Arc<Mutex<cnc::Cnc>>) {
    let wrap: controller::WrapIo = Box::new(move |io, cnc| {
        let cnc = cnc.unwrap_or_else(|| panic!("a part run has a kernel"));
        Box::new(OnDrives::new(io, cnc, times))
    });
    let mut c = common::part_controller(dir, program, None, Some(wrap));
    c.run(&mut Quiet);
    let cnc = c
        .part()
        .map(|p| p.cnc())
        .unwrap_or_else(|| panic!("a part run"));
    (c.scheduler().tick_count(), cnc)
}

fn bench(c: &mut Criterion) {
    let tmp = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let mill =
        common::machine_with_program("mill", tmp.path(), "BENCH", &common::long_mill_program());
    let times = Arc::new(Mutex::new(Vec::new()));
    let (ticks, cnc) = run(&mill, "BENCH", Arc::clone(&times));
    assert!(ended(&cnc), "the part ran to its end on the drives");
    let mut times = times.lock().map(|v| v.clone()).unwrap_or_default();
    times.sort_unstable();
    let q = |f: f64| times[((times.len() - 1) as f64 * f) as usize] as f64 / 1000.0;
    eprintln!(
        "kernel + drives per logic tick (mill, X Y Z S on drives, {ticks} ticks): p50 {:.2} µs  p99 {:.2} µs  max {:.2} µs",
        q(0.5),
        q(0.99),
        q(1.0)
    );
    let mut g = c.benchmark_group("drives");
    g.sample_size(10);
    g.bench_function("mill_10min_part_on_drives", |b| {
        b.iter(|| run(&mill, "BENCH", Arc::new(Mutex::new(Vec::new()))).0)
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
