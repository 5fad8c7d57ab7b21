//! `motion::PtpAxis` (jog, increments, handwheel and homing moves, on the rsruckig port) against
//! the reference Ruckig (PyPI `ruckig`, through `tests/peers/ruckig_peer.py`): 300 random cases of
//! moves, re-targeted moves, jogs, reversals and stops, with and without a jerk limit, at three
//! ticks; every tick's position must agree within 1e-9 mm and the moves must end at the same tick.
//!
//! Needs `python3` with `ruckig` (`python3 -m pip install ruckig`); without it the test is skipped
//! with a loud message (like the rs274 differential test).

use std::io::Write as _;
use std::process::{Command, Stdio};

use motion::PtpAxis;

/// One command at a tick: move to (target, speed) or jog (direction, speed).
#[derive(Debug, Clone, Copy)]
enum Cmd {
    To(f64, f64),
    Jog(i8, f64),
}

#[derive(Debug, Clone)]
struct Case {
    v: f64,
    a: f64,
    j: Option<f64>,
    dt: f64,
    p0: f64,
    ticks: usize,
    cmds: Vec<(usize, Cmd)>,
}

impl Case {
    fn line(&self) -> String {
        let mut s = format!(
            "{:?} {:?} {} {:?} {:?} {}",
            self.v,
            self.a,
            self.j.map_or("inf".to_string(), |j| format!("{j:?}")),
            self.dt,
            self.p0,
            self.ticks
        );
        for (t, c) in &self.cmds {
            match c {
                Cmd::To(x, v) => s += &format!(" {t}:to:{x:?}:{v:?}"),
                Cmd::Jog(d, v) => s += &format!(" {t}:jog:{d}:{v:?}"),
            }
        }
        s
    }

    /// The positions `PtpAxis` gives, tick by tick.
    fn ours(&self) -> Vec<f64> {
        let mut ax = PtpAxis::new(self.v, self.a, self.j, self.dt, self.p0);
        (0..self.ticks)
            .map(|t| {
                for (at, c) in &self.cmds {
                    if *at == t {
                        match *c {
                            Cmd::To(x, v) => ax.move_to(x, v),
                            Cmd::Jog(d, v) => ax.jog(d, v),
                        }
                    }
                }
                ax.tick()
            })
            .collect()
    }
}

/// A small deterministic generator (the cases must be the same on every run and machine).
struct Lcg(u64);

impl Lcg {
    fn unit(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        // Round to 1e-3 so the case lines are short and exact in decimal.
        ((lo + (hi - lo) * self.unit()) * 1000.0).round() / 1000.0
    }
}

fn cases() -> Vec<Case> {
    let mut r = Lcg(20261126);
    let dts = [0.001, 0.002, 0.004];
    (0..300)
        .map(|k| {
            let v = r.range(20.0, 200.0);
            let a = r.range(200.0, 5000.0);
            let j = (k % 2 == 0).then(|| r.range(5_000.0, 500_000.0));
            let dt = dts[k % 3];
            let p0 = r.range(-200.0, 200.0);
            let first = match k % 4 {
                0..=2 => Cmd::To(p0 + r.range(-50.0, 50.0), r.range(5.0, 250.0)),
                _ => Cmd::Jog(if r.unit() < 0.5 { -1 } else { 1 }, r.range(5.0, 250.0)),
            };
            let at = (r.range(1.0, 300.0) as usize).max(1);
            let second = match k % 5 {
                0 => Cmd::To(p0 + r.range(-50.0, 50.0), r.range(5.0, 250.0)),
                1 => Cmd::Jog(0, 0.0),
                2 => Cmd::Jog(if r.unit() < 0.5 { -1 } else { 1 }, r.range(5.0, 250.0)),
                _ => Cmd::To(p0 + r.range(-5.0, 5.0), r.range(5.0, 250.0)),
            };
            let mut cmds = vec![(0, first), (at, second)];
            // A jog always ends: stop it later.
            cmds.push((at + 400, Cmd::Jog(0, 0.0)));
            Case {
                v,
                a,
                j,
                dt,
                p0,
                ticks: (6.0 / dt) as usize,
                cmds,
            }
        })
        .collect()
}

#[test]
fn ptp_axis_agrees_with_the_reference_ruckig() {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/peers/ruckig_peer.py");
    let have = Command::new("python3")
        .args(["-c", "import ruckig"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !have {
        eprintln!(
            "SKIPPED: the reference Ruckig is missing (python3 -m pip install ruckig); PtpAxis was not compared"
        );
        return;
    }
    let cases = cases();
    let mut child = Command::new("python3")
        .arg(script)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("python3 runs");
    {
        let mut stdin = child.stdin.take().expect("stdin");
        for c in &cases {
            writeln!(stdin, "{}", c.line()).expect("write case");
        }
    }
    let out = child.wait_with_output().expect("the peer ends");
    assert!(out.status.success(), "the peer failed");
    let text = String::from_utf8_lossy(&out.stdout);
    let theirs: Vec<Vec<f64>> = text
        .lines()
        .map(|l| l.split(' ').map(|p| p.parse().expect("a float")).collect())
        .collect();
    assert_eq!(theirs.len(), cases.len());
    let mut worst = 0.0f64;
    for (k, (case, theirs)) in cases.iter().zip(&theirs).enumerate() {
        let ours = case.ours();
        assert_eq!(ours.len(), theirs.len(), "case {k}");
        assert!(
            ours.iter().any(|p| *p != case.p0),
            "case {k} never moves: it compares nothing"
        );
        for (t, (o, r)) in ours.iter().zip(theirs).enumerate() {
            let d = (o - r).abs();
            worst = worst.max(d);
            assert!(
                d <= 1e-9,
                "case {k} ({}) tick {t}: PtpAxis {o} vs Ruckig {r}",
                case.line()
            );
        }
        // The same last move: both at rest at the same position from the same tick on.
        let settle = |p: &[f64]| {
            p.windows(2)
                .rposition(|w| w[0] != w[1])
                .map_or(0, |i| i + 1)
        };
        assert_eq!(
            settle(&ours),
            settle(theirs),
            "case {k}: came to rest at another tick"
        );
    }
    eprintln!("300 cases: largest difference {worst:e} mm");
}
