//! The PLC program's named state as read-only variable nodes under `Objects/Variables`: every
//! internal variable (`DEF name : TYPE`, the compiler's `Program::vars`), every timer's `Q` and
//! `ET` (`NAME.Q`, `NAME.ET` in ms), every counter's `CV` (`NAME.CV`) and every pulse `P<n>`. Their
//! image bytes travel with each frame ([`crate::handoff`]) and are decoded here (little-endian,
//! the layout of `compiler::ir`: a timer's i32 ET at +0 and its Q in bit 0 of the flags at +4, a
//! counter's i32 CV at +0, a pulse's value in bit 0).
//!
//! **Invariants:** the served variables lie inside one window of at most [`VARS_MAX`] image
//! bytes (the frame's fixed copy); a variable past it is left out and named on stderr at start,
//! never served with a wrong value. The window and the offsets are those of the program loaded
//! at start: after an online change ([`Layout::same_program`] false) the values are no longer
//! published and every variable answers `BadOutOfService`.

use std::ops::Range;
use std::sync::Arc;

use compiler::ir::{FLAG_Q, Program, Ty};
use opcua::nodes::{AccessLevel, ObjectBuilder, VariableBuilder};
use opcua::server::address_space::AddressSpace;
use opcua::types::{DataTypeId, NodeId, ObjectId, QualifiedName, VariableTypeId, Variant};

/// Image bytes of variables a frame carries.
pub const VARS_MAX: usize = 1024;

/// The node id of the `Variables` folder.
pub const FOLDER: &str = "Variables";

/// What a node shows of its bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// A variable of that type.
    Value(Ty),
    /// A timer's Q (Boolean).
    TimerQ,
    /// A timer's elapsed time ET in ms (Int32).
    TimerEt,
    /// A counter's CV (Int32).
    CounterCv,
    /// A pulse's value (Boolean).
    Pulse,
}

impl Field {
    /// The bytes it reads from its offset.
    pub fn size(self) -> usize {
        match self {
            Field::Value(ty) => ty.size(),
            Field::TimerQ => 5,
            Field::TimerEt | Field::CounterCv => 4,
            Field::Pulse => 1,
        }
    }

    /// The OPC UA data type.
    pub fn data_type(self) -> DataTypeId {
        match self {
            Field::Value(ty) => data_type(ty),
            Field::TimerQ | Field::Pulse => DataTypeId::Boolean,
            Field::TimerEt | Field::CounterCv => DataTypeId::Int32,
        }
    }

    /// The value stored at `bytes` (short input reads as zeros).
    pub fn decode(self, bytes: &[u8]) -> Variant {
        let at = |i: usize| bytes.get(i).copied().unwrap_or(0);
        match self {
            Field::Value(ty) => decode(ty, bytes),
            Field::TimerQ => Variant::Boolean(at(4) & FLAG_Q != 0),
            Field::TimerEt | Field::CounterCv => decode(Ty::Dint, bytes),
            Field::Pulse => Variant::Boolean(at(0) & 1 != 0),
        }
    }

    /// What it is, for the node's description.
    fn what(self) -> String {
        match self {
            Field::Value(ty) => ty.name().to_string(),
            Field::TimerQ => "timer output Q".into(),
            Field::TimerEt => "timer elapsed time ET, ms".into(),
            Field::CounterCv => "counter value CV".into(),
            Field::Pulse => "one-shot pulse".into(),
        }
    }
}

/// One served variable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VarNode {
    /// The string node id (`Variables/CHAIN_OK`).
    pub id: String,
    /// The declared name (`BLINK_ON.Q` for a timer's output).
    pub name: String,
    /// What it shows.
    pub ty: Field,
    /// Its offset in the frame's variable bytes.
    pub at: usize,
    /// Kept across restarts.
    pub retain: bool,
}

/// The served variables and where their bytes are in the image.
#[derive(Debug, Clone, Default)]
pub struct Layout {
    /// The variables, by name.
    pub vars: Vec<VarNode>,
    /// The image bytes the frame copies.
    pub window: Range<usize>,
    /// The variables left out (past [`VARS_MAX`]).
    pub left_out: Vec<String>,
    program: Option<Arc<Program>>,
}

impl Layout {
    /// The layout of `program` (None: an engine without a compiler program: no variables).
    pub fn of(program: Option<&Arc<Program>>) -> Layout {
        let Some(p) = program else {
            return Layout::default();
        };
        let mut all: Vec<(String, Field, usize, bool)> = p
            .vars
            .iter()
            .map(|v| (v.name.clone(), Field::Value(v.ty), v.offset, v.retain))
            .collect();
        for t in &p.timers {
            all.push((format!("{}.Q", t.name), Field::TimerQ, t.offset, false));
            all.push((format!("{}.ET", t.name), Field::TimerEt, t.offset, false));
        }
        for c in &p.counters {
            all.push((format!("{}.CV", c.name), Field::CounterCv, c.offset, false));
        }
        for q in &p.pulses {
            all.push((format!("P{}", q.n), Field::Pulse, q.offset, false));
        }
        let start = all.iter().map(|v| v.2).min().unwrap_or(0);
        let mut vars = Vec::new();
        let mut left_out = Vec::new();
        let mut end = start;
        for (name, field, offset, retain) in all {
            let stop = offset + field.size();
            if stop - start > VARS_MAX {
                left_out.push(name);
                continue;
            }
            end = end.max(stop);
            vars.push(VarNode {
                id: format!("{FOLDER}/{name}"),
                name,
                ty: field,
                at: offset - start,
                retain,
            });
        }
        vars.sort_by(|a, b| a.name.cmp(&b.name));
        Layout {
            vars,
            window: start..end,
            left_out,
            program: Some(Arc::clone(p)),
        }
    }

    /// True while `program` is the one the layout was made for.
    pub fn same_program(&self, program: Option<&Arc<Program>>) -> bool {
        match (&self.program, program) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        }
    }
}

/// The OPC UA data type of `ty`.
pub fn data_type(ty: Ty) -> DataTypeId {
    match ty {
        Ty::Bool => DataTypeId::Boolean,
        Ty::Byte => DataTypeId::Byte,
        Ty::Word => DataTypeId::UInt16,
        Ty::Dword => DataTypeId::UInt32,
        Ty::Int => DataTypeId::Int16,
        Ty::Dint => DataTypeId::Int32,
        Ty::Real => DataTypeId::Float,
        Ty::Lreal => DataTypeId::Double,
    }
}

/// The value of a `ty` stored at `bytes` (little-endian; short input reads as zeros).
pub fn decode(ty: Ty, bytes: &[u8]) -> Variant {
    let mut b = [0u8; 8];
    let n = ty.size().min(bytes.len());
    b[..n].copy_from_slice(&bytes[..n]);
    let [b0, b1, b2, b3, ..] = b;
    match ty {
        Ty::Bool => Variant::Boolean(b0 != 0),
        Ty::Byte => Variant::Byte(b0),
        Ty::Word => Variant::UInt16(u16::from_le_bytes([b0, b1])),
        Ty::Dword => Variant::UInt32(u32::from_le_bytes([b0, b1, b2, b3])),
        Ty::Int => Variant::Int16(i16::from_le_bytes([b0, b1])),
        Ty::Dint => Variant::Int32(i32::from_le_bytes([b0, b1, b2, b3])),
        Ty::Real => Variant::Float(f32::from_le_bytes([b0, b1, b2, b3])),
        Ty::Lreal => Variant::Double(f64::from_le_bytes(b)),
    }
}

/// Adds `Objects/Variables` and a read-only node per variable (namespace `ns`).
pub fn add(space: &mut AddressSpace, ns: u16, layout: &Layout) {
    let folder = NodeId::new(ns, FOLDER);
    ObjectBuilder::new(&folder, QualifiedName::new(ns, FOLDER), FOLDER)
        .description("The PLC program's internal variables (DEF name : TYPE), read-only")
        .is_folder()
        .organized_by(NodeId::from(ObjectId::ObjectsFolder))
        .insert(space);
    for v in &layout.vars {
        let retain = if v.retain { ", RETAIN" } else { "" };
        VariableBuilder::new(
            &NodeId::new(ns, v.id.as_str()),
            QualifiedName::new(ns, v.name.as_str()),
            v.name.as_str(),
        )
        .description(format!("PLC variable {} : {}{retain}", v.name, v.ty.what()))
        .data_type(v.ty.data_type())
        .value_rank(-1)
        .value(v.ty.decode(&[]))
        .access_level(AccessLevel::CURRENT_READ)
        .user_access_level(AccessLevel::CURRENT_READ)
        .organized_by(folder.clone())
        .has_type_definition(VariableTypeId::BaseDataVariableType)
        .insert(space);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_decode_little_endian_by_type() {
        assert_eq!(decode(Ty::Bool, &[1]), Variant::Boolean(true));
        assert_eq!(decode(Ty::Word, &[0x58, 0x02]), Variant::UInt16(600));
        assert_eq!(decode(Ty::Int, &[0xFF, 0xFF]), Variant::Int16(-1));
        assert_eq!(
            decode(Ty::Dint, &[0xFE, 0xFF, 0xFF, 0xFF]),
            Variant::Int32(-2)
        );
        assert_eq!(decode(Ty::Real, &1.5f32.to_le_bytes()), Variant::Float(1.5));
        assert_eq!(
            decode(Ty::Lreal, &(-0.25f64).to_le_bytes()),
            Variant::Double(-0.25)
        );
        assert_eq!(decode(Ty::Dword, &[7]), Variant::UInt32(7), "short input");
        // A timer's state: ET 250 ms, flags Q | previous IN.
        let timer = [0xFA, 0, 0, 0, 3, 0, 0, 0];
        assert_eq!(Field::TimerEt.decode(&timer), Variant::Int32(250));
        assert_eq!(Field::TimerQ.decode(&timer), Variant::Boolean(true));
        assert_eq!(Field::TimerQ.decode(&timer[..4]), Variant::Boolean(false));
        assert_eq!(
            Field::Pulse.decode(&[2]),
            Variant::Boolean(false),
            "bit 1 is the input"
        );
    }
}
