//! The documents in `docs/` agree with the code: every ```plc example of the language reference
//! compiles without errors against the bundled lathe, and every entry of the default interface map
//! (`compiler/interface-map.toml`) is a row of the table in `docs/plc-interface-map.md`.

use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(root().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// The contents of the fenced blocks tagged `lang`, with the line each starts on.
fn blocks(doc: &str, lang: &str) -> Vec<(usize, String)> {
    let open = format!("```{lang}");
    let mut out = Vec::new();
    let mut current: Option<(usize, String)> = None;
    for (i, line) in doc.lines().enumerate() {
        match &mut current {
            None if line.trim_end() == open => current = Some((i + 2, String::new())),
            None => {}
            Some(_) if line.trim_end() == "```" => out.extend(current.take()),
            Some((_, text)) => {
                text.push_str(line);
                text.push('\n');
            }
        }
    }
    assert!(current.is_none(), "an unclosed ```{lang} block");
    out
}

#[test]
fn every_plc_example_of_the_language_reference_compiles() {
    let doc = read("docs/plc-language.md");
    let examples = blocks(&doc, "plc");
    // One per section that shows code: seeds, source text, signals, declarations, constants,
    // statements, expressions (two).
    assert_eq!(examples.len(), 8);
    let (ctx, _) =
        ncplc::cli::build::machine_context(&root().join("plc-programs/lathe")).expect("lathe");
    for (line, text) in examples {
        let name = format!("docs/plc-language.md:{line}");
        let c = compiler::compile_with_threads(&name, text.as_bytes(), &ctx, 1);
        let errors: Vec<String> = c
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| d.to_string())
            .collect();
        assert!(errors.is_empty(), "{name}:\n{text}\n{errors:#?}");
        assert!(c.program.is_some(), "{name}");
    }
}

#[test]
fn every_interface_map_entry_is_in_the_documented_table() {
    let doc = read("docs/plc-interface-map.md");
    let map: toml::Table = read("compiler/interface-map.toml")
        .parse()
        .expect("interface-map.toml");
    let entries = map["signal"].as_array().expect("[[signal]] entries");
    assert_eq!(entries.len(), 76);
    for e in entries {
        let field = |k: &str| e[k].as_str().unwrap_or_default().to_string();
        let row = format!(
            "| {} | {} | {} | {} | {} |",
            field("name"),
            field("address"),
            field("width"),
            field("dir"),
            field("meaning")
        );
        assert!(
            doc.lines().any(|l| l == row),
            "missing from docs/plc-interface-map.md: {row}"
        );
    }
}

#[test]
fn the_repository_points_to_docs_not_outside_it() {
    for rel in ["ARCHITECTURE.md", "README.md"] {
        let text = read(rel);
        assert!(
            !text.contains("../shared/"),
            "{rel} points outside the repository"
        );
        assert!(
            text.contains("docs/plc-language.md"),
            "{rel} names the reference"
        );
    }
}
