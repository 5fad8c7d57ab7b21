//! Cross-file rules of IOCFIL: CLO against the CPU tick of AXCFIL TIM, process numbers against
//! NBP, and the axes of ASM, TAx, UCDA and ADV against AXCFIL (existence, spindle, point-to-point
//! positions equal to PAS).

use diag::{Diagnostic, Sink};

use crate::axcfil::Axcfil;
use crate::pgcfil::axes;
use crate::pgcfil::fields::Emit;
use crate::pgcfil::locate::{self, param_span};
use crate::reader::ParsedFile;

use super::model::{Handwheel, Iocfil};

/// Checks `i` (decoded from `file`) against AXCFIL `ax`; returns the cross-file diagnostics.
pub fn check_against(i: &Iocfil, file: &ParsedFile, ax: &Axcfil) -> Vec<Diagnostic> {
    let mut diags = Sink::unbounded();
    check_against_into(i, file, ax, &mut diags);
    diags.into_vec()
}

/// [`check_against`] pushing the diagnostics into `diags` (a sink that may store only the first of
/// them).
pub fn check_against_into(i: &Iocfil, file: &ParsedFile, ax: &Axcfil, diags: &mut Sink) {
    let mut e = Emit::new(file, diags);
    clo(&mut e, i, file, ax);
    for section in [2, 3] {
        for (n, rec) in locate::pro_records(file, section) {
            if n > ax.nbp && (1..=5).contains(&n) {
                e.section = section;
                e.process = Some(n);
                e.error(
                    184,
                    param_span(rec, 0),
                    format!("process {n} exceeds NBP={} of AXCFIL", ax.nbp),
                    &format!("write PRO=1 ... PRO={}, or raise NBP in AXCFIL", ax.nbp),
                );
            }
        }
    }
    for section in [2, 3] {
        let present = locate::blocks(file, section);
        for n in (1..=ax.nbp).filter(|n| !present.contains(n)) {
            e.section = section;
            e.process = Some(n);
            let what = if section == 2 {
                "M functions"
            } else {
                "PLC-handled equipment"
            };
            e.warning(
                964,
                locate::section_span(file, section),
                format!("section *{section} has no block for process {n} ({what})"),
                &format!(
                    "the manual writes section *{section} for each declared process: add PRO={n}"
                ),
            );
        }
    }
    e.section = 3;
    for proc in i.processes.iter().filter(|p| p.number <= ax.nbp) {
        let n = proc.number;
        e.process = Some(n);
        let rec = |key: &str| locate::find(file, 3, n, key);
        if let (Some(s), Some(r)) = (proc.spindle, rec("ASM")) {
            if !axes::in_process(ax, n, s) {
                e.error(
                    117,
                    param_span(r, 0),
                    format!("spindle {s} is not an axis of process {n} in AXCFIL"),
                    "name the spindle declared in AXCFIL",
                );
            } else if !axes::axis_type(ax, n, s).is_some_and(|t| t.spindle()) {
                e.error(
                    118,
                    param_span(r, 0),
                    format!("axis {s} is not a spindle"),
                    "ASM names an axis whose TPA has bit 0010 or 0020 (spindle)",
                );
            }
        }
        for ta in &proc.ptp_axes {
            let Some(r) = rec(&format!("TA{}", ta.number)) else {
                continue;
            };
            if !axes::in_process(ax, n, ta.axis) {
                e.error(
                    117,
                    param_span(r, 0),
                    format!(
                        "point-to-point axis {} is not an axis of process {n} in AXCFIL",
                        ta.axis
                    ),
                    "name a point-to-point axis declared in AXCFIL",
                );
                continue;
            }
            if !axes::axis_type(ax, n, ta.axis).is_some_and(|t| t.ptp) {
                e.error(
                    127,
                    param_span(r, 0),
                    format!("axis {} is not a point-to-point axis", ta.axis),
                    "TAx names an axis whose TPA has bit 0002",
                );
                continue;
            }
            let Some(pas) = axes::axis_of(ax, n, ta.axis).and_then(|a| a.pas.as_ref()) else {
                continue;
            };
            let step = pas.mec_pitch.abs();
            if let Some(pos) = ta.positions.filter(|&pos| pos != step) {
                e.error(
                    131,
                    param_span(r, 3),
                    format!(
                        "TA{} has {pos} positions but PAS of axis {} has {step}",
                        ta.number, ta.axis
                    ),
                    &format!("write {step} positions, as in PAS"),
                );
            }
            if let Some(ph) = ta.phase_disp.filter(|&ph| ph.abs() >= step && step > 0.0) {
                e.error(
                    961,
                    param_span(r, 2),
                    format!(
                        "TA{} phase offset {ph} is not less than the mechanical step {step} of PAS",
                        ta.number
                    ),
                    &format!("write a phase offset below {step} positions"),
                );
            }
        }
        if let Some(r) = rec("UCDA") {
            let start = r.params.first().map_or(r.span.start, |q| q.span.start);
            let text = r.params.first().map_or("", |q| q.text.as_str());
            for (k, c) in text.char_indices() {
                let up = c.to_ascii_uppercase();
                if proc.ucda.contains(&up) && !axes::in_process(ax, n, up) {
                    e.error(
                        117,
                        start + k..start + k + c.len_utf8(),
                        format!("UCDA axis {c} does not exist in AXCFIL"),
                        "list coordinate or point-to-point axes declared in AXCFIL",
                    );
                }
            }
        }
        if let (Some(adv), Some(r)) = (proc.adv, rec("ADV")) {
            for (k, hw) in adv.iter().enumerate() {
                if let Some(Handwheel::Axis(c)) = hw
                    && axes::any_axis(ax, *c).is_none()
                {
                    e.error(117, param_span(r, k), format!("handwheel axis {c} does not exist in AXCFIL"), "name the handwheel axis defined in AXCFIL, or write 0 for the electronic-handwheel channel");
                }
            }
        }
    }
}

/// CLO against TIM: CPU tick not 0 (104), tick_logic a multiple of it (105), time_slow at least it (106).
fn clo(e: &mut Emit<'_>, i: &Iocfil, file: &ParsedFile, ax: &Axcfil) {
    let Some(rec) = file
        .section(1)
        .and_then(|s| s.records.iter().find(|r| r.key == "CLO"))
    else {
        return;
    };
    if i.tick_logic_ms == 0 {
        return;
    }
    e.section = 1;
    e.process = None;
    let cpu = ax.tim;
    if cpu == 0 {
        e.error(
            104,
            rec.key_span.clone(),
            "the CPU tick is 0, so the PLC cannot be timed",
            "review TIM in AXCFIL: CPU_tick is 1 ... 63 ms",
        );
        return;
    }
    if !i.tick_logic_ms.is_multiple_of(cpu) {
        let below = i.tick_logic_ms / cpu * cpu;
        let near = if below == 0 { cpu } else { below };
        e.error(
            105,
            param_span(rec, 0),
            format!(
                "logic tick {} ms is not a multiple of the CPU tick {cpu} ms (AXCFIL TIM)",
                i.tick_logic_ms
            ),
            &format!("write a multiple of {cpu}, e.g. {near}"),
        );
    }
    if i.time_slow_ms != 0 && i.time_slow_ms < cpu {
        e.error(
            106,
            param_span(rec, 1),
            format!(
                "slow-logic time {} ms is less than the CPU tick {cpu} ms",
                i.time_slow_ms
            ),
            &format!("time_slow is {cpu} ... {} ms", i.tick_logic_ms / 2),
        );
    } else if i.time_slow_ms == 0 && rec.params.get(1).is_some_and(|p| p.text == "0") {
        e.error(
            106,
            param_span(rec, 1),
            "slow-logic time is 0",
            &format!("time_slow is {cpu} ... {} ms", i.tick_logic_ms / 2),
        );
    }
}
