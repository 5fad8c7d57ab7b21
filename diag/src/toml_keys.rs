//! Every unknown key of a TOML file in one run: serde stops at the first unknown field of a struct
//! that denies them, so the user would fix typos one run at a time. [`from_toml`] reports that
//! error, blanks the unknown key's `key = value` out of the text (spaces, newlines kept, so every
//! later position is unchanged) and deserializes again, until the text deserializes or an error
//! is not an unknown key of a `key = value` line.
//!
//! An unknown *table* (`[bogus]`, `[[bogus]]`) ends the search: its keys would become keys of the
//! table before it. So does a text that would no longer parse once the entry is blanked out (a
//! dotted key in an inline table, say): the errors found so far are reported, the rest on the next
//! run. Work is at most `most` deserializations of a configuration file (at most 1 MiB, see
//! [`crate::read_config`]).

use std::ops::Range;

use toml::de::{DeTable, DeValue};

/// One error of a TOML file: where, and toml's own message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TomlError {
    /// Byte range in the text (the unknown key, the bad value; None: the whole file).
    pub span: Option<Range<usize>>,
    /// What is wrong, as toml says it (`unknown field `x`, expected one of …`).
    pub message: String,
}

impl From<toml::de::Error> for TomlError {
    fn from(e: toml::de::Error) -> Self {
        TomlError {
            span: e.span(),
            message: e.message().trim().to_string(),
        }
    }
}

/// Deserializes `text`; on failure, its errors in the order serde finds them: every unknown key
/// (up to `most` errors), then the first error of another kind.
pub fn from_toml<T: serde::de::DeserializeOwned>(
    text: &str,
    most: usize,
) -> Result<T, Vec<TomlError>> {
    let mut errors = Vec::new();
    // The `key = value` entries of the text, by the key's span: parsed once, since blanking keeps
    // every position.
    let mut entries: Option<Vec<(Range<usize>, Range<usize>)>> = None;
    let mut blanked: Option<String> = None;
    loop {
        let current = blanked.as_deref().unwrap_or(text);
        let e = match toml::from_str::<T>(current) {
            Ok(v) if errors.is_empty() => return Ok(v),
            Ok(_) => return Err(in_file_order(errors)),
            Err(e) => TomlError::from(e),
        };
        let key = e
            .span
            .clone()
            .filter(|_| e.message.starts_with("unknown field"));
        errors.push(e);
        let Some(key) = key.filter(|_| errors.len() < most.max(1)) else {
            return Err(in_file_order(errors));
        };
        let entries = entries.get_or_insert_with(|| key_values(text));
        let Some((_, entry)) = entries.iter().find(|(k, _)| *k == key) else {
            return Err(in_file_order(errors));
        };
        let next = blank(current, entry.clone());
        if DeTable::parse(&next).is_err() {
            return Err(in_file_order(errors));
        }
        blanked = Some(next);
    }
}

/// The errors by their place in the file (serde finds them in its own order).
fn in_file_order(mut errors: Vec<TomlError>) -> Vec<TomlError> {
    errors.sort_by_key(|e| e.span.as_ref().map_or(0, |s| s.start));
    errors
}

/// Every `key = value` entry of `text` (at any depth, inline tables and arrays of tables
/// included): the key's span and the span to blank (from the line's dotted-key start to the end
/// of the value, and a comma after it).
fn key_values(text: &str) -> Vec<(Range<usize>, Range<usize>)> {
    let mut out = Vec::new();
    if let Ok(root) = DeTable::parse(text) {
        walk(text, root.get_ref(), &mut out);
    }
    out
}

fn walk(text: &str, table: &DeTable<'_>, out: &mut Vec<(Range<usize>, Range<usize>)>) {
    for (k, v) in table {
        let (key, value) = (k.span(), v.span());
        let between = text.get(key.end..value.start).unwrap_or("");
        if between.trim() == "=" {
            out.push((key.clone(), entry_span(text, key, value.end)));
        } else if let Some(section) = section_span(text, key.clone()) {
            out.push((key, section));
        }
        visit(text, v.get_ref(), out);
    }
}

/// The lines of the table whose header names `key` last (`[key]`, `[[key]]`, `[a.key]`): from the
/// header to the next line that starts with `[` (the next header), so that no key of the table
/// is left to join the table before it.
fn section_span(text: &str, key: Range<usize>) -> Option<Range<usize>> {
    let line_start = text[..key.start].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[key.end..]
        .find('\n')
        .map_or(text.len(), |i| key.end + i);
    let before = text[line_start..key.start].trim_start();
    let after = text[key.end..line_end].trim_start();
    if !before.starts_with('[') || !after.starts_with(']') {
        return None;
    }
    let mut end = text.len();
    let mut at = line_end;
    while at < text.len() {
        let next = at + 1;
        if text[next..]
            .trim_start_matches([' ', '\t'])
            .starts_with('[')
        {
            end = next;
            break;
        }
        at = text[next..].find('\n').map_or(text.len(), |i| next + i);
    }
    Some(line_start..end)
}

fn visit(text: &str, value: &DeValue<'_>, out: &mut Vec<(Range<usize>, Range<usize>)>) {
    match value {
        DeValue::Table(t) => walk(text, t, out),
        DeValue::Array(a) => {
            for v in a.iter() {
                visit(text, v.get_ref(), out);
            }
        }
        _ => {}
    }
}

/// The bytes of the entry whose key starts at `key.start` and whose value ends at `end`: from the
/// start of a dotted key on the same line (`a.b.key = 1`), to the comma that follows the value
/// in an inline table.
fn entry_span(text: &str, key: Range<usize>, end: usize) -> Range<usize> {
    let line_start = text[..key.start].rfind('\n').map_or(0, |i| i + 1);
    let before = &text[line_start..key.start];
    let start = if before.trim_end().ends_with('.') && !before.contains(['{', ',', '=']) {
        line_start + (before.len() - before.trim_start().len())
    } else {
        key.start
    };
    let after = &text[end..];
    let rest = after.trim_start_matches([' ', '\t']);
    let end = if rest.starts_with(',') {
        end + (after.len() - rest.len()) + 1
    } else {
        end
    };
    start..end
}

/// `text` with the bytes of `range` turned into spaces (newlines kept).
fn blank(text: &str, range: Range<usize>) -> String {
    let mut s = String::with_capacity(text.len());
    s.push_str(&text[..range.start]);
    s.extend(
        text[range.clone()]
            .chars()
            .map(|c| if c == '\n' { '\n' } else { ' ' }),
    );
    s.push_str(&text[range.end..]);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct Device {
        name: String,
        #[serde(default)]
        unit: u8,
    }

    #[derive(Debug, serde::Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct File {
        #[serde(default)]
        bind: String,
        #[serde(default)]
        device: Vec<Device>,
        #[serde(default)]
        inline: Option<Device>,
    }

    fn errors(text: &str) -> Vec<(String, String)> {
        from_toml::<File>(text, 100)
            .expect_err("errors")
            .into_iter()
            .map(|e| (text[e.span.unwrap_or(0..0)].to_string(), e.message))
            .collect()
    }

    #[test]
    fn every_unknown_key_is_reported_in_one_run_at_its_own_place() {
        let text = "bynd = \"x\"\ninline = { name = \"c\", uni = 4 }\n[[device]]\nname = \"a\"\n\
                    unt = 3\n[[device]]\nname = \"b\"\nnme = \"b\"\n";
        let e = errors(text);
        let keys: Vec<&str> = e.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, ["bynd", "uni", "unt", "nme"]);
        assert_eq!(
            e[0].1,
            "unknown field `bynd`, expected one of `bind`, `device`, `inline`"
        );
        // A misspelt `name` leaves the second device without one: reported once its key is out,
        // and it ends the search (serde visits `inline` after `device`: its `uni` is reported on
        // the next run).
        let e = errors(&text.replace("name = \"b\"\n", ""));
        let keys: Vec<&str> = e.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, ["bynd", "unt", "[[device]]", "nme"]);
        assert_eq!(e[2].1, "missing field `name`");
    }

    #[test]
    fn a_valid_file_and_a_first_error_of_another_kind_are_as_toml_says() {
        assert_eq!(
            from_toml::<File>("bind = \"b\"\n[[device]]\nname = \"a\"\n", 100),
            Ok(File {
                bind: "b".into(),
                device: vec![Device {
                    name: "a".into(),
                    unit: 0
                }],
                inline: None
            })
        );
        let e = errors("bind = 3\nbogus = 1\n");
        assert_eq!(
            e,
            [(
                "3".to_string(),
                "invalid type: integer `3`, expected a string".to_string()
            )]
        );
    }

    #[test]
    fn an_unknown_table_goes_with_its_keys_and_the_cap_holds() {
        let e = errors("bogus1 = 1\n[bogus]\nx = 1\nbind = 2\n[[device]]\nname = \"a\"\nunt = 1\n");
        let keys: Vec<&str> = e.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, ["bogus1", "bogus", "unt"]);
        let many: String = (0..500).map(|i| format!("k{i} = 1\n")).collect();
        assert_eq!(
            from_toml::<File>(&many, 100).expect_err("errors").len(),
            100
        );
    }

    #[test]
    fn dotted_keys_and_inline_commas_are_blanked_whole() {
        let text = "inline.name = \"c\"\ninline.uni = 4\n[[device]]\nname = \"d\"\ndevice_x = { uni = 4, name = \"c\" }\n";
        let keys: Vec<String> = errors(text).into_iter().map(|(k, _)| k).collect();
        assert_eq!(keys, ["uni", "device_x"]);
        let text = "device = [{ uni = 4, name = \"c\" }]\n";
        let keys: Vec<String> = errors(text).into_iter().map(|(k, _)| k).collect();
        assert_eq!(keys, ["uni"]);
        assert_eq!(
            blank("a.b = 1\n", entry_span("a.b = 1\n", 2..3, 7)),
            "       \n"
        );
        assert_eq!(entry_span("{ u = 4, n = 1 }", 2..3, 7), 2..8);
    }
}
