//! Prints the set points of one program of the CAM set (`motion::cam::set`, by exact name) on
//! the mill under contour control, one tick per line (`x y z`, mm), in the format of
//! LinuxCNC's sampler files from `motion/compare/linuxcnc/run.sh`, so that
//! `motion/compare/linuxcnc/speed_along.py` can compare the path speeds of both along the path.
use motion::{Kernel, cam, samples};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let name = std::env::args()
        .nth(1)
        .ok_or("usage: cam_trace <program name>")?;
    let p = cam::set()
        .into_iter()
        .find(|p| p.name == name)
        .ok_or_else(|| format!("no CAM program {name}"))?;
    let mut k = Kernel::new(samples::mill(), &p.start)?;
    k.set_smoothing(true)?;
    let mut next = 0;
    let mut out = String::new();
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
        let t = k.tick();
        out.push_str(&format!(
            "{:.6} {:.6} {:.6}\n",
            t.position[0], t.position[1], t.position[2]
        ));
    }
    print!("{out}");
    Ok(())
}
