//! AXCFIL section 2, the instructions of special equipment: ADP (spindle load), ZNO (home
//! offset), FBF (encoder faults), HWC (correction handwheel), ATR (SSI), GRA (Gray code),
//! FOPP (PTP override), FTP (PTP position file), ADG (air gap) and LAS (laser).

use packets::Packet;

use super::super::model::{Adg, Adp, Axis, Fbf, Gra, Hwc, Las, PulseGenerator, Zno};
use super::Parse;
use crate::codes;
use crate::reader::{Param, Record};
use crate::values;

impl Parse<'_, '_> {
    /// Parses one special-equipment instruction into `axis`; false when it was rejected.
    pub(super) fn special(&mut self, r: &Record, axis: &mut Axis) -> bool {
        let key = r.key.as_str();
        match key {
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
                axis.ftp = super::file_ref(&self.ctx, &r.params[0])
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
                let generator = PulseGenerator {
                    channel: self.int(r.param(6)),
                    ticks_high: self.int(r.param(7)),
                    u_high: self.real(r.param(8)),
                    ticks_low: self.int(r.param(9)),
                    u_low: self.real(r.param(10)),
                };
                let set_g_control = self.signal(r.param(11));
                axis.las = Some(Las {
                    power: (pv, power),
                    set_p_control,
                    generator,
                    set_g_control,
                    override_percent: self.real(r.param(12)),
                });
            }
            _ => return false,
        }
        true
    }
}
