//! AXCFIL rules that relate several records: ticks and interpolators (section 1), the presence,
//! order and type rules of each axis (section 2), slave/master and switched pairs, and the
//! numeric rules of the compensation tables (section 3).

use diag::Sink;

use super::model::{Axcfil, Axis, Process};
use crate::codes;
use crate::reader::ParsedFile;
use crate::values::Ctx;

/// Continuous axes may only use these letters (003:1187).
const CONTINUOUS_LETTERS: &str = "ABCDXYZUVWPQ";

/// Applies every cross-record rule; `file` gives the section spans for whole-section problems.
pub fn check(file: &ParsedFile, model: &Axcfil, diags: &mut Sink) {
    let base = Ctx::new(file);
    let s1 = base.in_section(1);
    let s1_span = file.section(1).map_or(file.end_span(), |s| s.span.clone());
    for n in 1..=model.nbp {
        if model.process(n).is_none() {
            diags.push(s1.error(
                codes::PROCESS_INCOMPLETE,
                s1_span.clone(),
                format!(
                    "NBP declares {} processes but process {n} has no PRO in section 1",
                    model.nbp
                ),
                format!("add `PRO={n}` with its INx and CAS, or lower NBP"),
            ));
        }
    }
    let mut servo: Option<(u32, u32)> = None;
    for p in &model.processes {
        section1(&s1.in_process(Some(p.number)), model, p, &mut servo, diags);
    }
    let s2 = base.in_section(2);
    let s2_span = file.section(2).map_or(s1_span.clone(), |s| s.span.clone());
    for p in model.processes.iter().filter(|_| file.section(2).is_some()) {
        section2(&s2.in_process(Some(p.number)), &s2_span, model, p, diags);
    }
    let s3 = base.in_section(3);
    for p in &model.processes {
        section3(&s3.in_process(Some(p.number)), model, p, diags);
    }
    axis_table(&s1, &s1_span, model, diags);
}

fn section1(
    ctx: &Ctx,
    model: &Axcfil,
    p: &Process,
    servo: &mut Option<(u32, u32)>,
    diags: &mut Sink,
) {
    if p.interpolators.is_empty() {
        diags.push(ctx.error(
            codes::PROCESS_INCOMPLETE,
            p.span.clone(),
            format!("process {} declares no interpolator", p.number),
            "declare at least one interpolator, e.g. `IN1=1,XZ,S,1,16`",
        ));
    }
    let Some(cas) = &p.cas else {
        diags.push(ctx.error(
            codes::PROCESS_INCOMPLETE,
            p.span.clone(),
            format!("process {} has no CAS", p.number),
            "declare the drive-controlled axes, e.g. `CAS=1,XZS,1`",
        ));
        return;
    };
    for c in &p.common {
        for a in c.axes.iter().filter(|a| cas.axes.contains(a)) {
            diags.push(ctx.error(
                codes::CAS_TWICE,
                cas.span.clone(),
                format!(
                    "common axis {a} of process {} is listed again in CAS",
                    c.process
                ),
                format!(
                    "remove {a} from this CAS: it is controlled by process {}",
                    c.process
                ),
            ));
        }
    }
    let common: Vec<char> = p.common_axes().collect();
    let mut seen: Vec<(char, &str)> = Vec::new();
    for ip in &p.interpolators {
        for &a in &ip.axes {
            if let Some((_, other)) = seen.iter().find(|(s, _)| *s == a) {
                diags.push(ctx.error(
                    codes::AXIS_SEVERAL_INTERPOLATORS,
                    ip.span.clone(),
                    format!("axis {a} is already in interpolator {other}"),
                    "an axis is controlled by one interpolator only",
                ));
            }
            seen.push((a, &ip.name));
        }
        for a in ip.axes.iter().chain(ip.spindle.iter()) {
            if !cas.axes.contains(a) && !common.contains(a) {
                diags.push(ctx.error(
                    codes::AXIS_NOT_IN_CAS,
                    ip.span.clone(),
                    format!("axis {a} of interpolator {} is not in CAS", ip.name),
                    format!("add {a} to the CAS of process {}", p.number),
                ));
            }
        }
        if model.tim > 0 && ip.int_tick > 0 && ip.int_tick % model.tim != 0 {
            diags.push(ctx.error(
                codes::INT_TICK_CPU,
                ip.span.clone(),
                format!(
                    "interpolator tick {} ms is not a multiple of the CPU tick {} ms",
                    ip.int_tick, model.tim
                ),
                "make int_tick a whole multiple of TIM's CPU tick",
            ));
        } else if cas.servo_tick > 0 && ip.int_tick > 0 && ip.int_tick % cas.servo_tick != 0 {
            diags.push(ctx.error(
                codes::INT_TICK_SERVO,
                ip.span.clone(),
                format!(
                    "interpolator tick {} ms is not a multiple of the servo tick {} ms",
                    ip.int_tick, cas.servo_tick
                ),
                "make int_tick a whole multiple of CAS's servo tick",
            ));
        }
    }
    if model.tim > 0 && cas.servo_tick > 0 && cas.servo_tick % model.tim != 0 {
        diags.push(ctx.error(
            codes::SERVO_TICK_CPU,
            cas.span.clone(),
            format!(
                "servo tick {} ms is not a multiple of the CPU tick {} ms",
                cas.servo_tick, model.tim
            ),
            "make servo_tick a whole multiple of TIM's CPU tick",
        ));
    }
    match servo {
        Some((first, n)) if *first != cas.servo_tick && cas.servo_tick > 0 => {
            diags.push(ctx.error(
                codes::SERVO_TICKS_DIFFER,
                cas.span.clone(),
                format!(
                    "servo tick {} ms differs from the {} ms of process {n}",
                    cas.servo_tick, first
                ),
                "all drive control on CPU 1 runs with one servo tick",
            ));
        }
        None if cas.servo_tick > 0 => *servo = Some((cas.servo_tick, p.number)),
        _ => {}
    }
    // CAS lists the interpolated axes in interpolator order (spindles may stand anywhere).
    let spindles: Vec<char> = p.interpolators.iter().filter_map(|i| i.spindle).collect();
    let mut want: Vec<char> = Vec::new();
    for a in p.interpolators.iter().flat_map(|i| i.axes.iter().copied()) {
        if !spindles.contains(&a) && !want.contains(&a) {
            want.push(a);
        }
    }
    let mut got: Vec<char> = Vec::new();
    for a in cas.axes.iter().copied().filter(|a| want.contains(a)) {
        if !got.contains(&a) {
            got.push(a);
        }
    }
    if got != want && want.iter().all(|a| got.contains(a)) {
        let w: String = want.iter().collect();
        diags.push(ctx.error(codes::CAS_ORDER, cas.span.clone(), format!("CAS does not list the interpolated axes in interpolator order ({w})"), format!("write the axes of CAS in the order {w}, other axes (spindle, slaves, handwheels) may follow")));
    }
}

fn section2(
    ctx: &Ctx,
    section_span: &std::ops::Range<usize>,
    model: &Axcfil,
    p: &Process,
    diags: &mut Sink,
) {
    let Some(cas) = &p.cas else { return };
    for a in &cas.axes {
        if p.axis(*a).is_none() {
            diags.push(ctx.error(
                codes::AXIS_NOT_DEFINED,
                section_span.clone(),
                format!(
                    "axis {a} of process {} has no NAS subsection in section 2",
                    p.number
                ),
                format!("describe the axis with `NAS={a}` and its TPA, NTC, …"),
            ));
        }
    }
    let order: Vec<char> = p
        .axes
        .iter()
        .map(|a| a.name)
        .filter(|a| cas.axes.contains(a))
        .collect();
    let want: Vec<char> = cas
        .axes
        .iter()
        .copied()
        .filter(|a| order.contains(a))
        .collect();
    if order != want
        && let Some(first) = p
            .axes
            .iter()
            .zip(want.iter())
            .find(|(a, w)| a.name != **w)
            .map(|(a, _)| a)
    {
        let w: String = want.iter().collect();
        diags.push(ctx.error(
            codes::NAS_ORDER,
            first.span.clone(),
            format!("NAS={} is out of CAS order", first.name),
            format!("describe the axes in the order of CAS: {w}"),
        ));
    }
    let mut masters: Vec<(char, char)> = Vec::new();
    for (i, axis) in p.axes.iter().enumerate() {
        super::axis_rules::check(ctx, model, p, i, axis, diags);
        if let Some(skw) = &axis.skw
            && let Some(m) = skw.master.chars().next()
            && skw.master.len() == 1
        {
            let span = axis.span_of("SKW").unwrap_or(axis.span.clone());
            if let Some((_, other)) = masters.iter().find(|(mm, _)| *mm == m) {
                diags.push(ctx.error(
                    codes::SKW_MASTER_TWICE,
                    span.clone(),
                    format!("axis {m} is already the master of {other}"),
                    "a master axis has one slave",
                ));
            }
            if masters.iter().any(|(mm, _)| *mm == axis.name)
                || p.axes.iter().any(|o| {
                    o.name != axis.name
                        && o.skw
                            .as_ref()
                            .is_some_and(|s| s.master.starts_with(axis.name))
                })
            {
                diags.push(ctx.error(
                    codes::SKW_SLAVE_TWICE,
                    span.clone(),
                    format!("slave axis {} is named as master in another SKW", axis.name),
                    "a slave axis cannot also be a master",
                ));
            }
            masters.push((m, axis.name));
        }
    }
    let cub: Vec<&Axis> = p.axes.iter().filter(|a| a.cub.is_some()).collect();
    if cub.len() > 3 {
        let span = cub[3].span_of("CUB").unwrap_or(cub[3].span.clone());
        diags.push(ctx.error(
            codes::CUB_AXES,
            span,
            format!("{} axes declare CUB", cub.len()),
            "CUB is written for the 3 linear coordinate axes only",
        ));
    }
}

fn section3(ctx: &Ctx, model: &Axcfil, p: &Process, diags: &mut Sink) {
    let servo = p.cas.as_ref().map_or(0, |c| c.servo_tick);
    for t in &p.compensation {
        let Some(axis) = p.axis(t.axis) else {
            diags.push(ctx.error(
                codes::SECTION3,
                t.span.clone(),
                format!(
                    "axis {} is not described in section 2 of process {}",
                    t.axis, p.number
                ),
                "compensate only axes of the process",
            ));
            continue;
        };
        let master = match t.master {
            Some(m) => match p.axis(m) {
                Some(a) => a,
                None => {
                    diags.push(ctx.error(
                        codes::SECTION3,
                        t.span.clone(),
                        format!("NAC master axis {m} is not described in section 2"),
                        "name an axis of the process as master",
                    ));
                    continue;
                }
            },
            None => axis,
        };
        let Some(pitch) = t.pitch else {
            diags.push(ctx.error(
                codes::S3_NO_NAS,
                t.span.clone(),
                format!("the table of axis {} has no PAS", t.axis),
                "write the correction pitch with PAS after NAS",
            ));
            continue;
        };
        if master.axis_type().rotary {
            let k = 360.0 / pitch;
            if (k - k.round()).abs() > 1e-9 {
                diags.push(ctx.error(
                    codes::SECTION3,
                    t.span.clone(),
                    format!("pitch {pitch}° does not divide one revolution"),
                    "for a rotary axis 360° must be a whole multiple of the correction pitch",
                ));
            }
        }
        if let Some(fast) = master.rap.and_then(|r| r.a)
            && servo > 0
        {
            let min = fast * (f64::from(servo) / 1000.0) / 60.0 * 2.0;
            if pitch < min {
                diags.push(ctx.error(
                    codes::SECTION3,
                    t.span.clone(),
                    format!(
                        "correction pitch {pitch} is below the minimum {min:.4} (formula 4.15)"
                    ),
                    "the pitch must be at least 2 × rapid speed × servo tick / 60",
                ));
            }
        }
        let counts = axis
            .pas
            .map(|p| p.el_pitch / p.mec_pitch)
            .filter(|c| c.is_finite());
        for w in t.points.windows(2) {
            let step = w[1].1 - w[0].1;
            if step != 0.0 && (pitch / step).abs() > 32767.0 {
                diags.push(ctx.error(
                    codes::SECTION3,
                    t.span.clone(),
                    format!(
                        "E{:03}→E{:03}: step {step} is too small for pitch {pitch} (formula 4.13)",
                        w[0].0, w[1].0
                    ),
                    "adjacent values are equal or differ by at least pitch/32767",
                ));
            }
        }
        if let Some(c) = counts {
            for (n, e) in &t.points {
                if !(-32768.0..=32767.0).contains(&(c * e).trunc()) {
                    diags.push(ctx.error(
                        codes::SECTION3,
                        t.span.clone(),
                        format!("E{n:03}={e} is more than 32767 counts (formula 4.14)"),
                        "a correction must fit a signed 16-bit count",
                    ));
                }
            }
        }
        let _ = model;
    }
}

/// Error 114: at most 17 axes in all, at most 8 continuous coordinate axes without virtual ones.
fn axis_table(ctx: &Ctx, span: &std::ops::Range<usize>, model: &Axcfil, diags: &mut Sink) {
    let all: usize = model
        .processes
        .iter()
        .filter_map(|p| p.cas.as_ref())
        .map(|c| c.axes.len())
        .sum();
    let continuous = model
        .processes
        .iter()
        .flat_map(|p| p.axes.iter())
        .filter(|a| a.axis_type().coordinate && !a.axis_type().virtual_axis)
        .count();
    if all > 17 || continuous > 8 {
        diags.push(ctx.error(
            codes::AXIS_TABLE_FULL,
            span.clone(),
            format!("{all} axes, {continuous} continuous coordinate axes"),
            "at most 17 axes in all and 8 continuous coordinate axes (virtual axes excluded)",
        ));
    }
}

/// True when `c` may name a continuous axis.
pub fn continuous_letter(c: char) -> bool {
    CONTINUOUS_LETTERS.contains(c)
}
