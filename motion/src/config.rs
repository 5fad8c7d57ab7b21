//! The machine dynamics the kernel plans with: per-axis limits, the interpolation tick, the path
//! tolerance and the acceleration law, read from AXCFIL (RAP, MAN, GMxx, ACC, LO1/LOP, INx).

use characterization::axcfil::{Axcfil, Axis, Process};

/// The acceleration law of path-velocity changes (AXCFIL ACC, switched by ACC1/ACC2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Law {
    /// Constant acceleration (trapezoidal velocity).
    #[default]
    Linear,
    /// Jerk-limited S-shaped velocity (see the crate docs for the definition from ACC).
    SCurve,
    /// Exponentially growing acceleration (see the crate docs for the definition from ACC).
    Exponential,
}

impl Law {
    /// The name used on the CLI and in the trajectory header (`linear`, `s`, `exp`).
    pub fn name(self) -> &'static str {
        match self {
            Law::Linear => "linear",
            Law::SCurve => "s",
            Law::Exponential => "exp",
        }
    }
}

impl std::str::FromStr for Law {
    type Err = String;
    fn from_str(s: &str) -> Result<Law, String> {
        match s {
            "linear" => Ok(Law::Linear),
            "s" | "scurve" => Ok(Law::SCurve),
            "exp" | "exponential" => Ok(Law::Exponential),
            _ => Err(format!(
                "unknown acceleration law `{s}` (expected linear, s or exp)"
            )),
        }
    }
}

/// The limits of one interpolated axis (linear: mm, rotary: degrees).
#[derive(Debug, Clone, PartialEq)]
pub struct AxisLimits {
    /// Axis letter.
    pub name: char,
    /// Speed limit of feed moves, mm/s (GMxx Vmax).
    pub v_max: f64,
    /// Acceleration of feed moves, mm/s² (MAN max_accel).
    pub a_max: f64,
    /// Jerk of feed moves under the S law, mm/s³ (derived from ACC; None: no jerk limit).
    pub j_max: Option<f64>,
    /// Rapid-traverse speed, mm/s (RAP fast_speed).
    pub v_rapid: f64,
    /// Rapid-traverse acceleration, mm/s² (RAP fast_accel).
    pub a_rapid: f64,
    /// Jerk of rapids under the S law, mm/s³ (derived from ACC; None: no jerk limit).
    pub j_rapid: Option<f64>,
    /// Lower software limit, mm in programmed units (None: unchecked).
    pub soft_min: Option<f64>,
    /// Upper software limit, mm in programmed units (None: unchecked).
    pub soft_max: Option<f64>,
    /// A diameter axis (TPA code 0040, a lathe's X): programmed and shown as a diameter, moved
    /// as a radius. Positions in and out of the kernel are diameters; the speed, acceleration and
    /// jerk limits, the feed and the path geometry are those of the radius (the slide).
    pub diameter: bool,
}

/// The four ACC parameters (AXCFIL section 1, ECDF).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccParams {
    /// Slope of the linear part of the S law relative to the linear law (tg α2 = k · tg α1).
    pub linear_part_s: f64,
    /// Fraction (0…0.5) of a full-speed change spent in each jerk-limited part of the S law.
    pub nonlinear_part_s: f64,
    /// Relative acceleration at the start of an exponential change.
    pub min_exp: f64,
    /// Relative acceleration at the end of an exponential change.
    pub max_exp: f64,
}

impl Default for AccParams {
    /// The manual's example `ACC=1.5,0.5,1,4`.
    fn default() -> Self {
        AccParams {
            linear_part_s: 1.5,
            nonlinear_part_s: 0.5,
            min_exp: 1.0,
            max_exp: 4.0,
        }
    }
}

impl AccParams {
    /// The S-law jerk of an axis with acceleration `a` and speed `v`: each jerk phase of a change
    /// over the full speed `v` covers `nonlinear_part_s · v` at the peak `linear_part_s · a`.
    pub fn s_jerk(&self, a: f64, v: f64) -> Option<f64> {
        let ap = self.linear_part_s * a;
        (self.nonlinear_part_s > 0.0 && v > 0.0)
            .then(|| ap * ap / (2.0 * self.nonlinear_part_s * v))
    }
}

/// Everything the kernel needs about the machine.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// The interpolated axes, in set-point order.
    pub axes: Vec<AxisLimits>,
    /// Interpolation tick, s (INx int_tick).
    pub tick_s: f64,
    /// Path tolerance of corner blending, mm (MEFI R384, `--tolerance`).
    pub tolerance_mm: f64,
    /// The acceleration law at start.
    pub law: Law,
    /// Look-ahead window, blocks.
    pub window: usize,
    /// The ACC parameters that define the S and exponential laws.
    pub acc: AccParams,
    /// Complex speed (MEFI appendix A6): the joint criteria under contour control.
    pub complex: crate::complex::ComplexSpeed,
}

impl Config {
    /// The factor from programmed units to the slide's mm per axis: 0.5 for a diameter axis.
    pub fn slide_scale(&self) -> Vec<f64> {
        self.axes
            .iter()
            .map(|a| if a.diameter { 0.5 } else { 1.0 })
            .collect()
    }
}

/// A configuration that cannot drive the kernel.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConfigError {
    /// AXCFIL has no such process.
    #[error("AXCFIL has no process {0}")]
    NoProcess(u32),
    /// The process declares no coordinated interpolator.
    #[error("process {0} has no interpolator with axes (INx)")]
    NoInterpolator(u32),
    /// An axis value is missing or not positive.
    #[error("axis {axis}: {what}")]
    Axis {
        /// Axis letter.
        axis: char,
        /// What is wrong.
        what: String,
    },
    /// A general value is out of range.
    #[error("{0}")]
    Value(String),
    /// The start position has the wrong number of axes.
    #[error("start position has {got} coordinates, the configuration {want} axes")]
    Start {
        /// Coordinates given.
        got: usize,
        /// Axes configured.
        want: usize,
    },
}

/// The most axes one kernel interpolates.
pub const MAX_AXES: usize = 12;

impl Config {
    /// Checks that every limit is finite and positive and the tick and tolerance are usable.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.axes.is_empty() || self.axes.len() > MAX_AXES {
            return Err(ConfigError::Value(format!(
                "{} axes (1…{MAX_AXES} supported)",
                self.axes.len()
            )));
        }
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !pos(self.tick_s) {
            return Err(ConfigError::Value(format!("tick {} s", self.tick_s)));
        }
        if !(self.tolerance_mm.is_finite() && self.tolerance_mm >= 0.0) {
            return Err(ConfigError::Value(format!(
                "tolerance {} mm",
                self.tolerance_mm
            )));
        }
        if self.window < 2 {
            return Err(ConfigError::Value(format!(
                "look-ahead window {} (at least 2)",
                self.window
            )));
        }
        let a = &self.acc;
        if !(a.linear_part_s > 0.0
            && (0.0..=0.5).contains(&a.nonlinear_part_s)
            && a.min_exp > 0.0
            && a.max_exp > 0.0)
        {
            return Err(ConfigError::Value(format!("ACC {a:?} out of range")));
        }
        for x in &self.axes {
            for (what, v) in [
                ("v_max", x.v_max),
                ("a_max", x.a_max),
                ("v_rapid", x.v_rapid),
                ("a_rapid", x.a_rapid),
            ] {
                if !pos(v) {
                    return Err(ConfigError::Axis {
                        axis: x.name,
                        what: format!("{what} = {v} (must be > 0)"),
                    });
                }
            }
            if let (Some(lo), Some(hi)) = (x.soft_min, x.soft_max)
                && lo > hi
            {
                return Err(ConfigError::Axis {
                    axis: x.name,
                    what: format!("soft limits {lo} > {hi}"),
                });
            }
        }
        Ok(())
    }

    /// The axis letters in set-point order.
    pub fn axis_names(&self) -> Vec<char> {
        self.axes.iter().map(|a| a.name).collect()
    }
}

/// Builds the configuration of AXCFIL process `process`: the axes of its coordinated interpolator
/// (spindles excluded), RAP for rapids, GMxx Vmax and MAN max_accel for feed moves, the S-law jerk
/// from ACC, the software limits of LO1 (else LOP; both zero: unchecked), int_tick of INx. The
/// tolerance defaults to 0.01 mm and the window to 500 blocks (complex speed looks up to 500 blocks ahead).
pub fn config_from_axcfil(axcfil: &Axcfil, process: u32) -> Result<Config, ConfigError> {
    let p: &Process = axcfil
        .process(process)
        .ok_or(ConfigError::NoProcess(process))?;
    let inx = p
        .interpolators
        .iter()
        .filter(|i| !i.axes.is_empty())
        .max_by_key(|i| (i.spindle.is_some(), i.axes.len()))
        .ok_or(ConfigError::NoInterpolator(process))?;
    let acc = axcfil
        .acc
        .as_ref()
        .map(|a| AccParams {
            linear_part_s: a.linear_part_s,
            nonlinear_part_s: a.nonlinear_part_s,
            min_exp: a.min_exp,
            max_exp: a.max_exp,
        })
        .unwrap_or_default();
    let mut axes = Vec::new();
    for &name in &inx.axes {
        let Some(ax) = p.axis(name) else {
            return Err(ConfigError::Axis {
                axis: name,
                what: "declared in INx but has no NAS subsection".into(),
            });
        };
        if ax.axis_type().spindle() {
            continue;
        }
        axes.push(axis_limits(ax, &acc)?);
    }
    let cfg = Config {
        axes,
        tick_s: f64::from(inx.int_tick) / 1000.0,
        tolerance_mm: 0.01,
        law: Law::Linear,
        window: 500,
        acc,
        complex: crate::complex::ComplexSpeed::default(),
    };
    cfg.validate()?;
    Ok(cfg)
}

fn axis_limits(ax: &Axis, acc: &AccParams) -> Result<AxisLimits, ConfigError> {
    let missing = |what: &str| ConfigError::Axis {
        axis: ax.name,
        what: format!("{what} is missing"),
    };
    let rap = ax.rap.ok_or_else(|| missing("RAP"))?;
    let v_rapid = rap.a.ok_or_else(|| missing("RAP fast_speed"))? / 60.0;
    let a_rapid = rap.b.ok_or_else(|| missing("RAP fast_accel"))?;
    let man = ax.man.unwrap_or_default();
    let a_max = man.b.unwrap_or(a_rapid);
    let v_max = ax
        .gm
        .iter()
        .find(|g| g.range == 0)
        .and_then(|g| g.vmax)
        .map_or(v_rapid, |v| v / 60.0);
    let zone = ax
        .lo
        .iter()
        .find(|z| z.number == 1)
        .map(|z| (z.pos, z.neg))
        .or(ax.lop.map(|l| (l.a, l.b)));
    let (soft_max, soft_min) = match zone {
        Some((Some(hi), Some(lo))) if !(hi == 0.0 && lo == 0.0) => (Some(hi), Some(lo)),
        _ => (None, None),
    };
    Ok(AxisLimits {
        name: ax.name,
        v_max,
        a_max,
        j_max: acc.s_jerk(a_max, v_max),
        v_rapid,
        a_rapid,
        j_rapid: acc.s_jerk(a_rapid, v_rapid),
        soft_min,
        soft_max,
        diameter: ax.axis_type().diameter,
    })
}
