//! Geometry of the planner: program and machine positions, zero offsets, transformations G35–G37,
//! diameter programming and arc centres.
//!
//! The machine position of an axis is `transform(programmed) + offset`, where the transformation is
//! mirror (sign), then scale, then shift (G35, G36, G37; the manual does not fix the order), and the
//! offset is the active row of the zero-offset table G53…G59. Under diameter programming X values stay
//! diameters in both frames, and the X component of an arc centre offset (I/J) is a radius.

use crate::arith::ArithState;
use crate::canon::Plane;
use detmath::Det as _;

/// A programmed target of one block.
#[derive(Debug, Clone, Copy)]
pub struct Target {
    /// Programmed axis values (mm) by machine axis index.
    pub axes: [Option<f64>; 6],
    /// I, J, K.
    pub ijk: [Option<f64>; 3],
    /// Absolute (G90) or incremental (G91).
    pub abs: bool,
    /// Zero-offset row for this block (G53..G59 → 0..6).
    pub offset: usize,
}

/// A resolved arc.
#[derive(Debug, Clone)]
pub struct Arc {
    /// Centre in the machine frame, two plane axes.
    pub center: Vec<(char, f64)>,
    /// True when exactly one plane axis is mirrored (G2 and G3 swap).
    pub mirrored: bool,
    /// Clockwise angle from start to end about the centre, 0..2π (0 for a full circle).
    pub sweep_cw: f64,
}

/// Positions and coordinate transformations.
#[derive(Debug, Clone)]
pub struct Geometry {
    /// Axis letters in machine order.
    pub axes: Vec<char>,
    /// Machine position per axis.
    pub machine: [f64; 6],
    /// Programmed position (program frame, untransformed).
    pub prog: [f64; 6],
    /// Diameter programming of X.
    pub diameter: bool,
    /// Mirrored axes (G35).
    pub mirror: [bool; 6],
    /// Scale (G36).
    pub scale: f64,
    /// Independent shift (G37).
    pub shift: [f64; 6],
    offset: [f64; 6],
    /// Active length correction per axis (methods A, B, C of [`crate::length`]).
    pub length: [f64; 6],
}

impl Geometry {
    /// All axes at machine zero, no offsets or transformations.
    pub fn new(axes: &[char], diameter: bool) -> Self {
        Geometry {
            axes: axes.iter().copied().take(6).collect(),
            machine: [0.0; 6],
            prog: [0.0; 6],
            diameter,
            mirror: [false; 6],
            scale: 1.0,
            shift: [0.0; 6],
            offset: [0.0; 6],
            length: [0.0; 6],
        }
    }

    fn fwd(&self, i: usize, p: f64) -> f64 {
        let p = if self.mirror[i] { -p } else { p };
        p * self.scale + self.shift[i]
    }

    fn inv(&self, i: usize, m: f64) -> f64 {
        let p = (m - self.shift[i]) / self.scale;
        if self.mirror[i] { -p } else { p }
    }

    fn refresh_prog(&mut self) {
        for i in 0..self.axes.len() {
            self.prog[i] = self.inv(i, self.machine[i] - self.offset[i] - self.length[i]);
        }
    }

    /// Makes row `k` of the zero-offset table the active offset (programmed positions follow).
    pub fn select_offset(&mut self, st: &ArithState, k: usize) {
        self.offset = st.offsets[k.min(6)];
        self.refresh_prog();
    }

    /// Sets or cancels a transformation: G34 all off, G35 mirror the given axes, G36 scale (X, or X/Y),
    /// G37 shift by the given values.
    pub fn set_transform(&mut self, g: u16, axes: &[Option<f64>; 6]) {
        match g {
            34 => {
                self.mirror = [false; 6];
                self.scale = 1.0;
                self.shift = [0.0; 6];
            }
            35 => {
                for (m, a) in self.mirror.iter_mut().zip(axes.iter()) {
                    *m = a.is_some();
                }
            }
            36 => {
                let first = axes[0];
                let second = axes[1];
                self.scale = match (first, second) {
                    (Some(x), Some(y)) if y != 0.0 => x / y,
                    (Some(x), _) if x != 0.0 => x,
                    _ => 1.0,
                };
            }
            37 => {
                for (sh, a) in self.shift.iter_mut().zip(axes.iter()) {
                    *sh = a.unwrap_or(0.0);
                }
            }
            _ => {}
        }
        self.refresh_prog();
    }

    fn target(&self, t: &Target) -> [f64; 6] {
        let mut p = self.prog;
        for ((pi, prog), v) in p
            .iter_mut()
            .zip(self.prog)
            .zip(t.axes)
            .take(self.axes.len())
        {
            if let Some(v) = v {
                *pi = if t.abs { v } else { prog + v };
            }
        }
        p
    }

    fn apply(&mut self, t: &Target, p: [f64; 6], st: &ArithState) {
        let off = st.offsets[t.offset.min(6)];
        for i in 0..self.axes.len() {
            if t.axes[i].is_some() {
                self.machine[i] = self.fwd(i, p[i]) + off[i] + self.length[i];
            }
        }
        self.refresh_prog();
    }

    /// A straight move (G00/G01/G33) to the target.
    pub fn linear(&mut self, t: &Target, st: &ArithState) {
        let p = self.target(t);
        self.apply(t, p, st);
    }

    /// Moves to a machine position directly (G30 reference).
    pub fn move_machine(&mut self, m: [f64; 6], st: &ArithState, offset: usize) {
        self.machine = m;
        self.offset = st.offsets[offset.min(6)];
        self.refresh_prog();
    }

    fn index(&self, a: char) -> Option<usize> {
        self.axes.iter().position(|c| *c == a)
    }

    /// A circular move in `plane`: I along the first plane axis, J along the second, incremental from the
    /// start; checks that the end point lies on the circle within `tol` mm.
    pub fn arc(
        &mut self,
        t: &Target,
        plane: Plane,
        st: &ArithState,
        tol: f64,
    ) -> Result<Arc, String> {
        let (a1, a2) = plane.axes();
        let (Some(i1), Some(i2)) = (self.index(a1), self.index(a2)) else {
            return Err(format!(
                "the machine has no {}{} plane for circular interpolation",
                a1, a2
            ));
        };
        let end = self.target(t);
        let start = self.prog;
        let half = |i: usize| {
            if self.diameter && self.axes[i] == 'X' {
                0.5
            } else {
                1.0
            }
        };
        let (di, dj) = (t.ijk[0].unwrap_or(0.0), t.ijk[1].unwrap_or(0.0));
        // Centre in the program frame (X as diameter when diameter programming is on).
        let c1 = start[i1] + di / half(i1);
        let c2 = start[i2] + dj / half(i2);
        let r0 = ((start[i1] - c1) * half(i1)).dhypot((start[i2] - c2) * half(i2));
        let r1 = ((end[i1] - c1) * half(i1)).dhypot((end[i2] - c2) * half(i2));
        if (r0 - r1).abs() > tol {
            return Err(format!(
                "end point is not on the circle (error 7.56): start radius {r0:.4}, end radius {r1:.4}"
            ));
        }
        let off = st.offsets[t.offset.min(6)];
        let center = vec![
            (a1, self.fwd(i1, c1) + off[i1] + self.length[i1]),
            (a2, self.fwd(i2, c2) + off[i2] + self.length[i2]),
        ];
        let mirrored = self.mirror[i1] != self.mirror[i2];
        let a0 = ((start[i2] - c2) * half(i2)).datan2((start[i1] - c1) * half(i1));
        let a1 = ((end[i2] - c2) * half(i2)).datan2((end[i1] - c1) * half(i1));
        let sweep_cw = (a0 - a1).rem_euclid(std::f64::consts::TAU);
        self.apply(t, end, st);
        Ok(Arc {
            center,
            mirrored,
            sweep_cw,
        })
    }

    /// Sets the active length correction of axes 1..4 (from [`crate::length::mefi_lengths`]); the
    /// machine position stays, the programmed position follows.
    pub fn set_lengths(&mut self, lengths: &[f64; 4]) {
        for (k, v) in lengths.iter().enumerate() {
            if k < self.axes.len() {
                self.length[k] = *v;
            }
        }
        self.refresh_prog();
    }

    /// Moves axis `i` by `delta` mm (the towed axis of a helix).
    pub fn tow(&mut self, i: usize, delta: f64) {
        if i < self.axes.len() {
            self.machine[i] += delta;
            self.refresh_prog();
        }
    }

    /// Writes the programmed positions (X as radius under diameter programming) for arithmetic ops 25/26.
    pub fn export_programmed(&self, st: &mut ArithState) {
        for i in 0..self.axes.len() {
            let half = if self.diameter && self.axes[i] == 'X' {
                0.5
            } else {
                1.0
            };
            st.programmed[i] = self.prog[i] * half;
        }
    }

    /// The machine position as (axis, mm) pairs.
    /// The machine-frame position of the program zero of every axis (constant surface speed
    /// measures the radius from it).
    pub fn origin(&self) -> Vec<(char, f64)> {
        self.axes
            .iter()
            .enumerate()
            .map(|(i, a)| (*a, self.fwd(i, 0.0) + self.offset[i] + self.length[i]))
            .collect()
    }

    /// The machine position of every axis (axis letter, mm).
    pub fn end_list(&self) -> Vec<(char, f64)> {
        self.axes
            .iter()
            .enumerate()
            .map(|(i, a)| (*a, self.machine[i]))
            .collect()
    }
}
