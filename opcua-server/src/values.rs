//! The Machine Tools instance's values ([`crate::machine_tool`]) from a [`Frame`]: the packet
//! image (through [`crate::derive`]) and a part run's kernel values, keeping the active program's
//! state between ticks.
//!
//! **Invariant:** a node is reported only when its value changed since the last frame, so the
//! publisher sets (and a subscriber is notified of) changes only.

use opcua::types::{LocalizedText, NodeId, Variant};
use packets::Signal;

use crate::derive::{self, ProgramState};
use crate::handoff::Frame;
use crate::machine_tool::Source;

/// Computes the instance's values from images, keeping the program's state between ticks.
pub struct Evaluator {
    sources: Vec<(NodeId, Source)>,
    last: Vec<Option<Variant>>,
    program: ProgramState,
    mt: u16,
}

impl Evaluator {
    /// An evaluator of `sources` (MachineTool namespace `mt`).
    pub fn new(sources: Vec<(NodeId, Source)>, mt: u16) -> Evaluator {
        let last = vec![None; sources.len()];
        Evaluator {
            sources,
            last,
            program: ProgramState::Initializing,
            mt,
        }
    }

    /// The nodes whose value changed with `frame`, and their new values.
    pub fn changes(&mut self, frame: &Frame) -> Vec<(NodeId, Variant)> {
        let image = &frame.image[..];
        let kernel = |i: usize| frame.kernel.get(i).copied().unwrap_or_default();
        let bit = |s: Option<Signal>| derive::read(s, image) != 0;
        let mut out = Vec::new();
        let mut next_program = None;
        for (i, (id, src)) in self.sources.iter().enumerate() {
            let v = match *src {
                Source::ChannelState(c, h) => Variant::Int32(derive::channel_state(bit(c), bit(h))),
                Source::ChannelMode(m) => {
                    Variant::Int32(derive::channel_mode(derive::read(m, image)))
                }
                Source::OperationMode(m) => {
                    Variant::Int32(derive::operation_mode(derive::read(m, image)))
                }
                Source::Percent(s) => Variant::Double(f64::from(derive::read(s, image))),
                Source::Bit(s) => Variant::Boolean(s.read(image) != 0),
                Source::Blocks(i) => Variant::UInt64(kernel(i).blocks),
                Source::SpindleRpm(i) => Variant::Double(kernel(i).spindle_rpm),
                Source::Rotating(i) => Variant::Boolean(kernel(i).spindle_rpm != 0.0),
                Source::Dword(s) => Variant::Double(f64::from(derive::dword(s, image))),
                Source::ProgramState(c, h) | Source::ProgramStateId(c, h) => {
                    let st = *next_program.get_or_insert_with(|| self.program.next(bit(c), bit(h)));
                    match src {
                        Source::ProgramState(..) => {
                            Variant::from(LocalizedText::new("", st.name()))
                        }
                        _ => Variant::from(NodeId::new(self.mt, st.type_node())),
                    }
                }
            };
            if self.last[i].as_ref() != Some(&v) {
                self.last[i] = Some(v.clone());
                out.push((id.clone(), v));
            }
        }
        if let Some(p) = next_program {
            self.program = p;
        }
        out
    }
}
