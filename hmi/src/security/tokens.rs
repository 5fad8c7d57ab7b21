//! Session tokens: generated from the OS's CSPRNG, or read from a token file that maps tokens to
//! roles.
//!
//! The token file (`--hmi-token-file FILE`) has one `ROLE TOKEN` per line (`viewer`, `operator`
//! or `integrator`); blank lines and lines starting with `#` are skipped. A file whose only line
//! is a single word is the old format: that word is the token, with every right (`integrator`).
//! A token is 16 to 256 characters of `A-Z a-z 0-9 . _ ~ -` (safe in a URL query and a cookie)
//! and appears once.
//!
//! Invariant: a token is compared with every known token in time independent of where they
//! differ.

use super::roles::Role;

/// Fewest characters of a token (a guessable token is no token).
pub const MIN_LEN: usize = 16;
/// Most characters of a token.
pub const MAX_LEN: usize = 256;

/// The tokens a server accepts, each with its role.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Tokens {
    entries: Vec<(String, Role)>,
}

/// What is wrong in a token file, with its 1-based line and column.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{line}:{column}: {message}")]
pub struct TokenFileError {
    /// The line.
    pub line: usize,
    /// The column.
    pub column: usize,
    /// What is wrong and what to write instead.
    pub message: String,
}

impl Tokens {
    /// One token with a role.
    pub fn single(token: String, role: Role) -> Tokens {
        Tokens {
            entries: vec![(token, role)],
        }
    }

    /// A fresh `integrator` token of 32 hex digits from the OS's CSPRNG.
    pub fn generate() -> Result<Tokens, getrandom::Error> {
        Ok(Tokens::single(fresh()?, Role::Integrator))
    }

    /// Reads a token file's text.
    pub fn parse(text: &str) -> Result<Tokens, TokenFileError> {
        let lines: Vec<(usize, &str)> = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l))
            .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
            .collect();
        let err = |line: usize, column: usize, message: String| TokenFileError {
            line,
            column,
            message,
        };
        if lines.is_empty() {
            return Err(err(1, 1, "the file holds no token".into()));
        }
        let mut entries: Vec<(String, Role)> = Vec::new();
        let old_format = lines.len() == 1 && lines[0].1.split_whitespace().count() == 1;
        for (n, line) in lines {
            let words: Vec<(usize, &str)> = words(line);
            let (role, (col, token)) = match words.as_slice() {
                [t] if old_format => (Role::Integrator, *t),
                [(rc, r), t] => match Role::parse(r) {
                    Some(role) => (role, *t),
                    None => {
                        return Err(err(
                            n,
                            *rc,
                            format!("`{r}` is not a role (viewer, operator or integrator)"),
                        ));
                    }
                },
                _ => {
                    return Err(err(
                        n,
                        1,
                        "a line is `ROLE TOKEN` (role: viewer, operator or integrator)".into(),
                    ));
                }
            };
            check(token).map_err(|m| err(n, col, m))?;
            if entries.iter().any(|(t, _)| t == token) {
                return Err(err(n, col, "this token is listed twice".into()));
            }
            entries.push((token.to_string(), role));
        }
        Ok(Tokens { entries })
    }

    /// The role of `presented`, if it is one of the tokens.
    pub fn role(&self, presented: &str) -> Option<Role> {
        // Every entry is compared, so the time does not tell which one (nearly) matched.
        self.entries.iter().fold(
            None,
            |found, (t, r)| if same(t, presented) { Some(*r) } else { found },
        )
    }

    /// The first token (the one a start URL carries).
    pub fn first(&self) -> Option<&str> {
        self.entries.first().map(|(t, _)| t.as_str())
    }

    /// How many tokens of each role: (viewer, operator, integrator).
    pub fn counts(&self) -> (usize, usize, usize) {
        let n = |r| self.entries.iter().filter(|(_, x)| *x == r).count();
        (n(Role::Viewer), n(Role::Operator), n(Role::Integrator))
    }
}

/// 32 hex digits from the OS's CSPRNG.
fn fresh() -> Result<String, getrandom::Error> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes)?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// The whitespace-separated words of a line with their 1-based columns (in characters).
fn words(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in line.char_indices() {
        match (c.is_whitespace(), start) {
            (false, None) => start = Some(i),
            (true, Some(s)) => {
                out.push((line[..s].chars().count() + 1, &line[s..i]));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((line[..s].chars().count() + 1, &line[s..]));
    }
    out
}

/// Why `token` is not a usable token, if it is not.
fn check(token: &str) -> Result<(), String> {
    let n = token.chars().count();
    if !(MIN_LEN..=MAX_LEN).contains(&n) {
        return Err(format!(
            "a token has {MIN_LEN} to {MAX_LEN} characters; this one has {n}"
        ));
    }
    if let Some(c) = token
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '~' | '-')))
    {
        return Err(format!(
            "`{c}` is not allowed in a token (use A-Z a-z 0-9 . _ ~ -)"
        ));
    }
    Ok(())
}

/// Compares without stopping at the first difference.
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len()
        && a.bytes()
            .zip(b.bytes())
            .fold(0u8, |acc, (x, y)| acc | (x ^ y))
            == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: &str = "aaaaaaaaaaaaaaaa1";
    const B: &str = "bbbbbbbbbbbbbbbb2";

    #[test]
    fn the_old_format_is_one_integrator_token() {
        let t = Tokens::parse(&format!("\n  {A}  \n\n")).expect("old format");
        assert_eq!(t.role(A), Some(Role::Integrator));
        assert_eq!(t.role(B), None);
        assert_eq!(t.counts(), (0, 0, 1));
    }

    #[test]
    fn role_lines_map_tokens_to_roles_and_comments_are_skipped() {
        let text =
            format!("# shop floor\nviewer {A}\n\n  operator\t{B}\nintegrator cccccccccccccccc3\n");
        let t = Tokens::parse(&text).expect("role lines");
        assert_eq!(t.role(A), Some(Role::Viewer));
        assert_eq!(t.role(B), Some(Role::Operator));
        assert_eq!(t.role("cccccccccccccccc3"), Some(Role::Integrator));
        assert_eq!(t.role("cccccccccccccccc"), None);
        assert_eq!(t.first(), Some(A));
    }

    #[test]
    fn bad_lines_are_located_errors() {
        let e = |text: &str| Tokens::parse(text).expect_err(text).to_string();
        assert_eq!(e(""), "1:1: the file holds no token");
        assert_eq!(e("# only\n"), "1:1: the file holds no token");
        assert_eq!(
            e(&format!("viewer {A}\nadmin {B}")),
            "2:1: `admin` is not a role (viewer, operator or integrator)"
        );
        assert_eq!(
            e(&format!("viewer {A}\n{B}")),
            "2:1: a line is `ROLE TOKEN` (role: viewer, operator or integrator)"
        );
        assert_eq!(
            e("viewer short"),
            "1:8: a token has 16 to 256 characters; this one has 5"
        );
        assert_eq!(
            e("operator  aaaaaaaaaaaaaaaa;x"),
            "1:11: `;` is not allowed in a token (use A-Z a-z 0-9 . _ ~ -)"
        );
        assert_eq!(
            e(&format!("viewer {A}\noperator {A}")),
            "2:10: this token is listed twice"
        );
        assert_eq!(
            e(&format!("viewer {A} extra")),
            "1:1: a line is `ROLE TOKEN` (role: viewer, operator or integrator)"
        );
    }

    #[test]
    fn generated_tokens_are_32_hex_digits_and_differ() {
        let a = Tokens::generate().expect("random");
        let b = Tokens::generate().expect("random");
        let ta = a.first().expect("token");
        assert_eq!(ta.len(), 32);
        assert!(ta.chars().all(|c| c.is_ascii_hexdigit()));
        assert_ne!(a.first(), b.first());
        assert_eq!(a.role(ta), Some(Role::Integrator));
    }
}
