//! The active modal codes of a process for the Machine page: the motion mode, the plane, the
//! distance and feed mode, the work offset, cutter compensation with D, tool length with H, F, S,
//! T, the spindle and coolant M functions in effect at the kernel's current block, folded from
//! the loaded program's canonical blocks (on the HMI's render thread, incrementally: each block
//! is folded once per program run). Canonical blocks carry resolved positions, so the modes that
//! no position shows come from each block's modal record ([`partprogram::BlockModal`]); constant
//! surface speed from its `css` (each block carries it while G96 is in effect).

use partprogram::canon::{BlockModal, Canon, Kind, Plane, num};

/// The modal state after some blocks.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Modal {
    /// The last motion G code (G00, G01, G02, G03, G33).
    pub motion: Option<&'static str>,
    /// The plane of the last motion block.
    pub plane: Option<Plane>,
    /// The last programmed feed.
    pub feed: Option<f64>,
    /// The last programmed spindle speed.
    pub s: Option<f64>,
    /// The last selected tool.
    pub t: Option<i64>,
    /// The last spindle function (M03, M04, M05).
    pub spindle: Option<u16>,
    /// The last coolant function (M07, M08, M09).
    pub coolant: Option<u16>,
    /// Constant surface speed in m/min while G96 is in effect.
    pub css: Option<f64>,
    /// The last block's modal record (G90/G91, G94–G97, work offset, G40–G42 D, G43/G44/G49 H).
    pub block: Option<BlockModal>,
}

impl Modal {
    /// Applies one block.
    pub fn fold(&mut self, b: &Canon) {
        let motion = match b.kind {
            Kind::Rapid => Some("G00"),
            Kind::Linear if b.thread => Some("G33"),
            Kind::Linear => Some("G01"),
            Kind::ArcCw => Some("G02"),
            Kind::ArcCcw => Some("G03"),
            Kind::Dwell | Kind::Aux => None,
        };
        if motion.is_some() {
            self.motion = motion;
            self.plane = Some(b.plane);
        }
        self.feed = b.feed.or(self.feed);
        self.s = b.s.or(self.s);
        self.t = b.t.or(self.t);
        self.css = b.css.as_ref().map(|c| c.m_min);
        self.block = Some(b.modal);
        for m in &b.m {
            match m.m {
                3..=5 => self.spindle = Some(m.m),
                7..=9 => self.coolant = Some(m.m),
                _ => {}
            }
        }
    }

    /// The codes as the page shows them, e.g. `["G01", "G18", "G90", "G94", "G54", "G40",
    /// "F0.2", "S1200", "T1", "M03"]`.
    pub fn codes(&self) -> Vec<String> {
        let mut v: Vec<String> = self.motion.iter().map(|g| g.to_string()).collect();
        v.extend(self.plane.map(|p| format!("G{}", p.g())));
        v.extend(self.block.iter().flat_map(BlockModal::codes));
        // MEFI's feed modes G96/G97 are KŘR themselves; elsewhere G96 shows constant surface speed.
        let kr = self.block.is_some_and(|b| b.feed_mode >= 96);
        v.extend(self.css.filter(|_| !kr).map(|_| "G96".to_string()));
        v.extend(self.feed.map(|f| format!("F{}", num(f))));
        v.extend(self.s.map(|s| format!("S{}", num(s))));
        v.extend(self.t.map(|t| format!("T{t}")));
        v.extend(self.spindle.map(|m| format!("M{m:02}")));
        v.extend(self.coolant.map(|m| format!("M{m:02}")));
        v
    }
}

/// The modal state of one process's program, folded up to the current block.
#[derive(Debug, Clone, Default)]
pub struct ModalTracker {
    program: u64,
    folded: usize,
    state: Modal,
}

impl ModalTracker {
    /// The state with blocks `0..=block` of `program` (load number `id`) applied; every block is
    /// folded once while the block index only grows.
    pub fn at(&mut self, id: u64, program: &[Canon], block: usize) -> &Modal {
        let upto = block.saturating_add(1).min(program.len());
        if id != self.program || upto < self.folded {
            *self = ModalTracker {
                program: id,
                ..ModalTracker::default()
            };
        }
        for b in &program[self.folded..upto] {
            self.state.fold(b);
        }
        self.folded = upto;
        &self.state
    }
}

#[cfg(test)]
mod tests {
    use partprogram::canon::MFunc;

    use super::*;

    fn block(kind: Kind, feed: Option<f64>, s: Option<f64>, t: Option<i64>, m: &[u16]) -> Canon {
        Canon {
            n: None,
            unit: None,
            kind,
            end: Vec::new(),
            center: Vec::new(),
            plane: Plane::ZX,
            feed,
            m: m.iter().map(|&m| MFunc { m, before: true }).collect(),
            s,
            t,
            dwell: None,
            thread: false,
            thread_angle: 0.0,
            exact_stop: false,
            tolerance: None,
            css: None,
            feed_g94: true,
            modal: partprogram::canon::BlockModal::default(),
        }
    }

    #[test]
    fn codes_in_effect_are_folded_up_to_the_current_block() {
        let prog = vec![
            block(Kind::Aux, None, Some(1200.0), Some(1), &[3]),
            block(Kind::Rapid, None, None, None, &[8]),
            block(Kind::Linear, Some(150.0), None, None, &[]),
            block(Kind::Dwell, None, None, None, &[]),
            block(Kind::ArcCw, Some(80.5), None, Some(2), &[5, 9]),
        ];
        let mut m = ModalTracker::default();
        assert_eq!(
            m.at(1, &prog, 0).codes(),
            ["G90", "G94", "G40", "S1200", "T1", "M03"]
        );
        assert_eq!(
            m.at(1, &prog, 3).codes(),
            [
                "G01", "G18", "G90", "G94", "G40", "F150", "S1200", "T1", "M03", "M08"
            ]
        );
        // Past the end: every block applied; the dwell left G01 in effect before the arc.
        assert_eq!(
            m.at(1, &prog, 9).codes(),
            [
                "G02", "G18", "G90", "G94", "G40", "F80.5", "S1200", "T2", "M05", "M09"
            ]
        );
        // A block index that went back (a restart) folds again from the first block.
        assert_eq!(
            m.at(1, &prog, 1).codes(),
            [
                "G00", "G18", "G90", "G94", "G40", "S1200", "T1", "M03", "M08"
            ]
        );
        // Another program load starts over.
        assert_eq!(
            m.at(2, &prog[2..], 0).codes(),
            ["G01", "G18", "G90", "G94", "G40", "F150"]
        );
        // G96 while a block carries a cutting speed, gone with the first block without one.
        let mut g96 = block(Kind::Linear, Some(0.2), Some(120.0), None, &[]);
        g96.css = Some(partprogram::canon::Css {
            m_min: 120.0,
            max_rpm: None,
            origin: Vec::new(),
            diameter: true,
        });
        let css = vec![g96, block(Kind::Linear, None, Some(800.0), None, &[])];
        assert_eq!(
            m.at(3, &css, 0).codes(),
            ["G01", "G18", "G90", "G94", "G40", "G96", "F0.2", "S120"]
        );
        assert_eq!(
            m.at(3, &css, 1).codes(),
            ["G01", "G18", "G90", "G94", "G40", "F0.2", "S800"]
        );
    }

    #[test]
    fn the_blocks_modal_record_shows_distance_feed_offset_compensation_and_length() {
        // Fanuc: G91, work offset G154 P3, G42 D7, G43 H2.
        let mut b = block(Kind::Linear, Some(100.0), None, None, &[]);
        b.modal = BlockModal {
            distance: 91,
            feed_mode: 94,
            work: 154,
            work_p: 3,
            cutter: 42,
            d: 7,
            length: 43,
            h: 2,
            contour: false,
        };
        let mut m = ModalTracker::default();
        assert_eq!(
            m.at(1, &[b], 0).codes(),
            [
                "G01", "G18", "G91", "G94", "G154 P3", "G42", "D7", "G43", "H2", "F100"
            ]
        );
        // MEFI KŘR with feed per revolution (G97): the feed mode says it, no separate G96.
        let mut k = block(Kind::Linear, Some(0.2), Some(1200.0), None, &[]);
        k.modal = BlockModal {
            feed_mode: 97,
            work: 54,
            d: 1,
            ..BlockModal::default()
        };
        k.css = Some(partprogram::canon::Css {
            m_min: 120.0,
            max_rpm: None,
            origin: Vec::new(),
            diameter: true,
        });
        assert_eq!(
            m.at(2, &[k], 0).codes(),
            [
                "G01", "G18", "G90", "G97", "G54", "G40", "D1", "F0.2", "S1200"
            ]
        );
    }
}
