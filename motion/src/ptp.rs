//! One point-to-point axis (jog, increments, handwheel, homing moves): a time-optimal 1-D
//! profile within speed, acceleration and (optionally) jerk limits, recomputed by rsruckig from
//! the current state whenever the target changes.

use rsruckig::prelude::*;

/// What the axis is doing.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Goal {
    /// At rest, no target.
    Idle,
    /// Moving to a position.
    To(f64),
    /// Jogging at a signed speed.
    Jog(f64),
    /// Stopping as fast as the limits allow.
    Stop,
}

/// A point-to-point axis.
pub struct PtpAxis {
    otg: Ruckig<1, ThrowErrorHandler>,
    input: InputParameter<1>,
    output: OutputParameter<1>,
    v_max: f64,
    goal: Goal,
}

impl std::fmt::Debug for PtpAxis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PtpAxis")
            .field("position", &self.input.current_position[0])
            .field("velocity", &self.input.current_velocity[0])
            .field("goal", &self.goal)
            .finish()
    }
}

impl PtpAxis {
    /// An axis at rest at `pos` with limits in mm/s, mm/s², mm/s³ (None: no jerk limit) and the
    /// tick in s.
    pub fn new(v_max: f64, a_max: f64, j_max: Option<f64>, tick_s: f64, pos: f64) -> Self {
        let mut input = InputParameter::new(None);
        input.current_position[0] = pos;
        input.max_velocity[0] = v_max.abs();
        input.max_acceleration[0] = a_max.abs();
        input.max_jerk[0] = j_max.map_or(f64::INFINITY, f64::abs);
        PtpAxis {
            otg: Ruckig::new(None, tick_s),
            input,
            output: OutputParameter::new(None),
            v_max: v_max.abs(),
            goal: Goal::Idle,
        }
    }

    /// Moves to `target` at no more than `v` (capped by the axis limit).
    pub fn move_to(&mut self, target: f64, v: f64) {
        self.input.control_interface = ControlInterface::Position;
        self.input.target_position[0] = target;
        self.input.target_velocity[0] = 0.0;
        self.input.target_acceleration[0] = 0.0;
        self.input.max_velocity[0] = v.abs().min(self.v_max);
        self.goal = Goal::To(target);
    }

    /// Jogs in direction `dir` (−1, 0, +1) at speed `v` (capped); 0 stops.
    pub fn jog(&mut self, dir: i8, v: f64) {
        let s = f64::from(dir.signum()) * v.abs().min(self.v_max);
        self.input.control_interface = ControlInterface::Velocity;
        self.input.target_velocity[0] = s;
        self.input.target_acceleration[0] = 0.0;
        self.input.max_velocity[0] = self.v_max;
        self.goal = if s == 0.0 { Goal::Stop } else { Goal::Jog(s) };
    }

    /// Stops as fast as the limits allow.
    pub fn stop(&mut self) {
        self.jog(0, 0.0);
    }

    /// Advances one tick; returns the new position.
    pub fn tick(&mut self) -> f64 {
        if self.goal == Goal::Idle {
            return self.input.current_position[0];
        }
        match self.otg.update(&self.input, &mut self.output) {
            Ok(RuckigResult::Working) => self.output.pass_to_input(&mut self.input),
            Ok(RuckigResult::Finished) => {
                self.output.pass_to_input(&mut self.input);
                if let Goal::To(t) = self.goal {
                    self.input.current_position[0] = t;
                }
                if !matches!(self.goal, Goal::Jog(_)) {
                    self.input.current_velocity[0] = 0.0;
                    self.input.current_acceleration[0] = 0.0;
                    self.goal = Goal::Idle;
                }
            }
            // Invalid input (e.g. a zero limit): hold still rather than move unpredictably.
            _ => {
                self.input.current_velocity[0] = 0.0;
                self.input.current_acceleration[0] = 0.0;
                self.goal = Goal::Idle;
            }
        }
        self.input.current_position[0]
    }

    /// The current position.
    pub fn position(&self) -> f64 {
        self.input.current_position[0]
    }

    /// The current velocity.
    pub fn velocity(&self) -> f64 {
        self.input.current_velocity[0]
    }

    /// At rest with nothing to do.
    pub fn is_idle(&self) -> bool {
        self.goal == Goal::Idle
    }
}
