//! The simulated machine's handwheels (part runs): `sim.toml [[handwheel]]` wires an IOCFIL ADV
//! channel to a packet-A input byte that counts pulses modulo 256, and `[[part.at]] turn = { 1 =
//! 250 }` turns channel 1 by 250 pulses at that tick. A turn is delivered at no more than
//! [`MAX_PULSES_PER_TICK`] pulses per tick (one revolution), so that the kernel, which reads the
//! counter's change as −128 … 127, never loses one.

use std::collections::BTreeMap;

use packets::{Packet, Signal};

use super::SimError;
use super::script::{At, HandwheelWiring};

/// Pulses the simulated handwheel delivers per logic tick at most (100 pulses = 1 revolution).
pub const MAX_PULSES_PER_TICK: i64 = 100;

/// One wired channel: its counter, the count, and the pulses still to deliver.
#[derive(Debug, Clone)]
struct Wheel {
    process: u8,
    channel: u8,
    counter: Signal,
    count: u8,
    pending: i64,
}

/// The handwheels of the simulated machine and their scheduled turns.
#[derive(Debug, Clone, Default)]
pub struct HandwheelSim {
    wheels: Vec<Wheel>,
    turns: BTreeMap<u64, Vec<(u8, u8, i64)>>,
}

impl HandwheelSim {
    /// The wheels of `wiring` (`declared(process, channel)`: ADV declares the channel) and the
    /// turns taken out of `at` (which keeps the rest).
    pub fn new(
        wiring: &[HandwheelWiring],
        at: &mut [At],
        declared: impl Fn(u8, u8) -> bool,
    ) -> Result<HandwheelSim, SimError> {
        let mut wheels: Vec<Wheel> = Vec::new();
        for w in wiring {
            let counter: Signal = w.counter.parse().map_err(|e| {
                SimError::Invalid(format!("[[handwheel]] counter `{}`: {e}", w.counter))
            })?;
            if counter.packet() != Packet::A || counter.bit().is_some() {
                return Err(SimError::Invalid(format!(
                    "[[handwheel]] counter `{}`: a packet-A input byte (`W1A3`) is needed",
                    w.counter
                )));
            }
            if !declared(w.process, w.channel) {
                return Err(SimError::Invalid(format!(
                    "[[handwheel]] channel {} of process {}: IOCFIL ADV declares no such handwheel channel",
                    w.channel, w.process
                )));
            }
            if wheels
                .iter()
                .any(|x| x.process == w.process && x.channel == w.channel)
            {
                return Err(SimError::Invalid(format!(
                    "[[handwheel]] channel {} of process {} is wired twice",
                    w.channel, w.process
                )));
            }
            wheels.push(Wheel {
                process: w.process,
                channel: w.channel,
                counter,
                count: 0,
                pending: 0,
            });
        }
        let mut turns: BTreeMap<u64, Vec<(u8, u8, i64)>> = BTreeMap::new();
        for a in at.iter_mut() {
            for (k, pulses) in std::mem::take(&mut a.turn) {
                let channel = k.parse::<u8>().ok().filter(|c| {
                    wheels
                        .iter()
                        .any(|w| w.process == a.process && w.channel == *c)
                });
                let Some(channel) = channel else {
                    return Err(SimError::Invalid(format!(
                        "tick {}: turn `{k}`: process {} has no [[handwheel]] channel {k}",
                        a.tick, a.process
                    )));
                };
                turns
                    .entry(a.tick)
                    .or_default()
                    .push((a.process, channel, pulses));
            }
        }
        Ok(HandwheelSim { wheels, turns })
    }

    /// The counters of `process`'s channels 1 and 2 (for the kernel).
    pub fn counters(&self, process: u8) -> [Option<Signal>; 2] {
        std::array::from_fn(|c| {
            self.wheels
                .iter()
                .find(|w| w.process == process && usize::from(w.channel) == c + 1)
                .map(|w| w.counter)
        })
    }

    /// Tick `tick`: starts the turns scheduled now and writes every counter into `packets`.
    pub fn latch(&mut self, tick: u64, packets: &mut [u8]) {
        if let Some(list) = self.turns.remove(&tick) {
            for (process, channel, pulses) in list {
                if let Some(w) = self
                    .wheels
                    .iter_mut()
                    .find(|w| w.process == process && w.channel == channel)
                {
                    w.pending = w.pending.saturating_add(pulses);
                }
            }
        }
        for w in &mut self.wheels {
            let now = w.pending.clamp(-MAX_PULSES_PER_TICK, MAX_PULSES_PER_TICK);
            w.pending -= now;
            w.count = w.count.wrapping_add(now as i8 as u8);
            w.counter.write(packets, w.count);
        }
    }
}
