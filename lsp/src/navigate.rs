//! Navigation over the [`Index`]: go to definition, every reference (reads, writes and
//! declarations; writes marked through document highlights), rename of a `DEF` name, and the
//! document's symbols (the FAST and SLOW sections with their `DEF`s).
//!
//! The language has no labels, jumps, macros or include files: a `DEF` is the only thing a name can
//! be defined by (besides the interface map, whose machine override `interface.toml` is a place to
//! go to; the builtin map is embedded in the compiler and has none).

use crate::analysis::Analysis;
use crate::index::{Def, DefKind, Ref, Use};
use crate::machine::Machine;

/// Where the thing at `offset` is defined: a byte span of this document, or a span of
/// `interface.toml` (file, byte span) for a name of the machine's interface map.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    /// In this document.
    Here(std::ops::Range<usize>),
    /// In another file (the machine's interface.toml).
    File(String, std::ops::Range<usize>),
}

/// The definition of the name at `offset`.
pub fn definition(a: &Analysis, machine: &Machine, offset: usize) -> Option<Target> {
    let r = a.index.at(a.from_doc(offset))?;
    let name = r.name.as_ref()?;
    if let Some(d) = a.index.def(name) {
        return Some(Target::Here(a.to_doc(&d.name_span)));
    }
    let e = machine.ctx.interface.get(name)?;
    let file = &e.origin.file;
    std::path::Path::new(file)
        .is_file()
        .then(|| Target::File(file.clone(), e.origin.name.clone()))
}

/// Every place that stands for what is at `offset` (the same name, or the same signal through
/// any name), with how it is used; declarations only when `declarations`.
pub fn references(
    a: &Analysis,
    offset: usize,
    declarations: bool,
) -> Vec<(std::ops::Range<usize>, Use)> {
    let Some(r) = a.index.at(a.from_doc(offset)) else {
        return Vec::new();
    };
    a.index
        .same_as(r)
        .filter(|o| declarations || o.usage != Use::Decl)
        .map(|o| (a.to_doc(&o.span), o.usage))
        .collect()
}

/// Why a rename is refused, in words for the user.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RenameError {
    /// Nothing renamable under the cursor.
    #[error("only a name given by `DEF` can be renamed; this is {0}")]
    NotAName(&'static str),
    /// An interface-map name.
    #[error(
        "`{0}` is a name of the interface map (docs/plc-interface-map.md); the CNC knows it by that name, rename it in the machine's interface.toml instead"
    )]
    Interface(String),
    /// Not declared.
    #[error("`{0}` has no `DEF` in this file")]
    Undeclared(String),
    /// The new name is not a valid name.
    #[error(
        "`{0}` is not a valid name: letters, digits and `_`, starting with a letter, not a signal (U10K5), a one-shot (P2), a keyword or a type"
    )]
    Invalid(String),
    /// The new name is taken.
    #[error("`{0}` is already defined (by `DEF` or the interface map)")]
    Taken(String),
}

/// The `DEF` name under the cursor and where it is written, when it may be renamed.
pub fn prepare_rename<'a>(
    a: &'a Analysis,
    machine: &Machine,
    offset: usize,
) -> Result<(&'a Def, &'a Ref), RenameError> {
    let r = a
        .index
        .at(a.from_doc(offset))
        .ok_or(RenameError::NotAName("not a name"))?;
    let name = r.name.as_ref().ok_or(RenameError::NotAName(match r.addr {
        Some(crate::index::Addr::Pulse(_)) => "a one-shot",
        _ => "a signal address",
    }))?;
    if machine.ctx.interface.get(name).is_some() {
        return Err(RenameError::Interface(name.clone()));
    }
    let d = a
        .index
        .def(name)
        .ok_or_else(|| RenameError::Undeclared(name.clone()))?;
    Ok((d, r))
}

/// The spans to replace with `new_name` to rename the `DEF` name at `offset`.
pub fn rename(
    a: &Analysis,
    machine: &Machine,
    offset: usize,
    new_name: &str,
) -> Result<Vec<std::ops::Range<usize>>, RenameError> {
    let (d, _) = prepare_rename(a, machine, offset)?;
    if !valid_name(new_name) {
        return Err(RenameError::Invalid(new_name.to_string()));
    }
    let up = new_name.to_ascii_uppercase();
    if up != d.name && (a.index.def(&up).is_some() || machine.ctx.interface.get(&up).is_some()) {
        return Err(RenameError::Taken(new_name.to_string()));
    }
    Ok(a.index
        .refs
        .iter()
        .filter(|r| r.name.as_deref() == Some(d.name.as_str()))
        .map(|r| a.to_doc(&r.span))
        .collect())
}

/// True when `s` lexes as one name (not a signal, one-shot, keyword or type).
pub fn valid_name(s: &str) -> bool {
    use compiler::lexer::{Tok, tokenize};
    let (toks, errs) = tokenize(s);
    errs.is_empty()
        && matches!(toks.as_slice(), [(_, Tok::Ident(w), _), (_, Tok::Newline, _)] if w.len() == s.len())
        && !crate::keywords::TYPES.contains(&s.to_ascii_uppercase().as_str())
        && !crate::keywords::FUNCTIONS.contains(&s.to_ascii_uppercase().as_str())
}

/// One entry of the document outline.
#[derive(Debug, Clone, PartialEq)]
pub struct Symbol {
    /// Shown name.
    pub name: String,
    /// Type or signal.
    pub detail: String,
    /// Whole span and name span.
    pub span: std::ops::Range<usize>,
    /// The span of the name.
    pub name_span: std::ops::Range<usize>,
    /// A timer/counter (function block) rather than a variable or alias.
    pub block: bool,
    /// The FAST or SLOW section rather than a `DEF`.
    pub section: bool,
    /// Children (the `DEF`s of a section).
    pub children: Vec<Symbol>,
}

/// The outline: a FAST section and, after a `$` line, a SLOW section, each with its `DEF`s.
pub fn document_symbols(a: &Analysis, text_len: usize) -> Vec<Symbol> {
    let sep = a.index.separator.as_ref().map(|s| a.to_doc(s));
    let def_symbol = |d: &Def| Symbol {
        name: d.name.clone(),
        detail: def_detail(d),
        span: a.to_doc(&d.span),
        name_span: a.to_doc(&d.name_span),
        block: matches!(&d.kind, DefKind::Var { ty, .. } if matches!(ty.as_str(), "TON" | "TOF" | "TP" | "CTU" | "CTD")),
        section: false,
        children: Vec::new(),
    };
    let fast_end = sep.as_ref().map_or(text_len, |s| s.start);
    let mut out = vec![Symbol {
        name: "FAST".to_string(),
        detail: "every tick".to_string(),
        span: 0..fast_end,
        name_span: 0..0,
        block: false,
        section: true,
        children: a
            .index
            .defs
            .iter()
            .filter(|d| !d.slow)
            .map(def_symbol)
            .collect(),
    }];
    if let Some(s) = sep {
        out.push(Symbol {
            name: "SLOW".to_string(),
            detail: "one slice per tick".to_string(),
            span: s.start..text_len.max(s.end),
            name_span: s.clone(),
            block: false,
            section: true,
            children: a
                .index
                .defs
                .iter()
                .filter(|d| d.slow)
                .map(def_symbol)
                .collect(),
        });
    }
    out
}

/// The type or signal of a `DEF`, for outlines and completion.
pub fn def_detail(d: &Def) -> String {
    match &d.kind {
        DefKind::Alias(s) => format!("= {}", crate::index::signal_text(s)),
        DefKind::Var { ty, preset, at } => {
            let mut s = ty.clone();
            if let Some(p) = preset {
                s.push_str(&format!("({p})"));
            }
            if let Some(at) = at {
                s.push_str(&format!(" AT {}", crate::index::signal_text(at)));
            }
            s
        }
    }
}
