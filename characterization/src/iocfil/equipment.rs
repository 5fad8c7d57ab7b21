//! IOCFIL section 3: the equipment the PLC handles (spindle, point-to-point and index axes, DAC
//! axes, handwheels, disabled tasks, ADC/DAC channels).

use crate::pgcfil::fields::Emit;
use crate::pgcfil::structure::{Blocks, not_allowed};
use crate::reader::{Param, Record};

use super::model::{Handwheel, IndexAxis, IoProcess, PtpAxis};
use super::parse::indexed;

const S3: &str = "PRO, ASM, TA1 ... TA8, AS1 ... AS3, UCDA, ADV, CWD, ADC, DAC";

/// One section-3 record.
pub(crate) fn section3(e: &mut Emit<'_>, blocks: &mut Blocks, rec: &Record, proc: &mut IoProcess) {
    let ta = indexed(&rec.key, "TA", 1..=8);
    let as_ = indexed(&rec.key, "AS", 1..=3);
    if !matches!(
        rec.key.as_str(),
        "ASM" | "UCDA" | "ADV" | "CWD" | "ADC" | "DAC"
    ) && ta.is_none()
        && as_.is_none()
    {
        return not_allowed(e, rec, S3);
    }
    if !blocks.first_time(e, rec) {
        return;
    }
    let p = &rec.params;
    if let Some(n) = ta {
        return ptp(e, rec, proc, n as u8);
    }
    if let Some(n) = as_ {
        return index_axis(e, rec, proc, n as u8);
    }
    match rec.key.as_str() {
        "ASM" => {
            if e.count(rec, 1, 1) {
                proc.spindle = e.axis_name(&p[0], 115);
            }
        }
        "UCDA" => {
            if !e.count(rec, 1, 1) {
                return;
            }
            let Some(t) = e.ascii(&p[0]) else { return };
            let mut axes = Vec::new();
            for (i, c) in t.char_indices() {
                let at = p[0].span.start + i..p[0].span.start + i + c.len_utf8();
                if !c.is_ascii_alphabetic() {
                    e.error(
                        127,
                        at,
                        format!("'{c}' in UCDA is not an axis name"),
                        "list axis letters without separators, e.g. UCDA=B",
                    );
                } else if !axes.contains(&c.to_ascii_uppercase()) {
                    axes.push(c.to_ascii_uppercase());
                }
            }
            if axes.len() > 4 {
                e.error(
                    124,
                    p[0].span.clone(),
                    format!("UCDA lists {} axes", axes.len()),
                    "at most 4 axes (chapter 6.3.5 says 3)",
                );
            } else if axes.len() == 4 {
                e.warning(963, p[0].span.clone(), "UCDA lists 4 axes; chapter 6.3.5 allows at most 3 (error 124 of Table 7.4 allows 4)", "list at most 3 axes");
            }
            proc.ucda = axes;
        }
        "ADV" => {
            if !e.count(rec, 2, 2) {
                return;
            }
            let mut out = [None, None];
            for (slot, par) in out.iter_mut().zip(p) {
                *slot = handwheel(e, par);
            }
            proc.adv = Some(out);
        }
        "CWD" => {
            if e.count(rec, 1, 1) {
                proc.cwd = e.hex(&p[0], 4);
            }
        }
        _ => {
            // ADC and DAC: the semantics line has 8 channels, the format line 6 (spec §10 item 6).
            if !e.count(rec, 6, 8) {
                return;
            }
            let adc = rec.key == "ADC";
            let mut out = Vec::new();
            for par in p {
                let Some(v) = e.integer(par) else { continue };
                let ok = if adc {
                    (1..=8).contains(&v)
                } else {
                    (1..=16).contains(&v) || (-216..=-201).contains(&v)
                };
                if ok {
                    out.push(v);
                } else {
                    let hint = if adc {
                        "ADC channels are 1 ... 8"
                    } else {
                        "DAC channels are 1 ... 16, or -201 ... -216 for 16-bit converters"
                    };
                    e.error(
                        107,
                        par.span.clone(),
                        format!("{v} is not a {} channel number", rec.key),
                        hint,
                    );
                }
            }
            if adc { proc.adc = out } else { proc.dac = out }
        }
    }
}

fn handwheel(e: &mut Emit<'_>, p: &Param) -> Option<Handwheel> {
    if p.text == "0" {
        return Some(Handwheel::Electronic);
    }
    e.axis_name(p, 115).map(Handwheel::Axis)
}

fn ptp(e: &mut Emit<'_>, rec: &Record, proc: &mut IoProcess, number: u8) {
    if !e.count(rec, 6, 6) {
        return;
    }
    let p = &rec.params;
    let axis = e.axis_name(&p[0], 115);
    let axis_type = e.hex(&p[1], 2).unwrap_or(0) as u8;
    let phase_disp = e.real(&p[2]);
    let positions = e.real(&p[3]);
    let limit_1 = e.real(&p[4]);
    let limit_2 = e.real(&p[5]);
    if axis_type & 1 == 0
        && limit_1.is_none_or(|l| l <= 0.0)
        && (p[4].is_empty() || limit_1.is_some())
    {
        e.error(
            120,
            if p[4].is_empty() {
                rec.span.clone()
            } else {
                p[4].span.clone()
            },
            format!("TA{number} has no DAC but its first slow-down threshold is not above 0"),
            "write limit_1 > 0 (positions) for a point-to-point axis without DAC",
        );
    }
    if p[0].is_empty() {
        e.error(
            117,
            p[0].span.clone(),
            format!("TA{number} names no axis"),
            "write the name of a point-to-point axis declared in AXCFIL",
        );
    }
    if let Some(axis) = axis {
        proc.ptp_axes.push(PtpAxis {
            number,
            axis,
            axis_type,
            phase_disp,
            positions,
            limit_1,
            limit_2,
        });
    }
}

fn index_axis(e: &mut Emit<'_>, rec: &Record, proc: &mut IoProcess, number: u8) {
    if !e.count(rec, 4, 4) {
        return;
    }
    let p = &rec.params;
    let axis = e.axis_name(&p[0], 115);
    let bit = |e: &mut Emit<'_>, par: &Param, what: &str| -> Option<bool> {
        match e.hex(par, 2) {
            Some(0) => Some(false),
            Some(1) => Some(true),
            Some(v) => {
                e.error(
                    114,
                    par.span.clone(),
                    format!("AS{number} {what} {v:X} is neither 0 nor 1"),
                    "mode: 0 absolute, 1 incremental; type: 0 rotary, 1 linear",
                );
                None
            }
            None => Some(false),
        }
    };
    let incremental = bit(e, &p[1], "mode");
    let linear = bit(e, &p[2], "axis type");
    let positions = e.word(&p[3]);
    if positions.is_none_or(|n| n == 0) && (p[3].is_empty() || positions.is_some()) {
        e.error(
            129,
            if p[3].is_empty() {
                rec.span.clone()
            } else {
                p[3].span.clone()
            },
            format!("AS{number} declares no number of positions"),
            "the fourth parameter of ASx is the number of positions, e.g. 360",
        );
    }
    if let (Some(axis), Some(incremental), Some(linear), Some(positions)) =
        (axis, incremental, linear, positions.filter(|&n| n > 0))
    {
        proc.index_axes.push(IndexAxis {
            number,
            axis,
            incremental,
            linear,
            positions,
        });
    }
}
