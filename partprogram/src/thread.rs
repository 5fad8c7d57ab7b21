//! Thread run-in `E` and run-out `J` of a MEFI G33 block (structure-motion spec §11.2–11.4).
//!
//! Machine constant 8 is an 8-decade value `±d8…d1`. With decades 7–8 zero it holds the slope itself:
//! decade 6 = ordinal of the axis that moves during the run-in/run-out (X = 1 on lathes), decades 1–5
//! = the angle in 0.001° (at most 60°), the sign = the direction. Otherwise decades 7–8 name the
//! parameter holding the run-out slope and decades 5–6 the parameter holding the run-in slope (both
//! in the same format, e.g. `R04=120.0` = axis 1, +20°); without a run-in parameter the run-in uses the
//! run-out slope. R00 and R80 cannot be used. The two slopes must have the same axis and sign.
//!
//! Geometry: the thread axis is the programmed axis with the largest travel other than the slope
//! axis; `J` (`E`) is the length along it of the run-out at the end (run-in at the start). The
//! run-out moves the slope axis by `J·tan(angle)` in the angle's direction; the run-in moves it by
//! `E·tan(angle)` the other way, so the thread itself lies that far from the programmed line (the start
//! position is chosen so that the thread diameter is reached after the run-in, F21:
//! 64 + 2·12·tan 18° = 71.798). A diameter axis moves twice the distance. The block ends at the
//! programmed end plus both shifts; the next positions must be programmed again (rule S18).

use detmath::Det as _;
/// A run-in or run-out slope: machine axis index and signed angle in degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slope {
    /// Index of the axis that moves during the run-in/run-out.
    pub axis: usize,
    /// Angle in degrees; the sign is the direction of the run-out.
    pub degrees: f64,
}

/// Decodes the slope format `±d6 d5…d1` (axis ordinal, angle in 0.001°) of constant 8 and its
/// parameters; `what` names the source for messages.
pub fn decode(v: i64, what: &str) -> Result<Slope, String> {
    let a = v.unsigned_abs();
    let ordinal = (a / 100_000) % 10;
    let milli_deg = a % 100_000;
    if !(1..=6).contains(&ordinal) || a >= 1_000_000 {
        return Err(format!(
            "{what} = {v}: decade 6 must be the ordinal 1..6 of the run-out axis and decades 7–8 zero"
        ));
    }
    if milli_deg > 60_000 {
        return Err(format!("{what}: the run-in/run-out angle is at most 60°"));
    }
    let deg = milli_deg as f64 / 1000.0;
    Ok(Slope {
        axis: (ordinal - 1) as usize,
        degrees: if v < 0 { -deg } else { deg },
    })
}

/// The (run-out, run-in) slopes from machine constant `mc8` and the parameters `r` (thousandths);
/// only the slopes `need` (run-out, run-in) are read, and one not needed is a copy of the other.
pub fn slopes(mc8: i64, r: &[i64], need: (bool, bool)) -> Result<(Slope, Slope), String> {
    let a = mc8.unsigned_abs();
    let (p_out, p_in) = ((a / 1_000_000) % 100, (a / 10_000) % 100);
    if p_out == 0 {
        if mc8 == 0 {
            return Err(
                "thread run-in/run-out needs its angle: machine constant 8 is not set".into(),
            );
        }
        let s = decode(mc8, "machine constant 8")?;
        return Ok((s, s));
    }
    let param = |p: u64| -> Result<Slope, String> {
        let v = usize::try_from(p)
            .ok()
            .filter(|p| *p != 80)
            .and_then(|p| r.get(p))
            .ok_or_else(|| format!("machine constant 8 names R{p}, which cannot hold a slope"))?;
        // A parameter value v (thousandths) written as `±00120.000` holds the 8 decades of v.
        decode(*v, &format!("R{p:02}"))
    };
    let p_in = if p_in == 0 { p_out } else { p_in };
    match need {
        (true, true) => {
            let (out, inn) = (param(p_out)?, param(p_in)?);
            if out.axis != inn.axis || (out.degrees < 0.0) != (inn.degrees < 0.0) {
                return Err(
                    "the run-in and run-out parameters must have the same axis and sign".into(),
                );
            }
            Ok((out, inn))
        }
        (false, true) => param(p_in).map(|s| (s, s)),
        _ => param(p_out).map(|s| (s, s)),
    }
}

/// The end points of the thread segments from machine position `start` to the programmed end
/// `end`, with run-in `e` and run-out `j` (mm along the thread axis): run-in end, main thread end,
/// run-out end (segments of length 0 left out). `diameter` marks the axes programmed in diameter.
pub fn split(
    start: [f64; 6],
    end: [f64; 6],
    diameter: [bool; 6],
    (e, j): (Option<f64>, Option<f64>),
    (out, inn): (Slope, Slope),
) -> Result<Vec<[f64; 6]>, String> {
    let e = e.unwrap_or(0.0);
    let j = j.unwrap_or(0.0);
    if e < 0.0 || j < 0.0 {
        return Err("thread run-in E and run-out J are lengths (not negative)".into());
    }
    let thread_axis = (0..6)
        .filter(|i| *i != out.axis)
        .max_by(|a, b| {
            let (da, db) = ((end[*a] - start[*a]).abs(), (end[*b] - start[*b]).abs());
            da.total_cmp(&db)
        })
        .unwrap_or(0);
    let len = (end[thread_axis] - start[thread_axis]).abs();
    if len <= 0.0 || e + j > len + 1e-9 {
        return Err(format!(
            "thread run-in E{e} and run-out J{j} are longer than the thread ({len} mm along its axis)"
        ));
    }
    let shift = |s: Slope, l: f64| {
        let k = if diameter[s.axis] { 2.0 } else { 1.0 };
        k * l * s.degrees.to_radians().dtan()
    };
    let d_in = -shift(inn, e);
    let d_out = shift(out, j);
    let at = |f: f64, extra: f64| {
        let mut p = [0.0; 6];
        for i in 0..6 {
            p[i] = start[i] + f * (end[i] - start[i]);
        }
        p[out.axis] += extra;
        p
    };
    let mut pts = Vec::with_capacity(3);
    if e > 0.0 {
        pts.push(at(e / len, d_in));
    }
    if j > 0.0 && e + j < len {
        pts.push(at(1.0 - j / len, d_in));
    }
    pts.push(at(1.0, d_in + d_out));
    Ok(pts)
}
