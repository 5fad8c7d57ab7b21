//! Which image bits the kernel and its plant own: every CNC→PLC signal [`Process::step`] writes
//! (with the full width of the S and T codes) and the plant's contacts in packet A (home
//! switches, spindle at-speed and stopped). A replay recomputes these bits with the kernel and
//! compares them instead of applying the trace's values.

use packets::Signal;

use crate::process::Process;

/// Sets the bits of `s` in `mask` (one mask byte per image byte); a byte signal covers `width`
/// bytes from its own.
pub fn mark(mask: &mut [u8], s: Signal, width: usize) {
    let at = s.image_byte();
    match s.bit() {
        Some(b) => {
            if let Some(m) = mask.get_mut(at) {
                *m |= 1 << b;
            }
        }
        None => {
            for m in mask.iter_mut().skip(at).take(width) {
                *m = 0xFF;
            }
        }
    }
}

impl Process {
    /// Marks every image bit this process writes (see the module docs).
    pub fn written_mask(&self, mask: &mut [u8]) {
        let s = &self.sig;
        for sig in [
            s.conp, s.den, s.alarm, s.cycle, s.hold, s.standby, s.mode, s.mimm, s.fg96,
        ]
        .into_iter()
        .flatten()
        {
            mark(mask, sig, 1);
        }
        if let (Some(g), Some(cfg)) = (s.gear_request, &self.cfg.spindle)
            && cfg.ranges.len() > 1
        {
            mark(mask, g, 1);
        }
        for (i, c) in s.channels.iter().enumerate() {
            if let Some(c) = c {
                mark(mask, c.strobe, 1);
                mark(mask, c.code, if i == 0 { 1 } else { 4 });
            }
        }
        for (i, a) in self.cfg.axes.iter().enumerate() {
            if let (Some(input), Some(_)) = (a.home.and_then(|h| h.input), self.home_pressed(i)) {
                mark(mask, input, 1);
            }
        }
        if let (Some(_), Some(cfg)) = (&self.spindle, &self.cfg.spindle) {
            for sig in [
                cfg.at_speed_signal,
                cfg.stopped_signal,
                self.plant.at_speed,
                self.plant.stopped,
            ]
            .into_iter()
            .flatten()
            {
                mark(mask, sig, 1);
            }
        }
    }

    /// The drives' actual positions with their axis letters, in process axis order.
    pub fn actual_positions(&self) -> impl Iterator<Item = (char, f64)> + '_ {
        self.cfg
            .axes
            .iter()
            .zip(&self.drives)
            .map(|(a, d)| (a.name, d.actual()))
    }
}
