//! Closed-form profiles: a lone line under the linear and S laws, a full circle at the
//! centripetal limit, a feed-hold stop distance.

use motion::{AccParams, AxisLimits, Config, Kernel, Law, Move, Path};

fn axis(name: char, v: f64, a: f64) -> AxisLimits {
    AxisLimits {
        name,
        v_max: v,
        a_max: a,
        j_max: None,
        v_rapid: v,
        a_rapid: a,
        j_rapid: None,
        soft_min: None,
        soft_max: None,
    }
}

fn cfg(law: Law) -> Config {
    Config {
        axes: vec![
            axis('X', 100.0, 1000.0),
            axis('Y', 100.0, 1000.0),
            axis('Z', 100.0, 1000.0),
        ],
        tick_s: 0.001,
        tolerance_mm: 0.01,
        law,
        window: 256,
        acc: AccParams::default(),
    }
}

fn line(tag: u64, end: [f64; 3], f: f64) -> Move {
    Move {
        tag,
        path: Path::Line,
        end: end.to_vec(),
        feed_mm_min: Some(f),
        exact_stop: false,
        tolerance: None,
        thread_pitch: None,
    }
}

/// Runs to idle; returns the number of ticks with motion (the last tick reaching the end).
fn run(k: &mut Kernel) -> (usize, Vec<Vec<f64>>) {
    let mut pts = vec![k.position().to_vec()];
    let mut n = 0;
    while !k.is_idle() {
        pts.push(k.tick().position.clone());
        n += 1;
        assert!(n < 10_000_000);
    }
    (n, pts)
}

#[test]
fn lone_line_trapezoid_time() {
    // X 100 mm at F3000 (50 mm/s, A = 0.98·1000 along X): T = L/v + v/A.
    let mut k = Kernel::new(cfg(Law::Linear), &[0.0, 0.0, 0.0]).unwrap();
    k.push(line(1, [100.0, 0.0, 0.0], 3000.0)).unwrap();
    let (n, pts) = run(&mut k);
    let t = 100.0 / 50.0 + 50.0 / 980.0; // 2.051020 s
    assert_eq!(n, (t / 0.001_f64).ceil() as usize);
    assert_eq!(pts.last().unwrap(), &vec![100.0, 0.0, 0.0]);
}
