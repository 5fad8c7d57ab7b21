//! Diagnostic code numbers: the manual's chapter-7 numbers and the project's own 900–999 range.
//!
//! Codes 1–25 are Table 7.1 (common to AXCFIL, PGCFIL and IOCFIL). Codes 101–228 are
//! file-specific: the same number means different things in AXCFIL (Table 7.2), PGCFIL (7.3) and
//! IOCFIL (7.4); the diagnostic's `file` tells them apart, as the manual's INDEX field does.
//!
//! Rules the manual states without a number get a project number. The range is split between the
//! two modules that validate files: **900–949** reader, FCRSYS, AXCFIL and machine loading (this
//! list), **950–999** PGCFIL and IOCFIL (see their modules).
//!
//! | code | meaning |
//! |---|---|
//! | 900 | non-ASCII character outside a comment |
//! | 901 | boolean parameter is not 0 or 1 |
//! | 902 | a file cannot be read (missing FCRSYS, AXCFIL, PGCFIL or IOCFIL) |
//! | 903 | FCRSYS: lower-case letters (all FCRSYS text must be upper case) |
//! | 904 | FCRSYS: instruction not allowed in this section (unknown name, `MPx` with x > 6, …) |
//! | 905 | FCRSYS: mandatory `MP0` or `MP1` missing in section 1 |
//! | 906 | FCRSYS: bad path (empty, longer than 255 characters, or ending in `\`) |
//! | 907 | FCRSYS: unknown fixed logical name in section 2 |
//! | 908 | FCRSYS: mandatory logical name (AXCONF, PGCONF, IOCONF, FORMAT) missing in section 2 |
//! | 909 | FCRSYS: bad `file_name/MPx` reference (name not 1–6 alphanumerics starting with a letter, or no `/MPx`) |
//! | 910 | FCRSYS: section 2 refers to a logical path `MPx` not declared in section 1 |
//! | 911 | FCRSYS: IDE Primary Master declared as `CD` |
//! | 912 | FCRSYS: name declared twice |
//! | 913 | FCRSYS: the closing lone `*` is missing |
//! | 914 | FCRSYS: bad HDD drive letters (more than three, or not letters) |
//! | 915 | a file named in FCRSYS does not exist in the machine directory |
//! | 916 | warning: the PLC program (PLCSRC, default `MP0/PLCPRG`) does not exist |
//! | 917 | AXCFIL: NBP process count is 0 |
//! | 918 | AXCFIL: NBP software extension is not a sum of 0, 1, 2 and ECDF |
//! | 919 | AXCFIL: TIM CPU tick is 0 or missing its value |
//! | 920 | AXCFIL: instruction used before `PRO` opened a process subsection |
//! | 921 | AXCFIL: process declared twice (`PRO=n` repeated in one section) |
//! | 922 | AXCFIL: process missing a section-1 instruction (`INx` or `CAS`) or a section-2 subsection |
//! | 923 | AXCFIL: COM in process 1, or COM names a later process |
//! | 924 | AXCFIL: a common axis (COM) is listed again in the CAS of the current process |
//! | 925 | AXCFIL: continuous axis name not one of A B C D X Y Z U V W P Q |
//! | 926 | AXCFIL: block_num of a PTP interpolator is not 1, or of a coordinated interpolator not 2…64 |
//! | 927 | AXCFIL: the axes of CAS are not in the order of the interpolators |
//! | 928 | AXCFIL: NAS subsections are not in CAS order |
//! | 929 | AXCFIL: a parameter is out of the range the manual gives for it |
//! | 930 | AXCFIL: unknown or unused axis-type bit in TPA (bit 17, bits 22–31) |
//! | 931 | AXCFIL: instruction not allowed for this axis type (SRV not 0 for a spindle/PTP axis, MAN or RAP speed on a spindle, …) |
//! | 932 | AXCFIL: TSM missing for a spindle with controlled acceleration (0800) or AC motor (4000) |
//! | 933 | AXCFIL: tool-magazine PTP axis: PAS positions or motor revolutions is 0 |
//! | 934 | AXCFIL: section-3 rule broken (PAS ≤ 0, more than 1000 points, NAS of an unknown axis) |
//! | 935 | AXCFIL: ECDF form of an instruction used without ECDF in NBP |
//! | 936 | AXCFIL: the same PLC signal twice in one instruction where the manual requires two different ones |
//! | 937 | AXCFIL: an axis declared in two processes without COM |
//! | 938 | AXCFIL: PTP axis in the coordinated interpolator, or coordinate axis in a PTP interpolator |
//! | 939 | AXCFIL: interpolator name used in two processes |
//! | 940 | AXCFIL: slave parallel axis or handwheel axis listed in an interpolator |
//! | 941 | AXCFIL: the axis named in COM was not declared in the named process |
//! | 942 | AXCFIL: ACC written more than once |

/// Table 7.1 code 1: not enough sections.
pub const MISSING_SECTIONS: u32 = 1;
/// Table 7.1 code 2: a line must start with `*`, a letter or `;`.
pub const LINE_START: u32 = 2;
/// Table 7.1 code 3: section not defined (the file does not start with `*1`).
pub const NO_SECTION: u32 = 3;
/// Table 7.1 code 4: section number differs from the expected one.
pub const SECTION_ORDER: u32 = 4;
/// Table 7.1 code 5: the section marker is not alone on its line.
pub const SECTION_CR: u32 = 5;
/// Table 7.1 code 6: instruction not allowed in this section or configuration.
pub const NOT_ALLOWED: u32 = 6;
/// Table 7.1 code 7: instruction name longer than 5 characters.
pub const NAME_TOO_LONG: u32 = 7;
/// Table 7.1 code 8: no `=` after the instruction name.
pub const NO_EQUALS: u32 = 8;
/// Table 7.1 code 9: invalid character in the instruction name.
pub const BAD_NAME_CHAR: u32 = 9;
/// Table 7.1 code 10: not enough parameters.
pub const TOO_FEW_PARAMS: u32 = 10;
/// Table 7.1 code 11: too many parameters.
pub const TOO_MANY_PARAMS: u32 = 11;
/// Table 7.1 code 13: an INTEGER parameter has a non-digit.
pub const INTEGER_SYNTAX: u32 = 13;
/// Table 7.1 code 14: INTEGER outside −32768…32767.
pub const INTEGER_OVERFLOW: u32 = 14;
/// Table 7.1 code 15: a WORD parameter has a non-digit.
pub const WORD_SYNTAX: u32 = 15;
/// Table 7.1 code 16: WORD outside 0…65535.
pub const WORD_OVERFLOW: u32 = 16;
/// Table 7.1 code 17: a PLC signal must start with `I` or `U`.
pub const SIGNAL_PREFIX: u32 = 17;
/// Table 7.1 code 18: connector or contact number out of range.
pub const SIGNAL_NUMBER: u32 = 18;
/// Table 7.1 code 19: packet letter not K, N, A or T.
pub const SIGNAL_PACKET: u32 = 19;
/// Table 7.1 code 20: a REAL parameter has non-numeric characters.
pub const REAL_SYNTAX: u32 = 20;
/// Table 7.1 code 21: a hexadecimal parameter has a bad character.
pub const HEX_SYNTAX: u32 = 21;
/// Table 7.1 code 22: a hexadecimal parameter has too many digits.
pub const HEX_DIGITS: u32 = 22;
/// Table 7.1 code 23: ASCII parameter longer than 10 characters.
pub const ASCII_TOO_LONG: u32 = 23;
/// Table 7.1 code 24: too many sections.
pub const TOO_MANY_SECTIONS: u32 = 24;
/// Table 7.1 code 25: PGCFIL must start with NEW or OLD.
pub const PGCFIL_HEADER: u32 = 25;

/// Project 900: non-ASCII character outside a comment.
pub const NON_ASCII: u32 = 900;
/// Project 901: boolean parameter not 0 or 1.
pub const BOOLEAN: u32 = 901;
/// Project 902: a file cannot be read.
pub const FILE_UNREADABLE: u32 = 902;
/// Project 903: FCRSYS text not upper case.
pub const FCRSYS_CASE: u32 = 903;
/// Project 904: FCRSYS instruction not allowed in this section.
pub const FCRSYS_NOT_ALLOWED: u32 = 904;
/// Project 905: FCRSYS MP0/MP1 missing.
pub const FCRSYS_MP_MISSING: u32 = 905;
/// Project 906: FCRSYS bad path.
pub const FCRSYS_PATH: u32 = 906;
/// Project 907: FCRSYS unknown logical name.
pub const FCRSYS_UNKNOWN_NAME: u32 = 907;
/// Project 908: FCRSYS mandatory logical name missing.
pub const FCRSYS_NAME_MISSING: u32 = 908;
/// Project 909: FCRSYS bad `file/MPx` reference.
pub const FCRSYS_FILE_REF: u32 = 909;
/// Project 910: FCRSYS section 2 uses an undeclared `MPx`.
pub const FCRSYS_MP_UNDECLARED: u32 = 910;
/// Project 911: FCRSYS IDE PM = CD.
pub const FCRSYS_IDE_PM: u32 = 911;
/// Project 912: FCRSYS name declared twice.
pub const FCRSYS_DUPLICATE: u32 = 912;
/// Project 913: FCRSYS closing `*` missing.
pub const FCRSYS_END: u32 = 913;
/// Project 914: FCRSYS bad HDD letters.
pub const FCRSYS_HDD: u32 = 914;
/// Project 915: a file named in FCRSYS does not exist.
pub const FILE_MISSING: u32 = 915;
/// Project 916: the PLC program does not exist (warning).
pub const PLC_SOURCE_MISSING: u32 = 916;
/// Project 917: NBP process count 0.
pub const NBP_ZERO: u32 = 917;
/// Project 918: NBP extension not a valid sum.
pub const NBP_EXTENSION: u32 = 918;
/// Project 919: TIM tick 0 or missing.
pub const TIM_ZERO: u32 = 919;
/// Project 920: instruction before PRO.
pub const NO_PROCESS: u32 = 920;
/// Project 921: process declared twice.
pub const PROCESS_TWICE: u32 = 921;
/// Project 922: process lacks a mandatory instruction or subsection.
pub const PROCESS_INCOMPLETE: u32 = 922;
/// Project 923: COM in process 1 or naming a later process.
pub const COM_PROCESS: u32 = 923;
/// Project 924: common axis listed in CAS again.
pub const COM_IN_CAS: u32 = 924;
/// Project 925: bad continuous axis name.
pub const AXIS_LETTER: u32 = 925;
/// Project 926: block_num does not fit the interpolator kind.
pub const BLOCK_NUM: u32 = 926;
/// Project 927: CAS not in interpolator order.
pub const CAS_ORDER: u32 = 927;
/// Project 928: NAS not in CAS order.
pub const NAS_ORDER: u32 = 928;
/// Project 929: parameter outside the manual's range.
pub const RANGE: u32 = 929;
/// Project 930: unknown axis-type bit.
pub const TPA_BITS: u32 = 930;
/// Project 931: instruction not allowed for this axis type.
pub const TYPE_FORBIDS: u32 = 931;
/// Project 932: TSM missing.
pub const TSM_MISSING: u32 = 932;
/// Project 933: tool magazine PAS incomplete.
pub const TOOL_MAGAZINE: u32 = 933;
/// Project 934: section-3 rule.
pub const SECTION3: u32 = 934;
/// Project 935: ECDF form without ECDF.
pub const ECDF_FORM: u32 = 935;
/// Project 936: same signal twice in one instruction.
pub const SIGNAL_TWICE: u32 = 936;
/// Project 937: axis in two processes without COM.
pub const AXIS_TWO_PROCESSES: u32 = 937;
/// Project 938: axis kind does not fit the interpolator kind.
pub const INTERPOLATOR_KIND: u32 = 938;
/// Project 939: interpolator name used in two processes.
pub const INTERPOLATOR_NAME: u32 = 939;
/// Project 940: slave or handwheel axis in an interpolator.
pub const INTERPOLATOR_EXCLUDED: u32 = 940;
/// Project 941: COM axis not in the named process.
pub const COM_AXIS: u32 = 941;
/// Project 942: ACC written more than once.
pub const ACC_TWICE: u32 = 942;
