//! Prints, for the CAM benchmark set, ncplc's motion time on the mill without and with
//! tolerance-band smoothing, the lower bound and the ratios, and the lowest path speed as a
//! share of F over the middle 80 % of the program (with smoothing).
use motion::{Kernel, bound::lower_bound, cam, samples};

fn run(p: &cam::CamProgram, smooth: bool) -> Result<(f64, f64), Box<dyn std::error::Error>> {
    let mut k = Kernel::new(samples::mill(), &p.start)?;
    k.set_smoothing(smooth)?;
    let (mut next, mut feeds) = (0, Vec::new());
    loop {
        while next < p.moves.len() && k.space() > 0 {
            k.push(p.moves[next].clone())?;
            next += 1;
            if next == p.moves.len() {
                k.end_of_input()?;
            }
        }
        if next >= p.moves.len() && k.is_idle() {
            break;
        }
        feeds.push(k.tick().feed_mm_min);
    }
    let f = p.moves[0].feed_mm_min.unwrap_or(1.0);
    let mid = &feeds[feeds.len() / 10..feeds.len() * 9 / 10];
    let lo = mid.iter().cloned().fold(f64::INFINITY, f64::min) / f;
    Ok((feeds.len() as f64 * 0.001, lo))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let filter = std::env::args().nth(1).unwrap_or_default();
    for p in cam::set() {
        if !p.name.contains(&filter) {
            continue;
        }
        let lb = lower_bound(&samples::mill(), &p.start, &p.moves);
        let (t0, lo0) = run(&p, false)?;
        let (t1, lo1) = run(&p, true)?;
        println!(
            "{:>32}: bound {lb:7.3} s | plain {t0:7.3} s {:.4} min {:5.1} % | smooth {t1:7.3} s {:.4} min {:5.1} % | {} blocks",
            p.name,
            t0 / lb,
            lo0 * 100.0,
            t1 / lb,
            lo1 * 100.0,
            p.moves.len()
        );
    }
    Ok(())
}
