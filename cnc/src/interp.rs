//! The coordinated interpolator a process drives, as the kernel sees it: canonical blocks in,
//! set points per interpolation tick out, with the run-time commands (hold, overrides, abort).
//!
//! The one implementation is the `motion` crate's `Kernel` (`crate::motion_link`); the trait
//! keeps the executor independent of its construction and lets it own a `Box<dyn Interpolator>`.

use partprogram::Canon;

/// What one interpolation tick produced, besides the position.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TickOut {
    /// Tags of the blocks whose motion ended in this tick (DEN), in order.
    pub finished: Vec<u64>,
    /// The path is stopped by a hold.
    pub held: bool,
    /// Path feed in mm/min.
    pub feed_mm_min: f64,
    /// The tag of the block the set point is on (None at rest).
    pub tag: Option<u64>,
}

/// A coordinated interpolator.
pub trait Interpolator: Send {
    /// Queues the motion of a canonical block (rapid, line, arc or dwell) under `tag`.
    fn push(&mut self, tag: u64, block: &Canon) -> Result<(), String>;
    /// Every block before the path stops is queued (the program ends, or the next block waits
    /// for functions or is not run ahead): blocks the interpolator holds back to smooth them go
    /// to its queue now.
    fn end_of_input(&mut self) -> Result<(), String> {
        Ok(())
    }
    /// Free places in the queue.
    fn space(&self) -> usize;
    /// Feed override in percent.
    fn set_feed_override(&mut self, percent: u16);
    /// Rapid override in percent.
    fn set_rapid_override(&mut self, percent: u16);
    /// Feed hold on or off.
    fn set_hold(&mut self, on: bool);
    /// The spindle's position (revolutions, signed; an index pulse at every whole revolution) at
    /// the end of the coming tick: G33 threads are locked to it.
    fn set_spindle_position(&mut self, rev: f64);
    /// Stops as fast as the limits allow and forgets the queue.
    fn abort(&mut self);
    /// A fault that stops the process (a thread the spindle's actual speed makes too fast), once.
    fn take_fault(&mut self) -> Option<String> {
        None
    }
    /// A G33 thread waits at its start for the spindle's index pulse.
    fn waiting_for_spindle(&self) -> bool {
        false
    }
    /// The stop on a hardware limit switch: an abort with the axes' emergency deceleration
    /// (AXCFIL `AFC`) where they have one.
    fn emergency_stop(&mut self) {
        self.abort();
    }
    /// One interpolation tick; the set points are then [`Interpolator::position`].
    fn tick(&mut self, out: &mut TickOut);
    /// The set point of every axis (process axis order).
    fn position(&self) -> &[f64];
    /// Nothing queued and nothing moving.
    fn is_idle(&self) -> bool;
    /// At rest: the current position gets the coordinates `pos` (homing sets a new zero).
    fn set_position(&mut self, pos: &[f64]) -> Result<(), String>;
    /// Soft limits on or off (off while homing: the coordinates mean nothing before it).
    fn set_soft_limits(&mut self, _on: bool) -> Result<(), String> {
        Ok(())
    }
    /// The acceleration law from the PLC's ACC1/ACC2 bits: 0 linear, 1 S-shaped, 2 exponential.
    fn set_law(&mut self, _code: u8) {}
    /// The `ncplc nc run` summary line about contour control for a program with
    /// `contour_blocks` blocks under it (None: none, or no such interpolator).
    fn contour_summary(&self, _contour_blocks: usize) -> Option<String> {
        None
    }
    /// The trajectory header line (`ncplc nc run --trajectory` format), when it has one;
    /// `contour_blocks` is the number of the program's blocks under contour control.
    fn trajectory_header(&self, _contour_blocks: usize) -> Option<String> {
        None
    }
}

/// The "interpolator" of a process without coordinated axes (the mill's magazine process): it
/// accepts no motion, so such a process runs only auxiliary functions and dwell-free blocks.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoMotion;

impl Interpolator for NoMotion {
    fn push(&mut self, tag: u64, _: &Canon) -> Result<(), String> {
        Err(format!(
            "block tag {tag}: the process has no coordinated axes to move"
        ))
    }
    fn space(&self) -> usize {
        0
    }
    fn set_feed_override(&mut self, _: u16) {}
    fn set_rapid_override(&mut self, _: u16) {}
    fn set_hold(&mut self, _: bool) {}
    fn set_spindle_position(&mut self, _: f64) {}
    fn abort(&mut self) {}
    fn tick(&mut self, _: &mut TickOut) {}
    fn position(&self) -> &[f64] {
        &[]
    }
    fn is_idle(&self) -> bool {
        true
    }
    fn set_position(&mut self, _: &[f64]) -> Result<(), String> {
        Ok(())
    }
}
