//! AXCFIL section 1: NBP, TIM, PRO, COM, INx, CAS, ACC (and CANn), record by record.
//!
//! Only what one record can tell is checked here; rules that relate several records (ticks,
//! interpolator membership, CAS order) are in [`super::rules`].

use diag::{Diagnostic, Sink};

use super::model::{Acc, Axcfil, Cas, Common, Extension, Interpolator, Process};
use crate::codes;
use crate::reader::{Record, Section};
use crate::values::{self, Ctx};

/// The valid NBP extensions: sums of 0, 1, 2 and ECDF.
const ECDF: u32 = 0xECDF;

/// Decodes NBP's SW_extension, `None` when it is not a valid sum.
pub fn decode_extension(raw: u32) -> Option<Extension> {
    let (ecdf, rest) = if raw >= ECDF {
        (true, raw - ECDF)
    } else {
        (false, raw)
    };
    (rest <= 3).then_some(Extension {
        raw,
        ecdf,
        page7_layout2: rest & 1 != 0,
        adc_module: rest & 2 != 0,
    })
}

/// Reads section 1 into `model`; appends problems to `diags`.
pub fn read(ctx: Ctx, section: &Section, model: &mut Axcfil, diags: &mut Sink) {
    let mut s = State {
        ctx,
        model,
        diags,
        current: None,
        tim_seen: false,
        nbp_seen: false,
        acc_seen: false,
        bad_nbp: None,
    };
    for r in &section.records {
        s.record(r);
    }
    if let Some((n, span)) = s.bad_nbp.take() {
        s.settle_bad_nbp(n, span);
    }
    if !s.tim_seen {
        let d = ctx.error(
            codes::TIM_MISSING,
            section.span.clone(),
            "section 1 has no TIM instruction",
            "declare the CPU tick, e.g. `TIM=1,0,0,0,0`",
        );
        s.diags.push(d);
    }
}

struct State<'a, 'm> {
    ctx: Ctx<'a>,
    model: &'m mut Axcfil,
    diags: &'m mut Sink,
    current: Option<usize>,
    tim_seen: bool,
    nbp_seen: bool,
    acc_seen: bool,
    /// An NBP of 0 or above 5 and its span: reported once section 1 is read, with the processes
    /// the file does open as the likely intent.
    bad_nbp: Option<(u32, std::ops::Range<usize>)>,
}

impl<'a> State<'a, '_> {
    fn ok<T>(&mut self, r: Result<T, Diagnostic>) -> Option<T> {
        r.map_err(|d| self.diags.push(d)).ok()
    }

    fn ctx(&self) -> Ctx<'a> {
        let p = self
            .current
            .and_then(|i| self.model.processes.get(i))
            .map(|p| p.number);
        self.ctx.in_process(p)
    }

    fn push(
        &mut self,
        code: u32,
        span: std::ops::Range<usize>,
        msg: impl Into<String>,
        hint: impl Into<String>,
    ) {
        let d = self.ctx().error(code, span, msg, hint);
        self.diags.push(d);
    }

    fn once(&mut self, r: &Record, seen: bool) -> bool {
        if seen {
            self.push(
                codes::SECTION1_TWICE,
                r.key_span.clone(),
                format!("{} is written twice in section 1", r.key),
                format!("keep one {}", r.key),
            );
        }
        !seen
    }

    fn record(&mut self, r: &Record) {
        match r.key.as_str() {
            "NBP" => self.nbp(r),
            "TIM" => self.tim(r),
            "PRO" => self.pro(r),
            "COM" => self.com(r),
            "CAS" => self.cas(r),
            "ACC" => self.acc(r),
            k if k.len() == 3 && k.starts_with("IN") => self.interpolator(r),
            k if k.starts_with("CAN") => {
                if !matches!(&k[3..], "1" | "2" | "3" | "4") {
                    self.push(
                        codes::CAN_NUMBER,
                        r.key_span.clone(),
                        format!("`{k}`: the CAN interface number must be 1, 2, 3 or 4"),
                        "write CAN1, CAN2, CAN3 or CAN4",
                    );
                }
            }
            k => {
                let allowed = "section 1 allows NBP, TIM, PRO, COM, INx, CAS and ACC";
                let hint = values::suggest_key(k, allowed, allowed);
                self.push(
                    codes::NOT_ALLOWED,
                    r.key_span.clone(),
                    format!("instruction {k} is not allowed in AXCFIL section 1"),
                    hint,
                );
            }
        }
    }

    fn nbp(&mut self, r: &Record) {
        if !self.once(r, self.nbp_seen) {
            return;
        }
        self.nbp_seen = true;
        let ctx = self.ctx();
        if self.ok(ctx.arity(r, 2, 2)).is_none() {
            return;
        }
        let n = self
            .ok(values::word(&ctx, &r.params[0]))
            .flatten()
            .unwrap_or(0);
        if n == 0 || n > 5 {
            // Accept every PRO for now; the number is settled from them at the end of the section,
            // so that the processes the file does have bring no follow-on errors (issue 12).
            self.bad_nbp = Some((n, r.params[0].span.clone()));
            self.model.nbp = 5;
        } else {
            self.model.nbp = n;
        }
        if let Some(raw) = self.ok(values::hex(&ctx, &r.params[1], 4)).flatten() {
            match decode_extension(raw) {
                Some(ext) => self.model.extension = ext,
                None => self.push(
                    codes::NBP_EXTENSION,
                    r.params[1].span.clone(),
                    format!("NBP extension {raw:X} is not a sum of 0, 1, 2 and ECDF"),
                    "write 0, 1, 2, 3, ECDF, ECE0, ECE1 or ECE2",
                ),
            }
        }
    }

    /// Reports NBP=0 (182) or NBP above 5 (183) and takes the highest process the file opens with
    /// PRO as the number of processes, so that later checks follow the file, not the bad number.
    fn settle_bad_nbp(&mut self, n: u32, span: std::ops::Range<usize>) {
        self.current = None;
        let opened = self.model.processes.iter().map(|p| p.number).max();
        self.model.nbp = opened.unwrap_or(1).clamp(1, 5);
        let intent = match opened {
            Some(p) => format!("; section 1 opens processes up to PRO={p}: write NBP={p}"),
            None => String::new(),
        };
        if n == 0 {
            self.push(
                codes::NBP_ZERO,
                span,
                "NBP declares no process",
                format!("the number of processes is 1 to 5{intent}"),
            );
        } else {
            self.push(
                codes::NBP_TOO_MANY,
                span,
                format!("NBP declares {n} processes"),
                format!("at most 5 processes are allowed{intent}"),
            );
        }
    }

    fn tim(&mut self, r: &Record) {
        if !self.once(r, self.tim_seen) {
            return;
        }
        self.tim_seen = true;
        let ctx = self.ctx();
        if self.ok(ctx.arity(r, 1, 5)).is_none() {
            return;
        }
        let Some(tick) = self.ok(values::word(&ctx, &r.params[0])) else {
            return;
        };
        let tick = tick.unwrap_or(0);
        if tick > 63 {
            self.push(
                codes::TIM_TOO_BIG,
                r.params[0].span.clone(),
                format!("CPU tick {tick} ms is too large"),
                "TIM's CPU tick is 1 to 63 ms (NC-110: 1 or 2)",
            );
        } else if tick == 0 {
            let span = if r.params[0].is_empty() {
                r.key_span.clone()
            } else {
                r.params[0].span.clone()
            };
            self.push(
                codes::TIM_ZERO,
                span,
                "CPU tick is 0: the CPU can host neither drive control nor interpolators",
                "write the CPU tick in ms, 1 to 63, e.g. `TIM=1,0,0,0,0`",
            );
        }
        self.model.tim = if tick > 63 { 0 } else { tick };
    }

    fn pro(&mut self, r: &Record) {
        let ctx = self.ctx();
        let Some(n) = super::pro_number(&ctx, r, self.model.nbp, self.diags) else {
            return;
        };
        if let Some(i) = self.model.processes.iter().position(|p| p.number == n) {
            self.push(
                codes::PROCESS_TWICE,
                r.span.clone(),
                format!("process {n} is declared twice in section 1"),
                "write each process's PRO once per section",
            );
            self.current = Some(i);
            return;
        }
        self.model.processes.push(Process {
            number: n,
            span: r.span.clone(),
            ..Process::default()
        });
        self.current = Some(self.model.processes.len() - 1);
    }

    /// The current process, or an error 920 at `r`.
    fn process(&mut self, r: &Record) -> Option<usize> {
        if self.current.is_none() {
            self.push(
                codes::NO_PROCESS,
                r.key_span.clone(),
                format!("{} before any PRO", r.key),
                "open the process with `PRO=1` first",
            );
        }
        self.current
    }

    fn need_nbp(&mut self, r: &Record) {
        if !self.nbp_seen {
            self.push(
                codes::NO_NBP,
                r.key_span.clone(),
                format!("{} is declared before NBP", r.key),
                "write NBP (and TIM) at the start of section 1",
            );
        }
    }

    fn com(&mut self, r: &Record) {
        let Some(i) = self.process(r) else { return };
        let ctx = self.ctx();
        if self.ok(ctx.arity(r, 2, 2)).is_none() {
            return;
        }
        let current = self.model.processes[i].number;
        let Some(owner) = self.ok(values::word(&ctx, &r.params[0])).flatten() else {
            self.push(
                codes::TOO_FEW_PARAMS,
                r.params[0].span.clone(),
                "COM names no process",
                "write the process that defines the common axes, e.g. `COM=1,S`",
            );
            return;
        };
        let axes: Vec<char> = self
            .ok(values::ascii(&ctx, &r.params[1]))
            .flatten()
            .map(|s| s.chars().collect())
            .unwrap_or_default();
        if current == 1 || owner >= current {
            self.push(
                codes::COM_PROCESS,
                r.span.clone(),
                format!("COM in process {current} refers to process {owner}"),
                "COM is written only after process 1 and names an earlier process",
            );
        } else {
            let defined = self
                .model
                .process(owner)
                .and_then(|p| p.cas.as_ref())
                .map(|c| c.axes.clone())
                .unwrap_or_default();
            for a in axes.iter().filter(|a| !defined.contains(a)) {
                self.push(
                    codes::COM_AXIS,
                    r.params[1].span.clone(),
                    format!("common axis {a} is not declared in the CAS of process {owner}"),
                    format!("COM={owner},… may only name axes of process {owner}"),
                );
            }
        }
        self.model.processes[i].common.push(Common {
            process: owner,
            axes,
            span: r.span.clone(),
        });
    }

    fn interpolator(&mut self, r: &Record) {
        self.need_nbp(r);
        let Some(i) = self.process(r) else { return };
        let ctx = self.ctx();
        if self.ok(ctx.arity(r, 5, 5)).is_none() {
            return;
        }
        let name = r.key[2..].to_string();
        let cpu = self.cpu(&ctx, r, codes::INTERPOLATOR_CPU);
        let axes_text = self
            .ok(values::ascii(&ctx, &r.params[1]))
            .flatten()
            .unwrap_or_default();
        if r.params[1].is_empty() {
            self.push(
                codes::INTERPOLATOR_EMPTY,
                r.key_span.clone(),
                format!("interpolator {name} declares no axis"),
                "list the interpolated axes, e.g. `IN1=1,XZ,S,1,16`",
            );
        } else if axes_text.len() > 8 {
            self.push(
                codes::INTERPOLATOR_AXES,
                r.params[1].span.clone(),
                format!("interpolator {name} declares {} axes", axes_text.len()),
                "an interpolator controls at most 8 axes, virtual axes included",
            );
        }
        let spindle_text = self.ok(values::ascii(&ctx, &r.params[2])).flatten();
        let spindle = match spindle_text.as_deref() {
            Some(s) if s.chars().count() > 1 => {
                self.push(
                    codes::ONE_SPINDLE,
                    r.params[2].span.clone(),
                    format!("interpolator {name} names spindle `{s}`"),
                    "one interpolator controls one spindle: write one letter",
                );
                s.chars().next()
            }
            Some(s) => s.chars().next(),
            None => None,
        };
        let tick_parsed = self.ok(values::word(&ctx, &r.params[3]));
        let tick = tick_parsed.flatten().unwrap_or(0);
        if tick_parsed.is_some() && (tick == 0 || tick > 63) {
            let span = if r.params[3].is_empty() {
                r.end_span()
            } else {
                r.params[3].span.clone()
            };
            self.push(
                codes::INTERPOLATOR_TICK,
                span,
                format!("interpolator tick {tick} ms is zero or too large"),
                "the interpolator tick is 1 to 63 ms, a multiple of the servo tick",
            );
        }
        let blocks_parsed = self.ok(values::word(&ctx, &r.params[4]));
        let blocks = blocks_parsed.flatten().unwrap_or(0);
        if blocks_parsed.is_some() && (blocks == 0 || blocks > 64) {
            let span = if r.params[4].is_empty() {
                r.end_span()
            } else {
                r.params[4].span.clone()
            };
            self.push(
                codes::TOO_MANY_ELEMENTS,
                span,
                format!("interpolator {name} buffers {blocks} blocks"),
                "block_num is 1 to 64 (1 for a point-to-point interpolator)",
            );
        }
        let duplicate = self
            .model
            .processes
            .iter()
            .flat_map(|p| p.interpolators.iter().map(move |ip| (p.number, ip)))
            .find(|(_, ip)| ip.name == name)
            .map(|(n, _)| n);
        if let Some(owner) = duplicate {
            self.push(
                codes::INTERPOLATOR_DUPLICATE,
                r.key_span.clone(),
                format!("interpolator {name} is already declared in process {owner}"),
                "every interpolator has its own name, also across processes",
            );
        } else if self.model.processes[i].interpolators.len() >= 9 {
            self.push(
                codes::INTERPOLATOR_TABLE_FULL,
                r.key_span.clone(),
                "more than 9 interpolators in one process",
                "a process has at most 9 interpolators",
            );
        }
        let ip = Interpolator {
            name,
            cpu,
            axes: axes_text.chars().collect(),
            spindle,
            int_tick: tick,
            block_num: blocks,
            span: r.span.clone(),
        };
        self.model.processes[i].interpolators.push(ip);
    }

    /// cpu_num: empty → 102, not 1 → `code` (103 for CAS, 105 for INx).
    fn cpu(&mut self, ctx: &Ctx, r: &Record, code: u32) -> u32 {
        match self.ok(values::word(ctx, &r.params[0])).flatten() {
            None => {
                self.push(
                    codes::CPU_NOT_ONE,
                    r.key_span.clone(),
                    format!("{} gives no CPU number", r.key),
                    "the axis-control CPU is number 1: write `1` as the first parameter",
                );
                1
            }
            Some(1) => 1,
            Some(n) => {
                self.push(
                    code,
                    r.params[0].span.clone(),
                    format!("CPU number {n} in {}", r.key),
                    "the axis-control CPU is number 1",
                );
                n
            }
        }
    }

    fn cas(&mut self, r: &Record) {
        self.need_nbp(r);
        let Some(i) = self.process(r) else { return };
        let ctx = self.ctx();
        if self.ok(ctx.arity(r, 3, 3)).is_none() {
            return;
        }
        let cpu = self.cpu(&ctx, r, codes::CAS_CPU);
        let text = self
            .ok(values::ascii(&ctx, &r.params[1]))
            .flatten()
            .unwrap_or_default();
        let axes: Vec<char> = text.chars().collect();
        if axes.is_empty() {
            self.push(
                codes::CAS_EMPTY,
                r.key_span.clone(),
                "CAS declares no axis",
                "list the drive-controlled axes, e.g. `CAS=1,XZS,1`",
            );
        }
        for (k, a) in axes.iter().enumerate() {
            if axes[..k].contains(a) {
                let at = r.params[1].span.start + k;
                self.push(
                    codes::CAS_DUPLICATE,
                    at..at + 1,
                    format!("axis {a} appears twice in CAS"),
                    "name every axis once",
                );
            }
        }
        let tick_parsed = self.ok(values::word(&ctx, &r.params[2]));
        let tick = tick_parsed.flatten().unwrap_or(0);
        if tick_parsed.is_some() && (tick == 0 || tick > 63) {
            let span = if r.params[2].is_empty() {
                r.end_span()
            } else {
                r.params[2].span.clone()
            };
            self.push(
                codes::SERVO_TICK,
                span,
                format!("drive-control tick {tick} ms is zero or too large"),
                "the servo tick is 1 to 63 ms, a multiple of the CPU tick",
            );
        }
        if self.model.processes[i].cas.is_some() {
            let n = self.model.processes[i].number;
            self.push(
                codes::CAS_TWICE,
                r.key_span.clone(),
                format!("process {n} has a second CAS"),
                "declare all axes of a process in one CAS",
            );
            return;
        }
        self.model.processes[i].cas = Some(Cas {
            cpu,
            axes,
            servo_tick: tick,
            span: r.span.clone(),
        });
    }

    fn acc(&mut self, r: &Record) {
        if !self.once(r, self.acc_seen) {
            return;
        }
        self.acc_seen = true;
        let ctx = self.ctx();
        if !self.model.extension.ecdf {
            self.push(
                codes::NOT_ALLOWED,
                r.key_span.clone(),
                "ACC is an ECDF instruction but NBP does not enable ECDF",
                "add ECDF to NBP's extension (`NBP=1,ECDF`) or remove ACC",
            );
            return;
        }
        if self.ok(ctx.arity(r, 4, 4)).is_none() {
            return;
        }
        let v: Vec<f64> = r
            .params
            .iter()
            .map(|p| self.ok(values::real(&ctx, p)).flatten().unwrap_or(0.0))
            .collect();
        let bad = v[0] <= 0.0 || !(0.0..=0.5).contains(&v[1]) || v[2] <= 0.0 || v[3] <= 0.0;
        if bad {
            self.push(codes::ACC_COEFFICIENTS, r.span.clone(), "ACC coefficients out of range", "coefficients 1, 3 and 4 must be > 0 and coefficient 2 within 0…0.5, e.g. `ACC=1.5,0.5,1,4`");
            return;
        }
        self.model.acc = Some(Acc {
            linear_part_s: v[0],
            nonlinear_part_s: v[1],
            min_exp: v[2],
            max_exp: v[3],
        });
    }
}
