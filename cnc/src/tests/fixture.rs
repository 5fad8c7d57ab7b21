//! Test fixtures: a process on the default interface-map addresses, a stepping interpolator, and a
//! loop that plays the PLC.

use std::collections::{BTreeMap, VecDeque};

use packets::Signal;
use partprogram::canon::{Kind as CanonKind, MFunc, Plane};
use partprogram::{Canon, MTiming};

use crate::config::{AxisConfig, ProcessConfig};
use crate::interp::{Interpolator, TickOut};
use crate::{Cnc, MachineSignals, Process, ProcessSignals, Timing};

/// Moves at 1 mm per tick along X; each move reports its tag in the tick it arrives.
pub struct Stepper {
    pos: Vec<f64>,
    queue: VecDeque<(u64, f64)>,
    hold: bool,
}

impl Interpolator for Stepper {
    fn push(&mut self, tag: u64, b: &Canon) -> Result<(), String> {
        let x = b.end_of('X').ok_or("no X")?;
        self.queue.push_back((tag, x));
        Ok(())
    }
    fn space(&self) -> usize {
        8 - self.queue.len().min(8)
    }
    fn set_feed_override(&mut self, _: u16) {}
    fn set_rapid_override(&mut self, _: u16) {}
    fn set_hold(&mut self, on: bool) {
        self.hold = on;
    }
    fn set_spindle_position(&mut self, _: f64) {}
    fn abort(&mut self) {
        self.queue.clear();
    }
    fn tick(&mut self, out: &mut TickOut) {
        out.held = self.hold && !self.queue.is_empty();
        if self.hold {
            return;
        }
        out.tag = self.queue.front().map(|q| q.0);
        if let Some(&(tag, x)) = self.queue.front() {
            let d = (x - self.pos[0]).clamp(-1.0, 1.0);
            self.pos[0] += d;
            if self.pos[0] == x {
                self.queue.pop_front();
                out.finished.push(tag);
            }
        }
    }
    fn position(&self) -> &[f64] {
        &self.pos
    }
    fn is_idle(&self) -> bool {
        self.queue.is_empty()
    }
    fn set_position(&mut self, pos: &[f64]) -> Result<(), String> {
        self.pos = pos.to_vec();
        Ok(())
    }
}

pub fn sig(s: &str) -> Signal {
    s.parse().expect("test signal")
}

fn roles() -> BTreeMap<&'static str, &'static str> {
    BTreeMap::from([
        ("MSTB", "I1K0"),
        ("MFIN", "U11K0"),
        ("MCODE", "W3K0"),
        ("SSTB", "I1K1"),
        ("SFIN", "U11K1"),
        ("SCODE", "W4K0"),
        ("TSTB", "I1K2"),
        ("TFIN", "U11K2"),
        ("TCODE", "W5K0"),
        ("DEN", "I1K3"),
        ("ALARM", "I1K4"),
        ("CYCLE", "I1K5"),
        ("HOLD", "I1K6"),
        ("STANDBY", "I1K7"),
        ("MODE", "W2K0"),
        ("FOLD", "U10K5"),
        ("RABI1", "U10K8"),
        ("START", "U11K3"),
        ("ERS", "U11K5"),
        ("USO", "U12K0"),
        ("JOGP1", "U13K0"),
        ("JOGM1", "U13K8"),
        ("JINC", "W16K1"),
        ("BSKIP", "U12K1"),
        ("MIMM", "W3K1"),
        ("FG96", "I9K26"),
        ("GEARREQ", "W8K0"),
        ("GEARACK", "W47K2"),
        ("COMU", "U11K6"),
        ("CUB", "U10N0"),
        ("ZONE2", "U10N1"),
        ("HW_AXIS1", "W15N0"),
        ("HW_AXIS2", "W15N1"),
        ("HW_SCALE", "W15N2"),
        ("HW_ON1", "U15N24"),
        ("HW_ON2", "U15N25"),
    ])
}

/// The M declarations of the example lathe plus M06 with a tool-offset request.
pub fn lathe_m() -> BTreeMap<u16, MTiming> {
    let t = |m_type, m_request| MTiming {
        m_type,
        m_request,
        class: 0x10,
    };
    BTreeMap::from([
        (0, t(0x02, 0x08)),
        (1, t(0x02, 0x02)),
        (2, t(0x02, 0x24)),
        (3, t(0x45, 0x00)),
        (5, t(0x06, 0x00)),
        (6, t(0x02, 0x14)),
        (8, t(0x45, 0x00)),
        (30, t(0x02, 0x24)),
        (50, t(0x10, 0x00)),
    ])
}

/// One process with axis X, the given GPS, strobe timeout and RABI timeout (logic ticks).
pub fn cnc(parallel: bool, timeout: u64, rabi_timeout: u64) -> Cnc {
    cnc_with(parallel, timeout, rabi_timeout, None)
}

/// [`cnc`] with a spindle (and FG96 I9K26, GEARREQ W8K0, GEARACK W47K2 in the map).
pub fn cnc_with(
    parallel: bool,
    timeout: u64,
    rabi_timeout: u64,
    spindle: Option<crate::config::SpindleConfig>,
) -> Cnc {
    cnc_with_axis(parallel, timeout, rabi_timeout, spindle, axis_x())
}

/// The fixture's X: KV ∞ (an ideal drive: no lag), SRV unchecked, LO1 −5 … 3, LO2 −8 … 6.
pub fn axis_x() -> AxisConfig {
    AxisConfig {
        name: 'X',
        kv: f64::INFINITY,
        kvff: 1.0,
        kvffi: 0.0,
        fqf_hz: 0.0,
        srv: crate::following::SrvLimits::default(),
        needs_homing: false,
        limit_inputs: (None, None),
        soft: (Some(-5.0), Some(3.0)),
        soft2: (Some(-8.0), Some(6.0)),
        cub: None,
        accel: 1000.0,
        jog_speed: 1000.0,
        home: None,
    }
}

/// [`cnc_with`] with the axis `axis`.
pub fn cnc_with_axis(
    parallel: bool,
    timeout: u64,
    rabi_timeout: u64,
    spindle: Option<crate::config::SpindleConfig>,
    axis: AxisConfig,
) -> Cnc {
    let cfg = ProcessConfig {
        number: 1,
        axes: vec![axis],
        spindle,
        m_timing: lathe_m(),
        parallel,
        int_tick_s: 0.01,
        qfd: None,
        handwheels: [true, true],
    };
    let r = roles();
    let signals = ProcessSignals::from_roles(|role| r.get(role).map(|a| sig(a)));
    let stepper = Stepper {
        pos: vec![0.0],
        queue: VecDeque::new(),
        hold: false,
    };
    let timing = Timing {
        logic_tick_s: 0.01,
        strobe_timeout_ticks: timeout,
        rabi_timeout_ticks: rabi_timeout,
    };
    let mut p = Process::new(cfg, signals, Box::new(stepper), &[0.0], timing);
    p.set_handwheel_counters([Some(sig("W2A0")), None]);
    Cnc::new(
        vec![p],
        MachineSignals {
            reset: Some(sig("I0K1")),
            estop: Some(sig("U11K4")),
        },
    )
}

/// A canonical block: `kind` to X = `x` with M functions `m` (timing from [`lathe_m`]).
pub fn block(n: u32, kind: CanonKind, x: f64, m: &[u16], s: Option<f64>, t: Option<i64>) -> Canon {
    let decl = lathe_m();
    Canon {
        exact_stop: false,
        tolerance: None,
        css: None,
        feed_g94: true,
        modal: partprogram::canon::BlockModal::default(),
        n: Some(n),
        unit: None,
        kind,
        end: vec![('X', x)],
        center: Vec::new(),
        plane: Plane::ZX,
        feed: Some(100.0),
        m: m.iter()
            .map(|&m| MFunc {
                m,
                before: decl.get(&m).is_some_and(|d| d.before_motion()),
            })
            .collect(),
        s,
        t,
        dwell: None,
        thread: false,
        thread_angle: 0.0,
    }
}

/// The scripted PLC: which FINs answer, and the levels it drives.
pub struct Plc {
    /// Answer the M strobe (FIN = MSTB).
    pub m_fin: bool,
    /// ESTOP level (1 = chain closed).
    pub estop: u8,
    /// RABI1.
    pub rabi: u8,
    /// FOLD.
    pub fold: u8,
    /// USO.
    pub uso: u8,
    /// START level (an edge starts).
    pub start: u8,
    /// ERS level.
    pub ers: u8,
    /// JOGP1, JOGM1.
    pub jog: (u8, u8),
    /// JINC.
    pub jinc: u8,
    /// BSKIP.
    pub bskip: u8,
    /// COMU.
    pub comu: u8,
    /// ZONE2 and CUB.
    pub zone2: u8,
    /// CUB.
    pub cub: u8,
    /// Handwheel channel 1: HW_ON1, HW_AXIS1, HW_SCALE.
    pub hw: (u8, u8, u8),
    /// The handwheel counter of channel 1 (packet-A byte W2A0), as the machine latches it.
    pub wheel: u8,
}

impl Default for Plc {
    fn default() -> Self {
        Plc {
            m_fin: true,
            estop: 1,
            rabi: 1,
            fold: 0,
            uso: 0,
            start: 0,
            ers: 0,
            jog: (0, 0),
            jinc: 0,
            bskip: 0,
            comu: 0,
            zone2: 0,
            cub: 0,
            hw: (0, 0, 0),
            wheel: 0,
        }
    }
}

/// Watched signals per tick: MSTB, SSTB, TSTB, DEN, CYCLE.
pub type Row = [u8; 5];

/// The loop: kernel step, then the PLC's scan of the image; returns the watched bits per tick.
pub struct Bench {
    pub cnc: Cnc,
    pub image: Vec<u8>,
    pub out: Vec<u8>,
    pub tick: u64,
}

impl Bench {
    pub fn new(cnc: Cnc) -> Bench {
        Bench {
            cnc,
            image: vec![0; packets::PACKETS_LEN],
            out: vec![0; packets::PACKETS_LEN],
            tick: 0,
        }
    }

    /// One tick with the PLC `plc`; returns the watched CNC→PLC bits.
    pub fn step(&mut self, plc: &Plc) -> Row {
        sig("W2A0").write(&mut self.image, plc.wheel);
        self.cnc.step(self.tick, &self.out, &mut self.image);
        self.tick += 1;
        // the scan: FINs follow the strobes, levels as scripted
        let rd = |s: &str| sig(s).read(&self.image);
        let row = [rd("I1K0"), rd("I1K1"), rd("I1K2"), rd("I1K3"), rd("I1K5")];
        let w = |out: &mut Vec<u8>, s: &str, v: u8| sig(s).write(out, v);
        w(&mut self.out, "U11K0", if plc.m_fin { row[0] } else { 0 });
        w(&mut self.out, "U11K1", row[1]);
        w(&mut self.out, "U11K2", row[2]);
        w(&mut self.out, "U11K4", plc.estop);
        w(&mut self.out, "U10K8", plc.rabi);
        w(&mut self.out, "U10K5", plc.fold);
        w(&mut self.out, "U12K0", plc.uso);
        w(&mut self.out, "U11K3", plc.start);
        w(&mut self.out, "U11K5", plc.ers);
        w(&mut self.out, "U13K0", plc.jog.0);
        w(&mut self.out, "U13K8", plc.jog.1);
        w(&mut self.out, "W16K1", plc.jinc);
        w(&mut self.out, "U12K1", plc.bskip);
        w(&mut self.out, "U11K6", plc.comu);
        w(&mut self.out, "U10N0", plc.cub);
        w(&mut self.out, "U10N1", plc.zone2);
        w(&mut self.out, "U15N24", plc.hw.0);
        w(&mut self.out, "W15N0", plc.hw.1);
        w(&mut self.out, "W15N2", plc.hw.2);
        row
    }

    /// `n` ticks with `plc`.
    pub fn run(&mut self, n: usize, plc: &Plc) -> Vec<Row> {
        (0..n).map(|_| self.step(plc)).collect()
    }

    /// Loads `blocks`, selects AUTO and presses START through the PLC (edge at the next tick).
    pub fn start_program(&mut self, blocks: Vec<Canon>) {
        let p = self.cnc.process_mut(1).expect("process 1");
        p.load("test", blocks).expect("idle");
        p.command(crate::Command::SetMode(crate::Mode::Auto));
    }
}
