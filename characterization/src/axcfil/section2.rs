//! AXCFIL section 2: `PRO` subsections, `NAS` axis subsections and every per-axis instruction,
//! parsed record by record into [`Axis`] values.
//!
//! Record-local checks happen here (parameter counts and types, ECDF forms, number ranges that
//! need nothing but the record). Rules between instructions of one axis or between axes are in
//! [`super::rules`].

use diag::Diagnostic;
use packets::{Packet, Signal};

use super::model::{
    Adg, Adp, Axcfil, Axis, AxisType, Cam, Fbf, FileRef, Frc, Gas, Gm, Gra, Hwc, Las, Mcz, Ntc,
    Pair, Pas, Pom, Skw, Tpa, Zno, Zone,
};
use crate::codes;
use crate::reader::{Param, Record, Section};
use crate::values::{self, Ctx};

/// Reads section 2 into the processes of `model`.
pub fn read(ctx: Ctx, section: &Section, model: &mut Axcfil, diags: &mut Vec<Diagnostic>) {
    let mut s = State {
        ctx,
        ecdf: model.extension.ecdf,
        model,
        diags,
        process: None,
        seen: Vec::new(),
    };
    for r in &section.records {
        s.record(r);
    }
}

struct State<'a, 'm> {
    ctx: Ctx<'a>,
    ecdf: bool,
    model: &'m mut Axcfil,
    diags: &'m mut Vec<Diagnostic>,
    process: Option<usize>,
    seen: Vec<u32>,
}

/// Record-local parsing of one instruction into an axis.
struct Parse<'c, 'd> {
    ctx: Ctx<'c>,
    ecdf: bool,
    diags: &'d mut Vec<Diagnostic>,
}

impl<'a> State<'a, '_> {
    fn ctx(&self) -> Ctx<'a> {
        let p = self
            .process
            .and_then(|i| self.model.processes.get(i))
            .map(|p| p.number);
        self.ctx.in_process(p)
    }

    fn push(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    fn record(&mut self, r: &Record) {
        match r.key.as_str() {
            "PRO" => self.pro(r),
            "NAS" => self.nas(r),
            _ => self.instruction(r),
        }
    }

    fn pro(&mut self, r: &Record) {
        let ctx = self.ctx.in_process(None);
        let Some(n) = super::pro_number(&ctx, r, self.model.nbp, self.diags) else {
            self.process = None;
            return;
        };
        let ctx = self.ctx.in_process(Some(n));
        if self.seen.contains(&n) {
            self.push(ctx.error(
                codes::PROCESS_TWICE,
                r.span.clone(),
                format!("process {n} is opened twice in section 2"),
                "write each process's PRO once per section",
            ));
        }
        self.seen.push(n);
        self.process = self.model.processes.iter().position(|p| p.number == n);
        if self.process.is_none() {
            self.push(ctx.error(
                codes::PRO_ABOVE_NBP,
                r.span.clone(),
                format!("process {n} is not configured in section 1"),
                "declare the process in section 1 (PRO, INx, CAS) first",
            ));
        }
    }

    fn nas(&mut self, r: &Record) {
        let ctx = self.ctx();
        let Some(i) = self.process else {
            self.push(ctx.error(
                codes::NO_PROCESS,
                r.key_span.clone(),
                "NAS before any PRO in section 2",
                "open the process with `PRO=n` first",
            ));
            return;
        };
        if let Err(d) = ctx.arity(r, 1, 1) {
            self.push(d);
            return;
        }
        let name = match values::ascii(&ctx, &r.params[0]) {
            Ok(Some(n)) => n,
            Ok(None) => {
                self.push(ctx.error(
                    codes::TOO_FEW_PARAMS,
                    r.end_span(),
                    "NAS names no axis",
                    "write the axis name, e.g. `NAS=X`",
                ));
                return;
            }
            Err(d) => {
                self.push(d);
                return;
            }
        };
        let process = &self.model.processes[i];
        let mut chars = name.chars();
        let (Some(c), None) = (chars.next(), chars.next()) else {
            self.diags.push(ctx.error(
                codes::NAS_UNDECLARED,
                r.params[0].span.clone(),
                format!("`{name}` is not an axis name"),
                "an axis name is one letter declared in CAS of section 1",
            ));
            return;
        };
        let in_cas = process
            .cas
            .as_ref()
            .is_some_and(|cas| cas.axes.contains(&c));
        if !in_cas {
            let owner = process
                .common
                .iter()
                .find(|cm| cm.axes.contains(&c))
                .map(|cm| cm.process);
            let (msg, hint) = match owner {
                Some(o) => (
                    format!("axis {c} is common with process {o} and is described only there"),
                    format!("remove this NAS={c} subsection; describe {c} in process {o}"),
                ),
                None => (
                    format!(
                        "axis {c} is not declared in section 1 of process {}",
                        process.number
                    ),
                    "list the axis in the CAS of this process, or fix the name".to_string(),
                ),
            };
            self.diags
                .push(ctx.error(codes::NAS_UNDECLARED, r.params[0].span.clone(), msg, hint));
        }
        if process.axes.iter().any(|a| a.name == c) {
            self.diags.push(ctx.error(
                codes::NAS_ORDER,
                r.params[0].span.clone(),
                format!("axis {c} has a second NAS subsection"),
                "describe each axis once",
            ));
        }
        let axis = Axis {
            name: c,
            span: r.span.clone(),
            order: vec![("NAS".to_string(), r.span.clone())],
            ..Axis::default()
        };
        self.model.processes[i].axes.push(axis);
    }

    fn instruction(&mut self, r: &Record) {
        let ctx = self.ctx();
        let axis = self
            .process
            .and_then(|i| self.model.processes[i].axes.last_mut());
        let Some(axis) = axis else {
            self.diags.push(ctx.error(
                codes::NO_NAS,
                r.key_span.clone(),
                format!("{} without a preceding NAS", r.key),
                "open the axis subsection with `NAS=<axis>` first",
            ));
            return;
        };
        let key = canonical(&r.key);
        if axis.order.iter().any(|(k, _)| *k == key) {
            self.diags.push(ctx.error(
                codes::DUPLICATE_INSTRUCTION,
                r.key_span.clone(),
                format!("{key} is repeated in the subsection of axis {}", axis.name),
                format!("keep one {key} for axis {}", axis.name),
            ));
            return;
        }
        let mut p = Parse {
            ctx,
            ecdf: self.ecdf,
            diags: self.diags,
        };
        if p.instruction(r, axis) {
            axis.order.push((key, r.span.clone()));
        }
    }
}

/// The key used for duplicate detection (`GM01` and `GM1` are the same range).
fn canonical(key: &str) -> String {
    match key.strip_prefix("GM").and_then(|n| n.parse::<u32>().ok()) {
        Some(n) => format!("GM{n}"),
        None => key.to_string(),
    }
}

/// Known but misspelled keys of the manual's OCR, with the intended instruction.
fn alias(key: &str) -> Option<&'static str> {
    Some(match key {
        "TRA" => "TPA",
        "ZN0" => "ZNO",
        "FOOP" => "FOPP",
        "NMO" => "NM0",
        _ => return None,
    })
}

impl Parse<'_, '_> {
    fn ok<T>(&mut self, r: Result<T, Diagnostic>) -> Option<T> {
        r.map_err(|d| self.diags.push(d)).ok()
    }

    fn err(
        &mut self,
        code: u32,
        span: std::ops::Range<usize>,
        msg: impl Into<String>,
        hint: impl Into<String>,
    ) {
        let d = self.ctx.error(code, span, msg, hint);
        self.diags.push(d);
    }

    fn real(&mut self, p: Option<&Param>) -> Option<f64> {
        let ctx = self.ctx;
        p.and_then(|p| self.ok(values::real(&ctx, p)).flatten())
    }

    fn int(&mut self, p: Option<&Param>) -> Option<i32> {
        let ctx = self.ctx;
        p.and_then(|p| self.ok(values::integer(&ctx, p)).flatten())
    }

    fn word(&mut self, p: Option<&Param>) -> Option<u32> {
        let ctx = self.ctx;
        p.and_then(|p| self.ok(values::word(&ctx, p)).flatten())
    }

    fn signal(&mut self, p: Option<&Param>) -> Option<Signal> {
        let ctx = self.ctx;
        p.and_then(|p| self.ok(values::plc_variable(&ctx, p)).flatten())
    }

    fn text(&mut self, p: Option<&Param>) -> Option<String> {
        let ctx = self.ctx;
        p.and_then(|p| self.ok(values::ascii(&ctx, p)).flatten())
    }

    fn reals<const N: usize>(&mut self, r: &Record) -> [Option<f64>; N] {
        std::array::from_fn(|i| self.real(r.param(i)))
    }

    /// Parameter count, with the ECDF long form allowed only when NBP enables ECDF.
    fn arity(&mut self, r: &Record, base: usize, ecdf_max: usize) -> bool {
        let max = if self.ecdf { ecdf_max } else { base };
        if !self.ecdf && r.params.len() > base && r.params.len() <= ecdf_max {
            let span = r.params[base].span.start.saturating_sub(1)..r.span.end;
            self.err(
                codes::ECDF_FORM,
                span,
                format!(
                    "the {}-parameter form of {} needs ECDF in NBP",
                    r.params.len(),
                    r.key
                ),
                format!("write {base} parameters, or enable ECDF with `NBP=n,ECDF`"),
            );
            return false;
        }
        let ctx = self.ctx;
        self.ok(ctx.arity(r, base, max)).is_some()
    }

    fn fixed(&mut self, r: &Record, n: usize) -> bool {
        let ctx = self.ctx;
        self.ok(ctx.arity(r, n, n)).is_some()
    }

    fn ecdf_only(&mut self, r: &Record) -> bool {
        if !self.ecdf {
            self.err(
                codes::NOT_ALLOWED,
                r.key_span.clone(),
                format!(
                    "{} is an ECDF instruction but NBP does not enable ECDF",
                    r.key
                ),
                "enable ECDF with `NBP=n,ECDF` or remove the instruction",
            );
        }
        self.ecdf
    }

    /// Parses one instruction into `axis`; false when it was rejected (not recorded).
    fn instruction(&mut self, r: &Record, axis: &mut Axis) -> bool {
        let key = r.key.as_str();
        match key {
            "TPA" => return self.tpa(r, axis),
            "NTC" => return self.ntc(r, axis),
            "RAP" | "MAN" | "POS" | "LOP" | "TSM" => {
                if !self.fixed(r, 2) {
                    return false;
                }
                let [a, b] = self.reals::<2>(r);
                let pair = Some(Pair { a, b });
                match key {
                    "RAP" => axis.rap = pair,
                    "MAN" => axis.man = pair,
                    "POS" => axis.pos = pair,
                    "LOP" => axis.lop = pair,
                    _ => {
                        if a.unwrap_or(0.0) == 0.0 || b.unwrap_or(0.0) == 0.0 {
                            self.err(
                                codes::TSM_PARAMS,
                                r.span.clone(),
                                "a TSM parameter is omitted or 0",
                                "write the reversal time (s) and voltage (V), e.g. `TSM=4,18`",
                            );
                        }
                        axis.tsm = pair;
                    }
                }
            }
            "GAS" => {
                if !self.arity(r, 2, 4) {
                    return false;
                }
                let [backlash, dead_zone] = self.reals::<2>(r);
                let read = self.signal(r.param(2));
                let cor = self.signal(r.param(3));
                if read.is_some() && read == cor {
                    self.err(
                        codes::SIGNAL_TWICE,
                        r.span.clone(),
                        "zero_drift_read and zero_drift_cor are the same signal",
                        "use two different free signals",
                    );
                }
                axis.gas = Some(Gas {
                    backlash,
                    dead_zone,
                    zero_drift_read: read,
                    zero_drift_cor: cor,
                });
            }
            "VGAS" => {
                if !self.fixed(r, 3) {
                    return false;
                }
                let v = self.real(r.param(0));
                axis.vgas = Some((v, self.signal(r.param(1)), self.signal(r.param(2))));
            }
            "PAS" => return self.pas(r, axis),
            "SKW" => {
                if !self.fixed(r, 4) {
                    return false;
                }
                let master = self.text(r.param(0)).unwrap_or_default();
                let skew = self.real(r.param(1));
                let kds = self.real(r.param(2));
                let sgan = self.real(r.param(3));
                axis.skw = Some(Skw {
                    master,
                    skew,
                    kds,
                    sgan,
                });
            }
            "MCZ" => return self.mcz(r, axis),
            "SRV" => {
                if !self.fixed(r, 3) {
                    return false;
                }
                axis.srv = Some(self.reals::<3>(r));
            }
            "MSS" | "AFC" | "FQF" => {
                if !self.fixed(r, 1) {
                    return false;
                }
                let v = self.real(r.param(0));
                match key {
                    "MSS" => axis.mss = v,
                    "AFC" => axis.afc = v,
                    _ => axis.fqf = v,
                }
            }
            k if k.starts_with("GM")
                && k[2..].bytes().all(|b| b.is_ascii_digit())
                && k.len() > 2 =>
            {
                return self.gm(r, axis);
            }
            "FRC" => {
                if !self.ecdf_only(r) || !self.fixed(r, 9) {
                    return false;
                }
                let t_ffa = self.word(r.param(0));
                let values = std::array::from_fn(|i| self.real(r.param(i + 1)));
                let kvff = self.real(r.param(6)).unwrap_or(1.0);
                let kvffi = self.real(r.param(7)).unwrap_or(0.0);
                axis.frc = Some(Frc {
                    t_ffa,
                    values,
                    kvff,
                    kvffi,
                    input_ffa: self.signal(r.param(8)),
                });
            }
            "LO1" | "LO2" | "CUB" => {
                if !self.ecdf_only(r) || !self.fixed(r, 3) {
                    return false;
                }
                let [pos, neg, space] = self.reals::<3>(r);
                let number = key[2..].parse().unwrap_or(0);
                let zone = Zone {
                    number,
                    pos,
                    neg,
                    space,
                };
                if key == "CUB" {
                    axis.cub = Some(zone);
                } else {
                    axis.lo.push(zone);
                }
            }
            k if k.starts_with("SW") && k.len() == 3 && matches!(k.as_bytes()[2], b'1'..=b'8') => {
                if !self.ecdf_only(r) || !self.fixed(r, 3) {
                    return false;
                }
                let [pos, neg] = self.reals::<2>(r);
                let signal = self.signal(r.param(2));
                if signal.is_some_and(|s| s.packet() == Packet::A) {
                    self.err(
                        codes::SW_PACKET_A,
                        r.params[2].span.clone(),
                        format!("{k} uses a packet-A signal"),
                        "use a free signal of packet K (or N), e.g. U220K16",
                    );
                }
                axis.cams.push(Cam {
                    number: u32::from(k.as_bytes()[2] - b'0'),
                    pos,
                    neg,
                    signal,
                });
            }
            "MFC" => {
                if !self.fixed(r, 2) {
                    return false;
                }
                axis.mfc = Some((self.signal(r.param(0)), self.signal(r.param(1))));
            }
            "ASM" => {
                if !self.fixed(r, 1) {
                    return false;
                }
                let ctx = self.ctx;
                let m = match values::ascii(&ctx, &r.params[0]) {
                    Ok(m) => m.unwrap_or_default(),
                    Err(d) => {
                        self.diags.push(d);
                        return false;
                    }
                };
                if m.len() != 1 {
                    self.err(
                        codes::ASM_NAME,
                        r.params[0].span.start..r.span.end,
                        format!("ASM master `{m}` is not one letter"),
                        "write the master axis name, one letter, e.g. `ASM=X`",
                    );
                    return false;
                }
                axis.asm = Some(m);
            }
            "POM" => {
                if !self.arity(r, 2, 4) {
                    return false;
                }
                let [spiaz, limit_speed, max_deviation] = self.reals::<3>(r);
                if max_deviation.is_some_and(|d| !(0.0..=1.0).contains(&d)) {
                    self.err(
                        codes::RANGE,
                        r.params[2].span.clone(),
                        "POM max_deviation_speed is outside 0…1",
                        "the allowed relative speed deviation is 0 to 1, e.g. 0.2",
                    );
                }
                axis.pom = Some(Pom {
                    spiaz,
                    limit_speed,
                    max_deviation,
                    input_speed: self.signal(r.param(3)),
                });
            }
            "ADP" => {
                if !self.fixed(r, 4) {
                    return false;
                }
                let channel = self.int(r.param(0));
                self.adc_channel(r, channel);
                let p100 = self.real(r.param(1));
                let level1 = self.real(r.param(2));
                let level2 = self.real(r.param(3));
                if p100.unwrap_or(0.0) == 0.0 {
                    self.err(
                        codes::ADP_ZERO,
                        r.params[1].span.clone(),
                        "ADP's P_100 is zero",
                        "write the voltage at 100 % spindle load, -10 to 10 V",
                    );
                } else if let (Some(p), Some(l1), Some(l2)) = (p100, level1, level2)
                    && (p.abs() > 10.0 || l1 < 0.0 || l1 > l2.abs() || l2 > p.abs())
                {
                    self.err(
                        codes::RANGE,
                        r.span.clone(),
                        "ADP levels are out of order",
                        "need -10 ≤ P_100 ≤ 10 and 0 ≤ P_level_1 ≤ P_level_2 ≤ |P_100|",
                    );
                }
                axis.adp = Some(Adp {
                    channel,
                    p100,
                    level1,
                    level2,
                });
            }
            "ZNO" => {
                if !self.fixed(r, 5) {
                    return false;
                }
                let [null_offset, _, distance] = self.reals::<3>(r);
                let input_distance = self.signal(r.param(3));
                if distance.is_some_and(|d| d != 0.0) && r.params[3].is_empty() {
                    self.err(
                        codes::ZNO_SIGNAL,
                        r.params[2].span.clone(),
                        "ZNO sets a travel distance but no input_distance signal",
                        "put a free signal of packet K or N in parameter 4, or delete parameter 3",
                    );
                }
                axis.zno = Some(Zno {
                    null_offset,
                    distance,
                    input_distance,
                    dbrp: self.real(r.param(4)),
                });
            }
            "FBF" => {
                if !self.fixed(r, 4) {
                    return false;
                }
                let [space, time] = self.reals::<2>(r);
                let input_break_wire = self.signal(r.param(2));
                let ctx = self.ctx;
                let status_break_wire = r
                    .param(3)
                    .and_then(|p| self.ok(values::boolean(&ctx, p)).flatten());
                axis.fbf = Some(Fbf {
                    space,
                    time,
                    input_break_wire,
                    status_break_wire,
                });
            }
            "HWC" => {
                let ctx = self.ctx;
                if r.params.len() == 3 {
                    self.err(
                        codes::TOO_FEW_PARAMS,
                        r.end_span(),
                        "HWC has 3 parameters, 2 or 4 expected",
                        "write `HWC=axis,enable` or `HWC=axis,enable,reset,mode`",
                    );
                    return false;
                }
                if self.ok(ctx.arity(r, 2, 4)).is_none() {
                    return false;
                }
                let name = self.text(r.param(0)).unwrap_or_default();
                axis.hwc = Some(Hwc {
                    axis: name,
                    enable: self.signal(r.param(1)),
                    reset: self.signal(r.param(2)),
                    mode: self.signal(r.param(3)),
                });
            }
            "ATR" => {
                if !self.fixed(r, 2) {
                    return false;
                }
                let st = self.word(r.param(0));
                let mt = self.word(r.param(1));
                if st.is_some_and(|s| !(12..=31).contains(&s)) {
                    self.err(
                        codes::RANGE,
                        r.params[0].span.clone(),
                        "ATR resolution ST is outside 12…31 bits",
                        "single-turn or linear sensors: 12 to 31 bits; multi-turn: 12 to 19",
                    );
                } else if mt.is_some_and(|m| m > 12) {
                    self.err(
                        codes::RANGE,
                        r.params[1].span.clone(),
                        "ATR resolution MT is above 12 bits",
                        "MT is 0 for single-turn or linear sensors, at most 12 otherwise",
                    );
                } else if mt.is_some_and(|m| m > 0) && st.is_some_and(|s| s > 19) {
                    self.err(
                        codes::RANGE,
                        r.params[0].span.clone(),
                        "a multi-turn SSI sensor has at most 19 single-turn bits",
                        "with MT > 0, ST is 12 to 19",
                    );
                }
                axis.atr = Some((st, mt));
            }
            "GRA" => {
                if !self.fixed(r, 2) {
                    return false;
                }
                let input = self.signal(r.param(0));
                if let Some(s) = input
                    && (s.packet() != Packet::A || s.bit() != Some(0))
                {
                    self.err(codes::GRA_SIGNAL, r.params[0].span.clone(), format!("GRA input {s} is not the lowest bit of a packet-A byte"), "wire the sensor's LSB to contact 0, 8, 16 or 24 of a packet-A connector, e.g. I0A8");
                }
                let bits = self.word(r.param(1));
                if bits.is_some_and(|n| n > 16) {
                    self.err(
                        codes::GRA_BITS,
                        r.params[1].span.clone(),
                        "GRA resolution is above 16 bits",
                        "a Gray-code sensor on discrete inputs has at most 16 bits",
                    );
                }
                axis.gra = Some(Gra { input, bits });
            }
            "FOPP" => {
                if !self.fixed(r, 1) {
                    return false;
                }
                let s = self.signal(r.param(0));
                if let Some(sig) = s
                    && (sig.packet() == Packet::A || sig.bit() != Some(0))
                {
                    self.err(
                        codes::FOPP_SIGNAL,
                        r.params[0].span.clone(),
                        format!("FOPP input {sig} is not the lowest bit of a packet K or N word"),
                        "name the lowest bit of the PLC word, e.g. I222K16 for W222K2",
                    );
                }
                axis.fopp = s;
            }
            "FTP" => {
                if !self.fixed(r, 1) {
                    return false;
                }
                axis.ftp = file_ref(&self.ctx, &r.params[0])
                    .map_err(|d| self.diags.push(d))
                    .ok();
            }
            "ADG" => {
                if !self.fixed(r, 7) {
                    return false;
                }
                let channel = self.int(r.param(0));
                self.adc_channel(r, channel);
                let u_near = self.real(r.param(1));
                let u_far = self.real(r.param(2));
                for (i, u) in [(1, u_near), (2, u_far)] {
                    if u.is_some_and(|u| !(0.0..=10.0).contains(&u)) {
                        self.err(
                            codes::RANGE,
                            r.params[i].span.clone(),
                            "ADG voltage outside 0…10 V",
                            "U_near and U_far are 0 to +10 V",
                        );
                    }
                }
                if r.params[3..7].iter().any(Param::is_empty) {
                    self.err(
                        codes::ADG_SIGNALS,
                        r.params[3].span.start..r.span.end,
                        "ADG leaves a PLC signal of parameters 4–7 empty",
                        "name all four signals: remember, set mode, status, indication",
                    );
                }
                let signals = std::array::from_fn(|i| self.signal(r.param(i + 3)));
                axis.adg = Some(Adg {
                    channel,
                    u_near,
                    u_far,
                    signals,
                });
            }
            "LAS" => {
                if !self.fixed(r, 13) {
                    return false;
                }
                let pv = self.int(r.param(0));
                let power = [
                    self.real(r.param(1)),
                    self.real(r.param(2)),
                    self.real(r.param(3)),
                    self.real(r.param(4)),
                ];
                let set_p_control = self.signal(r.param(5));
                let generator = (
                    self.int(r.param(6)),
                    self.int(r.param(7)),
                    self.real(r.param(8)),
                    self.int(r.param(9)),
                    self.real(r.param(10)),
                );
                let set_g_control = self.signal(r.param(11));
                axis.las = Some(Las {
                    power: (pv, power),
                    set_p_control,
                    generator,
                    set_g_control,
                    override_percent: self.real(r.param(12)),
                });
            }
            k => {
                let hint = match alias(k) {
                    Some(right) => format!("`{k}` is a misspelling of `{right}` (OCR of the manual); write `{right}`"),
                    None => "section 2 allows TPA NTC RAP GAS VGAS PAS SKW MCZ POS SRV MAN MSS GMxx FRC LOP LOx MFC AFC CUB SWx TSM ASM POM ADP ZNO FBF HWC ATR GRA FOPP FTP ADG LAS FQF".to_string(),
                };
                self.err(
                    codes::NOT_ALLOWED,
                    r.key_span.clone(),
                    format!("instruction {k} is not allowed in AXCFIL section 2"),
                    hint,
                );
                return false;
            }
        }
        true
    }

    fn adc_channel(&mut self, r: &Record, channel: Option<i32>) {
        if channel.is_some_and(|c| !(1..=8).contains(&c)) {
            self.err(
                codes::ADC_NUMBER,
                r.params[0].span.clone(),
                format!("ADC channel {} is not admissible", channel.unwrap_or(0)),
                "ADC channels are 1 to 8",
            );
        }
    }

    fn tpa(&mut self, r: &Record, axis: &mut Axis) -> bool {
        let ctx = self.ctx;
        if r.params.len() == 3 {
            self.err(
                codes::TOO_FEW_PARAMS,
                r.end_span(),
                "TPA has 3 parameters, 2 or 4 expected",
                "write `TPA=type,` or, with Р-ПД, `TPA=type,switch,memory,recovery`",
            );
            return false;
        }
        if self.ok(ctx.arity(r, 2, 4)).is_none() {
            return false;
        }
        let Some(raw) = self.ok(values::hex(&ctx, &r.params[0], 8)).flatten() else {
            if r.params[0].is_empty() {
                self.err(
                    codes::TOO_FEW_PARAMS,
                    r.params[0].span.clone(),
                    "TPA has no axis type",
                    "write the sum of the Table 4.1 codes, e.g. `TPA=41,`",
                );
            }
            return false;
        };
        let switch_axis = self.text(r.param(1));
        let memory_signal = self.signal(r.param(2));
        let signal_recovery = self.signal(r.param(3));
        if memory_signal.is_some() && memory_signal == signal_recovery {
            self.err(
                codes::SIGNAL_TWICE,
                r.span.clone(),
                "memory_signal and signal_recovery are the same signal",
                "each axis needs two individual signals",
            );
        }
        if raw & !AxisType::DEFINED != 0 {
            self.err(
                codes::TPA_BITS,
                r.params[0].span.clone(),
                format!(
                    "axis type {raw:X} has undefined bits {:X}",
                    raw & !AxisType::DEFINED
                ),
                "use only the codes of Table 4.1 (20000 is not used)",
            );
        }
        axis.tpa = Some(Tpa {
            axis_type: AxisType::decode(raw),
            switch_axis,
            memory_signal,
            signal_recovery,
            span: r.span.clone(),
        });
        true
    }

    fn ntc(&mut self, r: &Record, axis: &mut Axis) -> bool {
        if !self.fixed(r, 2) {
            return false;
        }
        let trans = self.int(r.param(0));
        let conv = self.int(r.param(1));
        if let Some(t) = trans
            && !(0..=16).contains(&t)
        {
            self.err(
                codes::TRANSDUCER_NUMBER,
                r.params[0].span.clone(),
                format!("transducer number {t}"),
                "the transducer (encoder) number is 1 to 16, 0 or empty for none",
            );
        }
        if let Some(c) = conv {
            let ok =
                (0..=16).contains(&c) || (-216..=-201).contains(&c) || (-116..=-101).contains(&c);
            if c > 200 {
                self.err(
                    codes::CONVERTER_ABOVE_200,
                    r.params[1].span.clone(),
                    format!("DAC/DPC number {c} is above 200"),
                    "a 16-bit channel n is written -(200+n), e.g. -201",
                );
            } else if !ok {
                self.err(codes::CONVERTER_NUMBER, r.params[1].span.clone(), format!("converter number {c}"), "the converter (DAC/DPC) number is 1 to 16, -201 to -216 for 16-bit, -101 to -116 for a 12-bit DAC");
            }
        }
        axis.ntc = Some(Ntc { trans, conv });
        true
    }

    fn pas(&mut self, r: &Record, axis: &mut Axis) -> bool {
        if !self.arity(r, 2, 4) {
            return false;
        }
        let [el, mec, rev, start] = self.reals::<4>(r);
        let el = el.unwrap_or(0.0);
        let mec = mec.unwrap_or(0.0);
        if el == 0.0 {
            self.err(
                codes::EL_PITCH_ZERO,
                r.params[0].span.clone(),
                "the electrical pitch is zero",
                "write the sensor counts per mechanical pitch (pulses × 4), e.g. 5000",
            );
        } else if el < 0.0 {
            self.err(
                codes::RANGE,
                r.params[0].span.clone(),
                "the electrical pitch is negative",
                "el_pitch is positive; put the sign on mec_pitch",
            );
        }
        if mec == 0.0 {
            self.err(
                codes::MEC_PITCH_ZERO,
                r.params[1].span.clone(),
                "the mechanical pitch is zero",
                "write the distance per el_pitch counts, e.g. 10 (sign = count direction)",
            );
        }
        axis.pas = Some(Pas {
            el_pitch: el,
            mec_pitch: mec,
            rev_num_motor: rev,
            start_point: start,
        });
        true
    }

    fn mcz(&mut self, r: &Record, axis: &mut Axis) -> bool {
        let ctx = self.ctx;
        if r.params.len() == 4 {
            self.err(
                codes::TOO_FEW_PARAMS,
                r.end_span(),
                "MCZ has 4 parameters, 3 or 5 expected",
                "write `MCZ=input,direction,speed` or, for KKRM, `MCZ=,direction,speed,HDBRP,Δs`",
            );
            return false;
        }
        if self.ok(ctx.arity(r, 3, 5)).is_none() {
            return false;
        }
        let zero_input = self.signal(r.param(0));
        let negative = match values::boolean(&ctx, &r.params[1]) {
            Ok(v) => v.unwrap_or(false),
            Err(_) => {
                self.err(
                    codes::MCZ_DIRECTION,
                    r.params[1].span.clone(),
                    format!("homing direction `{}` is not 0 or 1", r.params[1].text),
                    "0 = search in the positive direction, 1 = negative",
                );
                false
            }
        };
        let speed = self.real(r.param(2));
        let hdbrp = self.real(r.param(3));
        let delta_s = self.real(r.param(4));
        axis.mcz = Some(Mcz {
            zero_input,
            negative,
            speed,
            hdbrp,
            delta_s,
        });
        true
    }

    fn gm(&mut self, r: &Record, axis: &mut Axis) -> bool {
        let range: u32 = r.key[2..].parse().unwrap_or(u32::MAX);
        if range > 99 {
            self.err(
                codes::GM_RANGE,
                r.key_span.clone(),
                format!("{}: range number above 99", r.key),
                "GMxx: xx is 0 for an axis, 1 to 99 for a spindle range",
            );
            return false;
        }
        if !self.arity(r, 3, 5) {
            return false;
        }
        let [vmax, kc, kv, limit_speed] = self.reals::<4>(r);
        if kc.is_some_and(|k| k > 10.0) {
            self.err(
                codes::KC_ABOVE_10,
                r.params[1].span.clone(),
                format!("KC {} V is above 10 V", kc.unwrap_or(0.0)),
                "the reference voltage at Vmax is at most 10 V (recommended 7.5 axis, 8.5 spindle)",
            );
        }
        let input_speed_limit = self.signal(r.param(4));
        axis.gm.push(Gm {
            range,
            vmax,
            kc,
            kv,
            limit_speed,
            input_speed_limit,
        });
        true
    }
}

/// Parses a `FILE/MPx` reference (FTP, FEG); error 944 otherwise.
pub fn file_ref(ctx: &Ctx, p: &Param) -> Result<FileRef, Diagnostic> {
    let parsed = p.text.split_once('/').and_then(|(f, mp)| {
        let x = mp
            .trim()
            .strip_prefix("MP")
            .or_else(|| mp.trim().strip_prefix("mp"))?
            .parse::<u8>()
            .ok()
            .filter(|&x| x <= 6)?;
        let f = f.trim();
        let ok = !f.is_empty() && f.len() <= 8 && f.bytes().all(|b| b.is_ascii_alphanumeric());
        ok.then(|| FileRef {
            file: f.to_ascii_uppercase(),
            mp: x,
        })
    });
    parsed.ok_or_else(|| ctx.error(codes::FILE_REF, p.span.clone(), format!("`{}` is not a file reference", p.text), "write `FILE/MPx` with a file name of letters and digits and x = 0…6, e.g. `TABTT1/MP0`"))
}
