//! The TPA axis type: the manual's Table 4.1 codes, summed in one hexadecimal number, decoded
//! into named flags.

use serde::{Deserialize, Serialize};

/// TPA axis type: the Table 4.1 bits decoded into named flags.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct AxisType {
    /// The hexadecimal value as a number.
    pub raw: u32,
    /// 0001 coordinate (continuous, interpolated) axis.
    pub coordinate: bool,
    /// 0002 point-to-point axis.
    pub ptp: bool,
    /// 0004 rotary axis.
    pub rotary: bool,
    /// 0008 switched axis (shares a DAC channel).
    pub switched: bool,
    /// 0010 spindle without encoder.
    pub spindle_without_encoder: bool,
    /// 0020 spindle with encoder.
    pub spindle_with_encoder: bool,
    /// 0040 diameter axis.
    pub diameter: bool,
    /// 0080 control-point axis (spindle as C axis).
    pub control_point: bool,
    /// 0100 virtual axis.
    pub virtual_axis: bool,
    /// 0200 absolute axis.
    pub absolute: bool,
    /// 0400 homed flag cleared when switched off.
    pub rehome_after_off: bool,
    /// 0800 spindle with controlled acceleration.
    pub controlled_acceleration: bool,
    /// 1000 slave parallel axis.
    pub slave_parallel: bool,
    /// 2000 rotary axis positioned 0…359.999°.
    pub rotary_modulo: bool,
    /// 4000 spindle with an AC motor.
    pub ac_motor: bool,
    /// 8000 restart from the current encoder position.
    pub restart_from_encoder: bool,
    /// 10000 encoder without reference mark.
    pub no_reference_mark: bool,
    /// 40000 distance-coded reference marks (KKRM).
    pub distance_coded: bool,
    /// 80000 Gray-code absolute encoder on discrete inputs.
    pub gray_code: bool,
    /// 100000 continuous dressing axis.
    pub dressing: bool,
    /// 200000 SSI absolute encoder.
    pub ssi: bool,
}

impl AxisType {
    /// Bits that Table 4.1 defines (0–16, 18–21).
    pub const DEFINED: u32 = 0x3D_FFFF;

    /// Decodes a TPA value.
    pub fn decode(raw: u32) -> Self {
        let b = |mask: u32| raw & mask != 0;
        AxisType {
            raw,
            coordinate: b(0x1),
            ptp: b(0x2),
            rotary: b(0x4),
            switched: b(0x8),
            spindle_without_encoder: b(0x10),
            spindle_with_encoder: b(0x20),
            diameter: b(0x40),
            control_point: b(0x80),
            virtual_axis: b(0x100),
            absolute: b(0x200),
            rehome_after_off: b(0x400),
            controlled_acceleration: b(0x800),
            slave_parallel: b(0x1000),
            rotary_modulo: b(0x2000),
            ac_motor: b(0x4000),
            restart_from_encoder: b(0x8000),
            no_reference_mark: b(0x1_0000),
            distance_coded: b(0x4_0000),
            gray_code: b(0x8_0000),
            dressing: b(0x10_0000),
            ssi: b(0x20_0000),
        }
    }

    /// True for a spindle (with or without encoder).
    pub fn spindle(&self) -> bool {
        self.spindle_with_encoder || self.spindle_without_encoder
    }
}
