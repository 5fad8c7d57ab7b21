//! The stable diagnostic codes of the PLC-language front end (range 1000–1999).
//!
//! Every code here has a row in `compiler/DIAGNOSTICS.md`; a test checks that the table and this
//! list agree. Codes are never renumbered: a retired code stays reserved.

/// A character outside a comment that starts no token (only ASCII is allowed outside comments).
pub const INVALID_CHAR: u32 = 1001;
/// A numeric literal (or the number in a signal or pulse name) that does not fit 32 bits.
pub const NUMBER_TOO_LARGE: u32 = 1002;
/// A token the grammar does not allow at that place.
pub const SYNTAX: u32 = 1003;
/// The file ends inside a statement.
pub const UNEXPECTED_EOF: u32 = 1004;
/// Text after the second `$` line.
pub const TEXT_AFTER_END: u32 = 1005;
/// `ELSE` without an open `IF`, or a second `ELSE`.
pub const ELSE_WITHOUT_IF: u32 = 1006;
/// `END_IF` without an open `IF`.
pub const END_IF_WITHOUT_IF: u32 = 1007;
/// `IF` without its `END_IF`.
pub const IF_WITHOUT_END_IF: u32 = 1008;
/// A `$` separator inside an `IF` block.
pub const DOLLAR_IN_IF: u32 = 1009;
/// A NUL byte: the file is not text (reading stops at its line; the program is not checked).
pub const NOT_TEXT: u32 = 1010;
/// Too many statement lines in a row with errors: not a PLC program (reading stops there).
pub const GAVE_UP: u32 = 1011;
/// The source is larger than [`crate::front::MAX_SOURCE_BYTES`]: not read at all.
pub const TOO_LARGE: u32 = 1012;

/// A connector number past the packet's last connector.
pub const CONNECTOR_RANGE: u32 = 1101;
/// A contact number past 31.
pub const CONTACT_RANGE: u32 = 1102;
/// A byte number past 3 (`W`) or past the packet (`S`).
pub const BYTE_RANGE: u32 = 1103;
/// A packet A connector that IOCFIL `INx`/`OUx` does not declare.
pub const A_UNDECLARED: u32 = 1104;
/// `I` on a packet A output connector.
pub const I_ON_OUTPUT: u32 = 1105;
/// `U` on a packet A input connector.
pub const U_ON_INPUT: u32 = 1106;
/// An assignment to a packet A input.
pub const WRITE_INPUT: u32 = 1107;
/// A one-shot number past 1023.
pub const PULSE_RANGE: u32 = 1108;
/// Warning: the logic writes a K/N signal written with `I` (the CNC's direction).
pub const WRITE_I_PREFIX: u32 = 1109;
/// A typed view that runs past the end of its connector.
pub const VIEW_CROSSES_CONNECTOR: u32 = 1110;
/// A typed view `AT` something that cannot hold it (a multi-byte type at a bit).
pub const VIEW_BAD_BASE: u32 = 1111;

/// A name defined twice.
pub const DUPLICATE: u32 = 1201;
/// A name that looks like a signal, a one-shot, a keyword, a type or a function.
pub const RESERVED_NAME: u32 = 1202;
/// More symbolic names than IOCFIL `SPL` allows.
pub const SPL_EXCEEDED: u32 = 1203;
/// An unknown type or function-block name after `DEF name :`.
pub const UNKNOWN_TYPE: u32 = 1204;
/// `DEF` of a predeclared interface name to another address.
pub const PREDECLARED_OTHER: u32 = 1205;
/// Warning: `DEF` of a predeclared interface name to its own address.
pub const PREDECLARED_SAME: u32 = 1206;
/// A name that is not defined.
pub const UNDEFINED: u32 = 1207;
/// An initial value that is not a constant of the variable's type, or one on a view or a block.
pub const BAD_INIT: u32 = 1208;
/// A timer or counter preset that is missing, not constant, negative or too large.
pub const BAD_PRESET: u32 = 1209;
/// `RETAIN` on something that is not an internal variable.
pub const BAD_RETAIN: u32 = 1210;

/// An operand of the wrong type.
pub const TYPE_MISMATCH: u32 = 1301;
/// A literal that does not fit the type it takes.
pub const LITERAL_RANGE: u32 = 1302;
/// Infix `/` between BOOLs.
pub const BOOL_DIVISION: u32 = 1303;
/// An operator that is not defined for the operand type.
pub const BAD_OPERATOR: u32 = 1304;
/// An assignment that would narrow a number without an explicit conversion.
pub const NARROWING: u32 = 1305;
/// An unknown function.
pub const UNKNOWN_FUNCTION: u32 = 1306;
/// A call with the wrong number of arguments.
pub const ARITY: u32 = 1307;
/// A bit number past the width of the integer.
pub const BIT_RANGE: u32 = 1308;
/// A `.member` the operand does not have.
pub const BAD_MEMBER: u32 = 1310;
/// An assignment to something that cannot be written (a constant, a member that is read-only, …).
pub const NOT_ASSIGNABLE: u32 = 1311;
/// `SET`/`RES` on a target that is not BOOL.
pub const SET_RES_NOT_BOOL: u32 = 1312;
/// A name used as a value that has no value (a timer's name inside `DEF`, …).
pub const NOT_A_VALUE: u32 = 1313;

/// A one-shot, timer or counter input driven by more than one statement.
pub const DRIVEN_TWICE: u32 = 1401;
/// A one-shot or a block input assigned inside an expression context it cannot have (a timer in a
/// `SET`/`RES`, …).
pub const BAD_STATEFUL_USE: u32 = 1402;

/// Warning: an output, internal variable, timer or counter that no statement writes.
pub const NEVER_WRITTEN: u32 = 1501;
/// Warning: a symbolic name that is never used.
pub const NEVER_USED: u32 = 1502;
/// Warning: a one-shot that is read but never assigned (it always reads 0).
pub const PULSE_NEVER_SET: u32 = 1503;
/// Warning: a timer preset shorter than the logic tick (it runs out at the first tick).
pub const SHORT_TIMER: u32 = 1504;
/// Warning: the program has no statements (an empty or comment-only file).
pub const EMPTY_PROGRAM: u32 = 1505;

/// Interface map: the TOML text does not have the map's shape.
pub const MAP_TOML: u32 = 1601;
/// Interface map: an entry's name, address or width is invalid, or its name is defined twice.
pub const MAP_ENTRY: u32 = 1602;
/// Interface map: the machine's `interface.toml` exists but cannot be read.
pub const MAP_IO: u32 = 1603;
/// Interface map: `role` names no fixed signal (or a machine-wide one for process 2..5).
pub const MAP_UNKNOWN_ROLE: u32 = 1604;
/// Interface map: `process` outside 1..5.
pub const MAP_PROCESS_RANGE: u32 = 1605;
/// Interface map: two entries for the same (process, role).
pub const MAP_DUPLICATE_ROLE: u32 = 1606;
/// Interface map: an entry's bits or bytes overlap another entry's.
pub const MAP_ADDRESS_CLASH: u32 = 1607;
/// Interface map: `dir` against the connector convention, the `I`/`U` prefix or the role.
pub const MAP_DIRECTION: u32 = 1608;
/// Interface map: a process 2..NBP lacks a handshake signal it needs.
pub const MAP_MISSING_ROLE: u32 = 1609;

/// The program's internal areas do not fit the image, or the IR rejected the lowered program.
pub const LOWERING: u32 = 1901;

/// Every code with its one-line summary, in order (used by the documentation test).
pub const ALL: &[(u32, &str)] = &[
    (INVALID_CHAR, "invalid character"),
    (NUMBER_TOO_LARGE, "number too large"),
    (SYNTAX, "syntax error"),
    (UNEXPECTED_EOF, "unexpected end of file"),
    (TEXT_AFTER_END, "text after the second `$`"),
    (ELSE_WITHOUT_IF, "`ELSE` without `IF`"),
    (END_IF_WITHOUT_IF, "`END_IF` without `IF`"),
    (IF_WITHOUT_END_IF, "`IF` without `END_IF`"),
    (DOLLAR_IN_IF, "`$` inside `IF`"),
    (NOT_TEXT, "not a text file"),
    (GAVE_UP, "not a PLC program: reading stopped"),
    (TOO_LARGE, "source over 2 MiB: not read"),
    (CONNECTOR_RANGE, "connector out of range"),
    (CONTACT_RANGE, "contact out of range"),
    (BYTE_RANGE, "byte out of range"),
    (A_UNDECLARED, "packet A connector not declared"),
    (I_ON_OUTPUT, "`I` on an output connector"),
    (U_ON_INPUT, "`U` on an input connector"),
    (WRITE_INPUT, "write to a packet A input"),
    (PULSE_RANGE, "one-shot number out of range"),
    (WRITE_I_PREFIX, "write to an `I` signal of K/N"),
    (
        VIEW_CROSSES_CONNECTOR,
        "typed view crosses the connector end",
    ),
    (VIEW_BAD_BASE, "typed view on a bit"),
    (DUPLICATE, "duplicate definition"),
    (RESERVED_NAME, "reserved name"),
    (SPL_EXCEEDED, "too many symbolic names for SPL"),
    (UNKNOWN_TYPE, "unknown type"),
    (PREDECLARED_OTHER, "predeclared name at another address"),
    (PREDECLARED_SAME, "predeclared name redefined"),
    (UNDEFINED, "undefined name"),
    (BAD_INIT, "bad initial value"),
    (BAD_PRESET, "bad preset"),
    (BAD_RETAIN, "bad RETAIN"),
    (TYPE_MISMATCH, "type mismatch"),
    (LITERAL_RANGE, "literal out of range"),
    (BOOL_DIVISION, "`/` between BOOLs"),
    (BAD_OPERATOR, "operator not defined for the type"),
    (NARROWING, "narrowing without conversion"),
    (UNKNOWN_FUNCTION, "unknown function"),
    (ARITY, "wrong number of arguments"),
    (BIT_RANGE, "bit number out of range"),
    (BAD_MEMBER, "no such member"),
    (NOT_ASSIGNABLE, "not assignable"),
    (SET_RES_NOT_BOOL, "SET/RES on a non-BOOL"),
    (NOT_A_VALUE, "not a value"),
    (DRIVEN_TWICE, "driven twice"),
    (BAD_STATEFUL_USE, "bad use of a stateful element"),
    (NEVER_WRITTEN, "never written"),
    (NEVER_USED, "never used"),
    (PULSE_NEVER_SET, "one-shot never assigned"),
    (SHORT_TIMER, "timer shorter than the tick"),
    (EMPTY_PROGRAM, "no statements"),
    (MAP_TOML, "interface map: bad TOML"),
    (MAP_ENTRY, "interface map: bad entry"),
    (MAP_IO, "interface map: unreadable file"),
    (MAP_UNKNOWN_ROLE, "interface map: unknown role"),
    (MAP_PROCESS_RANGE, "interface map: process outside 1..5"),
    (MAP_DUPLICATE_ROLE, "interface map: role given twice"),
    (MAP_ADDRESS_CLASH, "interface map: address clash"),
    (
        MAP_DIRECTION,
        "interface map: direction against the convention",
    ),
    (
        MAP_MISSING_ROLE,
        "interface map: process lacks a handshake signal",
    ),
    (LOWERING, "lowering failed"),
];

/// True for the usage warnings (1501–1503), which are dropped after a syntax error.
pub fn is_usage_warning(code: u32) -> bool {
    matches!(code, NEVER_WRITTEN | NEVER_USED | PULSE_NEVER_SET)
}
