//! No silent word in MEFI: a word that has a meaning only in some blocks is refused (2530) in a
//! block where it would do nothing, located at the word. K, H and P mean nothing in any block and
//! are refused by the static check (2038, `check.rs`).

use crate::codes;
use crate::exec::RunError;
use crate::program::CBlock;

/// What the block did, as far as the context-dependent words care.
pub(super) struct Done {
    /// The modal motion after the block's G functions (0–3, 33).
    pub motion: u16,
    /// The block interpolated a path (a move, an arc, a thread).
    pub interpolated: bool,
    /// G04 in the block.
    pub dwell: bool,
    /// The G70–G79 program-flow function of the block.
    pub flow: Option<u16>,
}

/// Refuses the first word of `b` that the block did not use.
pub(super) fn check(b: &CBlock, done: &Done) -> Result<(), RunError> {
    let arc = done.interpolated && matches!(done.motion, 2 | 3);
    let thread = done.interpolated && done.motion == 33;
    let calls = matches!(done.flow, Some(71..=73 | 78 | 79));
    for w in &b.words {
        let why = match w.addr {
            'I' | 'J' if !(arc || thread) => {
                "I and J are circle centres (G02/G03) or the G33 start angle and run-out"
            }
            'E' if !thread => "E is the thread run-in of a G33 move",
            'L' if !calls => "L is the unit or block of G71, G72, G73 or G79",
            'Q' if !(calls || done.dwell) => {
                "Q is the repeat count of G71/G72/G73 or the dwell of G04"
            }
            _ => continue,
        };
        return Err(RunError {
            code: codes::RUN_BAD_WORD,
            message: format!("address {}: {why}; this block would ignore it", w.addr),
            file: b.file,
            span: w.span,
        });
    }
    Ok(())
}
