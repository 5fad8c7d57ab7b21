//! AXCFIL section 2, the instructions with several forms or coded numbers: TPA (base and Р-ПД),
//! NTC (transducer and converter numbering), PAS (base and ECDF), MCZ (base and KKRM), GMxx
//! (base and ECDF), the ADC channel of ADP/ADG, and the `file/MPx` references of FTP and FEG.

use diag::Diagnostic;

use super::super::model::{Axis, AxisType, FileRef, Gm, Mcz, Ntc, Pas, Tpa};
use super::Parse;
use crate::codes;
use crate::reader::{Param, Record};
use crate::values::{self, Ctx};

impl Parse<'_, '_> {
    pub(super) fn adc_channel(&mut self, r: &Record, channel: Option<i32>) {
        if channel.is_some_and(|c| !(1..=8).contains(&c)) {
            self.err(
                codes::ADC_NUMBER,
                r.params[0].span.clone(),
                format!("ADC channel {} is not admissible", channel.unwrap_or(0)),
                "ADC channels are 1 to 8",
            );
        }
    }

    pub(super) fn tpa(&mut self, r: &Record, axis: &mut Axis) -> bool {
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

    pub(super) fn ntc(&mut self, r: &Record, axis: &mut Axis) -> bool {
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

    pub(super) fn pas(&mut self, r: &Record, axis: &mut Axis) -> bool {
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

    pub(super) fn mcz(&mut self, r: &Record, axis: &mut Axis) -> bool {
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

    pub(super) fn gm(&mut self, r: &Record, axis: &mut Axis) -> bool {
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
