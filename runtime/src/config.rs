//! The few machine facts the runtime needs, gathered in one [`RunConfig`].
//!
//! The lead fills a `RunConfig` from `characterization::Machine`. Until that glue exists,
//! [`RunConfig::from_machine_dir_temporary`] reads the handful of lines it needs (IOCFIL `CLO` and
//! section 4 `Txx`, the PGCFIL `NEW`/`OLD` word) straight from `<machine>/MP0/`.

use std::path::{Path, PathBuf};

use packets::Packet;

/// Runtime settings derived from the machine's characterization.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunConfig {
    /// The logic tick (IOCFIL `CLO tick_logic`), in milliseconds.
    pub tick_ms: u32,
    /// IOCFIL `CLO time_slow`, in milliseconds (the SLOW budget per tick).
    pub time_slow_ms: u32,
    /// Packet-A input connectors (IOCFIL `INx`).
    pub a_inputs: Vec<u16>,
    /// Packet-A output connectors (IOCFIL `OUx`).
    pub a_outputs: Vec<u16>,
    /// IOCFIL `SPL` (symbolic names allowed; manual default 1).
    pub spl: u32,
    /// Initial packet-T bytes (IOCFIL section 4), 64 bytes.
    pub t_init: Vec<u8>,
    /// PGCFIL `OLD`: restore logic-written T bytes and RETAIN variables at start.
    pub restore_old: bool,
    /// Consecutive overruns that trip the safe state.
    pub overrun_limit: u32,
    /// The PLC source file.
    pub plc_source: PathBuf,
    /// Where retained data is kept (None: nothing is retained).
    pub retain_file: Option<PathBuf>,
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig {
            tick_ms: 10,
            time_slow_ms: 2,
            a_inputs: Vec::new(),
            a_outputs: Vec::new(),
            spl: 1,
            t_init: vec![0; Packet::T.len()],
            restore_old: false,
            overrun_limit: 3,
            plc_source: PathBuf::new(),
            retain_file: None,
        }
    }
}

impl RunConfig {
    /// TEMPORARY (until the lead wires `characterization::Machine`): reads `CLO` and `Txx` from
    /// `<dir>/MP0/IOCFIL`, `NEW`/`OLD` from `<dir>/MP0/PGCFIL`, and takes `<dir>/MP0/PLCPRG` as the
    /// source. Missing files or lines leave the defaults. The retain file is `<dir>/retain.bin`.
    pub fn from_machine_dir_temporary(dir: &Path) -> RunConfig {
        Self::from_files_temporary(
            dir,
            &dir.join("MP0").join("IOCFIL"),
            &dir.join("MP0").join("PGCFIL"),
            &dir.join("MP0").join("PLCPRG"),
        )
    }

    /// TEMPORARY: as [`RunConfig::from_machine_dir_temporary`] with the files' paths given (the
    /// paths come from FCRSYS through `characterization::load_machine`).
    pub fn from_files_temporary(
        dir: &Path,
        iocfil: &Path,
        pgcfil: &Path,
        plc_source: &Path,
    ) -> RunConfig {
        let mut cfg = RunConfig {
            plc_source: plc_source.to_path_buf(),
            retain_file: Some(dir.join("retain.bin")),
            ..RunConfig::default()
        };
        if let Ok(bytes) = std::fs::read(iocfil) {
            cfg.apply_iocfil(&String::from_utf8_lossy(&bytes));
        }
        if let Ok(bytes) = std::fs::read(pgcfil) {
            let text = String::from_utf8_lossy(&bytes);
            let first = text.lines().map(strip_comment).find(|l| !l.is_empty());
            cfg.restore_old = first.is_some_and(|l| l.eq_ignore_ascii_case("OLD"));
        }
        cfg
    }

    /// Applies `CLO=tick,slow` and section-4 `Txx=hh` lines of an IOCFIL text.
    pub fn apply_iocfil(&mut self, text: &str) {
        let mut section = 0u32;
        for raw in text.lines() {
            let line = strip_comment(raw);
            if let Some(n) = line.strip_prefix('*') {
                section = n.trim().parse().unwrap_or(0);
                continue;
            }
            let Some((name, value)) = line.split_once('=') else {
                continue;
            };
            let name = name.trim().to_ascii_uppercase();
            let value = value.trim();
            let words: Vec<&str> = value.split(',').map(str::trim).collect();
            if name == "CLO" {
                if let Some(Ok(t)) = words.first().map(|v| v.parse::<u32>())
                    && t > 0
                {
                    self.tick_ms = t;
                }
                if let Some(Ok(t)) = words.get(1).map(|v| v.parse::<u32>()) {
                    self.time_slow_ms = t;
                }
            } else if section == 1 && name == "SPL" {
                if let Ok(n) = value.parse() {
                    self.spl = n;
                }
            } else if section == 1 && (name.starts_with("IN") || name.starts_with("OU")) {
                let list = if name.starts_with("IN") {
                    &mut self.a_inputs
                } else {
                    &mut self.a_outputs
                };
                list.extend(words.iter().filter_map(|w| w.parse::<u16>().ok()));
            } else if section == 4
                && let Some(num) = name.strip_prefix('T')
                && let Ok(n) = num.parse::<usize>()
                && (1..=64).contains(&n)
                && let Ok(v) = u8::from_str_radix(value.trim_end_matches(['H', 'h']), 16)
            {
                self.t_init[n - 1] = v;
            }
        }
    }
}

fn strip_comment(line: &str) -> &str {
    line.split(';').next().unwrap_or("").trim()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iocfil_clo_and_t_bytes_are_read() {
        let mut cfg = RunConfig::default();
        cfg.apply_iocfil("*1\nALM=0\nIN0=0,1,,,,,,\nOU0=4,5,,\nSPL=400\nCLO = 4, 2 ; fast\n*4\nT01=1F\nT64=0A\nT65=01\nT02=zz\n");
        assert_eq!(cfg.tick_ms, 4);
        assert_eq!(cfg.time_slow_ms, 2);
        assert_eq!(
            (cfg.a_inputs.as_slice(), cfg.a_outputs.as_slice(), cfg.spl),
            (&[0, 1][..], &[4, 5][..], 400)
        );
        assert_eq!(cfg.t_init[0], 0x1f);
        assert_eq!(cfg.t_init[63], 0x0a);
        assert_eq!(cfg.t_init[1], 0);
    }

    #[test]
    fn t_lines_outside_section_4_are_ignored() {
        let mut cfg = RunConfig::default();
        cfg.apply_iocfil("*1\nT01=1F\n");
        assert_eq!(cfg.t_init[0], 0);
        assert_eq!(cfg.tick_ms, 10);
    }
}
