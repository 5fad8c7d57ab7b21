//! The language's keywords, types and functions with their one-line syntax from the language
//! reference (docs/plc-language.md), for hover and completion.

/// `(word, one-line syntax and meaning)`, upper case.
pub const KEYWORDS: &[(&str, &str)] = &[
    (
        "DEF",
        "`DEF name = signal` names a signal; `DEF name : TYPE [AT W<c><P><b>] [:= value] [RETAIN]` declares a variable, a typed view or a timer/counter (§3.2)",
    ),
    (
        "AT",
        "`DEF name : WORD AT W13K2`: a typed view of consecutive bytes of one connector (§3.2)",
    ),
    (
        "RETAIN",
        "`DEF name : DINT RETAIN`: the value is kept across restarts (PGCFIL OLD) (§3.2)",
    ),
    (
        "SET",
        "`SET target = expr`: set coil, target := 1 when expr is 1 (§4)",
    ),
    (
        "RES",
        "`RES target = expr`: reset coil, target := 0 when expr is 1 (§4)",
    ),
    (
        "IF",
        "`IF expr THEN` … [`ELSE` …] `END_IF`: master-control zone, the statements inside run only while expr holds (§4)",
    ),
    ("THEN", "`IF expr THEN` ends the `IF` line (§4)"),
    (
        "ELSE",
        "`ELSE` on a line of its own: the statements up to `END_IF` run when the `IF` condition does not hold (§4)",
    ),
    (
        "END_IF",
        "`END_IF` on a line of its own closes the `IF` zone (§4)",
    ),
    ("OR", "`a OR b`: the same as `a + b` on BOOL (§5)"),
    ("AND", "`a AND b`: the same as `a * b` on BOOL (§5)"),
    ("NOT", "`NOT a`: the same as `/a` (§5)"),
    ("XOR", "`a XOR b`: exclusive or (§5)"),
    (
        "MOD",
        "`a MOD b`: integer remainder; MOD by zero gives 0 and sets PLCFAULT (§5)",
    ),
    ("TRUE", "`TRUE`: the BOOL constant 1 (§3.3)"),
    ("FALSE", "`FALSE`: the BOOL constant 0 (§3.3)"),
    (
        "TON",
        "`DEF t : TON(preset)` or inline `TON(in, preset)`: on-delay timer, Q = IN held for the preset (§4, §4.1)",
    ),
    (
        "TOF",
        "`DEF t : TOF(preset)` or inline `TOF(in, preset)`: off-delay timer, Q stays 1 for the preset after IN falls (§4.1)",
    ),
    (
        "TP",
        "`DEF t : TP(preset)` or inline `TP(in, preset)`: pulse of exactly the preset on a rising IN (§4.1)",
    ),
    (
        "CTU",
        "`DEF c : CTU(preset)`: up counter; `c = x` counts rising edges, `c.R = x` resets, `c` is CV >= preset (§4.1)",
    ),
    (
        "CTD",
        "`DEF c : CTD(preset)`: down counter; `c.LD = x` loads the preset, `c = x` counts down, `c` is CV <= 0 (§4.1)",
    ),
    (
        "BCD",
        "`BCD(x)`: binary to BCD, keeping the low decimal digits that fit the type (§5)",
    ),
    (
        "BIN",
        "`BIN(x)`: BCD to binary (`BIN(1AH)` = 20); `[BIN(W3K0) = 91]` compares the M code (§5)",
    ),
    ("MIN", "`MIN(a, b)`: the smaller of two numbers (§5)"),
    ("MAX", "`MAX(a, b)`: the larger of two numbers (§5)"),
    ("LIMIT", "`LIMIT(lo, x, hi)`: x clamped to lo..hi (§5)"),
    ("ABS", "`ABS(x)`: absolute value (§5)"),
    (
        "BOOL",
        "`BOOL` type (one bit); `BOOL(x)` converts (x <> 0) (§3.2, §5)",
    ),
    (
        "BYTE",
        "`BYTE` type (u8); `BYTE(x)` keeps the low 8 bits (§3.2, §5)",
    ),
    (
        "WORD",
        "`WORD` type (u16); `WORD(x)` keeps the low 16 bits (§3.2, §5)",
    ),
    (
        "DWORD",
        "`DWORD` type (u32); `DWORD(x)` converts (§3.2, §5)",
    ),
    (
        "INT",
        "`INT` type (i16); `INT(x)` keeps the low 16 bits (§3.2, §5)",
    ),
    ("DINT", "`DINT` type (i32); `DINT(x)` converts (§3.2, §5)"),
    ("REAL", "`REAL` type (f32); `REAL(x)` converts (§3.2, §5)"),
    (
        "LREAL",
        "`LREAL` type (f64); `LREAL(x)` converts (§3.2, §5)",
    ),
    ("ET", "`t.ET`: a timer's elapsed time in ms (DINT) (§4)"),
    (
        "Q",
        "`t.Q` / `c.Q`: a timer's or counter's output (the same as `t`) (§4)",
    ),
    ("CV", "`c.CV`: a counter's count (DINT) (§4)"),
    ("R", "`c.R = x`: resets a CTU counter while x is 1 (§4)"),
    (
        "LD",
        "`c.LD = x`: loads a CTD counter with its preset while x is 1 (§4)",
    ),
];

/// The one-line syntax of `word` (any case), when it is a keyword, type or function.
pub fn describe(word: &str) -> Option<&'static str> {
    let up = word.to_ascii_uppercase();
    KEYWORDS.iter().find(|(k, _)| *k == up).map(|(_, d)| *d)
}

/// Type names usable after `DEF name :`.
pub const TYPES: &[&str] = &[
    "BOOL", "BYTE", "WORD", "DWORD", "INT", "DINT", "REAL", "LREAL", "TON", "TOF", "TP", "CTU",
    "CTD",
];

/// Function names (calls).
pub const FUNCTIONS: &[&str] = &[
    "BCD", "BIN", "MIN", "MAX", "LIMIT", "ABS", "BOOL", "BYTE", "WORD", "DWORD", "INT", "DINT",
    "REAL", "LREAL", "TON", "TOF", "TP",
];
