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
//! | 920 | AXCFIL: instruction used before `PRO` opened a process subsection |
//! | 921 | AXCFIL: process declared twice (`PRO=n` repeated in one section) |
//! | 922 | AXCFIL: a process of NBP has no `PRO` in section 1, or a process has no `INx` or no `CAS` |
//! | 923 | AXCFIL: COM in process 1, or COM names a later process |
//! | 925 | AXCFIL: continuous axis name not one of A B C D X Y Z U V W P Q |
//! | 926 | AXCFIL: block_num of a PTP interpolator is not 1, or of a coordinated interpolator not 2…64 |
//! | 927 | AXCFIL: the axes of CAS are not in the order of the interpolators |
//! | 928 | AXCFIL: NAS subsections are not in CAS order |
//! | 929 | AXCFIL: a parameter is out of the range the manual gives for it (PAS el_pitch > 0, POM deviation 0…1, ADP levels, ATR ST/MT, ADG voltages, KKRM speed 4.9, HDBRP > 0 and Δs ≠ 0, SSI el_pitch = 2^ST) |
//! | 930 | AXCFIL: unknown or unused axis-type bit in TPA (bit 17, bits 22–31) |
//! | 931 | AXCFIL: instruction not allowed for this axis type (SRV not 0 for a spindle/PTP axis; VGAS without a GAS backlash; MAN, RAP speed or POS wait time on a spindle; 5-parameter MCZ without the KKRM bit) |
//! | 932 | AXCFIL: TSM missing for a spindle with controlled acceleration (0800) or AC motor (4000) |
//! | 934 | AXCFIL: section-3 rule broken (PAS ≤ 0, more than 1000 points, NAS/NAC of an unknown axis, formulas 4.13–4.15, rotary pitch not dividing 360°) |
//! | 935 | AXCFIL: ECDF form of an instruction used without ECDF in NBP |
//! | 936 | AXCFIL: the same PLC signal twice in one instruction where the manual requires two different ones |
//! | 938 | AXCFIL: point-to-point axis in the coordinated interpolator (with continuous axes or the spindle) |
//! | 940 | AXCFIL: handwheel (correction) axis listed in an interpolator |
//! | 941 | AXCFIL: the axis named in COM was not declared in the named process |
//! | 942 | AXCFIL: NBP, TIM or ACC written more than once in section 1 |
//! | 943 | AXCFIL: a section-3 FEG file does not exist or has a line that is not `Ennn=value` |
//! | 944 | AXCFIL: bad `file/MPx` reference in FTP or FEG |
//! | 945 | AXCFIL: a slave parallel axis homes (MCZ direction or speed) differently from its master |
//! | 946 | PLC message file: a line that is not `nnn text` (or a text with a control character, or longer than 200 characters) |
//! | 947 | PLC message file: message number outside 1..64 |
//! | 948 | PLC message file: message number given twice |
//! | 949 | PGCFIL FLC names a PLC message file that does not exist |
//! | 975 | warning: FCRSYS binds FILMS1–FILMS4 or FORMAT to an existing file, which ncplc does not read (its own messages and table formats) |
//! | 976 | FCRSYS binds FILCMD or FILMAS to an existing file: programs and blocks started on PLC request are not implemented |
//!
//! (975–979 are machine loading's too: 900–949 is full, its free numbers being retired codes.)

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
/// Project 920: instruction before PRO.
pub const NO_PROCESS: u32 = 920;
/// Project 921: process declared twice.
pub const PROCESS_TWICE: u32 = 921;
/// Project 922: process lacks a mandatory instruction or subsection.
pub const PROCESS_INCOMPLETE: u32 = 922;
/// Project 923: COM in process 1 or naming a later process.
pub const COM_PROCESS: u32 = 923;
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
/// Project 934: section-3 rule.
pub const SECTION3: u32 = 934;
/// Project 935: ECDF form without ECDF.
pub const ECDF_FORM: u32 = 935;
/// Project 936: same signal twice in one instruction.
pub const SIGNAL_TWICE: u32 = 936;
/// Project 938: axis kind does not fit the interpolator kind.
pub const INTERPOLATOR_KIND: u32 = 938;
/// Project 940: handwheel axis in an interpolator.
pub const INTERPOLATOR_EXCLUDED: u32 = 940;
/// Project 941: COM axis not in the named process.
pub const COM_AXIS: u32 = 941;
/// Project 942: instruction written twice in section 1.
pub const SECTION1_TWICE: u32 = 942;
/// Project 943: FEG file missing or malformed.
pub const FEG_FILE: u32 = 943;
/// Project 944: bad `file/MPx` reference.
pub const FILE_REF: u32 = 944;
/// Project 945: slave homes differently from its master.
pub const SLAVE_HOMING: u32 = 945;
/// Project 946: a PLC message file line that is not `nnn text`.
pub const MESSAGE_LINE: u32 = 946;
/// Project 947: PLC message number outside 1..64.
pub const MESSAGE_NUMBER: u32 = 947;
/// Project 948: PLC message number given twice.
pub const MESSAGE_TWICE: u32 = 948;
/// Project 949: the PLC message file FLC names does not exist.
pub const MESSAGE_FILE_MISSING: u32 = 949;
/// Project 975 (warning): a section-2 file ncplc does not read exists (FILMS1–4, FORMAT).
pub const FILE_NOT_READ: u32 = 975;
/// Project 976: FILCMD or FILMAS binds an existing file (PLC-requested programs: not implemented).
pub const FILE_NOT_IMPLEMENTED: u32 = 976;

// AXCFIL, Table 7.2 (numbers ≥ 101 are file-specific: these are the AXCFIL meanings).

/// AXCFIL 101: TIM tick greater than 63.
pub const TIM_TOO_BIG: u32 = 101;
/// AXCFIL 102: CPU number in INx or CAS missing (not 1).
pub const CPU_NOT_ONE: u32 = 102;
/// AXCFIL 103: CPU number in CAS not 1.
pub const CAS_CPU: u32 = 103;
/// AXCFIL 104: drive-control tick zero or too large.
pub const SERVO_TICK: u32 = 104;
/// AXCFIL 105: CPU number in INx not 1.
pub const INTERPOLATOR_CPU: u32 = 105;
/// AXCFIL 106: block_num outside 1…64.
pub const TOO_MANY_ELEMENTS: u32 = 106;
/// AXCFIL 107: interpolator tick zero or too large.
pub const INTERPOLATOR_TICK: u32 = 107;
/// AXCFIL 108: more than one spindle in an interpolator.
pub const ONE_SPINDLE: u32 = 108;
/// AXCFIL 109: interpolator without axes.
pub const INTERPOLATOR_EMPTY: u32 = 109;
/// AXCFIL 110: more than 9 interpolators in a process.
pub const INTERPOLATOR_TABLE_FULL: u32 = 110;
/// AXCFIL 111: duplicated interpolator name.
pub const INTERPOLATOR_DUPLICATE: u32 = 111;
/// AXCFIL 112: CAS without axes.
pub const CAS_EMPTY: u32 = 112;
/// AXCFIL 113: an axis twice in CAS.
pub const CAS_DUPLICATE: u32 = 113;
/// AXCFIL 114: axis table full (more than 17 axes, or more than 8 continuous axes).
pub const AXIS_TABLE_FULL: u32 = 114;
/// AXCFIL 115: more than 8 axes in one interpolator.
pub const INTERPOLATOR_AXES: u32 = 115;
/// AXCFIL 116: an axis in several interpolators.
pub const AXIS_SEVERAL_INTERPOLATORS: u32 = 116;
/// AXCFIL 118: an axis in several CAS (a second CAS, or a common axis listed again).
pub const CAS_TWICE: u32 = 118;
/// AXCFIL 119: interpolator axis not in CAS.
pub const AXIS_NOT_IN_CAS: u32 = 119;
/// AXCFIL 120: interpolator tick not a multiple of the servo tick.
pub const INT_TICK_SERVO: u32 = 120;
/// AXCFIL 121: TIM missing.
pub const TIM_MISSING: u32 = 121;
/// AXCFIL 124: CPU tick zero.
pub const TIM_ZERO: u32 = 124;
/// AXCFIL 126: different servo ticks on the same CPU.
pub const SERVO_TICKS_DIFFER: u32 = 126;
/// AXCFIL 127: servo tick not a multiple of the CPU tick.
pub const SERVO_TICK_CPU: u32 = 127;
/// AXCFIL 128: interpolator tick not a multiple of the CPU tick.
pub const INT_TICK_CPU: u32 = 128;
/// AXCFIL 131: instruction repeated in a NAS subsection.
pub const DUPLICATE_INSTRUCTION: u32 = 131;
/// AXCFIL 132: TPA missing.
pub const TPA_MISSING: u32 = 132;
/// AXCFIL 133: NTC missing.
pub const NTC_MISSING: u32 = 133;
/// AXCFIL 134: GAS missing on an axis with a transducer.
pub const GAS_MISSING: u32 = 134;
/// AXCFIL 135: PAS missing on an axis with a transducer.
pub const PAS_MISSING: u32 = 135;
/// AXCFIL 137: RAP missing.
pub const RAP_MISSING: u32 = 137;
/// AXCFIL 138: MAN missing.
pub const MAN_MISSING: u32 = 138;
/// AXCFIL 139: manual speed above rapid speed.
pub const MAN_SPEED: u32 = 139;
/// AXCFIL 140: manual acceleration above rapid acceleration.
pub const MAN_ACCEL: u32 = 140;
/// AXCFIL 141: POS missing on an axis with a transducer.
pub const POS_MISSING: u32 = 141;
/// AXCFIL 142: SRV missing on an axis with a transducer.
pub const SRV_MISSING: u32 = 142;
/// AXCFIL 147: GM0 on a spindle.
pub const GM0_ON_SPINDLE: u32 = 147;
/// AXCFIL 148: GM1 missing on a spindle.
pub const GM1_MISSING: u32 = 148;
/// AXCFIL 149: NAS axis not declared in section 1.
pub const NAS_UNDECLARED: u32 = 149;
/// AXCFIL 150: GMxx with xx ≠ 0 on a non-spindle axis.
pub const GM_NOT_ZERO: u32 = 150;
/// AXCFIL 151: section-2 instruction without a preceding NAS.
pub const NO_NAS: u32 = 151;
/// AXCFIL 152: GMnn, RAP, MAN or POS on an axis without interpolator.
pub const NO_INTERPOLATOR: u32 = 152;
/// AXCFIL 153: electrical pitch zero.
pub const EL_PITCH_ZERO: u32 = 153;
/// AXCFIL 154: mechanical pitch zero.
pub const MEC_PITCH_ZERO: u32 = 154;
/// AXCFIL 155: INx spindle without spindle type in section 2.
pub const SPINDLE_TYPE: u32 = 155;
/// AXCFIL 157: coordinate axis declared point-to-point.
pub const COORDINATE_PTP: u32 = 157;
/// AXCFIL 158: switched-axis name longer than one character.
pub const SWITCH_NAME: u32 = 158;
/// AXCFIL 159: switched axis not declared in section 1.
pub const SWITCH_UNDECLARED: u32 = 159;
/// AXCFIL 160: transducer number not 1…16.
pub const TRANSDUCER_NUMBER: u32 = 160;
/// AXCFIL 161: converter number not 1…16 / −201…−216.
pub const CONVERTER_NUMBER: u32 = 161;
/// AXCFIL 163: homing direction not 0 or 1.
pub const MCZ_DIRECTION: u32 = 163;
/// AXCFIL 166: ASM master name longer than one character.
pub const ASM_NAME: u32 = 166;
/// AXCFIL 167: ASM master not declared.
pub const ASM_UNDECLARED: u32 = 167;
/// AXCFIL 168: switched axes do not name each other.
pub const SWITCH_MISMATCH: u32 = 168;
/// AXCFIL 169: section-1 axis without a section-2 NAS.
pub const AXIS_NOT_DEFINED: u32 = 169;
/// AXCFIL 172: GMxx with xx > 99.
pub const GM_RANGE: u32 = 172;
/// AXCFIL 173: Ennn/NM0/PAS without NAS (and PAS) in section 3.
pub const S3_NO_NAS: u32 = 173;
/// AXCFIL 174: Ennn numbers not increasing.
pub const S3_ORDER: u32 = 174;
/// AXCFIL 175: fewer than 2 compensation values.
pub const S3_TOO_FEW: u32 = 175;
/// AXCFIL 176: NM0 syntax error.
pub const NM0_SYNTAX: u32 = 176;
/// AXCFIL 177: NM0 names a point that does not exist.
pub const NM0_UNKNOWN: u32 = 177;
/// AXCFIL 178: converter in TPA and NTC disagree.
pub const CONVERTER_MISMATCH: u32 = 178;
/// AXCFIL 179: spindle with and without encoder.
pub const SPINDLE_BOTH: u32 = 179;
/// AXCFIL 180: TSM parameter omitted or 0.
pub const TSM_PARAMS: u32 = 180;
/// AXCFIL 181: TSM on a non-spindle axis.
pub const TSM_NOT_SPINDLE: u32 = 181;
/// AXCFIL 182: GMnn or TSM before NTC.
pub const BEFORE_NTC: u32 = 182;
/// AXCFIL 183: more than 5 processes in NBP.
pub const NBP_TOO_MANY: u32 = 183;
/// AXCFIL 184: PRO above NBP or not configured.
pub const PRO_ABOVE_NBP: u32 = 184;
/// AXCFIL 185: CAS/INx before NBP.
pub const NO_NBP: u32 = 185;
/// AXCFIL 187: PRO without process number.
pub const PRO_EMPTY: u32 = 187;
/// AXCFIL 188: POM on a non-spindle axis.
pub const POM_NOT_SPINDLE: u32 = 188;
/// AXCFIL 189: POM missing on a spindle with encoder.
pub const POM_MISSING: u32 = 189;
/// AXCFIL 190: ADP/ADG converter number too large.
pub const ADC_NUMBER: u32 = 190;
/// AXCFIL 191: ADP P_100 zero.
pub const ADP_ZERO: u32 = 191;
/// AXCFIL 193: SKW on a non-slave axis.
pub const SKW_NOT_SLAVE: u32 = 193;
/// AXCFIL 194: SKW master name longer than one character.
pub const SKW_NAME: u32 = 194;
/// AXCFIL 195: SKW master not declared.
pub const SKW_UNDECLARED: u32 = 195;
/// AXCFIL 196: master already master of another axis.
pub const SKW_MASTER_TWICE: u32 = 196;
/// AXCFIL 197: slave already used in another SKW.
pub const SKW_SLAVE_TWICE: u32 = 197;
/// AXCFIL 198: slave axis with instructions other than NAS, TPA, NTC, GAS, PAS, MCZ, MFC, SKW.
pub const SLAVE_INSTRUCTIONS: u32 = 198;
/// AXCFIL 199: axis slave of itself.
pub const SKW_SELF: u32 = 199;
/// AXCFIL 200: slave axis in an interpolator.
pub const SLAVE_INTERPOLATED: u32 = 200;
/// AXCFIL 201: slave declared before its master.
pub const SLAVE_BEFORE_MASTER: u32 = 201;
/// AXCFIL 203: control-point axis without ASM.
pub const CONTROL_POINT_ASM: u32 = 203;
/// AXCFIL 204: ADG, CUB or SWn not allowed for the axis type.
pub const TYPE_FORBIDS_ZONE: u32 = 204;
/// AXCFIL 205: packet-A signal in SWn.
pub const SW_PACKET_A: u32 = 205;
/// AXCFIL 206: ACC coefficients out of range.
pub const ACC_COEFFICIENTS: u32 = 206;
/// AXCFIL 207: more than three CUB axes.
pub const CUB_AXES: u32 = 207;
/// AXCFIL 209: MCZ, FBF, ZNO or FTP before PAS.
pub const BEFORE_PAS: u32 = 209;
/// AXCFIL 210: DAC/DPC number above 200.
pub const CONVERTER_ABOVE_200: u32 = 210;
/// AXCFIL 211: type must be exactly 2 (tool magazine PAS, FTP).
pub const TYPE_NOT_2: u32 = 211;
/// AXCFIL 212: FRC before GM0.
pub const FRC_BEFORE_GM0: u32 = 212;
/// AXCFIL 213: FTP file not correct.
pub const FTP_FILE: u32 = 213;
/// AXCFIL 214: FTP file missing.
pub const FTP_MISSING: u32 = 214;
/// AXCFIL 215: ZNO distance without input_distance.
pub const ZNO_SIGNAL: u32 = 215;
/// AXCFIL 216: GRA signal not the lowest bit of a packet-A byte.
pub const GRA_SIGNAL: u32 = 216;
/// AXCFIL 217: GRA resolution above 16.
pub const GRA_BITS: u32 = 217;
/// AXCFIL 218: GRA without the Gray-code type bit.
pub const GRA_TYPE: u32 = 218;
/// AXCFIL 219: wrong axis name in HWC.
pub const HWC_AXIS: u32 = 219;
/// AXCFIL 220: CANn with n not 1…4.
pub const CAN_NUMBER: u32 = 220;
/// AXCFIL 221: MCZ zero_input written for a KKRM axis.
pub const MCZ_KKRM_INPUT: u32 = 221;
/// AXCFIL 222: GMnn KC above 10 V.
pub const KC_ABOVE_10: u32 = 222;
/// AXCFIL 223: FOPP signal in packet A or not the lowest bit of a byte.
pub const FOPP_SIGNAL: u32 = 223;
/// AXCFIL 224: FOPP on a non-PTP axis.
pub const FOPP_NOT_PTP: u32 = 224;
/// AXCFIL 225: ADG signals 4–7 missing.
pub const ADG_SIGNALS: u32 = 225;
/// AXCFIL 227: ATR without the SSI type bit.
pub const ATR_TYPE: u32 = 227;
/// AXCFIL 228: SSI type bit without ATR.
pub const ATR_MISSING: u32 = 228;
/// Project 970: NUL byte in a characterization file (not a text file; reading stops there).
pub const NOT_TEXT: u32 = 970;
/// Project 971: too many consecutive lines that are not records (reading stops).
pub const GAVE_UP: u32 = 971;
/// Project 972: the file is empty or holds only comments (not validated further).
pub const EMPTY_FILE: u32 = 972;
/// Project 973: more records than any valid file has ([`crate::reader::MAX_RECORDS`]; reading stops).
pub const TOO_MANY_RECORDS: u32 = 973;
/// Project 974: a file larger than [`crate::reader::MAX_BYTES`] (read that far, then abandoned).
pub const TOO_LARGE: u32 = 974;
