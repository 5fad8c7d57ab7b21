//! `ncplc run`: run a machine's logic in the cyclic runtime, with the simulated (or real) I/O,
//! a live status line, optional trace recording, retain and online change.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::clock::{Clock, RealClock, VirtualClock, enable_realtime};
use crate::compiled::EngineKind;
use crate::image::Image;
use crate::io::{IoKind, open_io_with};
use crate::machine::Machine;
use crate::online::{self, Note};
use crate::retain::{self, Restored, RetainLayout, RetainRecord};
use crate::scheduler::{Event, Scheduler, Settings};

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

fn run_inner(args: Args) -> Result<ExitCode, String> {
    if let Some(cpu) = args.scan_cpu {
        fieldbus::affinity::check_cpu(cpu).map_err(|e| format!("error: --scan-cpu: {e}"))?;
    }
    let machine = Machine::open(&args.machine, args.plc.as_deref()).map_err(|e| e.to_string())?;
    let tick_ms = args.tick_ms.unwrap_or(machine.config.tick_ms).max(1);
    // The first load compiles on every core (the scan is not running yet); online changes
    // compile on one thread beside the scan, reusing the code of unchanged functions.
    let flow_wanted = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(args.hmi.hmi_flow));
    let (first, compile, variant) =
        machine.compile_fns(args.engine, tick_ms, std::sync::Arc::clone(&flow_wanted));
    let source = machine.read_source().map_err(|e| e.to_string())?;
    let hmi_source = source.clone();
    // The I/O starts (connects, configures its nodes) on its own thread while the program
    // compiles: the first tick waits for the slower of the two, not for their sum.
    // A part run (`--program`/`--mdi`) puts the CNC kernel in front of the simulated I/O; its
    // start (planning the partprogram with the machine's view) likewise runs beside the compile.
    let part_run = args.program.is_some() || !args.mdi.is_empty();
    let declared = machine.declared_connectors();
    let mut started_part = None;
    let (compiled, opened) = std::thread::scope(|s| {
        if part_run {
            let part = s.spawn(|| crate::cli::part_run::start(&args, &machine, tick_ms));
            let compiled = first(&source);
            started_part = Some(part.join());
            return (compiled, None);
        }
        let io = s.spawn(|| {
            open_io_with(
                args.io,
                &machine.dir,
                &declared,
                machine.script.clone(),
                machine.signals.clone(),
                tick_ms,
                args.modbus_hmi,
            )
        });
        let compiled = first(&source);
        (compiled, Some(io.join()))
    });
    let loaded = match compiled {
        Ok(l) => l,
        Err(diags) => {
            eprintln!("{diags}");
            return Ok(ExitCode::from(1));
        }
    };
    let (io, handshakes, mut part) = match opened {
        None => {
            let (io, run) = started_part
                .ok_or("error: the part run did not start")?
                .map_err(|_| "error: the part-run start-up thread panicked".to_string())??;
            let io = match args.modbus_hmi {
                Some(bind) => crate::io::with_modbus_hmi(&machine.dir, &declared, io, bind)
                    .map_err(|e| e.to_string())?,
                None => io,
            };
            let mut run = run;
            let nobody = args.hmi.hmi.is_none() && args.modbus_hmi.is_none();
            if args.virtual_time && args.until_end && args.ticks.is_none() && nobody {
                // Ten minutes of machine time with nothing happening: nobody will press START.
                run.set_idle_limit(600_000 / u64::from(tick_ms));
            }
            (io, None, Some(run))
        }
        Some(opened) => {
            let (io, counts) = opened
                .map_err(|_| "error: the I/O start-up thread panicked".to_string())?
                .map_err(|e| e.to_string())?;
            (io, counts, None)
        }
    };
    let meta = loaded.meta.clone();
    let mut image = Image::new(meta.image_len(), &machine.config.t_init);
    meta.init_image(image.bytes_mut());
    let retain_path = args
        .retain_file
        .clone()
        .or_else(|| machine.config.retain_file.clone());
    // Retained data matters only with PGCFIL OLD; recordings and virtual runs start fresh.
    let use_retain = machine.config.restore_old && args.record.is_none() && !args.virtual_time;
    if use_retain && let Some(path) = &retain_path {
        match retain::load(path) {
            Ok(Some(rec)) => {
                let layout = RetainLayout::new(
                    &meta.written_signals(),
                    meta.retain_range(),
                    meta.retain_layout(),
                );
                match layout.restore(&rec, image.bytes_mut()) {
                    Restored::All => {
                        eprintln!("retain: restored T bytes and RETAIN variables (PGCFIL OLD)")
                    }
                    Restored::TOnly => eprintln!(
                        "retain: restored T bytes; RETAIN layout changed, variables start at 0"
                    ),
                    Restored::NotAllowed => {
                        eprintln!("retain: MUSPE was 0 at the last shutdown; nothing restored")
                    }
                }
            }
            Ok(None) => {}
            Err(e) => eprintln!("warning: {e}; starting without retained data"),
        }
    }
    let clock: Box<dyn Clock> = if args.virtual_time {
        Box::new(VirtualClock::new())
    } else {
        Box::new(RealClock::with_spin(args.spin_us * 1_000))
    };
    let settings = Settings {
        tick_ns: u64::from(tick_ms) * 1_000_000,
        overrun_limit: args.overrun_limit,
    };
    let kernel = part.as_ref().map(|p| {
        (
            p.cnc(),
            crate::hmi_link::kernel_cnc::sources(&args, &machine),
        )
    });
    let mut hmi = args.hmi.start(
        &machine,
        &hmi_source,
        tick_ms,
        handshakes.clone(),
        kernel,
        crate::hmi_link::flow_switch::FlowSwitch::new(flow_wanted, variant),
    )?;
    let mut sched = Scheduler::new(image, loaded, io, clock, settings);
    if let Some(path) = &args.record {
        let options = crate::trace::DurableOptions {
            flush: Duration::from_millis(args.record_flush_ms),
            wait_when_full: args.virtual_time,
            ..crate::trace::DurableOptions::default()
        };
        let header = part
            .as_ref()
            .map(|p| p.header(&crate::cli::part_run::PartSpec::of(&args)));
        let sink = crate::trace::create_part_sink(path, tick_ms, header.as_ref(), options)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        sched.record_to(sink);
        if let Some(p) = &part {
            let cnc = p.cnc();
            sched.record_positions(Box::new(move |out| {
                let c = cnc
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                crate::cli::part_replay::axis_positions(&c, out);
            }));
        }
    }
    let retain_writer = match (&retain_path, use_retain) {
        (Some(path), true) => Some(start_retain_writer(path.clone(), &mut sched)),
        _ => None,
    };
    let (notes_tx, notes_rx) = mpsc::channel();
    let _watch = if args.no_watch {
        None
    } else {
        let (swap_tx, swap_rx) = mpsc::channel();
        sched.accept_swaps(swap_rx);
        match online::watch(
            &machine.config.plc_source,
            source,
            compile,
            swap_tx,
            notes_tx,
        ) {
            Ok(w) => {
                eprintln!(
                    "online change: watching {}",
                    machine.config.plc_source.display()
                );
                Some(w)
            }
            Err(e) => {
                eprintln!("warning: online change disabled: {e}");
                None
            }
        }
    };
    install_stop_handler();
    // Only now: threads started before (watcher, compiler, retain writer) keep normal priority
    // and stay off the scan's CPU.
    if let Some(cpu) = args.scan_cpu
        && let Err(e) = fieldbus::affinity::pin_thread(0, &[cpu])
    {
        eprintln!("warning: cannot pin the scan thread to CPU {cpu} ({e}); running unpinned");
    }
    if !args.virtual_time
        && let Some(w) = enable_realtime(80).warning()
    {
        eprintln!("warning: {w}");
    }
    let status = std::io::stderr().is_terminal();
    // On a terminal, messages first erase the live status line; elsewhere they are plain lines.
    let clear = if status { "\r\x1b[K" } else { "" };
    let mut last_status = Instant::now();
    let mut alarms = 0u64;
    let mut last_alarm = String::new();
    sched.run(args.ticks, |s| {
        if let Some(p) = part.as_mut()
            && !p.each_tick(s.tick_count(), args.until_end)
        {
            return false;
        }
        let tick = s.tick_count();
        for ev in s.take_events() {
            if let Some(h) = &mut hmi {
                h.on_event(&ev, tick);
            }
            match ev {
                Event::Alarm(a) => {
                    alarms += 1;
                    eprintln!("{clear}alarm: {a}");
                    last_alarm = a;
                }
                Event::Cleared(a) => eprintln!("{clear}cleared: {a}"),
                Event::Swapped { tick, latency } => {
                    eprintln!("{clear}online change: new program runs from tick {tick}; edit-to-running {latency:.1?}")
                }
            }
        }
        for note in notes_rx.try_iter() {
            if let Some(h) = &mut hmi {
                h.on_note(&note);
            }
            match note {
                Note::Compiled { compile } => eprintln!("{clear}online change: compiled in {compile:.1?}"),
                Note::Rejected { diagnostics } => {
                    eprintln!("{clear}online change rejected; the running program stays:\n{diagnostics}")
                }
                Note::Error(e) => eprintln!("{clear}online change: {e}"),
            }
        }
        if status && last_status.elapsed() >= Duration::from_millis(200) {
            last_status = Instant::now();
            eprint!(
                "\r\x1b[Ktick {}  scan {:.1} µs (max {:.1})  overruns {}  alarms {}{}{}",
                s.tick_count(),
                s.stats.scan.value_at_quantile(0.5) as f64 / 1e3,
                s.stats.scan.max() as f64 / 1e3,
                s.stats.overruns,
                alarms,
                if last_alarm.is_empty() { "" } else { " — " },
                last_alarm
            );
        }
        if let Some(h) = &mut hmi {
            h.service(s);
        }
        !STOP.load(Ordering::Relaxed)
    });
    if status {
        eprintln!();
    }
    // The retained macro variables the run wrote, whatever ended it (never by a replay).
    let vars_saved = part.as_ref().map_or(Ok(()), |p| p.save_macro_vars());
    let image = sched_finish(&mut sched)?;
    if let (Some(writer), Some(path)) = (retain_writer, &retain_path) {
        sched.detach_retain();
        let _ = writer.join();
        let layout = RetainLayout::new(
            &meta.written_signals(),
            meta.retain_range(),
            meta.retain_layout(),
        );
        let seq = retain::load(path).ok().flatten().map_or(0, |r| r.seq) + 1;
        if let Err(e) = retain::save(path, &layout.snapshot(&image, seq)) {
            eprintln!("warning: {e}");
        }
    }
    eprintln!(
        "{} ticks of {tick_ms} ms on {}; engine {}",
        sched.tick_count(),
        args.io_name(),
        sched.engine_name()
    );
    if args.stats {
        print!("{}", sched.stats.summary());
        if let Some(first) = sched.first_tick_at() {
            println!(
                "start to first tick {:.1} ms",
                first
                    .saturating_duration_since(super::output::started())
                    .as_secs_f64()
                    * 1e3
            );
        }
        if let Some(h) = &handshakes {
            print!("{}", h.summary());
        }
    }
    if let Some(p) = part.as_mut() {
        print!("{}", p.summary(tick_ms));
        vars_saved.map_err(|e| format!("error: retained macro variables not saved: {e}"))?;
        if args.until_end {
            return Ok(p.exit_code());
        }
    }
    Ok(if sched.tripped() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

fn sched_finish(sched: &mut Scheduler) -> Result<Vec<u8>, String> {
    sched.finish().map_err(|e| format!("trace: {e}"))?;
    Ok(sched.image().bytes().to_vec())
}

/// Starts the thread that writes retain snapshots (coalescing bursts) and connects it.
fn start_retain_writer(path: PathBuf, sched: &mut Scheduler) -> std::thread::JoinHandle<()> {
    let (tx, rx) = mpsc::channel::<RetainRecord>();
    let start_seq = retain::load(&path).ok().flatten().map_or(0, |r| r.seq);
    let handle = std::thread::spawn(move || {
        while let Ok(first) = rx.recv() {
            let latest = rx.try_iter().last().unwrap_or(first);
            let rec = RetainRecord {
                seq: start_seq + latest.seq,
                ..latest
            };
            if let Err(e) = retain::save(&path, &rec) {
                eprintln!("warning: {e}");
            }
        }
    });
    sched.retain_to(Box::new(move |r| {
        let _ = tx.send(r);
    }));
    handle
}

impl Args {
    fn io_name(&self) -> &'static str {
        match self.io {
            IoKind::Sim => "sim",
            IoKind::Modbus => "modbus",
            IoKind::Canopen => "canopen",
        }
    }
}
