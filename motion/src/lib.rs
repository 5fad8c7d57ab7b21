//! The motion kernel: canonical blocks and axis limits in, one set point per axis per
//! interpolation tick out. Pure: no I/O, no clock, no threads; the same blocks and the same
//! run-time commands give bit-identical set points.
//!
//! # Planning
//! Each block becomes a *piece* of path parameterised by arc length (a line, an arc or helix).
//! The corner between two feed lines is replaced by a circular arc tangent to both whose middle
//! lies exactly `tolerance` from the programmed corner (shorter when either line is short: each
//! blend takes at most half of a line), so every set point is within the tolerance of the path
//! and the path passes within it of every corner. Corners that cannot be blended (involving an
//! arc, a rapid, a thread, an exact stop, or a turn over 179°) are either passed at the speed at
//! which the direction change within one tick stays inside 2 % of every axis's acceleration
//! (and jerk), or stopped at.
//!
//! A piece's speed cap is the programmed feed × override (rapids: the axes' rapid speeds ×
//! rapid override), capped by every axis's speed over its largest share of the direction and,
//! on arcs, by 70 % of every axis's acceleration as centripetal acceleration (80 % on corner
//! blends). Its tangential
//! acceleration is what is left of 98 % of every axis's limit over its share. A backward pass
//! over the look-ahead window (default 500 blocks) gives every piece the highest end speed from
//! which the rest of the queue, ending at rest, can still be met; the piece being entered is then
//! profiled in closed form (speed up to a peak, cruise, change to its end speed), sampled at the
//! tick, and many pieces may be consumed within one tick.
//!
//! Under contour control ([`Kernel::set_smoothing`]: Fanuc G05.1 Q1 / G08 P1, MEFI G23) runs of
//! short lines are smoothed within half the tolerance before planning ([`smooth`]) and the joint
//! speeds follow the MEFI manual's complex speed ([`complex`]: R39 stop, accuracy and dynamic
//! criteria, R386, R236); the axes' limits still hold at every tick.
//!
//! # Acceleration laws (ACC `lin_s, nonlin_s, min_exp, max_exp`)
//! Every velocity change starts and ends at zero path acceleration; a deceleration is the time
//! reversal of the acceleration between the same speeds.
//! * **Linear**: constant acceleration `a` (MAN max_accel for feed moves, RAP for rapids).
//! * **S**: the manual's tg α2 = lin_s · tg α1: the straight part accelerates at `lin_s · a`;
//!   the jerk `j = (lin_s·a)² / (2 · nonlin_s · V)` makes each curved part of a change over the
//!   axis's full speed V cover `nonlin_s · V`, as the manual's V2/V3 fraction says. Smaller
//!   changes use the same jerk (triangular acceleration). `nonlin_s = 0`: no jerk limit.
//! * **Exponential**: within a change the acceleration grows (decays, when slowing down)
//!   exponentially between `a · min_exp / m` and `a · max_exp / m`, `m = max(min_exp, max_exp)`,
//!   so its peak is the axis limit: `a(t) = a₀ e^{kt}`, `k = ln(max_exp/min_exp) / T`.
//!
//! Run-time changes (override, hold, abort) replan the executed piece from its current state at
//! once under the linear law. Under the S law while accelerating, the acceleration first falls to
//! 0 at the jerk limit (a bridge phase) and the new profile starts there; under the exponential law
//! while accelerating, the acceleration drops to 0 at once (as at the end of a change). Either
//! state is behind and slower than the old profile's end of acceleration, so every speed the
//! queue has to meet stays within reach. During a deceleration the replan waits for the next
//! instant of zero acceleration (inside a cruise or at the boundary of a change).

pub mod bound;
pub mod cam;
pub mod complex;
pub mod config;
mod emergency;
pub mod geom;
pub mod kernel;
pub mod monitor;
pub mod moves;
pub mod plan;
pub mod profile;
pub mod ptp;
pub mod samples;
pub mod smooth;
mod thread;

pub use config::{AccParams, AxisLimits, Config, ConfigError, Law, config_from_axcfil};
pub use kernel::{Kernel, Tick};
pub use moves::{MotionError, Move, Path};
pub use ptp::PtpAxis;
