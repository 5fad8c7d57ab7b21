//! Completion: the program's `DEF` names, the interface map's names with their addresses and
//! meanings, the machine's packet-A signals (IOCFIL `IN`/`OU` connectors), keywords, types,
//! functions, and snippets for the ladder idioms (a self-holding coil, an edge, a TON with its
//! preset). After `DEF name :` only the types are offered.

use lsp_types::{
    CompletionItem, CompletionItemKind, Documentation, InsertTextFormat, MarkupContent, MarkupKind,
};

use crate::analysis::Analysis;
use crate::keywords;
use crate::machine::Machine;
use crate::navigate::def_detail;
use crate::text::Text;

/// The snippets: label, detail, body (LSP snippet syntax).
pub const SNIPPETS: &[(&str, &str, &str)] = &[
    (
        "self-holding coil",
        "start/stop latch: the output holds itself until stop",
        "${1:U4A0} = (${2:I0A0} + ${1:U4A0}) * /${3:I0A1}",
    ),
    (
        "rising edge",
        "one-shot P<n>: 1 for one scan when the input rises",
        "P${1:1} = ${2:I0A0}",
    ),
    (
        "falling edge",
        "one-shot P<n>: 1 for one scan when the input falls",
        "P${1:2} = /${2:I0A0}",
    ),
    (
        "TON timer",
        "named on-delay timer with its preset, driven and read",
        "DEF ${1:delay} : TON(${2:2s})\n${1:delay} = ${3:I0A0}\n${4:U4A0} = ${1:delay}",
    ),
];

fn markdown(s: String) -> Option<Documentation> {
    Some(Documentation::MarkupContent(MarkupContent {
        kind: MarkupKind::Markdown,
        value: s,
    }))
}

/// The completion items at byte `offset`.
pub fn complete(
    a: &Analysis,
    machine: &Machine,
    text: &Text,
    offset: usize,
) -> Vec<CompletionItem> {
    let src = text.as_str();
    let offset = offset.min(src.len());
    let line_start = src
        .get(..offset)
        .and_then(|s| s.rfind('\n'))
        .map_or(0, |i| i + 1);
    let before = src
        .get(line_start..offset)
        .unwrap_or("")
        .to_ascii_uppercase();
    let mut items = Vec::new();
    let kw = |label: &str, kind| CompletionItem {
        label: label.to_string(),
        kind: Some(kind),
        documentation: keywords::describe(label)
            .map(|d| markdown(d.to_string()))
            .unwrap_or(None),
        ..CompletionItem::default()
    };
    let after_colon =
        before.trim_start().starts_with("DEF") && before.contains(':') && !before.contains('(');
    if after_colon {
        items.extend(
            keywords::TYPES
                .iter()
                .map(|t| kw(t, CompletionItemKind::CLASS)),
        );
        return items;
    }
    for d in &a.index.defs {
        items.push(CompletionItem {
            label: d.name.clone(),
            kind: Some(CompletionItemKind::VARIABLE),
            detail: Some(def_detail(d)),
            ..CompletionItem::default()
        });
    }
    for e in machine.ctx.interface.iter() {
        items.push(CompletionItem {
            label: e.name.clone(),
            kind: Some(CompletionItemKind::CONSTANT),
            detail: Some(format!("{} · {}", e.signal, e.meaning)),
            documentation: markdown(format!("**{}** = `{}`: {}", e.name, e.signal, e.meaning)),
            ..CompletionItem::default()
        });
    }
    if machine.dir.is_some() {
        for (conns, prefix, side) in [
            (&machine.ctx.a_inputs, 'I', "input"),
            (&machine.ctx.a_outputs, 'U', "output"),
        ] {
            for c in conns {
                for n in 0..32 {
                    items.push(CompletionItem {
                        label: format!("{prefix}{c}A{n}"),
                        kind: Some(CompletionItemKind::FIELD),
                        detail: Some(format!("{side} connector {c} contact {n} (IOCFIL)")),
                        ..CompletionItem::default()
                    });
                }
            }
        }
    }
    for (k, _) in keywords::KEYWORDS {
        if k.len() > 2 || matches!(*k, "AT" | "IF" | "OR" | "TP") {
            items.push(kw(k, CompletionItemKind::KEYWORD));
        }
    }
    for (label, detail, body) in SNIPPETS {
        items.push(CompletionItem {
            label: label.to_string(),
            kind: Some(CompletionItemKind::SNIPPET),
            detail: Some(detail.to_string()),
            insert_text: Some(body.to_string()),
            insert_text_format: Some(InsertTextFormat::SNIPPET),
            ..CompletionItem::default()
        });
    }
    items
}
