//! The cyclic scheduler: per tick latch inputs, run the logic, publish outputs (docs/plc-language.md §6).
//!
//! Tick `t` starts at `t × tick` after the start on the [`Clock`]. A tick that ends after the next
//! tick's start is an overrun; `overrun_limit` consecutive overruns trip the safe state (physical
//! outputs to 0, logic halted, alarm). Online change swaps the program at a tick boundary. HMI
//! writes and forces ([`Forces`]) go into the image after the latch and (forces) again after the
//! logic; the trace records both.

use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

use packets::PacketIo;

use crate::clock::Clock;
use crate::force::Forces;
use crate::image::Image;
use crate::program::Loaded;
use crate::retain::{RetainLayout, RetainRecord};
use crate::stats::Stats;
use trace::positions::{PositionSource, PositionTracker};
use trace::recorder::{InputDiff, OutputTracker};
use trace::{TickRecord, TraceError, TraceSink};

/// A new program for the running scheduler, compiled in the background.
pub struct Swap {
    /// The program.
    pub loaded: Loaded,
    /// When the edit was noticed (for the edit-to-running latency).
    pub noticed: Instant,
    /// The source file's modification time, when known.
    pub modified: Option<std::time::SystemTime>,
}

/// Something the operator should hear about.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// An alarm (overrun trip, I/O alarm, handshake timeout, …).
    Alarm(String),
    /// An alarm cleared.
    Cleared(String),
    /// A new program runs since tick `tick`; `latency` from the edit to its first scan.
    Swapped {
        /// First tick of the new program.
        tick: u64,
        /// Edit (file modification, or notice when unknown) to first scan.
        latency: Duration,
    },
}

/// Retain bookkeeping inside the loop.
struct RetainState {
    layout: RetainLayout,
    last: RetainRecord,
    sink: Box<dyn FnMut(RetainRecord) + Send>,
}

/// Scheduler settings.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Tick length.
    pub tick_ns: u64,
    /// Consecutive overruns that trip the safe state (0: never).
    pub overrun_limit: u32,
}

/// The scan loop and everything it owns.
pub struct Scheduler {
    image: Image,
    loaded: Loaded,
    io: Box<dyn PacketIo>,
    clock: Box<dyn Clock>,
    settings: Settings,
    /// Timing statistics.
    pub stats: Stats,
    tick: u64,
    start_ns: u64,
    started: bool,
    /// When the first tick started (wall clock), for the start-to-first-tick figure.
    first_tick_at: Option<Instant>,
    tripped: bool,
    events: Vec<Event>,
    recording: Option<(InputDiff, Box<dyn TraceSink>, TickRecord)>,
    /// Operator commands applied since the last tick, for the next tick's record.
    commands: Vec<trace::OperatorCommand>,
    tracker: OutputTracker,
    swaps: Option<Receiver<Swap>>,
    retain: Option<RetainState>,
    last_io_error: Option<TraceError>,
    forces: Forces,
    forced_scratch: Vec<trace::SignalValue>,
    positions: Option<(PositionSource, PositionTracker)>,
    drives: Option<(DriveSource, Vec<trace::DriveSample>)>,
    nodes_lost: Option<NodeLossSource>,
}

/// Fills the bus drives' feedback the kernel took at this tick's latch (a part run on drives).
pub type DriveSource = Box<dyn FnMut(&mut Vec<trace::DriveSample>) + Send>;

/// Fills the I/O nodes lost at the last latch (empty when none was newly lost).
pub type NodeLossSource = Box<dyn FnMut(&mut Vec<trace::NodeLoss>) + Send>;

impl Scheduler {
    /// A scheduler around `loaded`, starting from `image` (T set, retain restored by the caller).
    pub fn new(
        image: Image,
        loaded: Loaded,
        io: Box<dyn PacketIo>,
        clock: Box<dyn Clock>,
        settings: Settings,
    ) -> Self {
        let tracker = OutputTracker::new(&loaded.meta.written_signals());
        let mut image = image;
        if image.bytes().len() < loaded.meta.image_len() {
            image = image.resized_for(loaded.meta.image_len());
        }
        Scheduler {
            image,
            loaded,
            io,
            clock,
            settings,
            stats: Stats::new(),
            tick: 0,
            start_ns: 0,
            started: false,
            first_tick_at: None,
            tripped: false,
            events: Vec::new(),
            recording: None,
            commands: Vec::new(),
            tracker,
            swaps: None,
            retain: None,
            last_io_error: None,
            forces: Forces::default(),
            forced_scratch: Vec::new(),
            positions: None,
            drives: None,
            nodes_lost: None,
        }
    }

    /// Records every tick's inputs and changed outputs into `sink`.
    pub fn record_to(&mut self, sink: Box<dyn TraceSink>) {
        self.recording = Some((InputDiff::default(), sink, TickRecord::default()));
    }

    /// With a recording: every tick's axis positions that changed (a part run's kernel) go into
    /// its records; `source` lists them after the I/O latched the tick.
    pub fn record_positions(&mut self, source: PositionSource) {
        self.positions = Some((source, PositionTracker::default()));
    }

    /// With a recording: the bus drives' feedback of every tick where it differs from the last
    /// recorded one (a part run on CiA 402 drives).
    pub fn record_drives(&mut self, source: DriveSource) {
        self.drives = Some((source, Vec::new()));
    }

    /// Records the I/O nodes `source` says were lost at each latch (a part run on CANopen).
    pub fn record_nodes_lost(&mut self, source: NodeLossSource) {
        self.nodes_lost = Some(source);
    }

    /// Takes new programs from `rx` at tick boundaries.
    pub fn accept_swaps(&mut self, rx: Receiver<Swap>) {
        self.swaps = Some(rx);
    }

    /// Hands a retain snapshot to `sink` whenever the retained data changed (at most once a tick).
    pub fn retain_to(&mut self, sink: Box<dyn FnMut(RetainRecord) + Send>) {
        let meta = &self.loaded.meta;
        let layout = RetainLayout::new(
            &meta.written_signals(),
            meta.retain_range(),
            meta.retain_layout(),
        );
        let last = layout.snapshot(self.image.bytes(), 0);
        self.retain = Some(RetainState { layout, last, sink });
    }

    /// Restarts the timeline after a deliberate pause: the next tick is due now (tick numbers go on).
    pub fn resync(&mut self) {
        let now = self.clock.now_ns();
        self.start_ns = now.saturating_sub(self.tick * self.settings.tick_ns);
        self.started = true;
    }

    /// Stops handing out retain snapshots (drops the sink).
    pub fn detach_retain(&mut self) {
        self.retain = None;
    }

    /// The image.
    pub fn image(&self) -> &Image {
        &self.image
    }

    /// The next tick number (= ticks run).
    pub fn tick_count(&self) -> u64 {
        self.tick
    }

    /// When the first tick started its work (after waking), or `None` before it.
    pub fn first_tick_at(&self) -> Option<Instant> {
        self.first_tick_at
    }

    /// True after the overrun limit tripped the safe state.
    pub fn tripped(&self) -> bool {
        self.tripped
    }

    /// Where the running program writes its power flow, when it was compiled for it.
    pub fn flow(&self) -> Option<&std::sync::Arc<compiler::ir::flow::FlowMap>> {
        self.loaded.meta.flow()
    }

    /// The running program's facts.
    pub fn meta(&self) -> &std::sync::Arc<dyn crate::program::ProgramMeta> {
        &self.loaded.meta
    }

    /// From the next tick on, runs `loaded` in place of the running program and keeps the image
    /// as it is (no migration): `loaded` must be the running program with or without power flow
    /// ([`crate::compiled::variant`]), which lay out the image alike up to the flow area. The
    /// image grows to hold a flow area, which starts at 0. The scan's results do not change
    /// (power flow only writes its own area).
    pub fn switch_variant(&mut self, loaded: Loaded) {
        self.image.grow_to(loaded.meta.image_len());
        if let Some(f) = loaded.meta.flow()
            && let Some(area) = self.image.bytes_mut().get_mut(f.area.0..f.area.1)
        {
            area.fill(0);
        }
        self.loaded = loaded;
    }

    /// The running engine's name.
    pub fn engine_name(&self) -> &str {
        self.loaded.logic.name()
    }

    /// The HMI's writes and forces (applied from the next tick on).
    pub fn forces_mut(&mut self) -> &mut Forces {
        &mut self.forces
    }

    /// The active forces and pending writes.
    pub fn forces(&self) -> &Forces {
        &self.forces
    }

    /// With a recording: the kernel accepted operator command `c` at this tick boundary; it goes
    /// into the next tick's record (a replay gives it to its kernel before that tick's latch).
    pub fn record_command(&mut self, c: trace::OperatorCommand) {
        if self.recording.is_some() {
            self.commands.push(c);
        }
    }

    /// Events since the last call.
    pub fn take_events(&mut self) -> Vec<Event> {
        std::mem::take(&mut self.events)
    }

    /// Runs one tick (waiting for its start time on the clock).
    pub fn step(&mut self) {
        if !self.started {
            self.start_ns = self.clock.now_ns();
            self.started = true;
        }
        let t = self.tick;
        let due = self.start_ns + t * self.settings.tick_ns;
        let woke = self.clock.sleep_until(due);
        let work = Instant::now();
        self.first_tick_at.get_or_insert(work);
        self.take_swap(t);
        if let Some((diff, _, rec)) = &mut self.recording {
            diff.before_latch(self.image.bytes());
            rec.t = t;
            rec.inputs.clear();
            rec.outputs.clear();
            rec.forced.clear();
            rec.positions.clear();
            rec.commands.clear();
            rec.commands.append(&mut self.commands);
            rec.drives.clear();
            rec.nodes_lost.clear();
        }
        self.io.latch_inputs(t, self.image.packets_mut());
        self.forces.apply_before(self.image.bytes_mut());
        if let Some((diff, _, rec)) = &mut self.recording {
            diff.after_latch(self.image.bytes(), &mut rec.inputs);
            if let Some((source, tracker)) = &mut self.positions {
                tracker.diff(source, &mut rec.positions);
            }
            if let Some((source, last)) = &mut self.drives {
                source(&mut rec.drives);
                if rec.drives == *last {
                    rec.drives.clear();
                } else {
                    last.clone_from(&rec.drives);
                }
            }
            if let Some(source) = &mut self.nodes_lost {
                source(&mut rec.nodes_lost);
            }
        }
        if !self.tripped {
            self.loaded.logic.tick(self.image.bytes_mut());
            let changed = match &mut self.recording {
                Some((_, _, rec)) => &mut rec.forced,
                None => &mut self.forced_scratch,
            };
            self.forces.apply_after(self.image.bytes_mut(), changed);
            self.forced_scratch.clear();
        } else {
            self.image.clear_physical_outputs();
        }
        if let Some((_, sink, rec)) = &mut self.recording {
            self.tracker.diff(self.image.bytes(), &mut rec.outputs);
            if !(rec.inputs.is_empty()
                && rec.outputs.is_empty()
                && rec.forced.is_empty()
                && rec.positions.is_empty()
                && rec.commands.is_empty()
                && rec.drives.is_empty()
                && rec.nodes_lost.is_empty())
                && let Err(e) = sink.record(rec)
            {
                self.last_io_error = Some(e);
            }
        }
        self.io.publish_outputs(t, self.image.packets());
        for a in self.io.take_alarms() {
            let text = format!("{}: {}", a.device, a.message);
            self.events.push(if a.cleared {
                Event::Cleared(text)
            } else {
                Event::Alarm(text)
            });
        }
        self.save_retain_if_changed();
        let end = if self.clock.is_virtual() {
            woke
        } else {
            self.clock.now_ns()
        };
        let overrun = !self.clock.is_virtual() && end > due + self.settings.tick_ns;
        // Virtual time does not move during the work: measure the scan on the wall clock then.
        let scan_ns = if self.clock.is_virtual() {
            u64::try_from(work.elapsed().as_nanos()).unwrap_or(u64::MAX)
        } else {
            end.saturating_sub(woke)
        };
        let run = self.stats.tick(woke.saturating_sub(due), scan_ns, overrun);
        if overrun
            && !self.tripped
            && self.settings.overrun_limit > 0
            && run >= self.settings.overrun_limit
        {
            self.trip(run);
        }
        self.tick += 1;
    }

    fn trip(&mut self, run: u32) {
        self.tripped = true;
        self.image.clear_physical_outputs();
        self.io.safe_state();
        self.events.push(Event::Alarm(format!(
            "{run} consecutive overruns at tick {}: outputs in safe state, logic halted",
            self.tick
        )));
    }

    fn take_swap(&mut self, t: u64) {
        let Some(rx) = &self.swaps else { return };
        // Only the newest pending program matters.
        let Some(swap) = rx.try_iter().last() else {
            return;
        };
        let new_meta = swap.loaded.meta.clone();
        let mut image = self.image.resized_for(new_meta.image_len());
        new_meta.migrate_from(
            self.loaded.meta.as_ref(),
            self.image.bytes(),
            image.bytes_mut(),
        );
        let written = new_meta.written_signals();
        self.tracker = self.tracker.continue_from(&written, image.bytes());
        if let Some(r) = &mut self.retain {
            r.layout =
                RetainLayout::new(&written, new_meta.retain_range(), new_meta.retain_layout());
        }
        self.image = image;
        self.loaded = swap.loaded;
        let since_edit = swap
            .modified
            .and_then(|m| std::time::SystemTime::now().duration_since(m).ok())
            .unwrap_or_else(|| swap.noticed.elapsed());
        self.events.push(Event::Swapped {
            tick: t,
            latency: since_edit,
        });
    }

    fn save_retain_if_changed(&mut self) {
        let Some(r) = &mut self.retain else { return };
        if r.layout.differs(self.image.bytes(), &r.last) {
            let rec = r.layout.snapshot(self.image.bytes(), r.last.seq + 1);
            r.last = rec.clone();
            (r.sink)(rec);
        }
    }

    /// Runs `n` ticks, calling `each` after every tick (return `false` from it to stop early).
    pub fn run(&mut self, n: Option<u64>, mut each: impl FnMut(&mut Scheduler) -> bool) {
        let mut left = n;
        while left != Some(0) {
            self.step();
            if let Some(l) = &mut left {
                *l -= 1;
            }
            if !each(self) {
                break;
            }
        }
    }

    /// Finishes: flushes the trace, marks its end, puts the I/O in its safe state.
    pub fn finish(&mut self) -> Result<(), TraceError> {
        self.io.safe_state();
        if let Some((_, sink, rec)) = &mut self.recording {
            // A record with no changes marks how many ticks ran, unless the last tick had changes.
            if self.tick > 0
                && rec.inputs.is_empty()
                && rec.outputs.is_empty()
                && rec.forced.is_empty()
                && rec.positions.is_empty()
            {
                let end = TickRecord {
                    t: self.tick - 1,
                    ..TickRecord::default()
                };
                sink.record(&end)?;
            }
            sink.finish()?;
        }
        match self.last_io_error.take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// Ends the run: [`Scheduler::finish`], then hands back the image (for retain and tests).
    pub fn into_image(mut self) -> Result<Image, TraceError> {
        self.finish()?;
        Ok(self.image)
    }

    /// Wall-clock helper for status lines: the tick length.
    pub fn tick_duration(&self) -> Duration {
        Duration::from_nanos(self.settings.tick_ns)
    }
}
