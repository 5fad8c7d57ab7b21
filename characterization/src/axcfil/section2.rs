//! AXCFIL section 2: `PRO` subsections, `NAS` axis subsections and every per-axis instruction,
//! parsed record by record into [`Axis`] values.
//!
//! Record-local checks happen here (parameter counts and types, ECDF forms, number ranges that
//! need nothing but the record). Rules between instructions of one axis or between axes are in
//! [`super::rules`].

use diag::{Diagnostic, Sink};
use packets::{Packet, Signal};

use super::model::{Axcfil, Axis, Cam, Frc, Gas, Pair, Pom, Skw, Zone};
use crate::codes;
use crate::reader::{Param, Record, Section};
use crate::values::{self, Ctx};

#[path = "section2_forms.rs"]
mod forms;
#[path = "section2_special.rs"]
mod special;
pub use forms::file_ref;

/// Reads section 2 into the processes of `model`.
pub fn read(ctx: Ctx, section: &Section, model: &mut Axcfil, diags: &mut Sink) {
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
    diags: &'m mut Sink,
    process: Option<usize>,
    seen: Vec<u32>,
}

/// Record-local parsing of one instruction into an axis.
struct Parse<'c, 'd> {
    ctx: Ctx<'c>,
    ecdf: bool,
    diags: &'d mut Sink,
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
            "ADP" | "ZNO" | "FBF" | "HWC" | "ATR" | "GRA" | "FOPP" | "FTP" | "ADG" | "LAS" => {
                return self.special(r, axis);
            }
            k => {
                let hint = match alias(k) {
                    Some(right) => format!(
                        "`{k}` is a misspelling of `{right}` (OCR of the manual); write `{right}`"
                    ),
                    None => {
                        let allowed = "section 2 allows TPA NTC RAP GAS VGAS PAS SKW MCZ POS SRV MAN MSS GMxx FRC LOP LOx MFC AFC CUB SWx TSM ASM POM ADP ZNO FBF HWC ATR GRA FOPP FTP ADG LAS FQF";
                        crate::values::suggest_key(k, allowed, allowed)
                    }
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
}
