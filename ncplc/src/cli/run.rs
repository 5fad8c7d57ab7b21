//! `ncplc run`: run a machine's logic in the cyclic runtime, with the simulated (or real) I/O,
//! a live status line, optional trace recording, retain and online change.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use controller::io::IoKind;
use controller::settings::{self, PartSpec, VarsSource};
use controller::{Controller, Ending, Observer};
use runtime::compiled::EngineKind;
use runtime::online::Note;
use runtime::scheduler::{Event, Scheduler};

/// Arguments of `ncplc run`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The machine directory (e.g. plc-programs/lathe).
    #[arg(value_name = "MACHINE")]
    pub machine: PathBuf,
    /// Use this PLC source instead of the machine's.
    #[arg(long)]
    pub plc: Option<PathBuf>,
    /// Stop after N ticks.
    #[arg(long)]
    pub ticks: Option<u64>,
    /// Run unthrottled in virtual time.
    #[arg(long)]
    pub virtual_time: bool,
    /// Override the logic tick (ms).
    #[arg(long)]
    pub tick_ms: Option<u32>,
    /// Record a trace (text; `.ptrace` or `.bin`: binary). Starts from a fresh image (no retain).
    #[arg(long)]
    pub record: Option<PathBuf>,
    /// With --record: sync the recording to disk at least every N ms (a crash or power loss
    /// loses at most that much; `ncplc trace recover` reads the rest).
    #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u64).range(1..))]
    pub record_flush_ms: u64,
    /// The I/O.
    #[arg(long, value_enum, default_value = "sim")]
    pub io: IoKind,
    /// The engine.
    #[arg(long, value_enum, default_value = "jit")]
    pub engine: EngineKind,
    /// Print scan-time and wake-latency statistics at the end (with the simulated CNC: the M/S/T
    /// functions completed and the strobe timeouts of each process).
    #[arg(long)]
    pub stats: bool,
    /// Consecutive overruns that put the outputs in their safe state (0: never).
    #[arg(long, default_value_t = 3)]
    pub overrun_limit: u32,
    /// Do not watch the PLC source for online change.
    #[arg(long)]
    pub no_watch: bool,
    /// Busy-wait the last N µs before each tick (lower wake latency, costs CPU).
    #[arg(long, default_value_t = 0)]
    pub spin_us: u64,
    /// Keep retained data in this file (default: `<machine>/retain.bin`).
    #[arg(long)]
    pub retain_file: Option<PathBuf>,
    /// Serve the Modbus HMI on ADDR:PORT instead of io.toml's `[hmi] bind`; with the simulated
    /// I/O (and part runs) the Modbus HMI starts only when this is given.
    #[arg(long, value_name = "ADDR:PORT")]
    pub modbus_hmi: Option<std::net::SocketAddr>,
    /// Pin the scan thread to this CPU (0-based); the fieldbus I/O threads take io.toml
    /// `[affinity] io_cpus`.
    #[arg(long)]
    pub scan_cpu: Option<usize>,
    /// The web HMI.
    #[command(flatten)]
    pub hmi: super::hmi_args::HmiArgs,
    /// Serve OPC UA (the signals and the Machine Tools model; docs/opcua.md) on
    /// [opc.tcp://]IP:PORT (without a value: opc.tcp://127.0.0.1:4840; port 0 takes a free one).
    #[arg(long, value_name = "ADDR:PORT", num_args = 0..=1, require_equals = false,
          default_missing_value = opcua_server::DEFAULT_ENDPOINT, value_parser = parse_opcua)]
    pub opcua: Option<std::net::SocketAddr>,
    /// The OPC UA users file (`ROLE USER PASSWORD` lines; roles viewer, operator, integrator).
    #[arg(long, value_name = "FILE", requires = "opcua")]
    pub opcua_users: Option<PathBuf>,
    /// Run this partprogram on the CNC kernel (a name in <machine>/nc/, or a path), selected in
    /// AUTO; the cycle starts when the PLC raises START.
    #[arg(long)]
    pub program: Option<PathBuf>,
    /// The process that runs --program.
    #[arg(long, default_value_t = 1)]
    pub process: u8,
    /// Partprogram dialect, overriding the machine's (mefi or fanuc).
    #[arg(long)]
    pub dialect: Option<String>,
    /// Run these blocks in MDI mode (one option per block text), before --program.
    #[arg(long)]
    pub mdi: Vec<String>,
    /// With --program: the correction table (a TAB0.KOR file) the operator enters during the
    /// run; the following blocks take its offsets at each tool-correction request (IOCFIL
    /// m_request 10, e.g. M06). Without it a request re-reads the machine's own table.
    #[arg(long, value_name = "FILE")]
    pub kor_change: Option<PathBuf>,
    /// With --program/--mdi: write the set points of every interpolation tick of the process as
    /// JSON Lines (header, then `{"t":…,"p":[…],"block":…,"feed":…}`; the `ncplc nc run` format).
    #[arg(long)]
    pub trajectory: Option<PathBuf>,
    /// With --program/--mdi: stop when every selected program has ended (M02/M30): exit 0, or
    /// exit 1 on an alarm that stops it.
    #[arg(long)]
    pub until_end: bool,
}

/// `--opcua`'s value.
fn parse_opcua(text: &str) -> Result<std::net::SocketAddr, String> {
    opcua_server::parse_endpoint(text).map_err(|e| e.to_string())
}

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: libc::c_int) {
    STOP.store(true, Ordering::SeqCst);
}

fn install_stop_handler() {
    let handler = on_signal as extern "C" fn(libc::c_int);
    // SAFETY: the handler only stores to an atomic, which is async-signal-safe.
    unsafe {
        libc::signal(libc::SIGINT, handler as libc::sighandler_t);
        libc::signal(libc::SIGTERM, handler as libc::sighandler_t);
    }
}

/// Runs `ncplc run`.
pub fn run(args: Args) -> ExitCode {
    match run_inner(args) {
        Ok(code) => code,
        Err(msg) => {
            eprintln!("{msg}");
            ExitCode::from(2)
        }
    }
}

/// The controller `args` describe.
fn builder(args: &Args) -> controller::Builder {
    let part = (args.program.is_some() || !args.mdi.is_empty()).then(|| settings::Part {
        spec: part_spec(args),
        trajectory: args.trajectory.clone(),
        until_end: args.until_end,
    });
    let clock = if args.virtual_time {
        settings::Clock::Virtual
    } else {
        settings::Clock::Real {
            spin_us: args.spin_us,
        }
    };
    let b = Controller::builder(&args.machine);
    let b = match args.opcua {
        Some(addr) => b.server(Box::new(opcua_server::OpcuaServer::new(
            opcua_server::Settings {
                addr,
                users: args.opcua_users.clone(),
                program: args
                    .program
                    .as_ref()
                    .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned())),
            },
        ))),
        None => b,
    };
    b.plc(args.plc.clone())
        .engine(settings::Engine {
            kind: args.engine,
            flow: args.hmi.hmi_flow,
        })
        .io(settings::Io { kind: args.io })
        .part(part)
        .record(args.record.clone().map(|path| settings::Recording {
            path,
            flush_ms: args.record_flush_ms,
        }))
        .hmi(args.hmi.settings())
        .modbus_hmi(args.modbus_hmi)
        .clock(clock)
        .scan(settings::Scan {
            ticks: args.ticks,
            tick_ms: args.tick_ms,
            overrun_limit: args.overrun_limit,
            watch: !args.no_watch,
            retain_file: args.retain_file.clone(),
            scan_cpu: args.scan_cpu,
        })
}

/// The part-run options of `ncplc run`.
pub fn part_spec(args: &Args) -> PartSpec {
    PartSpec {
        program: args.program.clone(),
        process: args.process,
        dialect: args.dialect.clone(),
        mdi: args.mdi.clone(),
        kor_change: args.kor_change.clone(),
        vars: VarsSource::Machine,
    }
}

/// The errors `check` reports in `<machine>/io.toml`, rendered (None when it has none or does not
/// exist): `run` refuses them with every `--io`, the simulated I/O included, which reads no I/O
/// map (a machine `check` rejects does not run). The characterization's own errors are the
/// builder's to report.
fn io_map_refusal(dir: &std::path::Path) -> Option<String> {
    let path = dir.join("io.toml");
    if !path.exists() {
        return None;
    }
    let machine = characterization::load_machine_capped(dir, diag::DEFAULT_MAX_PER_FILE).machine?;
    let mut sources = diag::Sources::new();
    let diags = super::check::check_io_map(dir, &machine, &mut sources);
    let name = runtime::render::user_path(&path).display().to_string();
    let errors: Vec<diag::Diagnostic> = diags
        .into_iter()
        .filter(diag::Diagnostic::is_error)
        .map(|mut d| {
            d.file.clone_from(&name);
            d
        })
        .collect();
    if errors.is_empty() {
        return None;
    }
    let mut named = diag::Sources::new();
    named.add(name, diag::read_config(&path).unwrap_or_default());
    let rendered = runtime::render::render_diagnostics(&errors, &named);
    Some(rendered.trim_end().to_string())
}

fn run_inner(args: Args) -> Result<ExitCode, String> {
    if let Some(refusal) = io_map_refusal(&args.machine) {
        return Err(refusal);
    }
    let mut controller = match builder(&args).build() {
        Ok(c) => c,
        // Refused to start (exit 2, as for every other error of the machine, its part program or
        // the choices): `ncplc build` reports the program's errors with exit 1.
        Err(e) => return Err(e.to_string()),
    };
    install_stop_handler();
    let mut status = Status::new();
    controller.run(&mut status);
    if status.on_terminal {
        eprintln!();
    }
    let ending = controller.finish()?;
    report(&args, ending)
}

/// Prints the end of a run and picks the exit code.
fn report(args: &Args, ending: Ending) -> Result<ExitCode, String> {
    eprintln!(
        "{} ticks of {} ms on {}; engine {}",
        ending.ticks, ending.tick_ms, ending.io, ending.engine
    );
    if args.stats {
        print!("{}", ending.stats);
        if let Some(first) = ending.first_tick_at {
            println!(
                "start to first tick {:.1} ms",
                first
                    .saturating_duration_since(super::output::started())
                    .as_secs_f64()
                    * 1e3
            );
        }
        if let Some(h) = &ending.handshakes {
            print!("{h}");
        }
    }
    if let Some(summary) = &ending.part_summary {
        print!("{summary}");
        ending
            .vars_saved
            .map_err(|e| format!("error: retained macro variables not saved: {e}"))?;
        if let Some(code) = ending.until_end {
            return Ok(ExitCode::from(code));
        }
    }
    Ok(if ending.tripped {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// The run's messages and its live status line on a terminal.
struct Status {
    on_terminal: bool,
    /// On a terminal, messages first erase the live status line; elsewhere they are plain lines.
    clear: &'static str,
    last_status: Instant,
    alarms: u64,
    last_alarm: String,
}

impl Status {
    fn new() -> Status {
        let on_terminal = std::io::stderr().is_terminal();
        Status {
            on_terminal,
            clear: if on_terminal { "\r\x1b[K" } else { "" },
            last_status: Instant::now(),
            alarms: 0,
            last_alarm: String::new(),
        }
    }
}

impl Observer for Status {
    fn event(&mut self, ev: &Event) {
        let clear = self.clear;
        match ev {
            Event::Alarm(a) => {
                self.alarms += 1;
                eprintln!("{clear}alarm: {a}");
                self.last_alarm = a.clone();
            }
            Event::Cleared(a) => eprintln!("{clear}cleared: {a}"),
            Event::Swapped { tick, latency } => {
                eprintln!(
                    "{clear}online change: new program runs from tick {tick}; edit-to-running {latency:.1?}"
                )
            }
        }
    }

    fn message(&mut self, m: &controller::plc_messages::MessageEvent) {
        let clear = self.clear;
        let e = &m.entry;
        if m.raised {
            eprintln!(
                "{clear}message: P{} #{} at tick {}: {}",
                e.process, e.number, m.tick, e.text
            );
        } else {
            eprintln!(
                "{clear}message cleared: P{} #{} at tick {}: {}",
                e.process, e.number, m.tick, e.text
            );
        }
    }

    fn note(&mut self, note: &Note) {
        let clear = self.clear;
        match note {
            Note::Compiled { compile } => {
                eprintln!("{clear}online change: compiled in {compile:.1?}")
            }
            Note::Rejected { diagnostics } => {
                eprintln!(
                    "{clear}online change rejected; the running program stays:\n{diagnostics}"
                )
            }
            Note::Error(e) => eprintln!("{clear}online change: {e}"),
        }
    }

    fn after_tick(&mut self, s: &Scheduler) -> bool {
        if self.on_terminal && self.last_status.elapsed() >= Duration::from_millis(200) {
            self.last_status = Instant::now();
            eprint!(
                "\r\x1b[Ktick {}  scan {:.1} µs (max {:.1})  overruns {}  alarms {}{}{}",
                s.tick_count(),
                s.stats.scan.value_at_quantile(0.5) as f64 / 1e3,
                s.stats.scan.max() as f64 / 1e3,
                s.stats.overruns,
                self.alarms,
                if self.last_alarm.is_empty() {
                    ""
                } else {
                    " — "
                },
                self.last_alarm
            );
        }
        !STOP.load(Ordering::Relaxed)
    }
}
