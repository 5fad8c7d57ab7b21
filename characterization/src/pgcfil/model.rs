//! The typed PGCFIL model: load mode, the common sections 1 and 3, and one [`PgProcess`] per process.
//!
//! Every instruction of chapter 5 has a field here; values the file omitted are `None` (the
//! defaults the manual states are exposed by accessor methods, not filled in, so a model
//! serializes back to what the file said).

use serde::{Deserialize, Serialize};

use packets::Signal;

/// How per-process state is treated at start-up (first word of PGCFIL).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum LoadMode {
    /// `NEW`: everything accumulated for the processes is reset.
    #[default]
    New,
    /// `OLD`: selected program, tool in spindle, packet-T bytes written by the PLC and the RCM context are restored.
    Old,
}

/// The second parameter of TRI / JCL: a new name or `D` (delete).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub enum NewName {
    /// Rename the code to this name.
    Rename(String),
    /// `D`: delete the code.
    Delete,
}

/// `TRI` (section 1) or `JCL` (section 3): rename or delete a three-letter code.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CodeRename {
    /// Existing code.
    pub old_name: String,
    /// New name or delete.
    pub new_name: NewName,
    /// Synchronization code 1…4; `None` keeps the table default.
    pub synchro: Option<u8>,
}

/// `SIM`: change the attributes of a symbol-table variable or define a new one.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SimDecl {
    /// Table 5.2 name, or `NEW` for a new variable.
    pub var_name: String,
    /// New name (or the name of the new variable).
    pub var_new: Option<String>,
    /// Maximum number of elements.
    pub max_num: Option<u32>,
    /// Default type code 1…7 (Table 5.4).
    pub def_type: Option<u8>,
    /// Admissible types, sum of Table 5.5 weights (≤ 127).
    pub amm_type: Option<u32>,
    /// Synchronization code 1…4.
    pub synchro: Option<u8>,
}

/// `ASS`: initial value of a system variable.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Assignment {
    /// Variable name (`USO`, `SK1023`, …).
    pub var_name: String,
    /// Value; booleans take `value > 0`.
    pub value: f64,
}

/// `NPL`: number of subprograms and labels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Npl {
    /// Subprograms called by CLS (default 10).
    pub prog_num: Option<u32>,
    /// Labels (default 10).
    pub label_num: Option<u32>,
}

/// `PRF`: profiles and blocks per profile for turning roughing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Prf {
    /// Profiles definable with DFP (default 8).
    pub prof_num: Option<u32>,
    /// Blocks per profile (default 16).
    pub block_num: Option<u32>,
}

/// A `name/MPx` file reference.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileRef {
    /// File name.
    pub name: String,
    /// Memory device number x of MPx (0…6).
    pub device: u8,
}

/// `FIL`: process files.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct ProcessFiles {
    /// Origin (zero-point) file.
    pub origins: Option<FileRef>,
    /// Tool-offset file.
    pub offsets: Option<FileRef>,
    /// Tool-life file.
    pub tool_life: Option<FileRef>,
    /// Random-tool table.
    pub random_tool: Option<FileRef>,
    /// Fifth parameter (not used by the CNC).
    pub unused: Option<FileRef>,
}

/// `DPM`: probe measuring parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Dpm {
    /// Approach distance at measuring speed, mm.
    pub appro_quote: Option<f64>,
    /// Safety distance, mm.
    pub safe_quote: Option<f64>,
    /// Measuring speed, mm/min.
    pub mis_speed: Option<f64>,
}

/// `TOF`: machine type (base code plus auxiliary 10 / 20).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct MachineType {
    /// The raw value as written (hex).
    pub raw: u8,
}

impl MachineType {
    /// Base code: 1 mill, 2 lathe, 5 mill switchable to turning, 6 lathe switchable to milling.
    pub fn base(&self) -> u8 {
        self.raw & 0x0F
    }
    /// True for the turning configurations (2, 6).
    pub fn is_lathe(&self) -> bool {
        matches!(self.base(), 2 | 6)
    }
    /// Aux 10: tool length along the diametral axis entered in diameter.
    pub fn diameter_offsets(&self) -> bool {
        self.raw & 0x10 != 0
    }
    /// Aux 20: ordinate direction inverted.
    pub fn inverted_ordinate(&self) -> bool {
        self.raw & 0x20 != 0
    }
    /// The power-on G codes of the six GXX classes for this machine type.
    pub fn default_g(&self) -> [u8; 6] {
        if self.is_lathe() {
            [0, 27, 90, 70, 95, 96]
        } else {
            [0, 27, 90, 70, 94, 97]
        }
    }
}

/// `CWP`: console keys and overrides.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Cwp {
    /// Bit sum of Table 5.8.
    pub cw_console: Option<u16>,
    /// 1 = part programs do not use tool compensation and GTL.
    pub no_offsets: Option<bool>,
}

/// Units of the characterization parameters (`G70`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Units {
    /// 0: millimetres (default).
    Millimetres,
    /// 1: inches.
    Inches,
}

/// `TAS`: touch probe for G72/G73.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tas {
    /// Safety input of the probe.
    pub probe_input: Option<Signal>,
    /// 1 normally closed, 0 normally open.
    pub probe_status: Option<u8>,
    /// Preferred approach, axis letter plus `+`/`-` (unused by the CNC).
    pub path: Option<String>,
    /// `S` oriented / `N` non-oriented (unused by the CNC).
    pub probe_type: Option<char>,
    /// Measuring input (method 2).
    pub mes_input: Option<Signal>,
    /// Measuring input rest state.
    pub mes_status: Option<u8>,
}

/// `INU`: touch probe for G74.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Inu {
    /// Safety input.
    pub probe_input: Option<Signal>,
    /// 1 normally closed, 0 normally open.
    pub probe_status: Option<u8>,
}

/// `TGA`: rotary axis for tangential mode TGM.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Tga {
    /// Rotary axis.
    pub axis: char,
    /// Angle between ordinate and the axis micro-zero, −360…360 degrees.
    pub angle: Option<f64>,
}

/// Everything PGCFIL says about one process (sections 2, 4, 5, 6).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct PgProcess {
    /// Process number 1…5.
    pub number: u32,
    /// Section 2: SIM declarations.
    pub sim: Vec<SimDecl>,
    /// Section 4: ASS assignments.
    pub ass: Vec<Assignment>,
    /// Section 4: NPL.
    pub npl: Option<Npl>,
    /// Section 4: NDD, default part-program device x of MPx (default 1).
    pub ndd: Option<u8>,
    /// Section 4: PRF.
    pub prf: Option<Prf>,
    /// Section 4: FIL.
    pub fil: Option<ProcessFiles>,
    /// Section 4: FLC, PLC message file (third parameter).
    pub flc: Option<FileRef>,
    /// Section 4: STR, number of formatted-file structures.
    pub structures: Option<u32>,
    /// Section 4: SER, extra RS232 bytes.
    pub ser: Option<u8>,
    /// Section 4: CHN, ASSET logical channels.
    pub chn: Option<u32>,
    /// Section 4: SCR, ASSET display memory.
    pub scr: Option<u32>,
    /// Section 5: NIP, interpolator name.
    pub nip: Option<char>,
    /// Section 5: DPM.
    pub dpm: Option<Dpm>,
    /// Section 5: SMC.
    pub smc: Option<f64>,
    /// Section 5: TOF.
    pub tof: Option<MachineType>,
    /// Section 5: GXX, one optional G code per class.
    pub gxx: Option<[Option<u8>; 6]>,
    /// Section 5: PRC, computation precision in mm (default 0.01).
    pub prc: Option<f64>,
    /// Section 5: CWP.
    pub cwp: Option<Cwp>,
    /// Section 5: NAM, axis parallel to the spindle.
    pub nam: Option<char>,
    /// Section 5: NPD, default abscissa and ordinate.
    pub npd: Option<(char, char)>,
    /// Section 5: G70 units.
    pub g70: Option<Units>,
    /// Section 5: MBR, retrace depth 1…255.
    pub mbr: Option<u32>,
    /// Section 5: TAS.
    pub tas: Option<Tas>,
    /// Section 5: INU.
    pub inu: Option<Inu>,
    /// Section 5: CAX (ECDF), axes of the protected zone CUB.
    pub cax: Option<[char; 3]>,
    /// Section 5: QFD, alternative feed mm/min.
    pub qfd: Option<f64>,
    /// Section 5: TGA.
    pub tga: Option<Tga>,
    /// Section 6: MAS, axes for manual moves.
    pub mas: Vec<char>,
    /// Section 6: FRO feed-override table.
    pub fro: Option<Vec<f64>>,
    /// Section 6: SSO spindle-override table.
    pub sso: Option<Vec<f64>>,
    /// Section 6: FMO JOG-override table.
    pub fmo: Option<Vec<f64>>,
}

/// Table 5.10 (NC-XXX feed override).
pub const DEFAULT_FRO: [f64; 12] = [
    0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0, 1.125, 1.25, 1.25,
];
/// Table 5.12 (NC-XXX spindle override).
pub const DEFAULT_SSO: [f64; 12] = [
    0.75, 0.8, 0.85, 0.9, 0.95, 1.0, 1.05, 1.1, 1.15, 1.2, 1.25, 1.25,
];
/// Table 5.14 (NC-XXX JOG override).
pub const DEFAULT_FMO: [f64; 12] = [
    -1.0, -0.5, -0.2, -0.05, -0.01, 0.0, 0.01, 0.05, 0.2, 0.5, 1.0, 1.0,
];

impl PgProcess {
    /// The power-on G code of each class: GXX where given, else the TOF default.
    pub fn initial_g(&self) -> [u8; 6] {
        let mut g = self.tof.map_or([0, 27, 90, 70, 94, 97], |t| t.default_g());
        if let Some(gxx) = &self.gxx {
            for (slot, v) in g.iter_mut().zip(gxx) {
                if let Some(v) = v {
                    *slot = *v;
                }
            }
        }
        g
    }
    /// NDD or its default MP1.
    pub fn ndd_or_default(&self) -> u8 {
        self.ndd.unwrap_or(1)
    }
    /// PRC or its default 0.01 mm.
    pub fn prc_or_default(&self) -> f64 {
        self.prc.unwrap_or(0.01)
    }
    /// The feed-override table (FRO or Table 5.10).
    pub fn fro_table(&self) -> Vec<f64> {
        self.fro.clone().unwrap_or_else(|| DEFAULT_FRO.to_vec())
    }
    /// The spindle-override table (SSO or Table 5.12).
    pub fn sso_table(&self) -> Vec<f64> {
        self.sso.clone().unwrap_or_else(|| DEFAULT_SSO.to_vec())
    }
    /// The JOG-override table (FMO or Table 5.14).
    pub fn fmo_table(&self) -> Vec<f64> {
        self.fmo.clone().unwrap_or_else(|| DEFAULT_FMO.to_vec())
    }
    /// The value ASS gave `var` (last assignment wins).
    pub fn assigned(&self, var: &str) -> Option<f64> {
        self.ass
            .iter()
            .rev()
            .find(|a| a.var_name == var)
            .map(|a| a.value)
    }
}

/// A whole PGCFIL.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Pgcfil {
    /// NEW or OLD.
    pub load_mode: LoadMode,
    /// Section 1: TRI.
    pub tri: Vec<CodeRename>,
    /// Section 3: JCL.
    pub jcl: Vec<CodeRename>,
    /// Processes in ascending number.
    pub processes: Vec<PgProcess>,
}

impl Pgcfil {
    /// True for `OLD`: per-process state survives a restart.
    pub fn retains(&self) -> bool {
        self.load_mode == LoadMode::Old
    }
    /// The process with `number`.
    pub fn process(&self, number: u32) -> Option<&PgProcess> {
        self.processes.iter().find(|p| p.number == number)
    }
}
