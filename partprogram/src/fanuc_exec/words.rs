//! No silent word: every address of a Fanuc/HAAS block must be consumed by what the block does in
//! the current modal state, otherwise the block is refused with an error located at the word.
//! (G05.1 takes Q and G08 takes P: contour control on or off.)
//!
//! Axis words, F, S, T, D and H are always consumed (positions or modal settings). The others only
//! in the functions that define them (HAAS spec §6): I/J/K in an arc of their plane or a G12/G13
//! pocket, R in an arc, a canned cycle or `G10 L10/L12`, P in G04, G10, G64, G154, M97/M98, the
//! dwell of G82/G89, Q in the pecks of G73/G83 and the G12/G13 steps, L in M97/M98, G10, canned
//! cycles and G12/G13, P also in M99 (return to line P). (E, and U/W on a mill,
//! are refused by the static check already).

use super::Ex;
use crate::canon::Plane;
use crate::codes;
use crate::exec::RunError;
use crate::program::CBlock;

/// What a block does, as far as the words it may carry are concerned.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Uses {
    /// G04 in the block.
    pub dwell: bool,
    /// G10 in the block, with its L number.
    pub g10: Option<i64>,
    /// G12/G13 in the block.
    pub pocket: bool,
    /// G64, G154 or G08 in the block (P is their value).
    pub p_value: bool,
    /// G05.1 in the block (Q is its value).
    pub q_value: bool,
    /// A canned cycle runs in this block (×10 code).
    pub cycle: Option<u16>,
    /// G28, G52, G53 or G92 (no arc, no cycle).
    pub non_motion: bool,
    /// M97 or M98 in the block.
    pub call: bool,
    /// M99 in the block.
    pub ret: bool,
}

impl Ex<'_> {
    /// Refuses the first word of `b` that the block does not execute.
    pub(super) fn check_words(&self, b: &CBlock, u: &Uses) -> Result<(), RunError> {
        let arc = u.cycle.is_none()
            && !u.pocket
            && !u.non_motion
            && u.g10.is_none()
            && !u.dwell
            && matches!(self.motion, 20 | 30);
        let (c1, c2) = match (self.cyl, self.plane) {
            (Some(_), _) => ('J', 'K'),
            (None, Plane::XY) => ('I', 'J'),
            (None, Plane::ZX) => ('K', 'I'),
            (None, _) => ('J', 'K'),
        };
        let lathe = !self.axes.contains(&'Y');
        // Fanuc lets R win over I, J, K in one arc block and ignores the centre words; we refuse
        // them instead (as LinuxCNC does): a centre the control drops is a wrong part.
        let by_radius = arc && b.words.iter().any(|w| w.addr == 'R');
        for w in &b.words {
            let a = w.addr;
            if self.axes.contains(&a)
                || matches!(a, 'G' | 'M' | 'F' | 'S' | 'T' | 'D' | 'H')
                || (lathe && matches!(a, 'U' | 'W'))
            {
                continue;
            }
            let ok = match a {
                'I' | 'J' | 'K' if u.pocket => a != 'J',
                'I' | 'J' | 'K' => arc && (a == c1 || a == c2) && !by_radius,
                // G10 with an L other than 2/20 takes R (L10/L12) or is refused as a whole.
                'R' => arc || u.cycle.is_some() || matches!(u.g10, Some(l) if l != 2 && l != 20),
                'P' => {
                    u.dwell
                        || u.g10.is_some()
                        || u.p_value
                        || u.call
                        || u.ret
                        || matches!(u.cycle, Some(820 | 890))
                }
                'Q' => u.pocket || u.q_value || matches!(u.cycle, Some(730 | 830)),
                'L' => u.call || u.g10.is_some() || u.pocket || u.cycle.is_some(),
                _ => false,
            };
            if !ok {
                let why = match a {
                    'E' => "E sets the G187 corner accuracy, and G187 is not supported".to_string(),
                    'I' | 'J' | 'K' if by_radius && (a == c1 || a == c2) => format!(
                        "the arc is given by its radius R; {a} would be ignored (as Fanuc does), give the centre or R, not both"
                    ),
                    'I' | 'J' | 'K' if arc => format!(
                        "{a} is not a centre word of the G{} plane ({c1}{c2})",
                        self.plane.g()
                    ),
                    _ => format!("{a} has no meaning in this block"),
                };
                return Err(RunError {
                    code: codes::RUN_BAD_WORD,
                    message: format!("address {a}{}: {why}", lit_text(w)),
                    file: b.file,
                    span: w.span,
                });
            }
        }
        Ok(())
    }
}

fn lit_text(w: &crate::ast::Word) -> String {
    match w.val {
        crate::ast::Val::Lit(l) => format!("{}", l.value()),
        _ => String::new(),
    }
}
