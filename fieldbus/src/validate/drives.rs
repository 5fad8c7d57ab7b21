//! Validation of the `[[canopen.drive]]` tables: CiA 402 drives against the machine's AXCFIL axes.
//!
//! Each entry names an axis (and its process), a node id, a scale and a mode. The checks: the axis
//! exists in AXCFIL (when the caller knows the axes), it is on one drive only, its TPA type allows a
//! bus drive (the rule of AXCFIL error 226, 003:6700: none of the codes 8, 200, 1000, 10000, 80000;
//! and no virtual axis, which has no drive), the mode fits the axis type (a spindle, TPA 10 or 20,
//! runs `csv`; every other axis `csp`; `pp` is refused as not yet supported), the node id is in
//! 1..127 and used by no I/O node and no other drive, and the scale is finite and positive. Every
//! problem is a located diagnostic; an entry with errors is still returned (the map is refused as
//! a whole by the caller).

use std::collections::HashMap;
use std::ops::Range;

use toml::Spanned;

use super::{Ctx, codes};
use crate::map::{CanDrive, DeclaredAxis, DriveMode, DriveSimHooks, RawCanDrive, RawDriveSim};

/// TPA codes that error 226 forbids for an axis driven over CANopen, with their names.
const FORBIDDEN_TPA: [(u32, &str); 5] = [
    (0x8, "8 (switched axis)"),
    (0x200, "200 (absolute axis)"),
    (0x1000, "1000 (slave parallel axis)"),
    (0x1_0000, "10000 (encoder without reference mark)"),
    (0x8_0000, "80000 (Gray-code absolute encoder)"),
];
/// TPA code of a virtual axis (no physical drive).
const TPA_VIRTUAL: u32 = 0x100;
/// TPA codes of a spindle (without and with encoder).
const TPA_SPINDLE: u32 = 0x10 | 0x20;

/// Checks the drive entries; `io_nodes` are the node ids of the I/O nodes with their spans,
/// `axes` the AXCFIL axes (`None`: the caller does not know them, axis checks are skipped).
pub(super) fn drives(
    cx: &mut Ctx,
    raw: &[Spanned<RawCanDrive>],
    io_nodes: &HashMap<u8, Range<usize>>,
    axes: Option<&[DeclaredAxis]>,
    virtual_bus: bool,
) -> Vec<CanDrive> {
    let mut out = Vec::new();
    let mut nodes: HashMap<u8, Range<usize>> = HashMap::new();
    let mut claimed: HashMap<(u32, char), Range<usize>> = HashMap::new();
    for d in raw {
        let r = d.get_ref();
        let process = match &r.process {
            Some(p) if !(1..=5).contains(p.get_ref()) => {
                let msg = format!("process {} is out of range", p.get_ref());
                cx.err(codes::VALUE, p.span(), msg, "AXCFIL processes are 1..5");
                1
            }
            Some(p) => *p.get_ref(),
            None => 1,
        };
        let axis = axis_name(cx, &r.axis);
        let declared = axis.and_then(|a| declared_axis(cx, r, a, process, axes));
        if let Some(a) = axis {
            if let Some(first) = claimed.get(&(process, a)) {
                let line = cx.line_of(first);
                cx.err(
                    codes::DRIVE_AXIS_TWICE,
                    r.axis.span(),
                    format!("axis {a} of process {process} is on two drives"),
                    format!("its first drive entry is on line {line}; an axis has one drive"),
                );
            } else {
                claimed.insert((process, a), r.axis.span());
            }
        }
        let span = r.node_id.span();
        let node_id = node_id(cx, r, io_nodes, &mut nodes);
        let counts_per_unit = *r.counts_per_unit.get_ref();
        if !counts_per_unit.is_finite() || counts_per_unit <= 0.0 {
            cx.err(
                codes::DRIVE_SCALE,
                r.counts_per_unit.span(),
                format!("counts_per_unit {counts_per_unit} is not a positive finite number"),
                "give the drive's position units per mm, degree or revolution, e.g. 10000",
            );
        }
        let mode = mode(cx, r, declared);
        let homing = mode == DriveMode::Csp && declared.is_none_or(|d| d.homes);
        super::sections::check_sdo_writes(cx, &r.sdo);
        out.push(CanDrive {
            process,
            axis: axis.unwrap_or('?'),
            node_id,
            counts_per_unit,
            mode,
            heartbeat: cx.ms(&r.heartbeat_ms, 100, "heartbeat_ms"),
            sdo: r.sdo.iter().map(|s| *s.get_ref()).collect(),
            simulate: r
                .simulate
                .as_ref()
                .map(|h| simulate(cx, h, virtual_bus))
                .unwrap_or_default(),
            span,
            homing,
        });
    }
    out
}

/// The simulated drive's test hooks: only on the virtual bus; a fault needs its SYNC and code.
fn simulate(cx: &mut Ctx, h: &Spanned<RawDriveSim>, virtual_bus: bool) -> DriveSimHooks {
    let r = h.get_ref();
    if !virtual_bus {
        cx.err(
            codes::DRIVE_SIMULATE,
            h.span(),
            "`simulate` rehearses faults on simulated drives: it needs transport = \"virtual\"",
            "remove it for a real bus",
        );
    }
    let fault = match (r.fault_at_sync, r.fault_code) {
        (Some(at), Some(code)) if at > 0 && code != 0 => Some((at, code)),
        (None, None) => None,
        _ => {
            cx.err(
                codes::DRIVE_SIMULATE,
                h.span(),
                "a simulated fault needs both fault_at_sync (≥ 1) and fault_code (not 0)",
                "e.g. simulate = { fault_at_sync = 2000, fault_code = 0x5530 }",
            );
            None
        }
    };
    DriveSimHooks {
        fault,
        heartbeat_stop: r.heartbeat_stop_at_sync,
        refuse_enable: r.refuse_enable,
        sdo_abort: r.sdo_abort.as_ref().map(|a| (a.index, a.subindex, a.code)),
        max_speed: r.max_speed,
        machine: None,
    }
}

fn axis_name(cx: &mut Ctx, s: &Spanned<String>) -> Option<char> {
    let mut chars = s.get_ref().chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) if c.is_ascii_uppercase() => Some(c),
        _ => {
            let msg = format!("`{}` is not an axis name", s.get_ref());
            cx.err(
                codes::DRIVE_AXIS,
                s.span(),
                msg,
                "name one AXCFIL axis by its letter, e.g. axis = \"X\" (a spindle: \"S\")",
            );
            None
        }
    }
}

/// The AXCFIL axis of the entry, with the type checks; `None` when unknown (an error is given
/// when the axes are known).
fn declared_axis(
    cx: &mut Ctx,
    r: &RawCanDrive,
    axis: char,
    process: u32,
    axes: Option<&[DeclaredAxis]>,
) -> Option<DeclaredAxis> {
    let axes = axes?;
    let Some(found) = axes
        .iter()
        .find(|a| a.process == process && a.name == axis)
        .copied()
    else {
        let names: String = axes
            .iter()
            .filter(|a| a.process == process)
            .map(|a| a.name)
            .collect();
        let hint = if names.is_empty() {
            format!("AXCFIL has no process {process}")
        } else {
            format!("process {process} declares the axes {names}")
        };
        let msg = format!("AXCFIL declares no axis {axis} in process {process}");
        cx.err(codes::DRIVE_AXIS, r.axis.span(), msg, hint);
        return None;
    };
    let bad: Vec<&str> = FORBIDDEN_TPA
        .iter()
        .filter(|(bit, _)| found.tpa & bit != 0)
        .map(|(_, name)| *name)
        .collect();
    if !bad.is_empty() {
        let msg = format!(
            "axis {axis} has TPA={:X}, which includes {}: not allowed for an axis driven over CANopen",
            found.tpa,
            bad.join(", ")
        );
        cx.err(
            codes::DRIVE_AXIS_TYPE,
            r.axis.span(),
            msg,
            "AXCFIL error 226 (003:6700): a CANopen axis has none of the TPA codes 8, 200, 1000, 10000, 80000",
        );
    } else if found.tpa & TPA_VIRTUAL != 0 {
        let msg = format!(
            "axis {axis} is a virtual axis (TPA={:X}): it has no drive",
            found.tpa
        );
        cx.err(
            codes::DRIVE_AXIS_TYPE,
            r.axis.span(),
            msg,
            "drive the physical axes the virtual axis moves",
        );
    }
    Some(found)
}

fn node_id(
    cx: &mut Ctx,
    r: &RawCanDrive,
    io_nodes: &HashMap<u8, Range<usize>>,
    drives: &mut HashMap<u8, Range<usize>>,
) -> u8 {
    let span = r.node_id.span();
    let Ok(id @ 1..=127) = u8::try_from(*r.node_id.get_ref()) else {
        let msg = format!("node id {} is out of range", r.node_id.get_ref());
        cx.err(codes::VALUE, span, msg, "CANopen node ids are 1..127");
        return 1;
    };
    if let Some(first) = io_nodes.get(&id) {
        let line = cx.line_of(first);
        cx.err(
            codes::DRIVE_NODE,
            span,
            format!("node id {id} is already an I/O node"),
            format!("the [[canopen.node]] on line {line} uses it; give the drive its own node id"),
        );
    } else if let Some(first) = drives.get(&id) {
        let line = cx.line_of(first);
        cx.err(
            codes::DRIVE_NODE,
            span,
            format!("node id {id} is already a drive"),
            format!("the drive entry on line {line} uses it; one drive per node"),
        );
    } else {
        drives.insert(id, span);
    }
    id
}

fn mode(cx: &mut Ctx, r: &RawCanDrive, axis: Option<DeclaredAxis>) -> DriveMode {
    let span = r.mode.span();
    let mode = match r.mode.get_ref().as_str() {
        "csp" => DriveMode::Csp,
        "csv" => DriveMode::Csv,
        "pp" => {
            cx.err(
                codes::DRIVE_MODE_NOT_YET,
                span,
                "mode \"pp\" (profile position) is not supported yet",
                "use \"csp\" for an axis (the controller interpolates) or \"csv\" for a spindle",
            );
            return DriveMode::Csp;
        }
        other => {
            cx.err(
                codes::DRIVE_MODE,
                span,
                format!("unknown drive mode `{other}`"),
                "use \"csp\" (cyclic synchronous position) or \"csv\" (cyclic synchronous velocity)",
            );
            return DriveMode::Csp;
        }
    };
    if let Some(a) = axis {
        let spindle = a.tpa & TPA_SPINDLE != 0;
        let wanted = if spindle {
            DriveMode::Csv
        } else {
            DriveMode::Csp
        };
        if mode != wanted {
            let (what, hint) = if spindle {
                (
                    "a spindle",
                    "a spindle (TPA 10 or 20) runs in mode \"csv\": the controller commands its speed",
                )
            } else {
                (
                    "a positioned axis",
                    "an axis runs in mode \"csp\": the controller commands its position every tick",
                )
            };
            let msg = format!(
                "mode \"{}\" does not fit axis {} (TPA={:X}), {what}",
                r.mode.get_ref(),
                a.name,
                a.tpa
            );
            cx.err(codes::DRIVE_MODE, span, msg, hint);
        }
    }
    mode
}
