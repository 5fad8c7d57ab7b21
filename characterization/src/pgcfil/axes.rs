//! Questions PGCFIL and IOCFIL ask of AXCFIL: does an axis exist in a process, what type is it.
//!
//! Axis names are per process (two processes may both have an X); an axis shared with COM is
//! defined in the process COM names.

use crate::axcfil::{Axcfil, Axis, AxisType};

/// The section-2 definition of axis `c` as process `n` sees it: its own axis, or the axis of the
/// process a COM instruction shares it from.
pub(crate) fn axis_of(ax: &Axcfil, n: u32, c: char) -> Option<&Axis> {
    let p = ax.process(n)?;
    p.axis(c).or_else(|| {
        p.common
            .iter()
            .filter(|k| k.axes.contains(&c))
            .find_map(|k| ax.process(k.process).and_then(|q| q.axis(c)))
    })
}

/// The section-2 definition of axis `c` in any process (for names that are not per process, such
/// as handwheel axes).
pub(crate) fn any_axis(ax: &Axcfil, c: char) -> Option<&Axis> {
    ax.processes.iter().find_map(|p| p.axis(c))
}

/// The TPA type of axis `c` of process `n`, when defined.
pub(crate) fn axis_type(ax: &Axcfil, n: u32, c: char) -> Option<AxisType> {
    axis_of(ax, n, c)
        .and_then(|a| a.tpa.as_ref())
        .map(|t| t.axis_type)
}

/// True when process `n` of AXCFIL has axis `c` (own section-2 axis, COM axis, or interpolator axis).
pub(crate) fn in_process(ax: &Axcfil, n: u32, c: char) -> bool {
    ax.process(n).is_some_and(|p| {
        p.axis(c).is_some() || p.common_axes().any(|a| a == c) || p.interpolator_of(c).is_some()
    })
}

/// True for a continuous coordinate axis (not a spindle, not point-to-point).
pub(crate) fn continuous(t: &AxisType) -> bool {
    t.coordinate && !t.spindle() && !t.ptp
}

/// Number of continuous coordinate axes on the interpolators of process `n`.
pub(crate) fn continuous_count(ax: &Axcfil, n: u32) -> usize {
    ax.process(n).map_or(0, |p| {
        let mut names: Vec<char> = p
            .interpolators
            .iter()
            .flat_map(|i| i.axes.iter().copied())
            .collect();
        names.sort_unstable();
        names.dedup();
        names
            .into_iter()
            .filter(|&c| axis_type(ax, n, c).is_some_and(|t| continuous(&t)))
            .count()
    })
}
