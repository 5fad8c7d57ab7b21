//! "Did you mean" suggestions: the known name nearest to a misspelled one by edit distance
//! (optimal string alignment: Levenshtein plus neighbour transpositions).
//!
//! Used by every front end for names, keywords, instructions and characterization keys. The
//! distance is Levenshtein on characters, compared without case (the languages are case-blind);
//! a candidate is suggested only when it is close relative to the word's length, so that short
//! random words get no far-fetched advice.

/// The longest word that gets a suggestion, in characters (longer words get none: bounded work).
const MAX_WORD: usize = 64;

/// The longest candidate compared: a word of [`MAX_WORD`] characters plus its edit limit.
const MAX_CANDIDATE: usize = MAX_WORD + MAX_WORD / 3;

/// Edit distance between `a` and `b` on characters (insertions, deletions, substitutions and
/// transpositions of neighbours: `NPB` is one edit from `NBP`), ignoring ASCII case; stops early
/// and returns `limit + 1` once the distance is known to exceed `limit`. Both are upper-cased
/// already; `b` is at most [`MAX_CANDIDATE`] characters. Allocates nothing: [`nearest`] runs it
/// for every candidate of every misspelled word of a file.
fn distance_upper(a: &[char], b: &[char], limit: usize) -> usize {
    if a.len().abs_diff(b.len()) > limit {
        return limit + 1;
    }
    let mut before = [0usize; MAX_CANDIDATE + 1];
    let mut prev = [0usize; MAX_CANDIDATE + 1];
    let mut cur = [0usize; MAX_CANDIDATE + 1];
    for (j, p) in prev.iter_mut().enumerate().take(b.len() + 1) {
        *p = j;
    }
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

/// The characters of `s` upper-cased into `buf`, or `None` when `s` has more than `buf` holds.
fn upper_into<'b>(s: &str, buf: &'b mut [char]) -> Option<&'b [char]> {
    let mut n = 0;
    for c in s.chars() {
        *buf.get_mut(n)? = c.to_ascii_uppercase();
        n += 1;
    }
    Some(&buf[..n])
}

/// The characters of a word counted in 64 buckets (`char % 64`): the bag distance to another
/// word is a lower bound of their edit distance (an edit changes at most one character's count on
/// each side; a transposition none; merging characters into buckets only lowers it), so most
/// candidates are ruled out in time linear in their length before the quadratic [`distance_upper`].
struct Bag {
    /// How many characters of the word fall into each bucket.
    count: [u8; 64],
    /// The word's length in characters.
    len: usize,
}

impl Bag {
    fn of(word: &[char]) -> Self {
        let mut count = [0u8; 64];
        for c in word {
            count[*c as usize % 64] += 1;
        }
        Bag {
            count,
            len: word.len(),
        }
    }

    /// The bag distance between the word and `other`, or more than `limit` once that is known.
    fn lower_bound(&self, other: &[char], limit: usize) -> usize {
        let mut count = self.count;
        // `unmatched`: the word's characters not found in `other` so far; `extra`: `other`'s
        // characters not in the word.
        let (mut unmatched, mut extra) = (self.len, 0);
        for c in other {
            let slot = &mut count[*c as usize % 64];
            if *slot > 0 {
                *slot -= 1;
                unmatched -= 1;
            } else {
                extra += 1;
                if extra > limit {
                    break;
                }
            }
        }
        unmatched.max(extra)
    }
}

/// The candidate nearest to `word` (among equals, one with the same first letter, else the first
/// in the candidates' order: `RPA` → `RAP` rather than `TPA`), if it is within
/// one edit for words of up to four characters and a third of the word's length beyond; an exact
/// (case-blind) match is not a suggestion. Words over 64 characters get none (bounded work).
pub fn nearest<'a, I>(word: &str, candidates: I) -> Option<&'a str>
where
    I: IntoIterator<Item = &'a str>,
{
    let mut word_buf = ['\0'; MAX_WORD];
    let word = upper_into(word, &mut word_buf)?;
    let len = word.len();
    if len == 0 {
        return None;
    }
    let limit = (len / 3).max(1);
    let first = word[0];
    let mut cand_buf = ['\0'; MAX_CANDIDATE];
    let bag = Bag::of(word);
    // Rank: distance, then "first letter differs" (false sorts first).
    let mut best: Option<((usize, bool), &str)> = None;
    for c in candidates {
        // A candidate of n characters has n to 4n bytes: one whose byte length rules out every
        // length within the limit is skipped without reading it.
        if c.len() + limit < len || c.len() > 4 * (len + limit) {
            continue;
        }
        // A candidate longer than any within the limit is skipped without reading it all.
        let Some(upper) = upper_into(c, &mut cand_buf) else {
            continue;
        };
        if bag.lower_bound(upper, limit) > limit {
            continue;
        }
        let d = distance_upper(word, upper, limit);
        if d == 0 || d > limit {
            continue;
        }
        let rank = (d, upper.first() != Some(&first));
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

    /// The distance of two strings through the allocation-free kernel.
    fn distance(a: &str, b: &str, limit: usize) -> usize {
        let (mut x, mut y) = (['\0'; MAX_CANDIDATE], ['\0'; MAX_CANDIDATE]);
        let a = upper_into(a, &mut x).expect("short");
        let b = upper_into(b, &mut y).expect("short");
        distance_upper(a, b, limit)
    }

    #[test]
    fn distance_is_levenshtein_with_a_limit() {
        assert_eq!(distance("kitten", "sitting", 5), 3);
        assert_eq!(distance("kitten", "sitting", 2), 3);
        assert_eq!(distance("", "abc", 5), 3);
        assert_eq!(distance("NPB", "nbp", 5), 1);
    }

    #[test]
    fn long_words_and_long_candidates_get_no_suggestion() {
        let word = "A".repeat(64);
        let near = format!("{word}B");
        let far = "A".repeat(200);
        assert_eq!(
            nearest(&word, [far.as_str(), near.as_str()]),
            Some(near.as_str())
        );
        assert_eq!(nearest(&"A".repeat(65), [near.as_str()]), None);
        assert_eq!(nearest("", ["A"]), None);
    }

    #[test]
    fn the_bag_distance_never_exceeds_the_edit_distance() {
        let words = [
            "", "A", "AB", "BA", "ABC", "CAB", "NBP", "NPB", "KITTEN", "SITTING", "A@", "AA",
        ];
        for a in words {
            for b in words {
                let (mut x, mut y) = (['\0'; MAX_CANDIDATE], ['\0'; MAX_CANDIDATE]);
                let (a, b) = (
                    upper_into(a, &mut x).expect("short"),
                    upper_into(b, &mut y).expect("short"),
                );
                let d = distance_upper(a, b, 10);
                assert!(Bag::of(a).lower_bound(b, 10) <= d, "{a:?} {b:?}");
            }
        }
        // `KITTEN` → `SITTING`: K and E unmatched, S, I and G extra: 3, the edit distance.
        let (mut x, mut y) = (['\0'; MAX_CANDIDATE], ['\0'; MAX_CANDIDATE]);
        let k = upper_into("kitten", &mut x).expect("short");
        let s = upper_into("sitting", &mut y).expect("short");
        assert_eq!(Bag::of(k).lower_bound(s, 5), 3);
    }

    /// The textbook optimal-string-alignment distance (full table, no limit): the oracle.
    fn reference_distance(a: &str, b: &str) -> usize {
        let a: Vec<char> = a.chars().map(|c| c.to_ascii_uppercase()).collect();
        let b: Vec<char> = b.chars().map(|c| c.to_ascii_uppercase()).collect();
        let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
        for (i, row) in d.iter_mut().enumerate() {
            row[0] = i;
        }
        for (j, cell) in d[0].iter_mut().enumerate() {
            *cell = j;
        }
        for i in 1..=a.len() {
            for j in 1..=b.len() {
                let cost = usize::from(a[i - 1] != b[j - 1]);
                d[i][j] = (d[i - 1][j] + 1)
                    .min(d[i][j - 1] + 1)
                    .min(d[i - 1][j - 1] + cost);
                if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                    d[i][j] = d[i][j].min(d[i - 2][j - 2] + 1);
                }
            }
        }
        d[a.len()][b.len()]
    }

    /// [`nearest`]'s rule spelled out with the oracle distance.
    fn reference_nearest<'a>(word: &str, candidates: &[&'a str]) -> Option<&'a str> {
        let len = word.chars().count();
        if len == 0 || len > 64 {
            return None;
        }
        let limit = (len / 3).max(1);
        let first = word.chars().next().map(|c| c.to_ascii_uppercase());
        let mut best: Option<((usize, bool), &str)> = None;
        for c in candidates {
            let d = reference_distance(word, c);
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

    #[test]
    fn nearest_agrees_with_the_textbook_rule_on_random_words() {
        // A seeded linear congruential generator: words over a small alphabet so that near
        // misses, transpositions and bucket collisions (`A` and `a`, `!` and `a`) are common.
        let mut state: u64 = 20261129;
        let mut next = |n: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        let alphabet: Vec<char> = "ABCDEabc_1!Ж".chars().collect();
        let word = |next: &mut dyn FnMut(u64) -> u64| -> String {
            let len = next(9);
            (0..len)
                .map(|_| alphabet[next(alphabet.len() as u64) as usize])
                .collect()
        };
        let mut agreed_on_some = 0;
        for _ in 0..3000 {
            let w = word(&mut next);
            let cands: Vec<String> = (0..12).map(|_| word(&mut next)).collect();
            let cands: Vec<&str> = cands.iter().map(String::as_str).collect();
            let expected = reference_nearest(&w, &cands);
            assert_eq!(
                nearest(&w, cands.iter().copied()),
                expected,
                "{w:?} in {cands:?}"
            );
            agreed_on_some += usize::from(expected.is_some());
        }
        // The draw exercises suggestions, not only their absence.
        assert!(agreed_on_some > 300, "{agreed_on_some}");
    }
}
