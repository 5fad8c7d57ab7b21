//! `ncplc test --shard K/N`: one machine of a CI matrix replays its share of the traces.
//!
//! Invariants: the split depends on the trace paths only (sorted, then trace `i` goes to shard
//! `i mod N`, shards numbered 1..=N), so the N shards of one trace list are disjoint, their union
//! is the whole list, and every machine of the matrix computes the same split without talking to
//! the others. Shard sizes differ by at most one.

use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;

/// Shard `index` of `count` (1 ≤ index ≤ count), written `K/N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    index: usize,
    count: usize,
}

/// Why a `--shard` value is not `K/N` with 1 ≤ K ≤ N.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ShardError {
    /// Not two numbers around a slash.
    #[error("`{0}` is not K/N (for example 2/4: the second of four shards)")]
    Syntax(String),
    /// N is 0, or K is outside 1..=N.
    #[error("`{0}`: K must be between 1 and N (shards are numbered from 1)")]
    Range(String),
}

impl FromStr for Shard {
    type Err = ShardError;

    fn from_str(s: &str) -> Result<Shard, ShardError> {
        let syntax = || ShardError::Syntax(s.to_string());
        let (k, n) = s.split_once('/').ok_or_else(syntax)?;
        let number = |t: &str| {
            if t.is_empty() || !t.bytes().all(|b| b.is_ascii_digit()) {
                return Err(syntax());
            }
            t.parse::<usize>().map_err(|_| syntax())
        };
        let (index, count) = (number(k)?, number(n)?);
        if index == 0 || index > count {
            return Err(ShardError::Range(s.to_string()));
        }
        Ok(Shard { index, count })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// This shard's traces of `traces`: sorted by path, every N-th starting at the K-th.
    pub fn select(self, mut traces: Vec<PathBuf>) -> Vec<PathBuf> {
        traces.sort();
        traces
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % self.count == self.index - 1)
            .map(|(_, p)| p)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paths(names: &[&str]) -> Vec<PathBuf> {
        names.iter().map(PathBuf::from).collect()
    }

    #[test]
    fn parses_k_of_n_and_refuses_the_rest() {
        assert_eq!("2/3".parse(), Ok(Shard { index: 2, count: 3 }));
        assert_eq!("1/1".parse(), Ok(Shard { index: 1, count: 1 }));
        assert_eq!(
            "2/3".parse::<Shard>().map(|s| s.to_string()),
            Ok("2/3".into())
        );
        for bad in [
            "", "3", "1/", "/2", "a/2", "1/b", "+1/2", "1/2/3", " 1/2", "1.0/2",
        ] {
            assert_eq!(
                bad.parse::<Shard>(),
                Err(ShardError::Syntax(bad.into())),
                "{bad}"
            );
        }
        for bad in ["0/3", "4/3", "0/0", "1/0"] {
            assert_eq!(
                bad.parse::<Shard>(),
                Err(ShardError::Range(bad.into())),
                "{bad}"
            );
        }
    }

    #[test]
    fn trace_i_of_the_sorted_list_goes_to_shard_i_mod_n() {
        // Given out of order: sorted first, so every machine of the matrix splits alike.
        let all = paths(&["t/e", "t/a", "t/d", "t/b", "t/c"]);
        let pick = |s: &str| s.parse::<Shard>().map(|s| s.select(all.clone()));
        assert_eq!(pick("1/2"), Ok(paths(&["t/a", "t/c", "t/e"])));
        assert_eq!(pick("2/2"), Ok(paths(&["t/b", "t/d"])));
        assert_eq!(pick("1/3"), Ok(paths(&["t/a", "t/d"])));
        assert_eq!(pick("2/3"), Ok(paths(&["t/b", "t/e"])));
        assert_eq!(pick("3/3"), Ok(paths(&["t/c"])));
        assert_eq!(pick("1/1"), Ok(paths(&["t/a", "t/b", "t/c", "t/d", "t/e"])));
        assert_eq!(pick("5/5"), Ok(paths(&["t/e"])));
        // More shards than traces: the last ones are empty.
        assert_eq!(pick("6/7"), Ok(vec![]));
    }
}
