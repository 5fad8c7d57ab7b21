//! PGCFIL sections 5 (the controlled machine) and 6 (manual axes, override tables).

use std::ops::Range;

use crate::reader::{Record, Section};

use super::fields::Emit;
use super::model::{Cwp, Dpm, Inu, MachineType, PgProcess, Tas, Tga, Units};
use super::structure::{Blocks, not_allowed};
use super::tables::G_CLASSES;

const S5: &str =
    "PRO, NIP, DPM, SMC, TOF, GXX, PRC, CWP, NAM, NPD, G70, MBR, TAS, INU, CAX, QFD, TGA";
const S6: &str = "PRO, MAS, FRO, SSO, FMO";

/// Order and presence state of one section-5 process block.
#[derive(Debug, Default)]
pub(crate) struct BlockState {
    nip: bool,
    nam: bool,
    npd: bool,
    tof: bool,
    any: bool,
}

impl BlockState {
    /// Error 118 when the block that just ended lacks NIP, NAM, NPD or TOF.
    pub fn finish(&self, e: &mut Emit<'_>, blocks: &Blocks, section: &Section) {
        if blocks.dead || (!self.any && blocks.pro_span.is_none()) {
            return;
        }
        let missing: Vec<&str> = [
            ("NIP", self.nip),
            ("NAM", self.nam),
            ("NPD", self.npd),
            ("TOF", self.tof),
        ]
        .iter()
        .filter(|(_, ok)| !ok)
        .map(|(k, _)| *k)
        .collect();
        if !missing.is_empty() {
            let span: Range<usize> = blocks
                .pro_span
                .clone()
                .unwrap_or_else(|| section.span.clone());
            e.process = blocks.current;
            e.error(
                118,
                span,
                format!("process block lacks {}", missing.join(", ")),
                "section 5 of every process declares NIP, NAM, NPD and TOF",
            );
        }
    }
}

/// One section-5 record.
pub(crate) fn section5(
    e: &mut Emit<'_>,
    blocks: &mut Blocks,
    st: &mut BlockState,
    rec: &Record,
    proc: &mut PgProcess,
) {
    let known = [
        "NIP", "DPM", "SMC", "TOF", "GXX", "PRC", "CWP", "NAM", "NPD", "G70", "MBR", "TAS", "INU",
        "CAX", "QFD", "TGA",
    ];
    if !known.contains(&rec.key.as_str()) {
        return not_allowed(e, rec, S5);
    }
    st.any = true;
    if !blocks.first_time(e, rec) {
        return;
    }
    let p = &rec.params;
    match rec.key.as_str() {
        "NIP" => {
            st.nip = true;
            if blocks.position != 1 {
                e.error(
                    950,
                    rec.key_span.clone(),
                    "NIP is not written immediately after PRO",
                    "write NIP as the first instruction of the process block",
                );
            }
            if e.count(rec, 1, 1) {
                proc.nip = e.axis_name_like(&p[0], 113, "interpolator");
            }
        }
        "DPM" => {
            if e.count(rec, 3, 3) {
                proc.dpm = Some(Dpm {
                    appro_quote: e.real(&p[0]),
                    safe_quote: e.real(&p[1]),
                    mis_speed: e.real(&p[2]),
                });
            }
        }
        "SMC" => {
            if e.count(rec, 1, 1) {
                proc.smc = e.real(&p[0]);
            }
        }
        "PRC" => {
            if e.count(rec, 1, 1) {
                proc.prc = e.real(&p[0]);
            }
        }
        "QFD" => {
            if e.count(rec, 1, 1) {
                proc.qfd = e.real(&p[0]);
            }
        }
        "TOF" => {
            st.tof = true;
            if e.count(rec, 1, 1)
                && let Some(v) = e.hex(&p[0], 2)
            {
                let raw = v as u8;
                if matches!(raw & 0x0F, 1 | 2 | 5 | 6) && raw >> 4 <= 3 {
                    proc.tof = Some(MachineType { raw });
                } else {
                    e.error(
                        133,
                        p[0].span.clone(),
                        format!("TOF={} is not a machine type", p[0].text),
                        "the right digit is 1, 2, 5 or 6; add 10 and/or 20 for the auxiliary codes",
                    );
                }
            }
        }
        "GXX" => gxx(e, st, rec, proc),
        "CWP" => {
            if e.count(rec, 2, 2) {
                let cw = e.hex(&p[0], 4);
                let off = e.hex(&p[1], 2);
                if let Some(o) = off.filter(|o| *o > 1) {
                    e.error(
                        956,
                        p[1].span.clone(),
                        format!("CWP offset {o} is not 0 or 1"),
                        "0 = tool compensation and GTL used, 1 = not used",
                    );
                }
                proc.cwp = Some(Cwp {
                    cw_console: cw,
                    no_offsets: off.filter(|o| *o <= 1).map(|o| o == 1),
                });
            }
        }
        "NAM" => {
            st.nam = true;
            if !st.nip {
                e.error(
                    125,
                    rec.key_span.clone(),
                    "NAM is written before NIP",
                    "write NIP first in the process block",
                );
            }
            if e.count(rec, 1, 1) {
                proc.nam = e.axis_name(&p[0], 115);
            }
        }
        "NPD" => {
            st.npd = true;
            if !st.nip {
                e.error(
                    125,
                    rec.key_span.clone(),
                    "NPD is written before NIP",
                    "write NIP first in the process block",
                );
            }
            if e.count(rec, 2, 2) {
                let a = e.axis_name(&p[0], 115);
                let o = e.axis_name(&p[1], 115);
                if let (Some(a), Some(o)) = (a, o) {
                    proc.npd = Some((a, o));
                }
            }
        }
        "G70" => {
            if e.count(rec, 1, 1) {
                match e.hex(&p[0], 2) {
                    Some(0) => proc.g70 = Some(Units::Millimetres),
                    Some(1) => proc.g70 = Some(Units::Inches),
                    Some(v) => e.error(
                        957,
                        p[0].span.clone(),
                        format!("G70={v:X} is neither 0 nor 1"),
                        "0 = millimetres, 1 = inches",
                    ),
                    None => {}
                }
            }
        }
        "MBR" => {
            if e.count(rec, 1, 1) {
                match e.word(&p[0]) {
                    Some(v @ 1..=255) => proc.mbr = Some(v),
                    Some(v) => e.error(
                        958,
                        p[0].span.clone(),
                        format!("MBR={v} is outside 1 ... 255"),
                        "the retrace depth is 1 ... 255 blocks",
                    ),
                    None => {}
                }
            }
        }
        "TAS" => tas(e, rec, proc),
        "INU" => {
            if e.count(rec, 2, 2) {
                let probe_input = e.plc_variable(&p[0]);
                let probe_status = status(e, &p[1]);
                proc.inu = Some(Inu {
                    probe_input,
                    probe_status,
                });
            }
        }
        "CAX" => {
            if e.count(rec, 3, 3) {
                let names: Vec<Option<char>> = p.iter().map(|x| e.axis_name(x, 132)).collect();
                if let [Some(a), Some(b), Some(c)] = names[..] {
                    proc.cax = Some([a, b, c]);
                }
            }
        }
        _ => {
            if e.count(rec, 2, 2) {
                let axis = e.axis_name(&p[0], 115);
                let angle = e.real(&p[1]);
                if let Some(a) = angle.filter(|a| !(-360.0..=360.0).contains(a)) {
                    e.error(
                        147,
                        p[1].span.clone(),
                        format!("TGA angle {a} is outside -360 ... 360 degrees"),
                        "write an angle within -360 ... 360",
                    );
                }
                if let Some(axis) = axis {
                    proc.tga = Some(Tga {
                        axis,
                        angle: angle.filter(|a| (-360.0..=360.0).contains(a)),
                    });
                }
            }
        }
    }
}

fn status(e: &mut Emit<'_>, p: &crate::reader::Param) -> Option<u8> {
    let v = e.hex(p, 2)?;
    if v > 1 {
        e.error(
            120,
            p.span.clone(),
            format!("probe state {v:X} is not 0 or 1"),
            "1 = normally closed contact, 0 = normally open",
        );
        return None;
    }
    Some(v as u8)
}

fn tas(e: &mut Emit<'_>, rec: &Record, proc: &mut PgProcess) {
    if !e.count(rec, 6, 6) {
        return;
    }
    let p = &rec.params;
    let probe_input = e.plc_variable(&p[0]);
    let probe_status = status(e, &p[1]);
    let path = e.ascii(&p[2]);
    if let Some(t) = &path {
        let c: Vec<char> = t.chars().collect();
        if !(c.len() == 2 && c[0].is_ascii_alphabetic() && (c[1] == '+' || c[1] == '-')) {
            e.error(
                122,
                p[2].span.clone(),
                format!("TAS path '{t}' is not an axis name followed by + or -"),
                "write two characters, e.g. Z-",
            );
        }
    }
    let probe_type = e.ascii(&p[3]).and_then(|t| match t.as_str() {
        "S" | "N" => t.chars().next(),
        _ => {
            e.error(
                123,
                p[3].span.clone(),
                format!("probe type '{t}' is not S or N"),
                "S = oriented probe, N = non-oriented",
            );
            None
        }
    });
    let mes_input = e.plc_variable(&p[4]);
    let mes_status = status(e, &p[5]);
    if mes_input.is_some() && mes_input == probe_input {
        e.error(
            959,
            p[4].span.clone(),
            "TAS measuring input is the same signal as the probe safety input",
            "mes_input must be a different PLC signal than probe_input",
        );
    }
    proc.tas = Some(Tas {
        probe_input,
        probe_status,
        path,
        probe_type,
        mes_input,
        mes_status,
    });
}

fn gxx(e: &mut Emit<'_>, st: &BlockState, rec: &Record, proc: &mut PgProcess) {
    if !st.tof {
        e.error(
            139,
            rec.key_span.clone(),
            "GXX is written before TOF",
            "write TOF, then GXX",
        );
    }
    if !e.count(rec, 6, 6) {
        return;
    }
    let mut out = [None; 6];
    for (i, p) in rec.params.iter().enumerate() {
        if p.text.is_empty() {
            continue;
        }
        let ok = p.text.len() <= 2 && p.text.bytes().all(|b| b.is_ascii_digit());
        let g = if ok { p.text.parse::<u8>().ok() } else { None };
        match g.filter(|g| G_CLASSES[i].contains(g)) {
            Some(g) => out[i] = Some(g),
            None => {
                let allowed: Vec<String> = G_CLASSES[i].iter().map(|g| format!("{g:02}")).collect();
                e.error(
                    140,
                    p.span.clone(),
                    format!("'{}' is not a G code of class {}", p.text, i + 1),
                    &format!("class {} admits {}", i + 1, allowed.join(", ")),
                );
            }
        }
    }
    proc.gxx = Some(out);
}

/// One section-6 record.
pub(crate) fn section6(e: &mut Emit<'_>, blocks: &mut Blocks, rec: &Record, proc: &mut PgProcess) {
    if !["MAS", "FRO", "SSO", "FMO"].contains(&rec.key.as_str()) {
        return not_allowed(e, rec, S6);
    }
    if !blocks.first_time(e, rec) {
        return;
    }
    let p = &rec.params;
    if rec.key == "MAS" {
        if !e.count(rec, 1, 1) {
            return;
        }
        let Some(t) = e.ascii(&p[0]) else { return };
        let mut axes = Vec::new();
        for (i, c) in t.char_indices() {
            let at = p[0].span.start + i..p[0].span.start + i + c.len_utf8();
            if !c.is_ascii_alphabetic() {
                e.error(
                    132,
                    at,
                    format!("'{c}' in MAS is not an axis name"),
                    "list axis letters without separators, e.g. MAS=XYZ",
                );
            } else if axes.contains(&c.to_ascii_uppercase()) {
                e.error(
                    124,
                    at,
                    format!("axis {c} is listed twice in MAS"),
                    "list each axis once",
                );
            } else {
                axes.push(c.to_ascii_uppercase());
            }
        }
        if axes.len() > 8 {
            e.error(
                126,
                p[0].span.clone(),
                format!("MAS lists {} axes", axes.len()),
                "at most 8 axes (NC-110, NC-310), 6 on NC-200 ... NC-230",
            );
        }
        proc.mas = axes;
        return;
    }
    let (min, max) = if rec.key == "FRO" { (12, 17) } else { (12, 12) };
    if !e.count(rec, min, max) || (rec.key == "FRO" && p.len() != 12 && p.len() != 17) {
        if p.len() > 12 && p.len() < 17 {
            e.error(
                10,
                rec.span.clone(),
                format!("FRO has {} positions", p.len()),
                "FRO has 12 positions (17 on NC-301/302)",
            );
        }
        return;
    }
    let values: Vec<Option<f64>> = p.iter().map(|x| e.real(x)).collect();
    if let Some(i) = values.iter().position(Option::is_none) {
        if p[i].text.is_empty() {
            e.error(
                10,
                p[i].span.clone(),
                format!("{} position {} is empty", rec.key, i + 1),
                "write every position of an override table",
            );
        }
        return;
    }
    let values: Vec<f64> = values.into_iter().flatten().collect();
    let n = values.len();
    if values[n - 1] != values[n - 2] {
        e.error(
            960,
            p[n - 1].span.clone(),
            format!("{} positions {} and {} differ", rec.key, n - 1, n),
            "the last two positions of an override table must be equal",
        );
    }
    match rec.key.as_str() {
        "FRO" => proc.fro = Some(values),
        "SSO" => proc.sso = Some(values),
        _ => proc.fmo = Some(values),
    }
}
