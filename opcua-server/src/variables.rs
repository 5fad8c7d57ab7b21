//! The PLC program's named variables (`DEF name : TYPE`, the compiler's `Program::vars`) as
//! read-only variable nodes under `Objects/Variables`: their image bytes travel with each frame
//! ([`crate::handoff`]) and are decoded here (little-endian, as the engines store them).
//!
//! **Invariants:** the served variables lie inside one window of at most [`VARS_MAX`] image
//! bytes (the frame's fixed copy); a variable past it is left out and named on stderr at start,
//! never served with a wrong value. The window and the offsets are those of the program loaded
//! at start: after an online change ([`Layout::same_program`] false) the values are no longer
//! published and every variable answers `BadOutOfService`.

use std::ops::Range;
use std::sync::Arc;

use compiler::ir::{Program, Ty};
use opcua::nodes::{AccessLevel, ObjectBuilder, VariableBuilder};
use opcua::server::address_space::AddressSpace;
use opcua::types::{DataTypeId, NodeId, ObjectId, QualifiedName, VariableTypeId, Variant};

/// Image bytes of variables a frame carries.
pub const VARS_MAX: usize = 1024;

/// The node id of the `Variables` folder.
pub const FOLDER: &str = "Variables";

/// One served variable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VarNode {
    /// The string node id (`Variables/CHAIN_OK`).
    pub id: String,
    /// The declared name.
    pub name: String,
    /// Its type.
    pub ty: Ty,
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
        let start = p.vars.iter().map(|v| v.offset).min().unwrap_or(0);
        let mut vars = Vec::new();
        let mut left_out = Vec::new();
        let mut end = start;
        for v in &p.vars {
            let stop = v.offset + v.ty.size();
            if stop - start > VARS_MAX {
                left_out.push(v.name.clone());
                continue;
            }
            end = end.max(stop);
            vars.push(VarNode {
                id: format!("{FOLDER}/{}", v.name),
                name: v.name.clone(),
                ty: v.ty,
                at: v.offset - start,
                retain: v.retain,
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
        .description(format!("PLC variable {} : {}{retain}", v.name, v.ty.name()))
        .data_type(data_type(v.ty))
        .value_rank(-1)
        .value(decode(v.ty, &[]))
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
    }
}
