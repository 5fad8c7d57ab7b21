//! TEMPORARY stand-in for char-core's reader (replaced on merge): splits a file into sections and records.

use std::ops::Range;

/// One parameter of a record; empty text = omitted parameter.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Param {
    /// Trimmed text.
    pub text: String,
    /// Byte span.
    pub span: Range<usize>,
}

/// One `KEY=p1,p2` line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Record {
    /// Instruction name, upper-case.
    pub key: String,
    /// Span of the name.
    pub key_span: Range<usize>,
    /// Parameters.
    pub params: Vec<Param>,
    /// Span of the whole record.
    pub span: Range<usize>,
}

/// One `*n` section.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Section {
    /// Section number.
    pub number: u32,
    /// Span of the marker.
    pub span: Range<usize>,
    /// Records.
    pub records: Vec<Record>,
}

/// A read file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParsedFile {
    /// File name.
    pub name: String,
    /// Text.
    pub text: String,
    /// Sections.
    pub sections: Vec<Section>,
}

/// Reads a file (stand-in).
pub fn read(name: &str, bytes: &[u8]) -> (ParsedFile, Vec<diag::Diagnostic>) {
    let text = String::from_utf8_lossy(bytes).into_owned();
    let mut sections: Vec<Section> = Vec::new();
    let mut pre = Section { number: 0, span: 0..0, records: Vec::new() };
    let mut off = 0;
    for line in text.split_inclusive('\n') {
        let start = off;
        off += line.len();
        let l = line.trim_end_matches(['\n', '\r']);
        let t = l.trim();
        if t.is_empty() || t.starts_with(';') {
            continue;
        }
        let lead = l.len() - l.trim_start().len();
        if let Some(n) = t.strip_prefix('*') {
            sections.push(Section { number: n.trim().parse().unwrap_or(0), span: start + lead..start + l.len(), records: Vec::new() });
            continue;
        }
        let (key, rest, rest_off) = match l.find('=') {
            Some(i) => (&l[..i], &l[i + 1..], i + 1),
            None => (l, "", l.len()),
        };
        let key_t = key.trim();
        let key_start = start + lead;
        let mut params = Vec::new();
        if l.contains('=') {
            let mut p_off = start + rest_off;
            for piece in rest.split(',') {
                let lead_p = piece.len() - piece.trim_start().len();
                let tx = piece.trim();
                params.push(Param { text: tx.to_string(), span: p_off + lead_p..p_off + lead_p + tx.len() });
                p_off += piece.len() + 1;
            }
        }
        let rec = Record { key: key_t.to_ascii_uppercase(), key_span: key_start..key_start + key_t.len(), params, span: key_start..start + l.len() };
        match sections.last_mut() {
            Some(s) => s.records.push(rec),
            None => pre.records.push(rec),
        }
    }
    if !pre.records.is_empty() {
        sections.insert(0, pre);
    }
    (ParsedFile { name: name.to_string(), text, sections }, Vec::new())
}
