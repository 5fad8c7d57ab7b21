//! A diagnostic sink with a cap: it counts every diagnostic pushed into it but stores at most `max`
//! of each file (issue 23, item 4), so a reader of an error-dense file of any size keeps a constant
//! number of diagnostics in memory. `ncplc check|nc check --max-errors N` sets the cap.
//!
//! **Invariant:** the stored diagnostics of a file are exactly the first `max` of the stable order
//! by `(span.start, code)` of everything pushed for it (ties in push order), the order the machine
//! loader sorts a file's diagnostics in; so what is printed with a cap is what sorting every
//! diagnostic and cutting each file's list after `max` printed before. `max == 0` stores
//! everything. The sink holds at most `max` diagnostics per file at any moment (pushing the one too
//! many drops the largest).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::{Diagnostic, Hidden};

/// One stored diagnostic with its place in the order.
#[derive(Debug)]
struct Entry {
    key: (usize, u32, u64),
    diagnostic: Diagnostic,
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.key == other.key
    }
}

impl Eq for Entry {}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        self.key.cmp(&other.key)
    }
}

/// Collects diagnostics, storing at most `max` per file (0: all) and counting the rest per file.
#[derive(Debug, Default)]
pub struct Sink {
    max: usize,
    pushed: u64,
    errors: usize,
    warnings: usize,
    /// Per file (a handful), the stored diagnostics (with a cap).
    kept: Vec<(String, BinaryHeap<Entry>)>,
    /// Without a cap, every diagnostic in push order: nothing to rank or sort.
    all: Vec<Diagnostic>,
    dropped: Vec<Hidden>,
}

impl Sink {
    /// A sink that stores at most `max` diagnostics (0: all of them).
    pub fn new(max: usize) -> Self {
        Sink {
            max,
            ..Sink::default()
        }
    }

    /// A sink that stores every diagnostic.
    pub fn unbounded() -> Self {
        Sink::new(0)
    }

    /// Counts `d` and stores it unless `max` smaller ones of its file are stored already.
    pub fn push(&mut self, d: Diagnostic) {
        if d.is_error() {
            self.errors += 1;
        } else {
            self.warnings += 1;
        }
        if self.max == 0 {
            self.all.push(d);
            return;
        }
        let key = (d.span.start, d.code, self.pushed);
        self.pushed += 1;
        let i = match self.kept.iter().position(|(f, _)| *f == d.file) {
            Some(i) => i,
            None => {
                self.kept.push((d.file.clone(), BinaryHeap::new()));
                self.kept.len() - 1
            }
        };
        let heap = &mut self.kept[i].1;
        // Full, and after every stored one (as most are: readers report in file order): counted
        // and dropped without entering the heap.
        if heap.len() >= self.max && heap.peek().is_some_and(|top| key > top.key) {
            self.drop_one(&d);
            return;
        }
        heap.push(Entry { key, diagnostic: d });
        if heap.len() > self.max
            && let Some(out) = heap.pop()
        {
            self.drop_one(&out.diagnostic);
        }
    }

    /// Counts diagnostics another sink counted but did not store (its [`Sink::finish`]).
    pub fn count_hidden(&mut self, hidden: &[Hidden]) {
        for h in hidden {
            self.errors += h.errors;
            self.warnings += h.warnings;
        }
        merge_hidden(&mut self.dropped, hidden);
    }

    fn drop_one(&mut self, d: &Diagnostic) {
        let i = match self.dropped.iter().position(|h| h.file == d.file) {
            Some(i) => i,
            None => {
                self.dropped.push(Hidden {
                    file: d.file.clone(),
                    errors: 0,
                    warnings: 0,
                });
                self.dropped.len() - 1
            }
        };
        if d.is_error() {
            self.dropped[i].errors += 1;
        } else {
            self.dropped[i].warnings += 1;
        }
    }

    /// Errors pushed so far, stored or not.
    pub fn errors(&self) -> usize {
        self.errors
    }

    /// Warnings pushed so far, stored or not.
    pub fn warnings(&self) -> usize {
        self.warnings
    }

    /// Diagnostics pushed so far, stored or not.
    pub fn len(&self) -> usize {
        self.errors + self.warnings
    }

    /// True when nothing was pushed.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// True when an error was pushed.
    pub fn has_errors(&self) -> bool {
        self.errors > 0
    }

    /// Diagnostics stored now (at most the cap per file).
    pub fn stored(&self) -> usize {
        self.all.len() + self.kept.iter().map(|(_, h)| h.len()).sum::<usize>()
    }

    /// The stored diagnostics in push order and, per file in order of the first dropped one,
    /// how many were counted but not stored.
    pub fn finish(self) -> (Vec<Diagnostic>, Vec<Hidden>) {
        if self.max == 0 {
            return (self.all, self.dropped);
        }
        let mut kept: Vec<Entry> = self
            .kept
            .into_iter()
            .flat_map(|(_, h)| h.into_vec())
            .collect();
        kept.sort_by_key(|e| e.key.2);
        (
            kept.into_iter().map(|e| e.diagnostic).collect(),
            self.dropped,
        )
    }

    /// The stored diagnostics in push order (all of them for an unbounded sink).
    pub fn into_vec(self) -> Vec<Diagnostic> {
        self.finish().0
    }
}

impl Extend<Diagnostic> for Sink {
    fn extend<I: IntoIterator<Item = Diagnostic>>(&mut self, iter: I) {
        for d in iter {
            self.push(d);
        }
    }
}

/// Adds the counts of `more` to `hidden`, file by file (files new to `hidden` go last).
pub fn merge_hidden(hidden: &mut Vec<Hidden>, more: &[Hidden]) {
    for m in more {
        match hidden.iter_mut().find(|h| h.file == m.file) {
            Some(h) => {
                h.errors += m.errors;
                h.warnings += m.warnings;
            }
            None => hidden.push(m.clone()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(start: usize, code: u32) -> Diagnostic {
        Diagnostic::error(code, "F", start..start + 1, format!("{start}/{code}"))
    }

    #[test]
    fn keeps_exactly_the_first_max_of_the_sorted_order_and_counts_the_rest() {
        // Pushed out of order: positions 50, 10, 40, 10 (code 3), 30, 20, then a warning at 5.
        let mut s = Sink::new(3);
        for (start, code) in [(50, 1), (10, 7), (40, 1), (10, 3), (30, 1), (20, 1)] {
            s.push(err(start, code));
            assert!(s.stored() <= 3);
        }
        s.push(Diagnostic::warning(9, "F", 5..6, "w"));
        assert_eq!(
            (s.errors(), s.warnings(), s.len(), s.stored()),
            (6, 1, 7, 3)
        );
        let (kept, hidden) = s.finish();
        // The three smallest by (start, code), returned in push order: 10/7, 10/3, then the warning.
        let msgs: Vec<&str> = kept.iter().map(|d| d.message.as_str()).collect();
        assert_eq!(msgs, ["10/7", "10/3", "w"]);
        assert_eq!(
            hidden,
            [Hidden {
                file: "F".into(),
                errors: 4,
                warnings: 0
            }]
        );
    }

    #[test]
    fn a_capped_sink_stores_what_sorting_everything_and_cutting_stored() {
        // Pseudo-random positions and codes with many ties.
        let all: Vec<Diagnostic> = (0..500u64)
            .map(|i| err(((i * 7919) % 97) as usize, ((i * 31) % 5) as u32))
            .collect();
        let mut sorted = all.clone();
        sorted.sort_by_key(|d| (d.span.start, d.code));
        let mut s = Sink::new(40);
        s.extend(all.iter().cloned());
        let mut kept = s.into_vec();
        kept.sort_by_key(|d| (d.span.start, d.code));
        assert_eq!(kept, sorted[..40]);
    }

    #[test]
    fn the_cap_is_per_file_and_hidden_counts_of_another_sink_add_up() {
        let mut s = Sink::new(2);
        for i in 0..5 {
            s.push(err(i, 1));
            s.push(Diagnostic::error(1, "G", i..i + 1, "g"));
        }
        assert_eq!((s.stored(), s.errors()), (4, 10));
        s.count_hidden(&[Hidden {
            file: "G".into(),
            errors: 7,
            warnings: 2,
        }]);
        assert_eq!((s.errors(), s.warnings()), (17, 2));
        let (kept, hidden) = s.finish();
        let got: Vec<(&str, usize)> = kept
            .iter()
            .map(|d| (d.file.as_str(), d.span.start))
            .collect();
        assert_eq!(got, [("F", 0), ("G", 0), ("F", 1), ("G", 1)]);
        assert_eq!(
            hidden,
            [
                Hidden {
                    file: "F".into(),
                    errors: 3,
                    warnings: 0
                },
                Hidden {
                    file: "G".into(),
                    errors: 10,
                    warnings: 2
                }
            ]
        );
    }

    #[test]
    fn an_unbounded_sink_keeps_everything_in_push_order() {
        let mut s = Sink::unbounded();
        s.extend([err(9, 1), err(1, 1), err(5, 1)]);
        let (kept, hidden) = s.finish();
        let starts: Vec<usize> = kept.iter().map(|d| d.span.start).collect();
        assert_eq!(starts, [9, 1, 5]);
        assert!(hidden.is_empty());
    }
}
