//! Diagnostic codes of the partprogram compiler (2000–2999); `partprogram/DIAGNOSTICS.md` lists them.

/// A character that is not part of the language outside a comment.
pub const BAD_CHAR: u32 = 2001;
/// Tokens that do not form a word.
pub const SYNTAX: u32 = 2002;
/// The program does not start with `%n` (MEFI) or the header number is invalid.
pub const HEADER: u32 = 2003;
/// Words before the first `N` (MEFI) .
pub const NO_BLOCK_NUMBER: u32 = 2004;
/// Two blocks of one program unit carry the same number.
pub const DUPLICATE_N: u32 = 2005;
/// An address appears twice in a block.
pub const DUPLICATE_ADDRESS: u32 = 2006;
/// Two G (or M) functions of the same group in one block.
pub const GROUP_CONFLICT: u32 = 2007;
/// An address letter the dialect or machine does not have.
pub const UNKNOWN_ADDRESS: u32 = 2008;
/// A literal value outside the address's range or format.
pub const OUT_OF_RANGE: u32 = 2009;
/// An address that cannot take a parameter (`N`, `R`, `G79`).
pub const NOT_PARAMETRISABLE: u32 = 2010;
/// A parameter number outside 0..=95.
pub const BAD_PARAMETER: u32 = 2011;
/// A line longer than 80 characters (warning).
pub const LONG_LINE: u32 = 2012;
/// A number that belongs to no address (space inside a value, after a sign, …).
pub const ORPHAN_NUMBER: u32 = 2013;
/// A G function the dialect does not have.
pub const UNKNOWN_G: u32 = 2015;
/// An M function IOCFIL section 2 does not declare for the process.
pub const UNDECLARED_M: u32 = 2016;
/// G71/G72/G73/G79 (M97/M98) without the address L (P) in the block.
pub const MISSING_L: u32 = 2017;
/// A jump to a block that does not exist in the program unit.
pub const MISSING_BLOCK: u32 = 2018;
/// A call of a subprogram the file does not contain.
pub const MISSING_SUBPROGRAM: u32 = 2019;
/// A call of a macro file (or fixed cycle) the macro folder does not contain.
pub const MISSING_MACRO: u32 = 2020;
/// A call chain that calls itself: unbounded recursion.
pub const RECURSION: u32 = 2021;
/// A `G79` block with words other than N, G79 and L.
pub const G79_BLOCK: u32 = 2022;
/// More than 6 axis words in a block.
pub const TOO_MANY_AXES: u32 = 2023;
/// An integer address written with a decimal fraction.
pub const NOT_INTEGER: u32 = 2024;
/// A subprogram or macro without its closing `G70` (M99).
pub const UNIT_NOT_CLOSED: u32 = 2025;
/// Blocks after M02/M30 that do not belong to a subprogram.
pub const AFTER_END: u32 = 2026;
/// More than 99 subprograms.
pub const TOO_MANY_SUBPROGRAMS: u32 = 2027;
/// A thread run-in `E` without a decimal point.
pub const E_WITHOUT_POINT: u32 = 2030;
/// A macro or cycle file that cannot be read.
pub const MACRO_IO: u32 = 2031;
/// The main program has no M02/M30 (warning).
pub const NO_END: u32 = 2032;
/// G73 in a Fanuc file is peck drilling; R in MEFI must be a declaration.
pub const R_WORD: u32 = 2033;

/// Run time: arithmetic failure (division by zero, invalid argument, overflow).
pub const RUN_ARITH: u32 = 2500;
/// Run time: undefined or unsupported operation code.
pub const RUN_BAD_OP: u32 = 2501;
/// Run time: a substituted parameter does not fit the address.
pub const RUN_RANGE: u32 = 2502;
/// Run time: the end point is not on the circle (error 7.56).
pub const RUN_CIRCLE: u32 = 2503;
/// Run time: too many executed blocks or nested calls.
pub const RUN_LIMIT: u32 = 2504;
/// Run time: a computed jump or call target that does not exist.
pub const RUN_TARGET: u32 = 2505;
/// Run time: double-precision parameter numbers used while double precision is disabled.
pub const RUN_DOUBLE: u32 = 2506;
/// Run time: a G function computed through a parameter that is not allowed there.
pub const RUN_BAD_G: u32 = 2507;

/// `TAB*.KOR`: no `$KOR` keyword.
pub const KOR_NO_KEYWORD: u32 = 2040;
/// `TAB*.KOR`: a line that does not start with a two-digit correction number and `:`.
pub const KOR_LINE: u32 = 2041;
/// `TAB*.KOR`: a correction number defined twice.
pub const KOR_DUPLICATE_ENTRY: u32 = 2042;
/// `TAB*.KOR`: a field that is not R, X, Y, Z, U, 1..4 or P.
pub const KOR_UNKNOWN_FIELD: u32 = 2043;
/// `TAB*.KOR`: an axis name that is not the name of the machine's axis of that ordinal (lathe `Z=`).
pub const KOR_AXIS_NAME: u32 = 2044;
/// `TAB*.KOR`: a field without `=` or without a number.
pub const KOR_SYNTAX: u32 = 2045;
/// `TAB*.KOR`: a value out of format or range (no point, > 3 decimals, > ±999.999, P not 1..9).
pub const KOR_VALUE: u32 = 2046;
/// `TAB*.KOR`: a datum written twice in one entry.
pub const KOR_DUPLICATE_FIELD: u32 = 2047;
/// `TAB*.KOR`: a second `$KOR` keyword.
pub const KOR_SECOND_TABLE: u32 = 2048;
/// `TAB*.KOR`: the file cannot be read (reported by the runtime).
pub const KOR_IO: u32 = 2049;
/// `TAB0.POS`: no `$POS` keyword.
pub const POS_NO_KEYWORD: u32 = 2070;
/// `TAB0.POS`: a line that is not `G53`…`G59`, `:` and `axis=value` fields.
pub const POS_LINE: u32 = 2071;
/// `TAB0.POS`: a field naming no axis of the machine.
pub const POS_AXIS: u32 = 2072;
/// `TAB0.POS`: a value that is not a number of at most ±99999.999.
pub const POS_VALUE: u32 = 2073;
/// `TAB0.POS`: a row written twice.
pub const POS_DUPLICATE: u32 = 2074;
/// `TAB0.POS`: the file cannot be read (reported by the runtime).
pub const POS_IO: u32 = 2075;
/// `nc/MACROVARS` (retained `#500`–`#999`): a line that is not `#<n> = <value>`.
pub const VARS_LINE: u32 = 2076;
/// `nc/MACROVARS`: a variable outside `#500`–`#999`.
pub const VARS_NUMBER: u32 = 2077;
/// `nc/MACROVARS`: a value that is not a finite number.
pub const VARS_VALUE: u32 = 2078;
/// `nc/MACROVARS`: a variable written twice.
pub const VARS_DUPLICATE: u32 = 2079;
/// `nc/MACROVARS`: the file cannot be read or written (reported by the runtime).
pub const VARS_IO: u32 = 2080;
/// Fanuc `G43`/`G44` without `H` in the block.
pub const G43_WITHOUT_H: u32 = 2034;
/// G41/G42/G40 written in a G02/G03 block: compensation is switched only in linear blocks (S15).
pub const COMP_ON_ARC: u32 = 2035;
/// Run time: tool length compensation impossible (no tool axis for the plane, axis beyond the table).
pub const RUN_TOOL_LENGTH: u32 = 2508;
/// Run time: thread run-in/run-out without a valid slope (machine constant 8) or longer than the thread.
pub const RUN_THREAD: u32 = 2509;
/// Run time: radius compensation cannot join two elements (intersection of equidistants not found, or
/// an arc radius smaller than the tool radius on its inside).
pub const RUN_EQUIDISTANT: u32 = 2510;
/// Run time: a radius-compensation rule broken (G41/G42/G40 on an arc, plane changed while active).
pub const RUN_COMP_RULE: u32 = 2511;
/// Run time: radius compensation would gouge: a compensated line runs backwards or collapses, or a
/// compensated arc's sweep reverses or vanishes (interference check, project rule).
pub const RUN_GOUGE: u32 = 2512;
/// Run time: G14/G15/G16 (also computed through `GR<n>`) name an axis the process does not have.
pub const RUN_PLANE_AXIS: u32 = 2513;
/// Run time (both dialects): a word the block does not execute in the current modal state (no
/// silent word), located at the word.
pub const RUN_BAD_WORD: u32 = 2530;
/// MEFI: an address that means nothing in any block of this controller (K, and the H/P auxiliary
/// functions, which no interface signal carries to the PLC).
pub const NO_MEANING: u32 = 2038;
/// Fanuc Macro B: `WHILE … DO m` / `END m` that do not pair (missing, overlapping, reused number,
/// nested deeper than 3).
pub const MACRO_NESTING: u32 = 2037;
/// Run time (Fanuc Macro B): division by zero, a value out of range, a variable that does not exist
/// or cannot be written, `#3000` alarms.
pub const RUN_MACRO: u32 = 2531;
/// G14/G15/G16 written while the process has no axis of the machine-constant-341 plane they select.
pub const PLANE_AXIS: u32 = 2036;

/// True for the run-time errors of the motion geometry (circle 2503, G43/G44 tool axis 2508, G33
/// run-in/run-out 2509, radius compensation 2510–2512, G14–G16 plane 2513), which `ncplc nc check`
/// reports too: they are mistakes of the program text, found by executing it, not of one run.
pub fn is_geometric(code: u32) -> bool {
    matches!(code, RUN_CIRCLE | 2508..=2513)
}
