//! An independent check of a kernel's output: per-axis speed, acceleration and jerk from finite
//! differences of the set points, against the limits of the block being run, and the distance of
//! every set point from the programmed (unblended) path. A G33 thread has no ramps (it follows
//! the spindle, manual 000:618): its speed is checked, its start and end steps are not.

use std::collections::BTreeMap;

use crate::config::{Config, Law};
use crate::geom::{Seg, Vector, vector};
use crate::kernel::Tick;
use crate::moves::{Move, Path};
use crate::plan::{self, axis_vaj};

/// What the monitor found.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Report {
    /// Ticks sampled.
    pub ticks: u64,
    /// Peak |v| / limit per axis.
    pub v: Vec<f64>,
    /// Peak |a| / limit per axis.
    pub a: Vec<f64>,
    /// Peak |j| / limit per axis (None: no jerk limit under this law).
    pub j: Vec<Option<f64>>,
    /// Peak |j| per axis, mm/s³.
    pub j_abs: Vec<f64>,
    /// Largest distance of a set point from the programmed path, mm.
    pub deviation: f64,
    /// The tag at the largest deviation.
    pub deviation_tag: Option<u64>,
}

/// Samples ticks and records peaks; feed it every pushed move and every tick.
#[derive(Debug, Clone)]
pub struct Monitor {
    cfg: Config,
    law: Law,
    end: Vector,
    /// Per move: its programmed geometry, rapid, thread.
    segs: Vec<(Option<Seg>, bool, bool)>,
    index: BTreeMap<u64, usize>,
    /// The last set points: position, on a rapid, on a thread.
    hist: Vec<(Vector, bool, bool)>,
    report: Report,
    /// Programmed units → slide mm (see [`Config::slide_scale`]): the checks are on the slide.
    scale: Vec<f64>,
}

impl Monitor {
    /// A monitor for a kernel built from `cfg` starting at `start`, checking against `law`.
    pub fn new(cfg: &Config, start: &[f64], law: Law) -> Monitor {
        let n = cfg.axes.len();
        let scale = cfg.slide_scale();
        let start: Vec<f64> = start.iter().zip(&scale).map(|(x, k)| x * k).collect();
        let start = start.as_slice();
        Monitor {
            scale,
            cfg: cfg.clone(),
            law,
            end: vector(start),
            segs: Vec::new(),
            index: BTreeMap::new(),
            hist: vec![(vector(start), false, false)],
            report: Report {
                v: vec![0.0; n],
                a: vec![0.0; n],
                j: vec![None; n],
                j_abs: vec![0.0; n],
                ..Report::default()
            },
        }
    }

    /// Records the programmed geometry of a move the kernel accepted.
    pub fn push(&mut self, m: &Move) {
        let m = &m.scaled(&self.scale);
        let end = vector(&m.end);
        let seg = plan::segment(m, &self.end, &end).ok().flatten();
        self.index.insert(m.tag, self.segs.len());
        self.segs
            .push((seg, matches!(m.path, Path::Rapid), m.thread_pitch.is_some()));
        self.end = end;
    }

    /// Samples one tick.
    pub fn sample(&mut self, t: &Tick) {
        let slide: Vec<f64> = t
            .position
            .iter()
            .zip(&self.scale)
            .map(|(x, k)| x * k)
            .collect();
        let p = vector(&slide);
        let idx = t.tag.and_then(|g| self.index.get(&g).copied());
        let rapid = idx.is_some_and(|i| self.segs[i].1);
        let thread = idx.is_some_and(|i| self.segs[i].2);
        if let Some(i) = idx {
            let mut best = f64::INFINITY;
            for k in i.saturating_sub(1)..(i + 2).min(self.segs.len()) {
                if let (Some(s), _, _) = &self.segs[k] {
                    best = best.min(s.distance(&p));
                }
            }
            if best.is_finite() && best > self.report.deviation {
                self.report.deviation = best;
                self.report.deviation_tag = t.tag;
            }
        }
        self.hist.push((p, rapid, thread));
        if self.hist.len() > 4 {
            self.hist.remove(0);
        }
        self.report.ticks += 1;
        let dt = self.cfg.tick_s;
        let h = &self.hist;
        let any_rapid = h.iter().any(|x| x.1);
        let any_thread = h.iter().any(|x| x.2);
        let m = h.len();
        for (i, ax) in self.cfg.axes.iter().enumerate() {
            let (v_lim, a_lim, j_lim) = axis_vaj(ax, any_rapid, self.law, &self.cfg.acc);
            let d = |k: usize| (h[k].0[i] - h[k - 1].0[i]) / dt;
            let v = d(m - 1);
            self.report.v[i] = self.report.v[i].max(v.abs() / v_lim);
            if m >= 3 && !any_thread {
                let a = (v - d(m - 2)) / dt;
                self.report.a[i] = self.report.a[i].max(a.abs() / a_lim);
                if m >= 4 {
                    let a0 = (d(m - 2) - d(m - 3)) / dt;
                    let j = (a - a0) / dt;
                    self.report.j_abs[i] = self.report.j_abs[i].max(j.abs());
                    if j_lim.is_finite() {
                        let f = j.abs() / j_lim;
                        self.report.j[i] = Some(self.report.j[i].unwrap_or(0.0).max(f));
                    }
                }
            }
        }
    }

    /// The peaks so far.
    pub fn report(&self) -> &Report {
        &self.report
    }
}
