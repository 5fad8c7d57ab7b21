//! Hardware limit switches (AXCFIL `MFC`, characterization-system-axes.md §10.21, 003:2520-2546):
//! the simulated machine presses an axis's + or − switch beyond the edge `sim.toml [[axis]]`
//! gives (`limit_pos`, `limit_neg`, machine scale), the kernel writes the MFC inputs as the
//! normally-closed contacts the manual recommends (1 = released, 0 = on the switch), and an axis
//! that moves further onto a pressed switch stops the process with a stopping alarm naming the
//! axis, the direction and the input (every motion aborted, as for an e-stop).
//!
//! After RESET the axis may be jogged off the switch (away from it); moving onto it again raises
//! the alarm again. The stop decelerates every axis at its AFC emergency deceleration
//! (characterization-system-axes.md §10.22, 003:2548-2568; an axis without AFC at its own limit),
//! so the switch must be long enough for that stop, as 003:2540 asks of a real machine.

use crate::process::Process;

impl Process {
    /// Places the hardware limit switches of axis `i` of the simulated machine: the + switch is
    /// pressed at or beyond `positive`, the − switch at or below `negative` (machine scale).
    pub fn place_limit_switches(&mut self, i: usize, positive: Option<f64>, negative: Option<f64>) {
        if let Some(d) = self.drives.get_mut(i) {
            d.set_limit_switches(positive, negative);
        }
    }

    /// The MFC inputs (+, −) of axis `i` (both `None` for an axis without MFC or out of range).
    pub fn limit_inputs(&self, i: usize) -> (Option<packets::Signal>, Option<packets::Signal>) {
        self.cfg
            .axes
            .get(i)
            .map_or((None, None), |a| a.limit_inputs)
    }

    /// Writes the MFC inputs of every axis whose switches the machine simulates.
    pub(crate) fn write_limit_switches(&self, image: &mut [u8]) {
        for (a, d) in self.cfg.axes.iter().zip(&self.drives) {
            let inputs = [a.limit_inputs.0, a.limit_inputs.1];
            for (input, pressed) in inputs.iter().zip(d.limit_pressed()) {
                if let (Some(input), Some(pressed)) = (input, pressed) {
                    input.write(image, u8::from(!pressed));
                }
            }
        }
    }

    /// Stops the process with an alarm when an axis moved further onto a pressed switch in the
    /// last servo tick (the slide's actual motion) (once: the alarm stays until RESET, the stop is not restarted meanwhile).
    pub(crate) fn watch_limit_switches(&mut self) {
        let mut tripped = None;
        for (a, d) in self.cfg.axes.iter().zip(&self.drives) {
            let dir = d.direction();
            let [pos, neg] = d.limit_pressed();
            let (side, input) = if pos == Some(true) && dir > 0.0 {
                ("+", a.limit_inputs.0)
            } else if neg == Some(true) && dir < 0.0 {
                ("-", a.limit_inputs.1)
            } else {
                continue;
            };
            let input = input.map_or_else(|| "not wired".to_string(), |s| s.to_string());
            tripped = Some(format!(
                "axis {} ran onto its {side} hardware limit switch (MFC {input})",
                a.name
            ));
            break;
        }
        let Some(message) = tripped else {
            return;
        };
        let active = self.alarms().iter().any(|x| x.message.ends_with(&message));
        if !active {
            self.interp.emergency_stop();
            self.raise(message, true);
        }
    }
}
