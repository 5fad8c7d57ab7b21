//! The OPC UA users file (`--opcua-users FILE`): one `ROLE USER PASSWORD` per line, roles as the
//! web HMI's (`viewer`: browse, read, subscribe; `operator`: + methods, none offered yet;
//! `integrator`: + writes in the io.toml window); blank lines and `#` lines are skipped.
//!
//! **Invariants:** a user appears once; a password has at least 8 characters and no spaces; a
//! password is compared in time independent of where it differs.

use hmi::security::Role;

/// Fewest characters of a password.
pub const MIN_PASSWORD: usize = 8;

/// The users and their roles.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Users {
    entries: Vec<(String, String, Role)>,
}

/// What is wrong in a users file, with its 1-based line and column.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{line}:{column}: {message}")]
pub struct UsersFileError {
    /// The line.
    pub line: usize,
    /// The column.
    pub column: usize,
    /// What is wrong and what to write instead.
    pub message: String,
}

impl Users {
    /// Reads a users file's text.
    pub fn parse(text: &str) -> Result<Users, UsersFileError> {
        let mut entries: Vec<(String, String, Role)> = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let t = line.trim_start();
            if t.is_empty() || t.starts_with('#') {
                continue;
            }
            let col = |word: &str| {
                // `word` is a slice of `line`: its offset is its column.
                word.as_ptr() as usize - line.as_ptr() as usize + 1
            };
            let err = |column: usize, message: String| UsersFileError {
                line: i + 1,
                column,
                message,
            };
            let words: Vec<&str> = line.split_whitespace().collect();
            let [role, user, password] = words[..] else {
                return Err(err(
                    col(t),
                    format!(
                        "expected `ROLE USER PASSWORD`, found {} word(s)",
                        words.len()
                    ),
                ));
            };
            let role = Role::parse(role).ok_or_else(|| {
                err(
                    col(role),
                    format!("unknown role `{role}`: use viewer, operator or integrator"),
                )
            })?;
            if entries.iter().any(|(u, _, _)| u == user) {
                return Err(err(col(user), format!("user `{user}` appears twice")));
            }
            if password.chars().count() < MIN_PASSWORD {
                return Err(err(
                    col(password),
                    format!("the password of `{user}` is shorter than {MIN_PASSWORD} characters"),
                ));
            }
            entries.push((user.to_string(), password.to_string(), role));
        }
        Ok(Users { entries })
    }

    /// The role of `user` when `password` is theirs.
    pub fn check(&self, user: &str, password: &str) -> Option<Role> {
        let mut found = None;
        for (u, p, r) in &self.entries {
            // Every entry is compared, each in time independent of where it differs.
            let same = same_bytes(u.as_bytes(), user.as_bytes())
                & same_bytes(p.as_bytes(), password.as_bytes());
            if same {
                found = Some(*r);
            }
        }
        found
    }

    /// The role of a known `user`.
    pub fn role(&self, user: &str) -> Option<Role> {
        self.entries
            .iter()
            .find(|(u, _, _)| u == user)
            .map(|(_, _, r)| *r)
    }

    /// Every user name with its password (for the stack's endpoint configuration).
    pub fn credentials(&self) -> Vec<(String, String)> {
        self.entries
            .iter()
            .map(|(u, p, _)| (u.clone(), p.clone()))
            .collect()
    }

    /// How many users there are.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True without users.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

/// Equal byte strings, in time that depends on the lengths only.
fn same_bytes(a: &[u8], b: &[u8]) -> bool {
    let mut diff = a.len() ^ b.len();
    for (i, x) in a.iter().enumerate() {
        diff |= usize::from(x ^ b.get(i).copied().unwrap_or(!x));
    }
    diff == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_users_file_gives_roles_and_checks_passwords() {
        let u = Users::parse(
            "# plant users\nviewer mes mes-secret-1\n\noperator op op-secret-1\nintegrator int int-secret-1\n",
        )
        .expect("valid");
        assert_eq!(u.len(), 3);
        assert_eq!(u.check("mes", "mes-secret-1"), Some(Role::Viewer));
        assert_eq!(u.check("op", "op-secret-1"), Some(Role::Operator));
        assert_eq!(u.check("int", "int-secret-1"), Some(Role::Integrator));
        assert_eq!(u.check("int", "int-secret-2"), None);
        assert_eq!(u.check("int", "int-secret-1x"), None);
        assert_eq!(u.check("nobody", "int-secret-1"), None);
        assert_eq!(u.role("op"), Some(Role::Operator));
    }

    #[test]
    fn bad_lines_are_located() {
        let e = |t: &str| Users::parse(t).expect_err("invalid");
        assert_eq!(
            e("viewer a\n"),
            UsersFileError {
                line: 1,
                column: 1,
                message: "expected `ROLE USER PASSWORD`, found 2 word(s)".into()
            }
        );
        assert_eq!(e("\n  admin a secret-123\n").line, 2);
        assert_eq!(e("\n  admin a secret-123\n").column, 3);
        assert_eq!(
            e("viewer a secret-123\noperator a secret-456\n").message,
            "user `a` appears twice"
        );
        assert_eq!(e("viewer a short\n").column, 10);
    }
}
