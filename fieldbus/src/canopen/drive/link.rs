//! The drives inside the CANopen master task: one logic tick's orders in, one SYNC per
//! interpolation tick on the bus, the drives' answers out.
//!
//! The scan (the CNC kernel's step) writes a [`DriveOrders`] per logic tick: per drive, the set
//! points of the tick's interpolation ticks and the power request. When the scan publishes, the
//! master task runs [`MasterDrives::tick`]: for each interpolation tick n it commands every drive
//! with set point n, sends the RPDOs, then SYNC n, and waits for the drives' TPDOs (and a
//! pending `603Fh` read): in real time until SYNC n + 1 is due (after the tick's last SYNC until
//! a quarter of an interpolation tick before the next tick), in lock-step up to the answer
//! timeout; the answers to the tick's SYNCs go back as one
//! [`DriveAnswers`], which the scan takes at its next latch. In lock-step mode (virtual time on
//! the virtual bus) the scan waits for those answers before it latches, so a run is a function
//! of its inputs; in real time it never waits and takes the answers that are there.
//!
//! Invariants: the target in the RPDO before SYNC n is set point n of the orders being served;
//! an answer that is not healthy (faulted, silent, not operational) is `None`, never a position;
//! orders that were superseded before the master served them (it fell a logic tick behind) are
//! counted, and the scan reports them ([`ScanDrives::take_superseded`]): never skipped silently;
//! a tick served without fresh orders holds the last set point of the last orders (never replays
//! their earlier set points).

use std::io;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use tokio::time::{Duration, Instant};

use super::set::{AxisId, DriveCommand, DriveFault, DriveSet};
use crate::canopen::transport::CanBus;
use crate::canopen::{CanMsg, cob};
use crate::exchange::{TripleReader, TripleWriter, triple};
use crate::map::{CanDrive, DriveMode};

/// How the drives are clocked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DriveTiming {
    /// The interpolation tick: the SYNC period and `60C2h`.
    pub int_tick: Duration,
    /// SYNCs per logic tick (interpolation ticks per logic tick).
    pub syncs: usize,
    /// Lock-step: the scan waits for each tick's answers (virtual time on the virtual bus).
    pub lockstep: bool,
}

/// What the scan orders one drive for the next logic tick.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DriveOrder {
    /// The set point of each interpolation tick (axis units; a `csv` spindle: revolutions per
    /// second); missing ones repeat the last.
    pub set_points: Vec<f64>,
    /// Power the drive.
    pub enable: bool,
    /// Quick stop.
    pub quick_stop: bool,
    /// Fault reset (a rising controlword bit 7).
    pub fault_reset: bool,
    /// Arm the touch probe on the encoder's zero impulse (homing, `csp` only).
    pub probe: bool,
}

/// One logic tick's orders, per drive in io.toml order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DriveOrders {
    /// The scan's publish count (0: nothing ordered yet).
    pub seq: u64,
    /// When the scan published them: in real time the tick's SYNCs are due from then on, one
    /// per interpolation tick.
    pub published: Option<std::time::Instant>,
    /// Per drive.
    pub drives: Vec<DriveOrder>,
}

/// One drive's answers to a logic tick's SYNCs.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DriveAnswer {
    /// Per SYNC: the actual value (position for `csp`, velocity for `csv`, axis units), `None`
    /// without a healthy answer.
    pub values: Vec<Option<f64>>,
    /// The statusword of the last answer.
    pub statusword: u16,
    /// The drive's fault, while it has one.
    pub fault: Option<DriveFault>,
    /// The digital inputs `60FDh` of the last healthy answer (`csp`; bit 2: home switch).
    pub inputs: u32,
    /// The touch probe status `60B9h` of the last healthy answer (`csp`).
    pub probe_status: u16,
    /// The touch probe's latched position (`60BAh`, axis units) while `probe_status` says it
    /// stored one.
    pub probe: Option<f64>,
}

/// The answers to one logic tick's orders.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DriveAnswers {
    /// The `seq` of the orders answered.
    pub seq: u64,
    /// Per drive, in io.toml order.
    pub drives: Vec<DriveAnswer>,
}

/// The master task's half.
pub(crate) struct MasterDrives {
    set: DriveSet,
    cfg: Vec<CanDrive>,
    timing: DriveTiming,
    answer_timeout: Duration,
    orders: TripleReader<DriveOrders>,
    answers: TripleWriter<DriveAnswers>,
    done: Arc<AtomicU64>,
    last_order: Vec<DriveOrder>,
    /// In lock-step mode the drives' clock is the bus's: `base` + SYNCs sent × the
    /// interpolation tick (the heartbeat consumer then counts SYNCs, not the wall clock, which a
    /// run in virtual time outpaces).
    base: Instant,
    syncs_sent: u32,
    /// The `seq` of the last orders served.
    served: u64,
    /// Orders superseded by later ones before the master served them (shared with the scan).
    superseded: Arc<AtomicU64>,
    /// The scan tick of the last superseded orders (shared with the scan).
    superseded_tick: Arc<AtomicU64>,
}

/// The scan's half.
pub struct ScanDrives {
    cfg: Vec<CanDrive>,
    orders: TripleWriter<DriveOrders>,
    answers: TripleReader<DriveAnswers>,
    done: Arc<AtomicU64>,
    seq: u64,
    lockstep: bool,
    superseded: Arc<AtomicU64>,
    superseded_tick: Arc<AtomicU64>,
    /// How many superseded orders [`ScanDrives::take_superseded`] has reported.
    reported: u64,
}

/// Both halves around a started [`DriveSet`].
pub(crate) fn link(
    set: DriveSet,
    cfg: &[CanDrive],
    timing: DriveTiming,
) -> (MasterDrives, ScanDrives) {
    let n = cfg.len();
    let (otx, orx) = triple(DriveOrders {
        seq: 0,
        published: None,
        drives: vec![DriveOrder::default(); n],
    });
    let (atx, arx) = triple(DriveAnswers {
        seq: 0,
        drives: vec![DriveAnswer::default(); n],
    });
    let done = Arc::new(AtomicU64::new(0));
    let superseded = Arc::new(AtomicU64::new(0));
    let superseded_tick = Arc::new(AtomicU64::new(0));
    let answer_timeout = if timing.lockstep {
        Duration::from_millis(100)
    } else {
        timing.int_tick / 2
    };
    (
        MasterDrives {
            set,
            cfg: cfg.to_vec(),
            timing,
            answer_timeout,
            orders: orx,
            answers: atx,
            done: done.clone(),
            last_order: vec![DriveOrder::default(); n],
            base: Instant::now(),
            syncs_sent: 0,
            served: 0,
            superseded: superseded.clone(),
            superseded_tick: superseded_tick.clone(),
        },
        ScanDrives {
            cfg: cfg.to_vec(),
            orders: otx,
            answers: arx,
            done,
            seq: 0,
            lockstep: timing.lockstep,
            superseded,
            superseded_tick,
            reported: 0,
        },
    )
}

impl MasterDrives {
    /// Passes a frame that arrived between ticks (heartbeat, EMCY) to the drives; returns the
    /// frames to send (a `603Fh` read).
    pub(crate) fn on_frame(&mut self, m: &CanMsg) -> Vec<CanMsg> {
        let now = self.now();
        self.set.on_frame(m, now)
    }

    /// The drives' clock: the wall clock, or in lock-step mode the bus's SYNC count.
    fn now(&self) -> Instant {
        if self.timing.lockstep {
            self.base + self.timing.int_tick * self.syncs_sent
        } else {
            Instant::now()
        }
    }

    /// One logic tick: the SYNCs of its interpolation ticks with the drives' RPDOs before each;
    /// frames that are not the drives' go to `other`.
    pub(crate) async fn tick<B: CanBus>(
        &mut self,
        bus: &mut B,
        other: &mut Vec<CanMsg>,
    ) -> io::Result<()> {
        let (orders, _) = self.orders.read();
        let seq = orders.seq;
        if seq > 0 {
            self.last_order.clone_from(&orders.drives);
        }
        let fresh = seq > self.served;
        if fresh {
            // Orders published while the master was still serving earlier ones are superseded
            // by the latest: their set points never reach the drives.
            let lost = seq - self.served - 1;
            if lost > 0 {
                self.superseded.fetch_add(lost, Ordering::AcqRel);
                // The last superseded orders were the scan's tick seq − 2 (orders 1: tick 0).
                self.superseded_tick.store(seq - 2, Ordering::Release);
            }
            self.served = seq;
        }
        let published = orders.published.map(Instant::from_std);
        let axes: Vec<AxisId> = self.set.axes().collect();
        let syncs = self.timing.syncs.max(1);
        let start = tick_start(published.filter(|_| fresh), Instant::now());
        let mut out = DriveAnswers {
            seq,
            drives: vec![DriveAnswer::default(); axes.len()],
        };
        for k in 0..syncs {
            for (j, axis) in axes.iter().enumerate() {
                let o = self.last_order.get(j).cloned().unwrap_or_default();
                let held = self
                    .set
                    .feedback(*axis)
                    .map_or(0.0, |f| match self.cfg[j].mode {
                        DriveMode::Csp => f.position,
                        DriveMode::Csv => 0.0,
                    });
                // Without fresh orders (the scan has not published since the last tick was
                // served) every SYNC holds the last set point: replaying the served tick's set
                // points from its first would move a csp axis back by a tick's travel.
                let set_point = o
                    .set_points
                    .get(k)
                    .filter(|_| fresh)
                    .or(o.set_points.last())
                    .copied()
                    .unwrap_or(held);
                self.set.command(
                    *axis,
                    DriveCommand {
                        set_point,
                        enable: o.enable,
                        quick_stop: o.quick_stop,
                        fault_reset: o.fault_reset,
                        probe: o.probe,
                    },
                );
            }
            for m in self.set.rpdos(self.now()) {
                bus.send(&m).await?;
            }
            bus.send(&CanMsg::new(cob::SYNC, &[])).await?;
            self.syncs_sent = self.syncs_sent.saturating_add(1);
            let deadline = self.answer_deadline(start, k, Instant::now());
            while !self.set.all_answered() || self.set.code_pending() {
                let m = match tokio::time::timeout_at(deadline, bus.recv()).await {
                    Err(_) => break,
                    Ok(m) => m?,
                };
                if !self.ours(&m) {
                    other.push(m);
                }
                let now = self.now();
                for reply in self.set.on_frame(&m, now) {
                    bus.send(&reply).await?;
                }
            }
            let now = self.now();
            self.set.after_sync(now);
            for (j, axis) in axes.iter().enumerate() {
                let Some(f) = self.set.feedback(*axis) else {
                    continue;
                };
                let a = &mut out.drives[j];
                let value = match self.cfg[j].mode {
                    DriveMode::Csp => f.position,
                    DriveMode::Csv => f.velocity,
                };
                a.values.push(f.healthy.then_some(value));
                a.statusword = f.state.statusword();
                a.fault = f.fault;
                a.inputs = f.inputs;
                a.probe_status = f.probe_status;
                a.probe =
                    (f.probe_status & super::set::PROBE_STORED != 0).then_some(f.probe_position);
            }
            if !self.timing.lockstep && k + 1 < syncs {
                let next = start + self.timing.int_tick * (k as u32 + 1);
                tokio::time::sleep_until(next).await;
            }
        }
        let buf = self.answers.buf();
        *buf = out;
        self.answers.publish();
        self.done.store(seq, Ordering::Release);
        Ok(())
    }

    /// Until when the answers to SYNC `k` of a tick that began at `start` are waited for (the
    /// SYNC was sent at `now`). Lock-step: the answer timeout. Real time: until the next SYNC is
    /// due — an answer before it cannot be the next SYNC's, and a later one is owed
    /// ([`DriveSet`]) — and after the tick's last SYNC until a quarter of an interpolation tick
    /// before the next tick's orders are due, so that serving a tick never takes a whole
    /// logic tick (orders published meanwhile would be superseded before they are sent); at
    /// least an eighth of an interpolation tick after a SYNC that went out late.
    fn answer_deadline(&self, start: Instant, k: usize, now: Instant) -> Instant {
        if self.timing.lockstep {
            return now + self.answer_timeout;
        }
        let period = self.timing.int_tick;
        let syncs = self.timing.syncs.max(1);
        let due = if k + 1 < syncs {
            start + period * (k as u32 + 1)
        } else {
            start + period * syncs as u32 - period / 4
        };
        due.max(now + period / 8)
    }

    /// True for a frame of one of the drives (TPDO1, EMCY, heartbeat, SDO answer).
    fn ours(&self, m: &CanMsg) -> bool {
        let id = m.id as u16;
        self.cfg.iter().any(|d| {
            let n = u16::from(d.node_id);
            id == cob::tpdo(1, d.node_id)
                || id == cob::tpdo(2, d.node_id)
                || id == cob::tpdo(3, d.node_id)
                || id == 0x080 + n
                || id == cob::HEARTBEAT + n
                || id == cob::SDO_TX + n
        })
    }
}

/// When a tick's SYNC schedule starts: when the scan published its orders — so a master that
/// starts serving them late (the previous tick overran) sends its first SYNC at once and the others
/// on the publish's schedule, and lateness never accumulates from tick to tick — but not before
/// `now`; at `now` for orders served again (the safe state's).
fn tick_start(published: Option<Instant>, now: Instant) -> Instant {
    published.map_or(now, |p| p.min(now))
}

impl ScanDrives {
    /// The drives, in io.toml order.
    pub fn drives(&self) -> &[CanDrive] {
        &self.cfg
    }

    /// The orders for the next publish (every drive's entry is the scan's to fill).
    pub fn orders(&mut self) -> &mut Vec<DriveOrder> {
        &mut self.orders.buf().drives
    }

    /// Hands the orders to the master (at the scan's publish).
    pub(crate) fn publish(&mut self) {
        self.seq += 1;
        self.orders.buf().seq = self.seq;
        self.orders.buf().published = Some(std::time::Instant::now());
        self.orders.publish();
    }

    /// In lock-step mode, waits (at most `limit`) until the master answered the last published
    /// orders; false when it did not in time.
    pub(crate) fn wait(&self, limit: std::time::Duration) -> bool {
        if !self.lockstep || self.seq == 0 {
            return true;
        }
        let deadline = std::time::Instant::now() + limit;
        while self.done.load(Ordering::Acquire) < self.seq {
            if std::time::Instant::now() > deadline {
                return false;
            }
            std::thread::sleep(std::time::Duration::from_micros(20));
        }
        true
    }

    /// Orders superseded before the master served them since the last call (their set points
    /// never reached the drives: the master fell a whole logic tick behind), with the scan tick
    /// of the last of them.
    pub fn take_superseded(&mut self) -> (u64, u64) {
        let total = self.superseded.load(Ordering::Acquire);
        let new = total - self.reported.min(total);
        self.reported = total;
        (new, self.superseded_tick.load(Ordering::Acquire))
    }

    /// How many orders the scan has published (the `seq` of the last ones).
    pub fn published(&self) -> u64 {
        self.seq
    }

    /// The latest answers.
    pub fn answers(&mut self) -> &DriveAnswers {
        self.answers.read().0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Drive X on node 3, csp, 100 counts per mm.
    fn x_drive() -> CanDrive {
        CanDrive {
            process: 1,
            axis: 'X',
            node_id: 3,
            counts_per_unit: 100.0,
            mode: DriveMode::Csp,
            heartbeat: Duration::from_millis(50),
            sdo: Vec::new(),
            simulate: Default::default(),
            span: 0..0,
            homing: false,
        }
    }

    fn master(lockstep: bool) -> MasterDrives {
        let cfg = [x_drive()];
        let timing = DriveTiming {
            int_tick: Duration::from_millis(2),
            syncs: 5,
            lockstep,
        };
        link(DriveSet::new(&cfg, timing.int_tick), &cfg, timing).0
    }

    #[tokio::test]
    async fn orders_superseded_before_the_master_served_them_are_counted() {
        let cfg = [x_drive()];
        let timing = DriveTiming {
            int_tick: Duration::from_millis(1),
            syncs: 2,
            lockstep: false,
        };
        let (mut m, mut scan) = link(DriveSet::new(&cfg, timing.int_tick), &cfg, timing);
        let bus = crate::canopen::virtual_bus::VirtualBus::new();
        let (mut port, mut drive) = (bus.port(), bus.port());
        let publish = |scan: &mut ScanDrives, at: f64| {
            scan.orders()[0] = DriveOrder {
                set_points: vec![at, at + 0.5],
                enable: true,
                ..DriveOrder::default()
            };
            scan.publish();
        };
        // The scan publishes three ticks before the master serves any: the latest is sent,
        // the first two are superseded.
        for at in [1.0, 2.0, 3.0] {
            publish(&mut scan, at);
        }
        m.tick(&mut port, &mut Vec::new()).await.expect("tick");
        assert_eq!(
            scan.take_superseded(),
            (2, 1),
            "orders 1 and 2: ticks 0 and 1"
        );
        assert_eq!(scan.take_superseded().0, 0, "reported once");
        // The RPDOs on the bus: tick 3's two set points (300 and 350 counts), nothing of 1 or 2.
        let mut targets = Vec::new();
        while let Ok(Ok(f)) = tokio::time::timeout(Duration::from_millis(5), drive.recv()).await {
            if f.id == 0x203 {
                let d = f.payload();
                targets.push(i32::from_le_bytes([d[2], d[3], d[4], d[5]]));
            }
        }
        assert_eq!(targets, [300, 350]);
        // Served one by one, nothing is superseded.
        publish(&mut scan, 4.0);
        m.tick(&mut port, &mut Vec::new()).await.expect("tick");
        assert_eq!(scan.take_superseded().0, 0);
    }

    /// The RPDO targets of drive X (node 3) on the bus until it is quiet.
    async fn targets(drive: &mut crate::canopen::virtual_bus::VirtualPort) -> Vec<i32> {
        let mut targets = Vec::new();
        while let Ok(Ok(f)) = tokio::time::timeout(Duration::from_millis(5), drive.recv()).await {
            if f.id == 0x203 {
                let d = f.payload();
                targets.push(i32::from_le_bytes([d[2], d[3], d[4], d[5]]));
            }
        }
        targets
    }

    #[tokio::test]
    async fn a_tick_without_fresh_orders_holds_the_last_set_point() {
        let bus = crate::canopen::virtual_bus::VirtualBus::new();
        let (mut port, mut drive) = (bus.port(), bus.port());
        let cfg = [x_drive()];
        let timing = DriveTiming {
            int_tick: Duration::from_millis(1),
            syncs: 3,
            lockstep: false,
        };
        let (mut m, mut scan) = link(DriveSet::new(&cfg, timing.int_tick), &cfg, timing);
        scan.orders()[0] = DriveOrder {
            set_points: vec![1.0, 2.0, 3.0],
            enable: true,
            ..DriveOrder::default()
        };
        scan.publish();
        m.tick(&mut port, &mut Vec::new()).await.expect("tick");
        assert_eq!(targets(&mut drive).await, [100, 200, 300]);
        // The scan is late: the master's next tick has nothing fresh and holds 3.0 (300 counts)
        // at every SYNC, not 100, 200, 300 again (the axis would jump back by a tick's travel).
        m.tick(&mut port, &mut Vec::new()).await.expect("tick");
        assert_eq!(targets(&mut drive).await, [300, 300, 300]);
        assert_eq!(scan.take_superseded().0, 0);
    }

    #[test]
    fn a_tick_served_late_keeps_the_schedule_of_its_publish() {
        let now = Instant::now();
        let ms = Duration::from_millis;
        assert_eq!(tick_start(Some(now - ms(3)), now), now - ms(3));
        assert_eq!(tick_start(Some(now + ms(1)), now), now);
        assert_eq!(tick_start(None, now), now);
        // Published 3 ms ago: SYNC 0 goes at once and its answers get the floor (an eighth of an
        // interpolation tick: SYNC 1 is already due); SYNC 1 goes at once too, its answers are
        // waited for until SYNC 2 is due, 4 ms after the publish.
        let m = master(false);
        let start = tick_start(Some(now - ms(3)), now);
        assert_eq!(
            m.answer_deadline(start, 0, now),
            now + Duration::from_micros(250)
        );
        assert_eq!(m.answer_deadline(start, 1, now), now + ms(1));
    }

    #[test]
    fn real_time_answers_are_waited_for_until_the_next_sync_is_due() {
        let m = master(false);
        let start = Instant::now();
        let ms = |us: u64| Duration::from_micros(us);
        // SYNC k of the tick is due at 2k ms: its answers are taken until SYNC k + 1 is due (an
        // answer of 1.5 ms is no longer lost), those of the last one until 9.5 ms, a quarter of
        // an interpolation tick before the next tick's orders.
        for (k, sent, until) in [
            (0, 0, 2000),
            (1, 2300, 4000),
            (2, 4900, 6000),
            (3, 6000, 8000),
            (4, 8400, 9500),
        ] {
            assert_eq!(
                m.answer_deadline(start, k, start + ms(sent)),
                start + ms(until),
                "SYNC {k}"
            );
        }
        // A SYNC that went out late still gets an eighth of an interpolation tick.
        assert_eq!(
            m.answer_deadline(start, 1, start + ms(3900)),
            start + ms(4150)
        );
        assert_eq!(
            m.answer_deadline(start, 4, start + ms(9400)),
            start + ms(9650)
        );
        // Lock-step: the answer timeout after each SYNC.
        let l = master(true);
        assert_eq!(
            l.answer_deadline(start, 4, start + ms(10)),
            start + ms(100_010)
        );
    }
}
