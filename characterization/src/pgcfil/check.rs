//! Cross-file rules of PGCFIL: process numbers against AXCFIL NBP, the interpolator of NIP, the
//! axes of NAM, NPD, TGA, CAX and MAS, and the ECDF-only instruction CAX.

use diag::{Diagnostic, Sink};

use crate::axcfil::Axcfil;
use crate::reader::ParsedFile;

use super::axes;
use super::fields::Emit;
use super::locate::{self, param_span};
use super::model::Pgcfil;

/// Checks `p` (decoded from `file`) against AXCFIL `ax`; returns the cross-file diagnostics.
pub fn check_against(p: &Pgcfil, file: &ParsedFile, ax: &Axcfil) -> Vec<Diagnostic> {
    let mut diags = Sink::unbounded();
    check_against_into(p, file, ax, &mut diags);
    diags.into_vec()
}

/// [`check_against`] pushing the diagnostics into `diags` (a sink that may store only the first of
/// them).
pub fn check_against_into(p: &Pgcfil, file: &ParsedFile, ax: &Axcfil, diags: &mut Sink) {
    let mut e = Emit::new(file, diags);
    let nbp = ax.nbp;
    for section in [2, 4, 5, 6] {
        for (n, rec) in locate::pro_records(file, section) {
            if n > nbp && (1..=5).contains(&n) {
                e.section = section;
                e.process = Some(n);
                e.error(
                    184,
                    param_span(rec, 0),
                    format!("process {n} is not configured: AXCFIL NBP declares {nbp} process(es)"),
                    &format!("write PRO=1 ... PRO={nbp}, or raise NBP in AXCFIL"),
                );
            }
        }
    }
    for n in 1..=nbp {
        e.process = Some(n);
        if !locate::blocks(file, 4).contains(&n) {
            e.section = 4;
            e.error(951, locate::section_span(file, 4), format!("section *4 has no block for process {n}"), &format!("write PRO={n} and its library instructions in section *4 (the section is mandatory for each process)"));
        }
        if !locate::blocks(file, 5).contains(&n) {
            e.section = 5;
            e.error(
                118,
                locate::section_span(file, 5),
                format!(
                    "section *5 has no block for process {n}: NIP, NAM, NPD and TOF are missing"
                ),
                &format!("write PRO={n}, NIP, TOF, NAM and NPD in section *5"),
            );
        }
    }
    for proc in p.processes.iter().filter(|q| q.number <= nbp) {
        let n = proc.number;
        e.process = Some(n);
        e.section = 5;
        let rec = |key: &str| locate::find(file, 5, n, key);
        if let (Some(nip), Some(r)) = (proc.nip, rec("NIP")) {
            nip_rules(&mut e, ax, n, nip, param_span(r, 0));
        }
        if let (Some(nam), Some(r)) = (proc.nam, rec("NAM")) {
            axis_rule(&mut e, ax, n, nam, param_span(r, 0), "NAM");
        }
        if let (Some((a, o)), Some(r)) = (proc.npd, rec("NPD")) {
            let ok_a = axis_rule(&mut e, ax, n, a, param_span(r, 0), "NPD");
            let ok_o = axis_rule(&mut e, ax, n, o, param_span(r, 1), "NPD");
            if ok_a && ok_o && a == o && axes::continuous_count(ax, n) > 1 {
                e.error(
                    124,
                    param_span(r, 1),
                    format!(
                        "NPD names axis {a} twice although process {n} has several continuous axes"
                    ),
                    "write two different axes; the same axis twice only in a one-axis process",
                );
            }
        }
        if let (Some(tga), Some(r)) = (proc.tga, rec("TGA")) {
            let t = axes::axis_type(ax, n, tga.axis);
            let on_continuous = axes::in_process(ax, n, tga.axis)
                && ax
                    .process(n)
                    .and_then(|q| q.interpolator_of(tga.axis))
                    .is_some()
                && t.is_some_and(|t| !t.ptp && !t.spindle());
            if !on_continuous {
                e.error(
                    146,
                    param_span(r, 0),
                    format!(
                        "TGA axis {} is not on the interpolator of continuous axes of process {n}",
                        tga.axis
                    ),
                    "name a continuous rotary axis of the process's interpolator",
                );
            } else if !t.is_some_and(|t| t.rotary) {
                e.error(
                    148,
                    param_span(r, 0),
                    format!("TGA axis {} is not a rotary axis", tga.axis),
                    "name an axis whose TPA has the rotary bit 0004",
                );
            }
        }
        if let Some(r) = rec("CAX") {
            if !ax.extension.ecdf {
                e.error(
                    6,
                    r.key_span.clone(),
                    "CAX is an ECDF instruction but AXCFIL NBP has no ECDF extension",
                    "add ECDF to the second parameter of NBP in AXCFIL, or remove CAX",
                );
            } else if let Some(cax) = proc.cax {
                for (i, c) in cax.iter().enumerate() {
                    if !axes::in_process(ax, n, *c) {
                        e.error(
                            132,
                            param_span(r, i),
                            format!("CAX axis {c} is not an axis of process {n}"),
                            "name three axes of the process",
                        );
                    }
                }
            }
        }
        e.section = 6;
        if let Some(r) = locate::find(file, 6, n, "MAS") {
            let start = r.params.first().map_or(r.span.start, |q| q.span.start);
            let text = r.params.first().map_or("", |q| q.text.as_str());
            for (i, c) in text.char_indices() {
                let up = c.to_ascii_uppercase();
                if proc.mas.contains(&up) && !axes::in_process(ax, n, up) {
                    e.error(
                        132,
                        start + i..start + i + c.len_utf8(),
                        format!("MAS axis {c} is not an axis of process {n} in AXCFIL"),
                        "list axes of this process only",
                    );
                }
            }
        }
    }
}

/// NIP: the interpolator exists in the process (114) and is the continuous one, holding both
/// axes of every switchable pair (131).
fn nip_rules(e: &mut Emit<'_>, ax: &Axcfil, n: u32, nip: char, span: std::ops::Range<usize>) {
    let Some(process) = ax.process(n) else { return };
    let name = nip.to_string();
    let Some(int) = process
        .interpolators
        .iter()
        .find(|i| i.name.eq_ignore_ascii_case(&name))
    else {
        let names: Vec<&str> = process
            .interpolators
            .iter()
            .map(|i| i.name.as_str())
            .collect();
        e.error(
            114,
            span,
            format!("interpolator {nip} is not declared for process {n} in AXCFIL"),
            &format!("process {n} has interpolator(s) {}", names.join(", ")),
        );
        return;
    };
    let ptp_only = !int.axes.is_empty()
        && int
            .axes
            .iter()
            .all(|&c| axes::axis_type(ax, n, c).is_some_and(|t| t.ptp));
    if ptp_only && axes::continuous_count(ax, n) > 0 {
        e.error(
            131,
            span,
            format!("interpolator {nip} drives point-to-point axes only"),
            "NIP names the interpolator of the continuous coordinate axes",
        );
        return;
    }
    for &c in &int.axes {
        let partner = axes::axis_of(ax, n, c)
            .and_then(|a| a.tpa.as_ref())
            .filter(|t| t.axis_type.switched)
            .and_then(|t| t.switch_axis.as_deref())
            .and_then(|s| s.chars().next());
        if let Some(p) =
            partner.filter(|p| !int.axes.contains(p) && axes::axis_of(ax, n, *p).is_some())
        {
            e.error(131, span.clone(), format!("axis {c} of interpolator {nip} is switchable with {p}, which is on another interpolator"), "switchable axes must be declared on the same interpolator");
            return;
        }
    }
}

/// NAM/NPD axis: defined in AXCFIL (116) and a continuous coordinate axis (117). True when valid.
fn axis_rule(
    e: &mut Emit<'_>,
    ax: &Axcfil,
    n: u32,
    c: char,
    span: std::ops::Range<usize>,
    key: &str,
) -> bool {
    if !axes::in_process(ax, n, c) {
        e.error(
            116,
            span,
            format!("{key} axis {c} is not defined for process {n} in AXCFIL"),
            "name an axis of the process declared in AXCFIL",
        );
        return false;
    }
    // A process without continuous axes (a tool magazine) still needs NAM and NPD (118): they
    // name its point-to-point axis then.
    match axes::axis_type(ax, n, c) {
        Some(t) if !axes::continuous(&t) && axes::continuous_count(ax, n) > 0 => {
            e.error(117, span, format!("{key} axis {c} is not a continuous coordinate axis"), "NAM and NPD name continuous coordinate axes, never the spindle or a point-to-point axis");
            false
        }
        _ => true,
    }
}
