//! The rules of one section-2 axis subsection: mandatory instructions, type-dependent presence
//! and absence (Table 4.1 codes), instruction order, slave/master and switched-axis pairs.

use diag::Sink;

use super::model::{Axcfil, Axis, Process};
use crate::codes;
use crate::values::Ctx;

/// Checks axis `index` of process `p`.
pub fn check(ctx: &Ctx, model: &Axcfil, p: &Process, index: usize, axis: &Axis, diags: &mut Sink) {
    let mut err = |code: u32, span: std::ops::Range<usize>, msg: String, hint: &str| {
        diags.push(ctx.error(code, span, msg, hint))
    };
    let name = axis.name;
    let at = |key: &str| axis.span_of(key).unwrap_or(axis.span.clone());
    let Some(tpa) = &axis.tpa else {
        err(
            codes::TPA_MISSING,
            axis.span.clone(),
            format!("axis {name} has no TPA"),
            "declare the axis type after NAS, e.g. `TPA=1,`",
        );
        if axis.ntc.is_none() {
            err(
                codes::NTC_MISSING,
                axis.span.clone(),
                format!("axis {name} has no NTC"),
                "declare encoder and converter numbers, e.g. `NTC=1,1`",
            );
        }
        return;
    };
    let t = tpa.axis_type;
    let spindle = t.spindle();
    let Some(ntc) = axis.ntc else {
        err(
            codes::NTC_MISSING,
            axis.span.clone(),
            format!("axis {name} has no NTC"),
            "declare encoder and converter numbers, e.g. `NTC=1,1`",
        );
        return;
    };
    let sensor = ntc.has_transducer();
    let slave = t.slave_parallel;
    let interpolator = p.interpolator_of(name);
    // Type consistency.
    if t.coordinate && t.ptp {
        err(
            codes::COORDINATE_PTP,
            tpa.span.clone(),
            format!("axis {name} is both coordinate (1) and point-to-point (2)"),
            "choose 1 or 2",
        );
    }
    if t.spindle_with_encoder && t.spindle_without_encoder {
        err(
            codes::SPINDLE_BOTH,
            tpa.span.clone(),
            format!("spindle {name} is declared with (20) and without (10) encoder"),
            "choose 10 or 20",
        );
    }
    if (t.ptp || spindle) && !ntc.has_converter() {
        err(
            codes::CONVERTER_MISMATCH,
            at("NTC"),
            format!(
                "axis {name} is a {} but NTC declares no converter",
                if t.ptp {
                    "point-to-point axis"
                } else {
                    "spindle"
                }
            ),
            "write the DAC/DPC channel as NTC's second parameter",
        );
    } else if t.virtual_axis && ntc.has_converter() {
        err(
            codes::CONVERTER_MISMATCH,
            at("NTC"),
            format!("virtual axis {name} declares a converter"),
            "a virtual axis has no drive: write `NTC=0,0`",
        );
    }
    // Switched axes.
    if let Some(sw) = &tpa.switch_axis {
        if sw.len() > 1 {
            err(
                codes::SWITCH_NAME,
                tpa.span.clone(),
                format!("switched-axis name `{sw}` is longer than one letter"),
                "write one axis letter",
            );
        } else if let Some(other) = sw.chars().next() {
            let declared = p.cas.as_ref().is_some_and(|c| c.axes.contains(&other));
            if !declared {
                err(
                    codes::SWITCH_UNDECLARED,
                    tpa.span.clone(),
                    format!("switched axis {other} is not declared in section 1"),
                    "name an axis of this process's CAS",
                );
            } else if let Some(o) = p.axis(other) {
                let back = o.tpa.as_ref().is_some_and(|ot| {
                    ot.axis_type.switched && ot.switch_axis.as_deref() == Some(&name.to_string())
                });
                if !t.switched || !back {
                    err(
                        codes::SWITCH_MISMATCH,
                        tpa.span.clone(),
                        format!(
                            "axes {name} and {other} are not declared switchable onto each other"
                        ),
                        "both axes need code 8 and each other's name, e.g. X: `TPA=9,Y`, Y: `TPA=9,X`",
                    );
                }
            }
        }
    } else if t.switched {
        err(
            codes::SWITCH_MISMATCH,
            tpa.span.clone(),
            format!("axis {name} is switched (8) but names no other axis"),
            "write the axis it is switched onto, e.g. `TPA=9,Y`",
        );
    }
    // Mandatory instructions.
    if sensor && !slave {
        for (key, code, what) in [
            ("GAS", codes::GAS_MISSING, "GAS"),
            ("PAS", codes::PAS_MISSING, "PAS"),
            ("POS", codes::POS_MISSING, "POS"),
            ("SRV", codes::SRV_MISSING, "SRV"),
        ] {
            if axis.index_of(key).is_none() {
                err(
                    code,
                    axis.span.clone(),
                    format!("axis {name} has a transducer but no {what}"),
                    "an axis with an encoder declares PAS, GAS, POS and SRV",
                );
            }
        }
    } else if sensor && slave && axis.gas.is_none() {
        err(
            codes::GAS_MISSING,
            axis.span.clone(),
            format!("slave axis {name} has no GAS"),
            "a slave parallel axis declares NAS, TPA, NTC, GAS, MCZ, MFC, SKW",
        );
    }
    if sensor && ntc.has_converter() && !spindle && !slave {
        if axis.rap.is_none() {
            err(
                codes::RAP_MISSING,
                axis.span.clone(),
                format!("axis {name} has no RAP"),
                "declare rapid speed and acceleration, e.g. `RAP=12000,800`",
            );
        }
        if axis.man.is_none() {
            err(
                codes::MAN_MISSING,
                axis.span.clone(),
                format!("axis {name} has no MAN"),
                "declare manual speed and acceleration, e.g. `MAN=2000,200`",
            );
        }
    }
    if let (Some(rap), Some(man)) = (axis.rap, axis.man) {
        if let (Some(r), Some(m)) = (rap.a, man.a)
            && m > r
        {
            err(
                codes::MAN_SPEED,
                at("MAN"),
                format!("manual speed {m} is above the rapid speed {r}"),
                "MAN's speed must not exceed RAP's",
            );
        }
        if let (Some(r), Some(m)) = (rap.b, man.b)
            && m > r
        {
            err(
                codes::MAN_ACCEL,
                at("MAN"),
                format!("manual acceleration {m} is above the rapid acceleration {r}"),
                "MAN's acceleration must not exceed RAP's",
            );
        }
    }
    // GMxx.
    for gm in &axis.gm {
        let key = format!("GM{}", gm.range);
        if spindle && gm.range == 0 {
            err(
                codes::GM0_ON_SPINDLE,
                at(&key),
                format!("spindle {name} has GM0"),
                "a spindle declares its ranges GM1, GM2, …",
            );
        } else if !spindle && gm.range != 0 {
            err(
                codes::GM_NOT_ZERO,
                at(&key),
                format!("axis {name} is not a spindle but has {key}"),
                "an axis that is not a spindle declares only GM0",
            );
        }
    }
    if spindle && !axis.gm.iter().any(|g| g.range == 1) {
        err(
            codes::GM1_MISSING,
            axis.span.clone(),
            format!("spindle {name} has no GM1"),
            "declare the first speed range, e.g. `GM1=5000,8.5,6`",
        );
    }
    // No interpolator: no GMnn, RAP, MAN, POS with values (handwheel axes write them empty).
    if interpolator.is_none() && !spindle && !slave {
        let valued = [
            (
                "RAP",
                axis.rap.is_some_and(|r| r.a.is_some() || r.b.is_some()),
            ),
            (
                "MAN",
                axis.man.is_some_and(|m| m.a.is_some() || m.b.is_some()),
            ),
            (
                "POS",
                axis.pos.is_some_and(|m| m.a.is_some() || m.b.is_some()),
            ),
            ("GM", !axis.gm.is_empty()),
        ];
        if let Some((key, _)) = valued.iter().find(|(_, v)| *v) {
            let span = if *key == "GM" {
                axis.gm
                    .first()
                    .and_then(|g| axis.span_of(&format!("GM{}", g.range)))
                    .unwrap_or(axis.span.clone())
            } else {
                at(key)
            };
            err(
                codes::NO_INTERPOLATOR,
                span,
                format!("axis {name} has {key} values but belongs to no interpolator"),
                "GMnn, RAP, MAN and POS need the axis in an INx",
            );
        }
    }
    // Spindle-only and forbidden-for-spindle instructions.
    if let Some(i) = p.interpolators.iter().find(|i| i.spindle == Some(name))
        && !spindle
    {
        err(
            codes::SPINDLE_TYPE,
            tpa.span.clone(),
            format!(
                "{name} is the spindle of interpolator {} but TPA has no spindle code",
                i.name
            ),
            "a spindle with encoder has code 20 in TPA",
        );
    }
    if axis.tsm.is_some() && !spindle {
        err(
            codes::TSM_NOT_SPINDLE,
            at("TSM"),
            format!("TSM on axis {name}, which is not a spindle"),
            "TSM is written only for a spindle (TPA 10 or 20)",
        );
    }
    if (t.controlled_acceleration || t.ac_motor) && axis.tsm.is_none() {
        err(
            codes::TSM_MISSING,
            tpa.span.clone(),
            format!(
                "spindle {name} with code {} has no TSM",
                if t.ac_motor { "4000" } else { "800" }
            ),
            "declare the reversal time and voltage, e.g. `TSM=4,18`",
        );
    }
    if axis.pom.is_some() && !t.spindle_with_encoder {
        err(
            codes::POM_NOT_SPINDLE,
            at("POM"),
            format!("POM on axis {name}, which is not a spindle with encoder"),
            "POM is written only for a spindle with encoder (TPA 20)",
        );
    }
    if t.spindle_with_encoder && axis.pom.is_none() {
        err(
            codes::POM_MISSING,
            axis.span.clone(),
            format!("spindle {name} has an encoder but no POM"),
            "declare the orientation, e.g. `POM=0.5,100`",
        );
    }
    if (spindle || t.ptp)
        && let Some(srv) = axis.srv
        && srv.iter().any(|v| v.unwrap_or(0.0) != 0.0)
    {
        err(
            codes::TYPE_FORBIDS,
            at("SRV"),
            format!(
                "SRV of {} {name} is not 0,0,0",
                if spindle {
                    "spindle"
                } else {
                    "point-to-point axis"
                }
            ),
            "write `SRV=0,0,0` (or `SRV=,,`) for spindles and point-to-point axes",
        );
    }
    if spindle {
        if axis.rap.is_some_and(|r| r.a.is_some_and(|v| v != 0.0)) {
            err(
                codes::TYPE_FORBIDS,
                at("RAP"),
                format!("RAP gives spindle {name} a rapid speed"),
                "for a spindle write only the acceleration, e.g. `RAP=,20`",
            );
        }
        if axis.man.is_some() {
            err(
                codes::TYPE_FORBIDS,
                at("MAN"),
                format!("MAN on spindle {name}"),
                "MAN is not written for a spindle",
            );
        }
        if axis.pos.is_some_and(|p| p.b.is_some_and(|v| v != 0.0)) {
            err(
                codes::TYPE_FORBIDS,
                at("POS"),
                format!("POS gives spindle {name} a wait time"),
                "for a spindle write only the tolerance, e.g. `POS=0.01,`",
            );
        }
    }
    if t.control_point && axis.asm.is_none() {
        err(
            codes::CONTROL_POINT_ASM,
            tpa.span.clone(),
            format!("control-point axis {name} has no ASM"),
            "name the spindle it uses, e.g. `ASM=S`",
        );
    }
    if let Some(m) = axis.asm.as_ref().and_then(|m| m.chars().next()) {
        let declared =
            p.cas.as_ref().is_some_and(|c| c.axes.contains(&m)) || p.common_axes().any(|c| c == m);
        if !declared {
            err(
                codes::ASM_UNDECLARED,
                at("ASM"),
                format!("ASM master axis {m} is not declared in section 1"),
                "name an axis of this process",
            );
        }
    }
    // Zones and cams.
    if axis.adg.is_some() && !t.restart_from_encoder {
        err(
            codes::TYPE_FORBIDS_ZONE,
            at("ADG"),
            format!("ADG on axis {name} without code 8000 in TPA"),
            "add 8000 to the axis type, e.g. `TPA=8001,`",
        );
    }
    const CUB_FORBIDDEN: u32 =
        0x2 | 0x4 | 0x10 | 0x20 | 0x80 | 0x100 | 0x800 | 0x1000 | 0x2000 | 0x4000;
    if axis.cub.is_some() && t.raw & CUB_FORBIDDEN != 0 {
        err(
            codes::TYPE_FORBIDS_ZONE,
            at("CUB"),
            format!("CUB on axis {name} of type {:X}", t.raw),
            "CUB is for linear coordinate axes only (not 2, 4, 10, 20, 80, 100, 800, 1000, 2000, 4000)",
        );
    }
    if !axis.cams.is_empty() && (t.spindle_without_encoder || t.virtual_axis || slave) {
        let key = format!("SW{}", axis.cams[0].number);
        err(
            codes::TYPE_FORBIDS_ZONE,
            at(&key),
            format!("{key} on axis {name} of type {:X}", t.raw),
            "software cams are not allowed for types 10, 100 and 1000",
        );
    }
    // Order: GMnn/TSM after NTC; MCZ/FBF/ZNO/FTP after PAS; FRC after GM0.
    let ntc_at = axis.index_of("NTC").unwrap_or(usize::MAX);
    for (i, (key, span)) in axis.order.iter().enumerate() {
        if (key.starts_with("GM") || key == "TSM") && i < ntc_at {
            err(
                codes::BEFORE_NTC,
                span.clone(),
                format!("{key} of axis {name} is written before NTC"),
                "write NTC right after TPA, then GMnn and TSM",
            );
        }
    }
    let pas_at = axis.index_of("PAS");
    for key in ["MCZ", "FBF", "ZNO", "FTP"] {
        if let Some(i) = axis.index_of(key)
            && pas_at.is_none_or(|p| i < p)
        {
            err(
                codes::BEFORE_PAS,
                at(key),
                format!("{key} of axis {name} is written before PAS"),
                "declare PAS first; MCZ, FBF, ZNO and FTP need the pitch",
            );
        }
    }
    if let Some(i) = axis.index_of("FRC")
        && axis.index_of("GM0").is_none_or(|g| g > i)
    {
        err(
            codes::FRC_BEFORE_GM0,
            at("FRC"),
            format!("FRC of axis {name} is not after GM0"),
            "write GM0 before FRC",
        );
    }
    // Tool magazine / PTP-only instructions.
    if axis
        .pas
        .is_some_and(|p| p.rev_num_motor.is_some_and(|r| r != 0.0))
        && t.raw != 2
    {
        err(
            codes::TYPE_NOT_2,
            at("PAS"),
            format!(
                "axis {name} declares motor revolutions in PAS but its type is {:X}",
                t.raw
            ),
            "a tool-magazine axis is exactly `TPA=2,`",
        );
    }
    if axis.ftp.is_some() && t.raw != 2 {
        err(
            codes::TYPE_NOT_2,
            at("FTP"),
            format!("FTP on axis {name} of type {:X}", t.raw),
            "FTP is written only for a point-to-point axis `TPA=2,`",
        );
    }
    if axis.fopp.is_some() && !t.ptp {
        err(
            codes::FOPP_NOT_PTP,
            at("FOPP"),
            format!("FOPP on axis {name}, which is not point-to-point"),
            "FOPP is written only for a point-to-point axis",
        );
    }
    // Encoders.
    if axis.gra.is_some() && !t.gray_code {
        err(
            codes::GRA_TYPE,
            at("GRA"),
            format!("GRA on axis {name} without code 80000 in TPA"),
            "add 80000 (Gray-code encoder) to the axis type",
        );
    }
    if axis.atr.is_some() && !t.ssi {
        err(
            codes::ATR_TYPE,
            at("ATR"),
            format!("ATR on axis {name} without code 200000 in TPA"),
            "add 200000 (SSI encoder) to the axis type",
        );
    }
    if t.ssi && axis.atr.is_none() {
        err(
            codes::ATR_MISSING,
            tpa.span.clone(),
            format!("axis {name} has an SSI encoder (200000) but no ATR"),
            "declare the sensor resolution, e.g. `ATR=13,0`",
        );
    }
    if let (Some((Some(st), _)), Some(pas)) = (axis.atr, axis.pas)
        && t.ssi
        && st < 32
        && pas.el_pitch != f64::from(1u32 << st)
    {
        err(
            codes::RANGE,
            at("PAS"),
            format!(
                "PAS el_pitch {} is not 2^{st} for the SSI sensor",
                pas.el_pitch
            ),
            "for an SSI encoder el_pitch = 2^resolution ST",
        );
    }
    if axis.vgas.is_some() && axis.gas.as_ref().and_then(|g| g.backlash).unwrap_or(0.0) == 0.0 {
        err(
            codes::TYPE_FORBIDS,
            at("VGAS"),
            format!("VGAS on axis {name}, whose GAS declares no backlash"),
            "VGAS sets the backlash take-up speed; write it only with a GAS backlash",
        );
    }
    if let Some(mcz) = &axis.mcz {
        let long = mcz.hdbrp.is_some() || mcz.delta_s.is_some();
        if t.distance_coded
            && (mcz.hdbrp.is_some_and(|h| h <= 0.0) || mcz.delta_s.is_some_and(|d| d == 0.0))
        {
            err(
                codes::RANGE,
                at("MCZ"),
                format!("KKRM MCZ of axis {name}: HDBRP must be > 0 and Δs not 0"),
                "HDBRP is half the distance between basic marks (default 20 mm), Δs the change of distance (e.g. 0.02)",
            );
        }
        if t.distance_coded && mcz.zero_input.is_some() {
            err(
                codes::MCZ_KKRM_INPUT,
                at("MCZ"),
                format!(
                    "MCZ of axis {name} names a home switch, but the encoder has distance-coded marks"
                ),
                "leave zero_input empty for a KKRM encoder: `MCZ=,0,300,10,0.02`",
            );
        }
        if long && !t.distance_coded {
            err(
                codes::TYPE_FORBIDS,
                at("MCZ"),
                format!("5-parameter MCZ on axis {name} without code 40000 in TPA"),
                "the HDBRP and Δs parameters are for KKRM encoders (type 40000)",
            );
        }
        if t.distance_coded
            && let (Some(speed), Some(ds)) = (mcz.speed, mcz.delta_s)
            && model.tim > 0
        {
            let max = ds.abs() * 60.0 * 1000.0 / (2.0 * f64::from(model.tim));
            if speed > max {
                err(
                    codes::RANGE,
                    at("MCZ"),
                    format!("KKRM search speed {speed} is above {max} (formula 4.9)"),
                    "V ≤ Δs·60·1000/(2·CPU_tick)",
                );
            }
        }
    }
    super::axis_pairs::check(ctx, p, index, axis, diags);
}
