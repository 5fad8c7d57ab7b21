//! QCKFD: the alternative feed PGCFIL QFD replaces the programmed F while the PLC holds QCKFD = 1
//! (003:5318-5330), in AUTO, STEP and MDI, for feed moves whose F was programmed under G94.
//! Without QFD the request is ignored (003:5330). Rapid moves keep their speed (the manual's
//! activation condition names only F under G94; spec §10 ambiguity).
//!
//! The replacement applies to the blocks handed to the interpolator while QCKFD = 1: the block
//! already in motion, and blocks already queued by look-ahead, keep the feed they were planned
//! with (the interpolator's feed can change only through the override, in whole percent).

use partprogram::Canon;
use partprogram::canon::Kind;

/// The block as the interpolator gets it: `b` with its feed replaced by `qfd` when `on`.
pub fn apply(b: &Canon, qfd: Option<f64>, on: bool) -> Option<Canon> {
    let qfd = qfd.filter(|_| on)?;
    if !b.feed_g94 || b.thread || b.feed.is_none() {
        return None;
    }
    if !matches!(b.kind, Kind::Linear | Kind::ArcCw | Kind::ArcCcw) {
        return None;
    }
    let mut c = b.clone();
    c.feed = Some(qfd);
    Some(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::fixture::block;

    fn line(f: f64, g94: bool) -> Canon {
        let mut b = block(10, Kind::Linear, 5.0, &[], None, None);
        b.feed = Some(f);
        b.feed_g94 = g94;
        b
    }

    #[test]
    fn qfd_replaces_g94_feeds_only_while_requested() {
        let b = line(300.0, true);
        assert_eq!(
            apply(&b, Some(500.0), true).and_then(|c| c.feed),
            Some(500.0)
        );
        assert_eq!(apply(&b, Some(500.0), false), None);
        // Without QFD the request is ignored.
        assert_eq!(apply(&b, None, true), None);
        // F programmed per revolution (MEFI G95) keeps its feed.
        assert_eq!(apply(&line(300.0, false), Some(500.0), true), None);
        let mut rapid = line(300.0, true);
        rapid.kind = Kind::Rapid;
        rapid.feed = None;
        assert_eq!(apply(&rapid, Some(500.0), true), None);
    }
}
