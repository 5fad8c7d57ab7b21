//! The blocks the kernel executes: a path (rapid, line, arc or helix, dwell), its end point on
//! every axis, feed and exact-stop settings; built from the planner's canonical blocks.

use partprogram::canon::{Canon, Kind};

/// The geometry of one block.
#[derive(Debug, Clone, PartialEq)]
pub enum Path {
    /// G00: a straight line at rapid speed.
    Rapid,
    /// G01 (and G33 with `thread_pitch`): a straight line at the feed.
    Line,
    /// G02/G03: an arc in the plane of two axes (indices in Config order), a helix when other
    /// axes move too; `turns` extra full turns.
    Arc {
        /// The (first, second) plane axes, Config indices.
        plane: (usize, usize),
        /// The centre in the plane.
        center: [f64; 2],
        /// Clockwise (G02) seen from the positive third axis.
        cw: bool,
        /// Extra full turns.
        turns: u32,
    },
    /// A dwell at rest.
    Dwell {
        /// Duration, s.
        seconds: f64,
    },
}

/// One block for the kernel.
#[derive(Debug, Clone, PartialEq)]
pub struct Move {
    /// The caller's identifier, echoed in ticks and DEN.
    pub tag: u64,
    /// The path to the end point.
    pub path: Path,
    /// End point of every axis, Config order, mm.
    pub end: Vec<f64>,
    /// Programmed feed, mm/min (required for lines and arcs).
    pub feed_mm_min: Option<f64>,
    /// Exact stop at the end (G09/G61, MEFI G98/G24): no blending into the next block.
    pub exact_stop: bool,
    /// The block's own path tolerance, mm (None: the configured one).
    pub tolerance: Option<f64>,
    /// G33: the thread pitch, mm per spindle revolution (the move is locked to the spindle).
    pub thread_pitch: Option<f64>,
    /// G33: the start angle after the spindle's index pulse, degrees (MEFI `I`; 0: at the index).
    pub thread_angle: f64,
}

/// A block the kernel refuses, with the block's tag.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotionError {
    /// The path leaves an active software limit.
    #[error(
        "block {tag}: axis {axis} would reach {reach:.4} mm, beyond its soft limit {limit:.4} mm"
    )]
    SoftLimit {
        /// Block tag.
        tag: u64,
        /// Axis letter.
        axis: char,
        /// The limit crossed.
        limit: f64,
        /// The farthest coordinate the path reaches.
        reach: f64,
    },
    /// A feed move without a usable feed.
    #[error("block {tag}: {what} without a feed (F)")]
    NoFeed {
        /// Block tag.
        tag: u64,
        /// The kind of move.
        what: &'static str,
    },
    /// The block is malformed (wrong axis count, non-finite value, bad arc).
    #[error("block {tag}: {what}")]
    Invalid {
        /// Block tag.
        tag: u64,
        /// What is wrong.
        what: String,
    },
    /// A G33 thread whose speed at the spindle speed (programmed when queued, actual when it
    /// starts) exceeds the axes' feed limits.
    #[error(
        "block {tag}: the thread needs {need:.1} mm/min along its path at the spindle speed, the axes allow {limit:.1} mm/min"
    )]
    ThreadTooFast {
        /// Block tag.
        tag: u64,
        /// Path speed the thread needs, mm/min.
        need: f64,
        /// The axes' limit along the path, mm/min.
        limit: f64,
    },
    /// The look-ahead queue is full.
    #[error("block {tag}: the look-ahead queue is full")]
    QueueFull {
        /// Block tag.
        tag: u64,
    },
}

impl Move {
    /// The move with every coordinate (end point, arc centre) multiplied by its axis's factor
    /// ([`crate::Config::slide_scale`]: a diameter becomes the slide's radius). An arc of a
    /// diameter axis is a circle in the radius frame (its centre was found there).
    pub fn scaled(&self, scale: &[f64]) -> Move {
        let k = |i: usize| scale.get(i).copied().unwrap_or(1.0);
        let mut m = self.clone();
        for (i, e) in m.end.iter_mut().enumerate() {
            *e *= k(i);
        }
        if let Path::Arc { plane, center, .. } = &mut m.path {
            center[0] *= k(plane.0);
            center[1] *= k(plane.1);
        }
        m
    }

    /// Converts a canonical block: `axes` are the kernel's axes in Config order (every one must be
    /// in `c.end`). Aux blocks become zero-length dwells (their M/S/T functions are the caller's).
    ///
    /// `exact_stop` and `tolerance` come from Canon (Fanuc G09/G61, G64 P). A G33 block's pitch is its feed per revolution, recovered as feed (mm/min) ÷ S (rev/min).
    pub fn from_canon(tag: u64, c: &Canon, axes: &[char]) -> Result<Move, MotionError> {
        let mut end = Vec::with_capacity(axes.len());
        for &a in axes {
            match c.end_of(a) {
                Some(v) => end.push(v),
                None => {
                    return Err(MotionError::Invalid {
                        tag,
                        what: format!("the block has no coordinate for axis {a}"),
                    });
                }
            }
        }
        for (a, _) in &c.end {
            if !axes.contains(a) {
                return Err(MotionError::Invalid {
                    tag,
                    what: format!("axis {a} is not interpolated by this kernel"),
                });
            }
        }
        let path = match c.kind {
            Kind::Rapid => Path::Rapid,
            Kind::Linear => Path::Line,
            Kind::ArcCw | Kind::ArcCcw => {
                let (pa, pb) = c.plane.axes();
                let idx = |x: char| {
                    axes.iter()
                        .position(|&y| y == x)
                        .ok_or_else(|| MotionError::Invalid {
                            tag,
                            what: format!("arc plane axis {x} is not interpolated"),
                        })
                };
                let ctr = |x: char| {
                    c.center
                        .iter()
                        .find(|(y, _)| *y == x)
                        .map(|(_, v)| *v)
                        .ok_or_else(|| MotionError::Invalid {
                            tag,
                            what: format!("arc without a centre coordinate on {x}"),
                        })
                };
                Path::Arc {
                    plane: (idx(pa)?, idx(pb)?),
                    center: [ctr(pa)?, ctr(pb)?],
                    cw: c.kind == Kind::ArcCw,
                    turns: 0,
                }
            }
            Kind::Dwell => Path::Dwell {
                seconds: c.dwell.unwrap_or(0.0),
            },
            Kind::Aux => Path::Dwell { seconds: 0.0 },
        };
        let thread_pitch = if c.thread {
            match (c.feed, c.s) {
                (Some(f), Some(s)) if s > 0.0 => Some(f / s),
                _ => {
                    return Err(MotionError::Invalid {
                        tag,
                        what: "G33 thread without a feed and a spindle speed S".into(),
                    });
                }
            }
        } else {
            None
        };
        Ok(Move {
            tag,
            path,
            end,
            feed_mm_min: c.feed,
            exact_stop: c.exact_stop,
            tolerance: c.tolerance,
            thread_pitch,
            thread_angle: c.thread_angle,
        })
    }
}
