//! The rules of one section-2 axis that involve another axis: slave parallel axes and their
//! master (SKW), handwheel/correction axes (HWC), and the kind and letters of the interpolator
//! the axis is in.

use diag::{Diagnostic, Sink};

use super::model::{Axis, Process};
use crate::codes;
use crate::values::Ctx;

/// Instructions a slave parallel axis may have (003:990, error 198; PAS from 003:994).
const SLAVE_KEYS: [&str; 8] = ["NAS", "TPA", "NTC", "GAS", "PAS", "MCZ", "MFC", "SKW"];

/// Checks axis `index` of process `p` against the other axes of the process.
pub fn check(ctx: &Ctx, p: &Process, index: usize, axis: &Axis, diags: &mut Sink) {
    // Diagnostics about section-1 records (the interpolator) carry section 1.
    let s1 = ctx.in_section(1);
    let mut later: Vec<Diagnostic> = Vec::new();
    let mut err = |code: u32, span: std::ops::Range<usize>, msg: String, hint: &str| {
        diags.push(ctx.error(code, span, msg, hint))
    };
    let name = axis.name;
    let at = |key: &str| axis.span_of(key).unwrap_or(axis.span.clone());
    let t = axis.axis_type();
    let slave = t.slave_parallel;
    let interpolator = p.interpolator_of(name);
    // Slave parallel axes: homing direction and speed equal the master's (003:992).
    if let Some(master) = axis
        .skw
        .as_ref()
        .and_then(|k| k.master.chars().next())
        .and_then(|m| p.axis(m))
        && slave
        && let (Some(mine), Some(theirs)) = (&axis.mcz, &master.mcz)
        && (mine.negative != theirs.negative || mine.speed != theirs.speed)
    {
        err(
            codes::SLAVE_HOMING,
            at("MCZ"),
            format!(
                "slave {name} homes differently from its master {}",
                master.name
            ),
            "give the slave the master's MCZ direction and speed",
        );
    }
    if let Some(skw) = &axis.skw {
        let span = at("SKW");
        if !slave {
            err(
                codes::SKW_NOT_SLAVE,
                span.clone(),
                format!("SKW on axis {name}, which is not a slave parallel axis"),
                "SKW is written only for an axis with code 1000",
            );
        }
        if skw.master.len() != 1 {
            err(
                codes::SKW_NAME,
                span.clone(),
                format!("SKW master `{}` is not one letter", skw.master),
                "write the master axis letter",
            );
        } else if let Some(m) = skw.master.chars().next() {
            if m == name {
                err(
                    codes::SKW_SELF,
                    span.clone(),
                    format!("axis {name} is declared slave of itself"),
                    "name another axis as master",
                );
            } else if !p.cas.as_ref().is_some_and(|c| c.axes.contains(&m)) {
                err(
                    codes::SKW_UNDECLARED,
                    span.clone(),
                    format!("SKW master {m} is not declared"),
                    "the master must be an axis of this process",
                );
            } else if p
                .axes
                .iter()
                .position(|a| a.name == m)
                .is_none_or(|mi| mi > index)
            {
                err(
                    codes::SLAVE_BEFORE_MASTER,
                    span.clone(),
                    format!("slave {name} is described before its master {m}"),
                    "describe the master axis first in section 2",
                );
            }
        }
    }
    if slave {
        if interpolator.is_some() {
            err(
                codes::SLAVE_INTERPOLATED,
                axis.span.clone(),
                format!(
                    "slave axis {name} is listed in interpolator {}",
                    interpolator.map_or("", |i| i.name.as_str())
                ),
                "list slave parallel axes only in CAS, not in INx",
            );
        }
        for (key, span) in axis
            .order
            .iter()
            .filter(|(k, _)| !SLAVE_KEYS.contains(&k.as_str()))
        {
            err(
                codes::SLAVE_INSTRUCTIONS,
                span.clone(),
                format!("slave axis {name} has {key}"),
                "a slave axis has only NAS, TPA, NTC, GAS, PAS, MCZ, MFC and SKW",
            );
        }
    }
    // Handwheel / correction axes.
    if let Some(hwc) = &axis.hwc {
        let ok = hwc.axis.len() == 1
            && hwc.axis.chars().next().is_some_and(|c| {
                c != name && p.cas.as_ref().is_some_and(|cas| cas.axes.contains(&c))
            });
        if !ok {
            err(
                codes::HWC_AXIS,
                at("HWC"),
                format!(
                    "HWC names `{}`, which is not another axis of the process",
                    hwc.axis
                ),
                "name the correction axis, one letter from CAS",
            );
        } else if let Some(c) = hwc.axis.chars().next()
            && let Some(i) = p.interpolator_of(c)
        {
            err(
                codes::INTERPOLATOR_EXCLUDED,
                at("HWC"),
                format!("handwheel axis {c} is listed in interpolator {}", i.name),
                "list a handwheel axis only in CAS, not in INx",
            );
        }
    }
    // Interpolator kinds and letters.
    if let Some(ip) = interpolator {
        let coordinated = ip.spindle.is_some()
            || ip
                .axes
                .iter()
                .any(|a| p.axis(*a).is_some_and(|x| !x.axis_type().ptp));
        if t.ptp && coordinated && ip.spindle != Some(name) {
            err(
                codes::INTERPOLATOR_KIND,
                axis.span.clone(),
                format!(
                    "point-to-point axis {name} is in the coordinated interpolator {}",
                    ip.name
                ),
                "declare a point-to-point axis in its own interpolator, e.g. `IN2=1,T,,1,1`",
            );
        }
        if t.coordinate && !super::rules::continuous_letter(name) && ip.axes.contains(&name) {
            err(
                codes::AXIS_LETTER,
                axis.span.clone(),
                format!("continuous axis {name} uses a letter not allowed for continuous axes"),
                "continuous axes are named A B C D X Y Z U V W P Q",
            );
        }
        let ptp_only = ip.spindle.is_none()
            && ip
                .axes
                .iter()
                .all(|a| p.axis(*a).is_some_and(|x| x.axis_type().ptp));
        if ptp_only && ip.block_num != 1 && ip.axes.first() == Some(&name) {
            later.push(s1.error(
                codes::BLOCK_NUM,
                ip.span.clone(),
                format!(
                    "point-to-point interpolator {} buffers {} blocks",
                    ip.name, ip.block_num
                ),
                "a point-to-point interpolator has block_num 1",
            ));
        } else if !ptp_only && ip.block_num == 1 && ip.axes.first() == Some(&name) {
            later.push(s1.error(
                codes::BLOCK_NUM,
                ip.span.clone(),
                format!("coordinated interpolator {} buffers 1 block", ip.name),
                "a coordinated interpolator has block_num 2 to 64",
            ));
        }
    }
    diags.extend(later);
}
