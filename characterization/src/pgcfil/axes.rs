//! Questions PGCFIL and IOCFIL ask of AXCFIL: does an axis exist in a process, what type is it.

use crate::axcfil::{Axcfil, Axis, AxisType};

/// The section-2 definition of axis `c`, searched in every process (COM axes are defined once).
pub(crate) fn axis<'a>(ax: &'a Axcfil, c: char) -> Option<&'a Axis> {
    ax.processes.iter().find_map(|p| p.axis(c))
}

/// The TPA type of axis `c`, when defined.
pub(crate) fn axis_type(ax: &Axcfil, c: char) -> Option<AxisType> {
    axis(ax, c).and_then(|a| a.tpa.as_ref()).map(|t| t.axis_type)
}

/// True when process `n` of AXCFIL has axis `c` (own section-2 axis, COM axis, or interpolator axis).
pub(crate) fn in_process(ax: &Axcfil, n: u32, c: char) -> bool {
    ax.process(n).is_some_and(|p| p.axis(c).is_some() || p.common_axes().any(|a| a == c) || p.interpolator_of(c).is_some())
}

/// True for a continuous coordinate axis (not a spindle, not point-to-point, not virtual-only).
pub(crate) fn continuous(t: &AxisType) -> bool {
    t.coordinate && !t.spindle() && !t.ptp
}

/// Number of continuous coordinate axes of process `n`.
pub(crate) fn continuous_count(ax: &Axcfil, n: u32) -> usize {
    ax.process(n).map_or(0, |p| {
        let mut names: Vec<char> = p.interpolators.iter().flat_map(|i| i.axes.iter().copied()).collect();
        names.sort_unstable();
        names.dedup();
        names.into_iter().filter(|&c| axis_type(ax, c).is_some_and(|t| continuous(&t))).count()
    })
}
