//! The `motion` crate's kernel as the process's [`Interpolator`]: its configuration from AXCFIL
//! and the complex-speed constants (`nc/CONSTANTS`), canonical blocks turned into moves in the
//! process's axis order.
//!
//! Contour control (Fanuc G05.1 Q1 / G08 P1, MEFI G23: `BlockModal::contour`) is switched on the
//! kernel before each block is pushed, exactly as `ncplc nc run` does, so a part run plans and
//! smooths a program as `nc run` does (the executor pushes blocks before every interpolation tick
//! and calls [`Interpolator::end_of_input`] where `nc run` would push a block with functions).

use partprogram::Canon;

use crate::config::ProcessConfig;
use crate::interp::{Interpolator, TickOut};

/// The motion kernel of one process and its axis letters (Config order).
pub struct MotionKernel {
    kernel: motion::Kernel,
    axes: Vec<char>,
    /// AFC of every axis (emergency deceleration on a limit switch, mm/s²), Config order.
    afc: Vec<Option<f64>>,
}

impl MotionKernel {
    /// The kernel of process `cfg.number` configured from AXCFIL and the complex-speed constants,
    /// at rest at `start`; its axes must be the process's coordinated axes in the same order.
    pub fn new(
        axcfil: &characterization::axcfil::Axcfil,
        cfg: &ProcessConfig,
        start: &[f64],
        complex: motion::complex::ComplexSpeed,
    ) -> Result<MotionKernel, String> {
        let mut mc = motion::config_from_axcfil(axcfil, u32::from(cfg.number))
            .map_err(|e| format!("motion configuration: {e}"))?;
        mc.complex = complex;
        let axes = mc.axis_names();
        if axes != cfg.axis_names() {
            return Err(format!(
                "the motion kernel interpolates {:?}, the process has {:?}",
                axes,
                cfg.axis_names()
            ));
        }
        // The process checks the active zone (LO1 or LO2 by ZONE2) and the CUB box itself
        // (`crate::zones`): the motion kernel's own LO1 check would refuse what LO2 allows.
        for a in &mut mc.axes {
            (a.soft_min, a.soft_max) = (None, None);
        }
        let kernel = motion::Kernel::new(mc, start).map_err(|e| format!("motion: {e}"))?;
        let afc = axcfil
            .process(u32::from(cfg.number))
            .map(|p| {
                axes.iter()
                    .map(|&a| p.axis(a).and_then(|x| x.afc))
                    .collect()
            })
            .unwrap_or_default();
        Ok(MotionKernel { kernel, axes, afc })
    }
}

impl Interpolator for MotionKernel {
    fn push(&mut self, tag: u64, block: &Canon) -> Result<(), String> {
        let mut b = block.clone();
        b.end.retain(|(a, _)| self.axes.contains(a));
        let m = motion::Move::from_canon(tag, &b, &self.axes).map_err(|e| e.to_string())?;
        self.kernel
            .set_smoothing(block.modal.contour)
            .map_err(|e| e.to_string())?;
        self.kernel.push(m).map_err(|e| e.to_string())
    }
    fn end_of_input(&mut self) -> Result<(), String> {
        self.kernel.end_of_input().map_err(|e| e.to_string())
    }
    fn space(&self) -> usize {
        self.kernel.space()
    }
    fn set_feed_override(&mut self, percent: u16) {
        self.kernel.set_feed_override(percent);
    }
    fn set_rapid_override(&mut self, percent: u16) {
        self.kernel.set_rapid_override(percent);
    }
    fn set_hold(&mut self, on: bool) {
        self.kernel.set_hold(on);
    }
    fn set_spindle_position(&mut self, rev: f64) {
        self.kernel.set_spindle_position(rev);
    }
    fn abort(&mut self) {
        self.kernel.abort();
    }
    fn take_fault(&mut self) -> Option<String> {
        self.kernel.take_fault().map(|e| e.to_string())
    }
    fn waiting_for_spindle(&self) -> bool {
        self.kernel.waiting_for_index()
    }
    fn emergency_stop(&mut self) {
        self.kernel.emergency_stop(&self.afc);
    }
    fn tick(&mut self, out: &mut TickOut) {
        let t = self.kernel.tick();
        out.finished.extend_from_slice(&t.finished);
        out.held = t.held;
        out.feed_mm_min = t.feed_mm_min;
        out.tag = t.tag;
    }
    fn position(&self) -> &[f64] {
        self.kernel.position()
    }
    fn is_idle(&self) -> bool {
        self.kernel.is_idle()
    }
    fn set_soft_limits(&mut self, _on: bool) -> Result<(), String> {
        // The limits are the process's (`crate::zones`); the kernel restarts at rest where it
        // stands, as homing expects.
        let cfg = self.kernel.config().clone();
        let pos = self.kernel.position().to_vec();
        self.kernel = motion::Kernel::new(cfg, &pos).map_err(|e| format!("motion: {e}"))?;
        Ok(())
    }
    fn set_law(&mut self, code: u8) {
        let law = match code {
            1 => motion::Law::SCurve,
            2 => motion::Law::Exponential,
            _ => motion::Law::Linear,
        };
        if self.kernel.law() != law {
            self.kernel.set_law(law);
        }
    }
    fn contour_summary(&self, contour_blocks: usize) -> Option<String> {
        let c = self.kernel.config();
        (contour_blocks > 0)
            .then(|| motion::smooth::summary_line(c.tolerance_mm, contour_blocks, &c.complex))
    }
    fn trajectory_header(&self, contour_blocks: usize) -> Option<String> {
        let c = self.kernel.config();
        let num = |v: f64| partprogram::canon::num(v);
        let opt = |v: Option<f64>| v.map_or("null".to_string(), num);
        let limits: Vec<String> = c
            .axes
            .iter()
            .map(|a| {
                format!(
                    "\"{}\":{{\"v\":{},\"a\":{},\"j\":{}}}",
                    a.name,
                    num(a.v_max),
                    num(a.a_max),
                    opt(a.j_max)
                )
            })
            .collect();
        let axes: Vec<String> = self.axes.iter().map(|a| format!("\"{a}\"")).collect();
        Some(format!(
            "{{\"tick_s\":{},\"axes\":[{}],\"limits\":{{{}}},\"tolerance_mm\":{},\"law\":\"{}\",\"contour\":{}}}",
            num(c.tick_s),
            axes.join(","),
            limits.join(","),
            num(c.tolerance_mm),
            c.law.name(),
            motion::smooth::header_json(c.tolerance_mm, contour_blocks, &c.complex)
        ))
    }
    fn set_position(&mut self, pos: &[f64]) -> Result<(), String> {
        let cfg = self.kernel.config().clone();
        self.kernel = motion::Kernel::new(cfg, pos).map_err(|e| format!("motion: {e}"))?;
        Ok(())
    }
}
