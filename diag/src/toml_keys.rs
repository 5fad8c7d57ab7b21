//! Every unknown key of a TOML file in one run: serde stops at the first unknown field of a struct
//! that denies them, so the user would fix typos one run at a time. [`from_toml`] parses the text
//! once into toml's spanned tree, deserializes a copy of it, and on an unknown field removes that
//! key (with its value: a whole table for `[bogus]`) from the tree and deserializes again, until
//! the tree deserializes or an error is of another kind (an entry left without a required key,
//! say: it ends the search, the rest comes on the next run).
//!
//! Work is bounded: at most `most` errors, and the copies deserialized stay under
//! [`WORK_BYTES`] of text in all (a configuration file is at most 1 MiB, see
//! [`crate::read_config`]: a file of that size full of unknown keys reports the first 32, in
//! 0.8 s with the release build).

use std::ops::Range;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// The most text the deserializations of one file may cover together (copies × file length).
pub const WORK_BYTES: usize = 32 << 20;

/// One error of a TOML file: where, and toml's own message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TomlError {
    /// Byte range in the text (the unknown key, the bad value; None: the whole file).
    pub span: Option<Range<usize>>,
    /// What is wrong, as toml says it (`unknown field `x`, expected one of …`).
    pub message: String,
}

impl TomlError {
    /// This error as a diagnostic `code` of `file` with `hint` (not yet located: no line).
    pub fn diagnostic(self, code: u32, file: &str, hint: &str) -> crate::Diagnostic {
        crate::Diagnostic::error(code, file, self.span.unwrap_or(0..0), self.message)
            .with_hint(hint)
    }
}

/// [`from_toml`] with its errors as diagnostics `code` of `file` with `hint` (not yet located).
pub fn from_toml_diagnosed<T: serde::de::DeserializeOwned>(
    text: &str,
    file: &str,
    code: u32,
    hint: &str,
) -> Result<T, Vec<crate::Diagnostic>> {
    from_toml(text, crate::DEFAULT_MAX_PER_FILE).map_err(|errors| {
        errors
            .into_iter()
            .map(|e| e.diagnostic(code, file, hint))
            .collect()
    })
}

impl From<toml::de::Error> for TomlError {
    fn from(e: toml::de::Error) -> Self {
        TomlError {
            span: e.span(),
            message: e.message().trim().to_string(),
        }
    }
}

/// Deserializes `text`; on failure, its errors in file order: every unknown key (up to `most`
/// errors and [`WORK_BYTES`] of work), then the first error of another kind.
pub fn from_toml<T: serde::de::DeserializeOwned>(
    text: &str,
    most: usize,
) -> Result<T, Vec<TomlError>> {
    let mut tree = DeTable::parse(text).map_err(|e| vec![TomlError::from(e)])?;
    let mut errors = Vec::new();
    let mut work = 0;
    loop {
        work += text.len().max(1);
        let e = match T::deserialize(toml::Deserializer::from(tree.clone())) {
            Ok(v) if errors.is_empty() => return Ok(v),
            Ok(_) => return Err(in_file_order(errors)),
            Err(e) => TomlError::from(e),
        };
        let key = e
            .span
            .clone()
            .filter(|_| e.message.starts_with("unknown field"));
        errors.push(e);
        let go_on = errors.len() < most.max(1) && work < WORK_BYTES;
        match key.filter(|_| go_on) {
            Some(key) if remove_key(tree.get_mut(), &key) => {}
            _ => return Err(in_file_order(errors)),
        }
    }
}

/// The errors by their place in the file (serde finds them in its own order).
fn in_file_order(mut errors: Vec<TomlError>) -> Vec<TomlError> {
    errors.sort_by_key(|e| e.span.as_ref().map_or(0, |s| s.start));
    errors
}

/// Removes the entry whose key is at `span` from `table` or a table inside it; false when there
/// is none.
fn remove_key(table: &mut DeTable<'_>, span: &Range<usize>) -> bool {
    let key = table.keys().find(|k| k.span() == *span).cloned();
    match key {
        Some(k) => table.remove(&k).is_some(),
        None => table.iter_mut().any(|(_, v)| remove_in(v, span)),
    }
}

fn remove_in(value: &mut Spanned<DeValue<'_>>, span: &Range<usize>) -> bool {
    match value.get_mut() {
        DeValue::Table(t) => remove_key(t, span),
        DeValue::Array(a) => a.iter_mut().any(|v| remove_in(v, span)),
        _ => false,
    }
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
        // A file of 1 MiB of unknown keys: 32 deserializations of it, then the errors found.
        let mut big = String::new();
        let mut i = 0;
        while big.len() < 1 << 20 {
            big.push_str(&format!("k{i} = 1\n"));
            i += 1;
        }
        let e = from_toml::<File>(&big, 100).expect_err("errors");
        assert_eq!(e.len(), WORK_BYTES.div_ceil(big.len()));
        assert_eq!(
            e[0].message,
            "unknown field `k0`, expected one of `bind`, `device`, `inline`"
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
    }
}
