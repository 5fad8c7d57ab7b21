//! `sim.toml` checked against the machine, as located diagnostics (codes 3600–3619): the one
//! validation `ncplc check` reports and `ncplc run` / `replay` refuse (through
//! `Machine::open`), so the two cannot disagree.
//!
//! Invariants: every signal the script names exists on the machine — a packet-A input (set,
//! follow input, spindle feedback, handwheel counter) on a connector IOCFIL declares as input, a
//! packet-A output (follow outputs, spindle contactors) on one it declares as output, a K/N
//! signal of the interface map, or any T byte; every value fits its signal; every `[[at]]` tick
//! of a periodic script lies inside the period; every process is 1..5 and has the handshake its
//! M/S/T need; `[cnc] programs` names processes of the machine and programs in its `nc/`;
//! `[[axis]]` places each coordinated axis of process 1 once, limit switches only on MFC inputs;
//! `[part]` issues no M/S/T and sets no signal the CNC kernel writes. An unknown table or key is
//! a located TOML error (3600), never ignored. Spans come from a second, spanned parse of the
//! same text ([`toml::de::DeTable`]), so the typed [`Script`] stays plain.

use std::ops::Range;

use diag::{Diagnostic, LineIndex};
use packets::{Packet, Signal};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::{CncSignals, Script};

/// The code range of sim.toml diagnostics (docs/sim-toml.md §Diagnostics).
pub mod codes {
    /// TOML syntax, an unknown table or key, a value of the wrong type.
    pub const SYNTAX: u32 = 3600;
    /// Not a signal address (`I29X3`).
    pub const SIGNAL: u32 = 3601;
    /// A signal the machine does not have (undeclared connector, K/N outside the interface map).
    pub const UNDECLARED: u32 = 3602;
    /// A value outside its signal's range.
    pub const VALUE: u32 = 3603;
    /// A tick that never comes (outside the period).
    pub const TICK: u32 = 3604;
    /// A process outside 1..5 or without the handshake its M/S/T need.
    pub const PROCESS: u32 = 3605;
    /// `[part]` issues M/S/T or sets a signal the CNC kernel writes.
    pub const PART: u32 = 3606;
    /// `[signals]` names no handshake role.
    pub const ROLE: u32 = 3607;
    /// `sim.toml` exists but cannot be read.
    pub const IO: u32 = 3608;
    /// `[[handwheel]]`: not a packet-A byte, no IOCFIL ADV channel, wired twice, or a `turn` without wiring.
    pub const HANDWHEEL: u32 = 3609;
    /// `turn` in the top-level `[[at]]` (it belongs to `[[part.at]]`).
    pub const TURN: u32 = 3610;
    /// `[cnc] programs`: not a process of the machine, or a program that does not exist.
    pub const PROGRAMS: u32 = 3611;
    /// `[[axis]]`: not a coordinated axis of process 1, placed twice, or a limit switch without
    /// its AXCFIL MFC input.
    pub const AXIS: u32 = 3612;
}

/// A coordinated axis of process 1 as `[[axis]]` may place it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AxisWiring {
    /// The axis letter.
    pub name: char,
    /// AXCFIL MFC wires its + and − limit switch inputs.
    pub limits: (bool, bool),
}

/// The coordinated axes of process 1 of `machine` (what the kernel's `[[axis]]` placement
/// finds).
pub fn process1_axes(machine: &characterization::Machine) -> Vec<AxisWiring> {
    cnc::ProcessConfig::all(&machine.axcfil, machine.iocfil.as_ref())
        .into_iter()
        .find(|p| p.number == 1)
        .map(|p| {
            p.axes
                .iter()
                .map(|a| AxisWiring {
                    name: a.name,
                    limits: (a.limit_inputs.0.is_some(), a.limit_inputs.1.is_some()),
                })
                .collect()
        })
        .unwrap_or_default()
}

/// What the script is checked against.
pub struct Machine<'a> {
    /// Packet-A input connectors IOCFIL declares.
    pub a_inputs: &'a [u16],
    /// Packet-A output connectors IOCFIL declares.
    pub a_outputs: &'a [u16],
    /// The interface map (K/N signals).
    pub interface: &'a compiler::InterfaceMap,
    /// The handshake signals of processes 1..NBP.
    pub signals: &'a CncSignals,
    /// The signals the CNC kernel writes in a part run.
    pub kernel_written: &'a [Signal],
    /// `declared(process, channel)`: IOCFIL ADV declares the handwheel channel.
    pub adv: &'a dyn Fn(u8, u8) -> bool,
    /// The machine directory, where a part run finds the programs of `[cnc] programs` (`None`:
    /// their existence is not checked).
    pub dir: Option<&'a std::path::Path>,
    /// The coordinated axes of process 1 ([`process1_axes`]).
    pub axes: &'a [AxisWiring],
}

/// Parses and checks `text` (the file `file`): the script when it has no error, and every
/// diagnostic, located.
pub fn check(file: &str, text: &str, machine: &Machine) -> (Option<Script>, Vec<Diagnostic>) {
    let index = LineIndex::new(text);
    let mut cx = Cx {
        file,
        diags: Vec::new(),
    };
    let Some(script) = cx.parse(text) else {
        return (None, cx.located(text, &index));
    };
    // Parsed once already, so this cannot fail; an empty table locates everything at 0.
    let root = DeTable::parse(text)
        .map(Spanned::into_inner)
        .unwrap_or_default();
    cx.roles(&script, &root, machine);
    for (i, at) in script.at.iter().enumerate() {
        cx.at(at, at_of(&root, i, false), machine, &script, false);
    }
    cx.follows(&script.follow, root.get("follow"), machine);
    if let Some(part) = &script.part {
        let t = root.get("part").and_then(|p| p.get_ref().as_table());
        for (i, at) in part.at.iter().enumerate() {
            cx.at(at, at_of(&root, i, true), machine, &script, true);
        }
        cx.follows(&part.follow, t.and_then(|t| t.get("follow")), machine);
    }
    cx.spindle(&script, root.get("spindle"), machine);
    cx.handwheels(&script, root.get("handwheel"), machine);
    cx.programs(&script, root.get("cnc"), machine);
    cx.axes(&script, root.get("axis"), machine);
    let diags = cx.located(text, &index);
    let ok = !diag::has_errors(&diags);
    (ok.then_some(script), diags)
}

/// The table of `[[at]]` number `i` (of `[[part.at]]` when `part`).
fn at_of<'a, 'i>(root: &'a DeTable<'i>, i: usize, part: bool) -> Option<&'a DeTable<'i>> {
    let t = if part {
        root.get("part")?.get_ref().as_table()?
    } else {
        root
    };
    t.get("at")?
        .get_ref()
        .as_array()?
        .get(i)?
        .get_ref()
        .as_table()
}

/// Whether a signal is read by the logic (set by the machine) or written by it.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Way {
    Input,
    Output,
}

struct Cx<'f> {
    file: &'f str,
    diags: Vec<Diagnostic>,
}

fn span_of(v: Option<&Spanned<DeValue<'_>>>) -> Range<usize> {
    v.map_or(0..0, Spanned::span)
}

/// The span of key `key` of `table` (the whole table's when absent).
fn key_span(table: Option<&DeTable<'_>>, key: &str) -> Range<usize> {
    table
        .and_then(|t| t.iter().find(|(k, _)| k.get_ref() == key))
        .map_or(0..0, |(k, _)| k.span())
}

/// The span of value `key` of `table`.
fn value_span(table: Option<&DeTable<'_>>, key: &str) -> Range<usize> {
    span_of(table.and_then(|t| t.get(key)))
}

impl Cx<'_> {
    fn err(&mut self, code: u32, span: Range<usize>, message: String, hint: &str) {
        self.diags
            .push(Diagnostic::error(code, self.file, span, message).with_hint(hint));
    }

    /// The script of `text`, or `None` with every TOML error (syntax, unknown table or key,
    /// wrong type) reported.
    fn parse(&mut self, text: &str) -> Option<Script> {
        let hint = "see docs/sim-toml.md for the tables and keys of sim.toml";
        match diag::toml_keys::from_toml_diagnosed(text, self.file, codes::SYNTAX, hint) {
            Ok(s) => Some(s),
            Err(errors) => {
                self.diags.extend(errors);
                None
            }
        }
    }

    fn located(self, text: &str, index: &LineIndex) -> Vec<Diagnostic> {
        self.diags
            .into_iter()
            .map(|d| d.locate_in(text, index))
            .collect()
    }

    /// Checks that `name` is a signal of the machine used as `way`; the signal when it parses.
    fn signal(&mut self, name: &str, span: Range<usize>, way: Way, m: &Machine) -> Option<Signal> {
        let s: Signal = match name.parse() {
            Ok(s) => s,
            Err(e) => {
                self.err(
                    codes::SIGNAL,
                    span,
                    format!("`{name}` is not a signal address: {e}"),
                    "a signal is written like I0A3 (bit), W3K0 (byte), U4A0 (output bit)",
                );
                return None;
            }
        };
        let (ok, what) = match (s.packet(), way) {
            (Packet::A, Way::Input) => (
                m.a_inputs
                    .iter()
                    .any(|&c| usize::from(c) == s.packet_byte() / 4),
                "packet-A inputs are on the IN connectors IOCFIL declares",
            ),
            (Packet::A, Way::Output) => (
                m.a_outputs
                    .iter()
                    .any(|&c| usize::from(c) == s.packet_byte() / 4),
                "packet-A outputs are on the OUT connectors IOCFIL declares",
            ),
            (Packet::K | Packet::N, _) => (
                m.interface.iter().any(|e| e.signal == s),
                "K and N signals are those of the interface map (docs/plc-interface-map.md, <machine>/interface.toml)",
            ),
            (Packet::T, _) => (true, ""),
        };
        if !ok {
            let side = if way == Way::Input { "input" } else { "output" };
            self.err(
                codes::UNDECLARED,
                span,
                format!("{name} is not an {side} signal of this machine"),
                what,
            );
        }
        Some(s)
    }

    fn roles(&mut self, script: &Script, root: &DeTable<'_>, m: &Machine) {
        let table = root.get("signals").and_then(|t| t.get_ref().as_table());
        let mut probe = m.signals.clone();
        for (name, addr) in &script.signals {
            let s: Signal = match addr.parse() {
                Ok(s) => s,
                Err(e) => {
                    self.err(
                        codes::SIGNAL,
                        value_span(table, name),
                        format!("[signals] {name} = `{addr}` is not a signal address: {e}"),
                        "a signal is written like I1K0 (bit) or W3K0 (byte)",
                    );
                    continue;
                }
            };
            if !probe.set_process1(&name.to_ascii_uppercase(), s) {
                self.err(
                    codes::ROLE,
                    key_span(table, name),
                    format!("[signals] `{name}` is not a handshake signal"),
                    "the handshake roles are RESET, MSTB, MFIN, MCODE, SSTB, SFIN, SCODE, TSTB, TFIN, TCODE",
                );
            }
        }
    }

    fn at(
        &mut self,
        at: &super::At,
        t: Option<&DeTable<'_>>,
        m: &Machine,
        script: &Script,
        part: bool,
    ) {
        let where_ = if part { "[[part.at]]" } else { "[[at]]" };
        if let Some(p) = script.period.filter(|&p| p > 0 && !part)
            && at.tick >= p
        {
            self.err(
                codes::TICK,
                value_span(t, "tick"),
                format!(
                    "{where_} tick {} never comes: the script repeats every {p} ticks",
                    at.tick
                ),
                "a tick of a periodic script is 0..period-1",
            );
        }
        let set = t
            .and_then(|t| t.get("set"))
            .and_then(|s| s.get_ref().as_table());
        for (name, v) in &at.set {
            let span = key_span(set, name);
            let Some(s) = self.signal(name, span.clone(), Way::Input, m) else {
                continue;
            };
            let max = if s.bit().is_some() { 1 } else { 255 };
            if *v > max {
                self.err(
                    codes::VALUE,
                    value_span(set, name),
                    format!("{name} = {v} is out of range (0..{max})"),
                    "a bit is 0 or 1, a byte 0..255",
                );
            }
            if part && m.kernel_written.contains(&s) {
                self.err(
                    codes::PART,
                    span,
                    format!("{name} is written by the CNC kernel in a part run"),
                    "the kernel drives the CNC→PLC handshake and status signals; remove it from [[part.at]]",
                );
            }
        }
        if part {
            if !at.m.is_empty() || at.s.is_some() || at.t.is_some() {
                let key = ["m", "s", "t"]
                    .into_iter()
                    .find(|k| t.is_some_and(|t| t.get(*k).is_some()))
                    .unwrap_or("tick");
                self.err(
                    codes::PART,
                    key_span(t, key),
                    format!(
                        "tick {}: m, s and t come from the partprogram in a part run",
                        at.tick
                    ),
                    "remove m, s and t from [[part.at]]",
                );
            }
            return;
        }
        if let Err(e) = super::check_functions(at, m.signals) {
            let key = if (1..=5).contains(&at.process) {
                ["m", "s", "t"]
                    .into_iter()
                    .find(|k| t.is_some_and(|t| t.get(*k).is_some()))
                    .unwrap_or("tick")
            } else {
                "process"
            };
            self.err(
                codes::PROCESS,
                value_span(t, key),
                e.to_string().trim_start_matches("sim script: ").to_string(),
                "processes are 1..NBP; a process 2..5 has a handshake when interface.toml gives its three roles",
            );
        }
        if !at.turn.is_empty() {
            self.err(
                codes::TURN,
                key_span(t, "turn"),
                format!(
                    "tick {}: `turn` turns a handwheel of the CNC kernel",
                    at.tick
                ),
                "move it to [[part.at]] of a part run",
            );
        }
    }

    fn follows(
        &mut self,
        follow: &[super::Follow],
        list: Option<&Spanned<DeValue<'_>>>,
        m: &Machine,
    ) {
        let list = list.and_then(|l| l.get_ref().as_array());
        for (i, f) in follow.iter().enumerate() {
            let t = list
                .and_then(|l| l.get(i))
                .and_then(|e| e.get_ref().as_table());
            self.signal(&f.input, value_span(t, "input"), Way::Input, m);
            self.signal(&f.output, value_span(t, "output"), Way::Output, m);
            let ors = t
                .and_then(|t| t.get("or_outputs"))
                .and_then(|o| o.get_ref().as_array());
            for (k, o) in f.or_outputs.iter().enumerate() {
                let span = span_of(ors.and_then(|a| a.get(k)));
                self.signal(o, span, Way::Output, m);
            }
        }
    }

    fn spindle(&mut self, script: &Script, t: Option<&Spanned<DeValue<'_>>>, m: &Machine) {
        let t = t.and_then(|t| t.get_ref().as_table());
        let w = &script.spindle;
        for (key, v) in [("at_speed", &w.at_speed), ("stopped", &w.stopped)] {
            if let Some(name) = v {
                self.signal(name, value_span(t, key), Way::Input, m);
            }
        }
        let run = t
            .and_then(|t| t.get("run"))
            .and_then(|o| o.get_ref().as_array());
        for (k, o) in w.run.iter().enumerate() {
            self.signal(o, span_of(run.and_then(|a| a.get(k))), Way::Output, m);
        }
    }

    /// `[cnc] programs`: each key a process of the machine, each program one a part run finds
    /// in the machine directory (when the check has one).
    fn programs(&mut self, script: &Script, cnc: Option<&Spanned<DeValue<'_>>>, m: &Machine) {
        let t = cnc
            .and_then(|c| c.get_ref().as_table())
            .and_then(|c| c.get("programs"))
            .and_then(|p| p.get_ref().as_table());
        let nbp = m.signals.processes.len();
        for (key, name) in &script.cnc.programs {
            if !key.parse::<usize>().is_ok_and(|p| (1..=nbp).contains(&p)) {
                self.err(
                    codes::PROGRAMS,
                    key_span(t, key),
                    format!("[cnc] programs: `{key}` is not a process of the machine (1..{nbp})"),
                    "the keys are process numbers 1..NBP (AXCFIL), the values program names in nc/",
                );
            }
            let path = m
                .dir
                .map(|d| crate::part::program_path(d, std::path::Path::new(name)));
            if path.is_some_and(|p| !p.is_file()) {
                self.err(
                    codes::PROGRAMS,
                    value_span(t, key),
                    format!("[cnc] programs: the program `{name}` of process {key} does not exist"),
                    "a part run reads it from the machine's nc/ folder (nc/<name>)",
                );
            }
        }
    }

    /// `[[axis]]`: each a coordinated axis of process 1, placed once, its limit switches on the
    /// MFC inputs AXCFIL wires.
    fn axes(&mut self, script: &Script, list: Option<&Spanned<DeValue<'_>>>, m: &Machine) {
        let list = list.and_then(|l| l.get_ref().as_array());
        let letters: Vec<String> = m.axes.iter().map(|a| a.name.to_string()).collect();
        let hint = "[[axis]] places the coordinated axes of process 1 (AXCFIL)";
        for (i, a) in script.axis.iter().enumerate() {
            let t = list
                .and_then(|l| l.get(i))
                .and_then(|e| e.get_ref().as_table());
            let Some(axis) = m.axes.iter().find(|x| x.name == a.name) else {
                self.err(
                    codes::AXIS,
                    value_span(t, "name"),
                    format!(
                        "[[axis]] {}: not a coordinated axis of process 1 ({})",
                        a.name,
                        letters.join(", ")
                    ),
                    hint,
                );
                continue;
            };
            if script.axis[..i].iter().any(|b| b.name == a.name) {
                self.err(
                    codes::AXIS,
                    value_span(t, "name"),
                    format!("[[axis]] {}: placed twice", a.name),
                    hint,
                );
            }
            for (key, set, wired, side) in [
                ("limit_pos", a.limit_pos.is_some(), axis.limits.0, '+'),
                ("limit_neg", a.limit_neg.is_some(), axis.limits.1, '-'),
            ] {
                if set && !wired {
                    self.err(
                        codes::AXIS,
                        key_span(t, key),
                        format!(
                            "[[axis]] {}: a {side} limit switch without its AXCFIL MFC input",
                            a.name
                        ),
                        "AXCFIL MFC names the inputs the kernel writes a limit switch to",
                    );
                }
            }
        }
    }

    fn handwheels(&mut self, script: &Script, list: Option<&Spanned<DeValue<'_>>>, m: &Machine) {
        let list = list.and_then(|l| l.get_ref().as_array());
        let mut seen: Vec<(u8, u8)> = Vec::new();
        for (i, h) in script.handwheel.iter().enumerate() {
            let t = list
                .and_then(|l| l.get(i))
                .and_then(|e| e.get_ref().as_table());
            let span = value_span(t, "counter");
            if let Some(s) = self.signal(&h.counter, span.clone(), Way::Input, m)
                && (s.packet() != Packet::A || s.bit().is_some())
            {
                self.err(
                    codes::HANDWHEEL,
                    span,
                    format!(
                        "[[handwheel]] counter `{}` is not a packet-A input byte",
                        h.counter
                    ),
                    "a handwheel counter is a byte such as W1A3",
                );
            }
            if !(m.adv)(h.process, h.channel) {
                self.err(
                    codes::HANDWHEEL,
                    value_span(t, "channel"),
                    format!(
                        "[[handwheel]] channel {} of process {}: IOCFIL ADV declares no such handwheel channel",
                        h.channel, h.process
                    ),
                    "IOCFIL section 3 ADV declares channels 1 and 2",
                );
            } else if seen.contains(&(h.process, h.channel)) {
                self.err(
                    codes::HANDWHEEL,
                    value_span(t, "channel"),
                    format!(
                        "[[handwheel]] channel {} of process {} is wired twice",
                        h.channel, h.process
                    ),
                    "wire each channel once",
                );
            }
            seen.push((h.process, h.channel));
        }
    }
}

/// `<dir>/sim.toml` read and checked for `machine` with `interface`.
pub struct Loaded {
    /// The script (the default one when the machine has no sim.toml); `None` on an error.
    pub script: Option<Script>,
    /// Every diagnostic, in the file `sim.toml`.
    pub diagnostics: Vec<Diagnostic>,
    /// The file's text, for rendering (`None` when there is no file).
    pub text: Option<String>,
}

/// The file name of the script in diagnostics.
pub const FILE: &str = "sim.toml";

/// Reads `<dir>/sim.toml` and checks it against `machine` and `interface` (what `check` reports
/// and `run` refuses).
pub fn load(
    dir: &std::path::Path,
    machine: &characterization::Machine,
    interface: &compiler::InterfaceMap,
) -> Loaded {
    let text = match read(dir) {
        Ok(text) => text,
        Err(loaded) => return *loaded,
    };
    let (a_inputs, a_outputs) = machine
        .iocfil
        .as_ref()
        .map(|io| (io.input_connectors(), io.output_connectors()))
        .unwrap_or_default();
    let nbp = runtime::process_map::nbp(machine);
    let signals = CncSignals::from_map(interface, nbp);
    let written =
        super::kernel::kernel_written(&machine.axcfil, machine.iocfil.as_ref(), interface);
    let adv = |p: u8, c: u8| {
        machine
            .iocfil
            .as_ref()
            .and_then(|f| f.process(u32::from(p)))
            .and_then(|io| io.adv)
            .is_some_and(|adv| (1..=2).contains(&c) && adv[usize::from(c) - 1].is_some())
    };
    let m = Machine {
        a_inputs: &a_inputs,
        a_outputs: &a_outputs,
        interface,
        signals: &signals,
        kernel_written: &written,
        adv: &adv,
        dir: Some(dir),
        axes: &process1_axes(machine),
    };
    let (script, diagnostics) = check(FILE, &text, &m);
    Loaded {
        script,
        diagnostics,
        text: Some(text),
    }
}

/// Reads `<dir>/sim.toml` and checks only its form: TOML syntax, tables and keys, value types
/// (code 3600). What `check` reports while the interface map, which the names of the signals
/// need, has errors of its own; `run` refuses that map before it reads sim.toml.
pub fn load_form(dir: &std::path::Path) -> Loaded {
    let text = match read(dir) {
        Ok(text) => text,
        Err(loaded) => return *loaded,
    };
    let index = LineIndex::new(&text);
    let mut cx = Cx {
        file: FILE,
        diags: Vec::new(),
    };
    let script = cx.parse(&text);
    Loaded {
        script,
        diagnostics: cx.located(&text, &index),
        text: Some(text),
    }
}

/// The text of `<dir>/sim.toml`, or what loading ends with: the default script when there is no
/// file, a located error when it cannot be read or is not UTF-8.
fn read(dir: &std::path::Path) -> Result<String, Box<Loaded>> {
    let path = dir.join(FILE);
    let bytes = match diag::read_config_bytes(&path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(Box::new(Loaded {
                script: Some(Script {
                    strobe_timeout_ms: 10_000,
                    ..Script::default()
                }),
                diagnostics: Vec::new(),
                text: None,
            }));
        }
        Err(e) => {
            let hint = if e.kind() == std::io::ErrorKind::FileTooLarge {
                "a scenario is a few kilobytes of [[at]] tables: shorten it, or record the inputs once and replay the trace"
            } else {
                "make the file readable or remove it"
            };
            let d = Diagnostic::error(codes::IO, FILE, 0..0, format!("cannot read sim.toml: {e}"))
                .with_hint(hint);
            return Err(Box::new(Loaded {
                script: None,
                diagnostics: vec![d],
                text: None,
            }));
        }
    };
    let text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            let at = e.utf8_error().valid_up_to();
            let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
            let d = Diagnostic::error(codes::SYNTAX, FILE, at..at + 1, "sim.toml is not UTF-8")
                .with_hint("TOML files are UTF-8 text")
                .locate(&text);
            return Err(Box::new(Loaded {
                script: None,
                diagnostics: vec![d],
                text: Some(text),
            }));
        }
    };
    Ok(text)
}
