//! Section-level rules shared by PGCFIL and IOCFIL: the sections a file must have, per-section
//! instruction whitelists (error 6) and the `PRO=n` process blocks of per-process sections.

use std::collections::BTreeSet;

use crate::reader::Record;

use super::fields::Emit;

/// Reports error 6 when `rec.key` is not allowed; `allowed` lists the names for the hint.
pub(crate) fn not_allowed(e: &mut Emit<'_>, rec: &Record, allowed: &str) {
    e.error(
        6,
        rec.key_span.clone(),
        format!(
            "instruction {} is not allowed in section *{}",
            rec.key, e.section
        ),
        &crate::values::suggest_key(
            &rec.key,
            allowed,
            &format!("section *{} allows {allowed}", e.section),
        ),
    );
}

/// Tracks the process blocks of one per-process section.
#[derive(Debug, Default)]
pub(crate) struct Blocks {
    /// PRO numbers already opened in this section.
    pub seen: BTreeSet<u32>,
    /// Current process (1 before any PRO: the manual's example writes SIM without PRO).
    pub current: Option<u32>,
    /// Keys of single-valued instructions already written in the current block.
    pub keys: BTreeSet<String>,
    /// Number of records since the block was opened.
    pub position: usize,
    /// Span of the PRO record of the current block, if written.
    pub pro_span: Option<std::ops::Range<usize>>,
    /// True after an invalid PRO: records are checked but belong to no process.
    pub dead: bool,
}

impl Blocks {
    /// Handles `PRO=n` (error 184 for a number outside 1…5 or repeated); returns the new process when valid.
    pub fn open(&mut self, e: &mut Emit<'_>, rec: &Record) -> Option<u32> {
        if !e.count(rec, 1, 1) {
            return None;
        }
        self.dead = true;
        self.keys.clear();
        self.position = 0;
        self.pro_span = Some(rec.span.clone());
        e.process = None;
        let p = rec.params.first()?;
        let n = e.integer(p)?;
        let n = match u32::try_from(n) {
            Ok(n @ 1..=5) => n,
            _ => {
                e.error(
                    184,
                    p.span.clone(),
                    format!("process number {n} is not configurable"),
                    "a process number is 1 ... 5 and not above NBP of AXCFIL",
                );
                return None;
            }
        };
        if !self.seen.insert(n) {
            e.error(
                184,
                p.span.clone(),
                format!("process {n} was already declared in section *{}", e.section),
                "write PRO once per process in each section",
            );
            return None;
        }
        self.current = Some(n);
        self.dead = false;
        e.process = Some(n);
        Some(n)
    }

    /// The process of a non-PRO record (1 when no PRO was written yet; `None` after an invalid
    /// PRO) and advances the position.
    pub fn record(&mut self, e: &mut Emit<'_>) -> Option<u32> {
        self.position += 1;
        if self.dead {
            e.process = None;
            return None;
        }
        let n = *self.current.get_or_insert(1);
        self.seen.insert(n);
        e.process = Some(n);
        Some(n)
    }

    /// Error 101 when a single-valued instruction repeats in the block; true when it is new.
    pub fn first_time(&mut self, e: &mut Emit<'_>, rec: &Record) -> bool {
        if self.keys.insert(rec.key.clone()) {
            true
        } else {
            e.error(
                101,
                rec.key_span.clone(),
                format!("instruction {} is duplicated", rec.key),
                "write each instruction once per process",
            );
            false
        }
    }
}
