//! A rigorous lower bound on the motion time of a program (issue 10's yardstick): the larger of
//! (a) the path bound Σ (length − corner slack) / allowed speed and (b) for each axis, the time of
//! its monotone runs under its own speed and acceleration limits.

use crate::config::Config;
use crate::geom::{Shape, turn_angle, vector};
use crate::moves::{Move, Path};
use crate::plan;
use detmath::Det as _;

/// The lower bound, s, for feed moves from `start` under `cfg` (linear law limits).
pub fn lower_bound(cfg: &Config, start: &[f64], moves: &[Move]) -> f64 {
    let tol = cfg.tolerance_mm;
    let mut p = vector(start);
    let mut segs = Vec::new();
    for m in moves {
        let e = vector(&m.end);
        if let Ok(Some(s)) = plan::segment(m, &p, &e)
            && s.len > 0.0
        {
            let f = m.feed_mm_min.map_or(f64::INFINITY, |f| f / 60.0);
            segs.push((s, f, matches!(m.path, Path::Arc { .. })));
        }
        p = e;
    }
    // (a) the path bound.
    let mut a = 0.0;
    for (k, (s, f, is_arc)) in segs.iter().enumerate() {
        let share = s.max_share();
        let mut allowed = *f;
        for (i, ax) in cfg.axes.iter().enumerate() {
            if share[i] > 0.0 && !*is_arc {
                allowed = allowed.min(ax.v_max / share[i]);
            }
        }
        if *is_arc {
            // Any direction in the plane: at best every axis at its limit.
            let v: f64 = cfg
                .axes
                .iter()
                .map(|x| x.v_max * x.v_max)
                .sum::<f64>()
                .sqrt();
            allowed = allowed.min(v);
        }
        let mut slack = 0.0;
        if k > 0 {
            let th = turn_angle(&segs[k - 1].0.tangent(true), &s.tangent(false));
            slack += tol * (th / 2.0).dsin();
        }
        if let Some(nx) = segs.get(k + 1) {
            let th = turn_angle(&s.tangent(true), &nx.0.tangent(false));
            slack += tol * (th / 2.0).dsin();
        }
        a += ((s.len - slack).max(0.0)) / allowed;
    }
    // (b) the axis bound over monotone runs (sampled finely on arcs).
    let mut b: f64 = 0.0;
    for (i, (ax, &s0)) in cfg.axes.iter().zip(start).enumerate() {
        let (v, acc) = (ax.v_max, ax.a_max);
        let mut pts: Vec<f64> = vec![s0];
        for (s, _, _) in &segs {
            let steps = match s.shape {
                Shape::Line { .. } => 1,
                Shape::Arc { sweep, .. } => ((sweep / 0.01).ceil() as usize).max(1),
            };
            for k in 1..=steps {
                pts.push(s.at(s.len * k as f64 / steps as f64)[i]);
            }
        }
        let mut total = 0.0;
        let mut run = 0.0;
        let mut dir = 0.0;
        let close = |d: f64| {
            let d = (d - 2.0 * tol).max(0.0);
            if d <= v * v / acc {
                2.0 * (d / acc).sqrt()
            } else {
                d / v + v / acc
            }
        };
        for w in pts.windows(2) {
            let d = w[1] - w[0];
            if d == 0.0 {
                continue;
            }
            let sg = d.signum();
            if dir != 0.0 && sg != dir {
                total += close(run);
                run = 0.0;
            }
            dir = sg;
            run += d.abs();
        }
        total += close(run);
        b = b.max(total);
    }
    a.max(b)
}
