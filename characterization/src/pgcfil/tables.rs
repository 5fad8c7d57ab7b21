//! The manual's built-in tables that PGCFIL personalizes: three-letter codes (Table 5.1), system
//! variables of the symbol table (Table 5.2), JCL codes (Table 5.6) and the GXX classes (Table 5.7).

/// Table 5.1: part-program three-letter codes and their default synchronization code.
pub const THREE_LETTER_CODES: &[(&str, u8)] = &[
    ("WAI", 1),
    ("REL", 1),
    ("UAV", 1),
    ("USS", 1),
    ("MOV", 1),
    ("WTA", 1),
    ("SCF", 1),
    ("RQO", 1),
    ("MPT", 1),
    ("DPI", 1),
    ("MDV", 1),
    ("DTL", 1),
    ("EXE", 2),
    ("SND", 2),
    ("GTA", 2),
    ("PTA", 2),
    ("EAX", 2),
    ("DAX", 2),
    ("DAW", 2),
    ("ADR", 2),
    ("TRD", 2),
    ("CLS", 3),
    ("DPT", 3),
    ("RED", 3),
    ("BNC", 3),
    ("DIS", 3),
    ("SCR", 3),
    ("BGT", 3),
    ("TOF", 3),
    ("WRT", 3),
    ("BLT", 3),
    ("RQU", 3),
    ("BEQ", 3),
    ("RQP", 3),
    ("BNE", 3),
    ("UCG", 3),
    ("BGE", 3),
    ("CLG", 3),
    ("BLE", 3),
    ("DCG", 3),
    ("EPP", 3),
    ("RPT", 3),
    ("DEF", 3),
    ("ERP", 3),
    ("FIL", 3),
    ("UAO", 3),
    ("TGL", 3),
    ("UOT", 3),
    ("DFP", 3),
    ("UIO", 3),
    ("EPF", 3),
    ("MIR", 3),
    ("SPA", 3),
    ("URT", 3),
    ("SPF", 3),
    ("SPP", 3),
    ("CLP", 3),
    ("DLY", 3),
    ("CAN", 3),
    ("RLG", 3),
    ("DLO", 3),
    ("CLO", 3),
    ("BSP", 3),
    ("DSA", 3),
    ("CRE", 3),
    ("ESP", 3),
    ("ASC", 3),
    ("DER", 3),
    ("DSC", 3),
    ("INP", 3),
    ("CTL", 3),
    ("OPN", 3),
    ("DAM", 3),
    ("OUT", 3),
];

/// Table 5.6: JCL command codes (default synchronization code 4 for all).
pub const JCL_CODES: &[&str] = &[
    "CAC", "CAO", "CTU", "ORA", "VOA", "UCA", "VTU", "DIS", "DPT", "EVA", "RCM", "ERM", "ESE",
    "SPG", "REL", "RIF", "RLG", "VLG", "MTO", "DBT", "GSE", "UCG", "CLG", "DCG", "URP", "PTM",
    "VIC",
];

/// One row of Table 5.2.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SystemVariable {
    /// Name (case-sensitive: `o`, `p`, `l`, `c` are lower-case).
    pub name: &'static str,
    /// Default maximum number of elements.
    pub max_num: u32,
    /// Default type code (Table 5.4), 0 = none.
    pub def_type: u8,
    /// Admissible types (Table 5.5 bit sum).
    pub amm_type: u32,
    /// Default synchronization code, 0 where the table is empty.
    pub synchro: u8,
    /// Modification parameter: 2 = max_num may change, 1 = only the name.
    pub modif: u8,
}

const fn v(
    name: &'static str,
    max_num: u32,
    def_type: u8,
    amm_type: u32,
    synchro: u8,
    modif: u8,
) -> SystemVariable {
    SystemVariable {
        name,
        max_num,
        def_type,
        amm_type,
        synchro,
        modif,
    }
}

/// Table 5.2, copied as printed (inconsistent rows kept, see spec §10 item 12).
pub const SYSTEM_VARIABLES: &[SystemVariable] = &[
    v("E", 40, 6, 62, 3, 2),
    v("o", 5, 0, 0, 3, 2),
    v("p", 15, 0, 0, 3, 2),
    v("l", 15, 0, 0, 3, 2),
    v("c", 15, 0, 0, 3, 2),
    v("TMR", 1, 6, 32, 3, 1),
    v("UOV", 1, 6, 32, 3, 1),
    v("JOG", 1, 6, 32, 3, 1),
    v("RTA", 1, 6, 8, 3, 1),
    v("RTO", 1, 6, 8, 3, 1),
    v("ERF", 1, 6, 32, 3, 1),
    v("MCD", 1, 6, 32, 3, 1),
    v("USB", 1, 1, 1, 3, 1),
    v("UVR", 1, 1, 1, 3, 1),
    v("USO", 1, 1, 1, 3, 1),
    v("URL", 1, 1, 1, 3, 1),
    v("UCV", 1, 2, 2, 3, 1),
    v("RAP", 1, 1, 1, 3, 1),
    v("MDF", 1, 1, 1, 3, 1),
    v("UAS", 1, 1, 1, 3, 1),
    v("RMS", 1, 2, 2, 3, 1),
    v("UEP", 1, 1, 1, 3, 1),
    v("SA", 1024, 1, 127, 2, 1),
    v("SK", 1024, 1, 127, 2, 1),
    v("SN", 1024, 1, 127, 2, 1),
    v("SYVAR", 200, 2, 127, 3, 1),
    v("TIM", 7, 4, 16, 3, 1),
    v("TOT", 7, 4, 16, 3, 1),
    v("SSL", 1, 6, 32, 4, 1),
    v("ACP", 1, 6, 32, 4, 1),
    v("VOL", 1, 1, 1, 3, 1),
    v("ERR", 1, 1, 1, 3, 1),
    v("IOSTA", 1, 2, 2, 3, 1),
    v("MBR", 1, 1, 1, 3, 1),
    v("RTR", 1, 1, 1, 0, 1),
    v("SRT", 1, 6, 32, 0, 1),
    v("VRT", 1, 6, 32, 0, 1),
    v("PRT", 1, 6, 32, 0, 1),
];

/// The Table 5.2 row of `name`.
pub fn system_variable(name: &str) -> Option<&'static SystemVariable> {
    SYSTEM_VARIABLES.iter().find(|r| r.name == name)
}

/// Default synchronization code of a Table 5.1 code.
pub fn three_letter_code(name: &str) -> Option<u8> {
    THREE_LETTER_CODES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| *s)
}

/// Table 5.7: admissible G codes of GXX class 1…6 (index 0…5).
pub const G_CLASSES: [&[u8]; 6] = [
    &[0, 1, 2, 3],
    &[27, 28, 29],
    &[90, 91],
    &[70, 71],
    &[93, 94, 95],
    &[96, 97],
];

/// Variables ASS may assign besides Table 5.2 names: the 5.8.2 list (E25, E30 and packet-byte forms are matched separately).
pub const ASS_ONLY: &[&str] = &["E25", "E30"];

/// True when `name` is something ASS may assign: a Table 5.2 name, an indexed form of an array
/// variable (`SK1023`, `E30`, `SYVAR5`) within its default size, or one of `extra` (SIM-defined names).
pub fn assignable(name: &str, extra: &[String]) -> bool {
    if system_variable(name).is_some()
        || ASS_ONLY.contains(&name)
        || extra.iter().any(|e| e == name)
    {
        return true;
    }
    let split = name
        .find(|c: char| c.is_ascii_digit())
        .unwrap_or(name.len());
    let (base, index) = name.split_at(split);
    if index.is_empty() || !index.bytes().all(|b| b.is_ascii_digit()) {
        return false;
    }
    match (system_variable(base), index.parse::<u32>()) {
        (Some(row), Ok(i)) => row.max_num > 1 && i < row.max_num.max(65535),
        _ => false,
    }
}
