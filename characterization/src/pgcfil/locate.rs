//! Finds the records of a per-process file again for cross-file diagnostics: which process blocks
//! each section has, and the record of a given instruction in a given process.

use std::ops::Range;

use crate::reader::{ParsedFile, Record};

/// A record with the process block it belongs to (`None` before any PRO is process 1).
pub(crate) struct Located<'f> {
    /// Process of the block (1 before any PRO).
    pub process: u32,
    /// The record.
    pub record: &'f Record,
}

/// Every non-PRO record of the per-process sections in `sections`, with its process.
pub(crate) fn records<'f>(file: &'f ParsedFile, sections: &[u32]) -> Vec<Located<'f>> {
    let mut out = Vec::new();
    for s in sections.iter().filter_map(|&n| file.section(n)) {
        let mut process = 1;
        for r in &s.records {
            if r.key == "PRO" {
                process = r
                    .params
                    .first()
                    .and_then(|p| p.text.parse::<u32>().ok())
                    .unwrap_or(0);
                continue;
            }
            out.push(Located { process, record: r });
        }
    }
    out
}

/// The PRO records of `section` with their numbers (unparsable numbers are left out).
pub(crate) fn pro_records(file: &ParsedFile, section: u32) -> Vec<(u32, &Record)> {
    file.section(section)
        .into_iter()
        .flat_map(|s| s.records.iter())
        .filter(|r| r.key == "PRO")
        .filter_map(|r| {
            r.params
                .first()
                .and_then(|p| p.text.parse::<u32>().ok())
                .map(|n| (n, r))
        })
        .collect()
}

/// The process numbers that have a block in `section` (1 when records precede any PRO).
pub(crate) fn blocks(file: &ParsedFile, section: u32) -> Vec<u32> {
    let mut out = Vec::new();
    if file
        .section(section)
        .and_then(|s| s.records.first())
        .is_some_and(|r| r.key != "PRO")
    {
        out.push(1);
    }
    out.extend(pro_records(file, section).into_iter().map(|(n, _)| n));
    out
}

/// The record `key` of `process` in `section`.
pub(crate) fn find<'f>(
    file: &'f ParsedFile,
    section: u32,
    process: u32,
    key: &str,
) -> Option<&'f Record> {
    records(file, &[section])
        .into_iter()
        .find(|l| l.process == process && l.record.key == key)
        .map(|l| l.record)
}

/// Span of parameter `i` of `rec`, or of the record.
pub(crate) fn param_span(rec: &Record, i: usize) -> Range<usize> {
    rec.params
        .get(i)
        .map_or_else(|| rec.span.clone(), |p| p.span.clone())
}

/// The span of the `*n` marker, or the end of the file.
pub(crate) fn section_span(file: &ParsedFile, n: u32) -> Range<usize> {
    file.section(n)
        .map_or_else(|| file.end_span(), |s| s.span.clone())
}
