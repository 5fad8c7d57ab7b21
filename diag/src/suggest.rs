//! "Did you mean" suggestions: the known name nearest to a misspelled one by edit distance
//! (optimal string alignment: Levenshtein plus neighbour transpositions).
//!
//! Used by every front end for names, keywords, instructions and characterization keys. The
//! distance is Levenshtein on characters, compared without case (the languages are case-blind);
//! a candidate is suggested only when it is close relative to the word's length, so that short
//! random words get no far-fetched advice.

/// Edit distance between `a` and `b` on characters (insertions, deletions, substitutions and
/// transpositions of neighbours: `NPB` is one edit from `NBP`), ignoring ASCII case; stops early
/// and returns `limit + 1` once the distance is known to exceed `limit`.
fn distance(a: &str, b: &str, limit: usize) -> usize {
    let a: Vec<char> = a.chars().map(|c| c.to_ascii_uppercase()).collect();
    let b: Vec<char> = b.chars().map(|c| c.to_ascii_uppercase()).collect();
    if a.len().abs_diff(b.len()) > limit {
        return limit + 1;
    }
    let mut before: Vec<usize> = vec![0; b.len() + 1];
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.iter().enumerate() {
        cur[0] = i + 1;
        let mut row_min = cur[0];
        for (j, cb) in b.iter().enumerate() {
            let cost = usize::from(ca != cb);
            cur[j + 1] = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
            if i > 0 && j > 0 && *ca == b[j - 1] && a[i - 1] == *cb {
                cur[j + 1] = cur[j + 1].min(before[j - 1] + 1);
            }
            row_min = row_min.min(cur[j + 1]);
        }
        if row_min > limit {
            return limit + 1;
        }
        std::mem::swap(&mut before, &mut prev);
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// The candidate nearest to `word` (among equals, one with the same first letter, else the first
/// in the candidates' order: `RPA` → `RAP` rather than `TPA`), if it is within
/// one edit for words of up to four characters and a third of the word's length beyond; an exact
/// (case-blind) match is not a suggestion. Words over 64 characters get none (bounded work).
pub fn nearest<'a, I>(word: &str, candidates: I) -> Option<&'a str>
where
    I: IntoIterator<Item = &'a str>,
{
    let len = word.chars().count();
    if len == 0 || len > 64 {
        return None;
    }
    let limit = (len / 3).max(1);
    let first = word.chars().next().map(|c| c.to_ascii_uppercase());
    // Rank: distance, then "first letter differs" (false sorts first).
    let mut best: Option<((usize, bool), &str)> = None;
    for c in candidates {
        let d = distance(word, c, limit);
        if d == 0 || d > limit {
            continue;
        }
        let rank = (d, c.chars().next().map(|c| c.to_ascii_uppercase()) != first);
        if best.is_none_or(|(br, _)| rank < br) {
            best = Some((rank, c));
        }
    }
    best.map(|(_, c)| c)
}

/// `did you mean `X`?` for the [`nearest`] candidate, or `None`.
pub fn did_you_mean<'a, I>(word: &str, candidates: I) -> Option<String>
where
    I: IntoIterator<Item = &'a str>,
{
    nearest(word, candidates).map(|c| format!("did you mean `{c}`?"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_finds_one_typo_and_ignores_case_and_far_words() {
        let keys = ["NBP", "GRA", "TPA", "ENDPRG"];
        assert_eq!(nearest("NPB", keys), Some("NBP"));
        assert_eq!(nearest("endprq", keys), Some("ENDPRG"));
        assert_eq!(nearest("XYZ", keys), None);
        assert_eq!(nearest("RPA", ["TPA", "NTC", "RAP"]), Some("RAP"));
        assert_eq!(nearest("NBP", keys), None);
        assert_eq!(
            did_you_mean("GRB", keys).as_deref(),
            Some("did you mean `GRA`?")
        );
    }

    #[test]
    fn distance_is_levenshtein_with_a_limit() {
        assert_eq!(distance("kitten", "sitting", 5), 3);
        assert_eq!(distance("kitten", "sitting", 2), 3);
        assert_eq!(distance("", "abc", 5), 3);
        assert_eq!(distance("NPB", "nbp", 5), 1);
    }
}
