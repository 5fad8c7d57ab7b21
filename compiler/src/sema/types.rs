//! Type rules of the language (docs/plc-language.md §4.2, §5): implicit widening, the common type of
//! two operands, and the conversion of untyped literals to a type with a range check.

use crate::ir::{Ty, Value};

/// All types, in the order the language lists them.
pub const ALL_TYPES: [Ty; 8] = [
    Ty::Bool,
    Ty::Byte,
    Ty::Word,
    Ty::Dword,
    Ty::Int,
    Ty::Dint,
    Ty::Real,
    Ty::Lreal,
];

/// The type named `name` (upper case), if it is a type keyword.
pub fn type_by_name(name: &str) -> Option<Ty> {
    ALL_TYPES.into_iter().find(|t| t.name() == name)
}

/// True when every value of `from` is a value of `to` (so the conversion may be implicit).
pub fn widens(from: Ty, to: Ty) -> bool {
    use Ty::*;
    from == to
        || matches!(
            (from, to),
            (Byte, Word | Dword | Int | Dint | Real | Lreal)
                | (Word, Dword | Dint | Real | Lreal)
                | (Dword, Lreal)
                | (Int, Dint | Real | Lreal)
                | (Dint, Lreal)
                | (Real, Lreal)
        )
}

/// The narrowest number type both `a` and `b` widen to (`None` for BOOL with a number).
pub fn common(a: Ty, b: Ty) -> Option<Ty> {
    if a == Ty::Bool || b == Ty::Bool {
        return (a == b).then_some(a);
    }
    if widens(a, b) {
        return Some(b);
    }
    if widens(b, a) {
        return Some(a);
    }
    [Ty::Int, Ty::Dint, Ty::Real, Ty::Lreal]
        .into_iter()
        .find(|&t| widens(a, t) && widens(b, t))
}

/// An untyped constant as written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Lit {
    /// An integer (decimal, hex, a whole duration in ms), possibly negated.
    Int(i64),
    /// A real number (or a fractional duration in ms).
    Real(f64),
    /// `TRUE`/`FALSE`.
    Bool(bool),
}

impl Lit {
    /// The type a literal takes when nothing else decides: DINT, DWORD when larger, REAL, BOOL.
    pub fn default_ty(self) -> Ty {
        match self {
            Lit::Int(v) if i32::try_from(v).is_ok() => Ty::Dint,
            Lit::Int(_) => Ty::Dword,
            Lit::Real(_) => Ty::Real,
            Lit::Bool(_) => Ty::Bool,
        }
    }

    /// Text for messages.
    pub fn describe(self) -> String {
        match self {
            Lit::Int(v) => v.to_string(),
            Lit::Real(v) => v.to_string(),
            Lit::Bool(b) => if b { "TRUE" } else { "FALSE" }.to_string(),
        }
    }
}

/// Why a literal does not become a value of a type.
#[derive(Debug, Clone, PartialEq)]
pub enum LitError {
    /// The value is outside the type's range.
    Range(String),
    /// The kinds do not mix (a real for an integer, a number for a BOOL beyond 0/1, …).
    Kind,
}

/// The range of an integer type as text.
pub fn range_text(ty: Ty) -> String {
    match ty {
        Ty::Bool => "0..1".into(),
        Ty::Byte => "0..255".into(),
        Ty::Word => "0..65535".into(),
        Ty::Dword => "0..4294967295".into(),
        Ty::Int => "-32768..32767".into(),
        Ty::Dint => "-2147483648..2147483647".into(),
        Ty::Real | Ty::Lreal => "any real".into(),
    }
}

/// Converts literal `lit` to a constant of `ty`.
pub fn lit_value(lit: Lit, ty: Ty) -> Result<Value, LitError> {
    let range = || LitError::Range(range_text(ty));
    Ok(match (lit, ty) {
        (Lit::Bool(b), Ty::Bool) => Value::Bool(b),
        (Lit::Int(v @ (0 | 1)), Ty::Bool) => Value::Bool(v == 1),
        (Lit::Int(_), Ty::Bool) => return Err(range()),
        (Lit::Int(v), Ty::Byte) => Value::Byte(u8::try_from(v).map_err(|_| range())?),
        (Lit::Int(v), Ty::Word) => Value::Word(u16::try_from(v).map_err(|_| range())?),
        (Lit::Int(v), Ty::Dword) => Value::Dword(u32::try_from(v).map_err(|_| range())?),
        (Lit::Int(v), Ty::Int) => Value::Int(i16::try_from(v).map_err(|_| range())?),
        (Lit::Int(v), Ty::Dint) => Value::Dint(i32::try_from(v).map_err(|_| range())?),
        (Lit::Int(v), Ty::Real) => Value::Real(v as f32),
        (Lit::Int(v), Ty::Lreal) => Value::Lreal(v as f64),
        (Lit::Real(v), Ty::Real) => Value::Real(v as f32),
        (Lit::Real(v), Ty::Lreal) => Value::Lreal(v),
        _ => return Err(LitError::Kind),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn common_types() {
        assert_eq!(common(Ty::Byte, Ty::Byte), Some(Ty::Byte));
        assert_eq!(common(Ty::Byte, Ty::Int), Some(Ty::Int));
        assert_eq!(common(Ty::Word, Ty::Int), Some(Ty::Dint));
        assert_eq!(common(Ty::Dword, Ty::Dint), Some(Ty::Lreal));
        assert_eq!(common(Ty::Dint, Ty::Real), Some(Ty::Lreal));
        assert_eq!(common(Ty::Bool, Ty::Byte), None);
        assert_eq!(common(Ty::Bool, Ty::Bool), Some(Ty::Bool));
    }

    #[test]
    fn literals_take_types_with_range_checks() {
        assert_eq!(lit_value(Lit::Int(0x91), Ty::Byte), Ok(Value::Byte(0x91)));
        assert_eq!(
            lit_value(Lit::Int(256), Ty::Byte),
            Err(LitError::Range("0..255".into()))
        );
        assert_eq!(lit_value(Lit::Int(1), Ty::Bool), Ok(Value::Bool(true)));
        assert_eq!(lit_value(Lit::Int(-1), Ty::Int), Ok(Value::Int(-1)));
        assert_eq!(lit_value(Lit::Real(2.5), Ty::Dint), Err(LitError::Kind));
        assert_eq!(Lit::Int(3_000_000_000).default_ty(), Ty::Dword);
    }
}
