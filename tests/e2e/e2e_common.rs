//! Shared by the end-to-end tests: the workspace root, running the `ncplc` binary, the `Ncplc::run`
//! builder of `ncplc run` command lines, and copying a bundled machine into a temporary directory.

#![allow(dead_code)]

use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The workspace root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Runs the `ncplc` binary with `args` and collects its output.
pub fn ncplc<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(args)
        .output()
        .expect("ncplc runs")
}

/// Runs the `ncplc` binary with `args` in `dir` (paths in its diagnostics are relative to it).
pub fn ncplc_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("ncplc runs")
}

/// Runs the `ncplc` binary in the workspace root (the bundled machines are
/// `plc-programs/<name>` there).
pub fn ncplc_at_root(args: &[&str]) -> Output {
    ncplc_in(&root(), args)
}

/// A copy of the bundled machine `name` (`plc-programs/<name>`) in a temporary directory.
pub fn copy_machine(name: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    copy_dir(&root().join("plc-programs").join(name), dir.path());
    dir
}

/// The `ncplc` binary's subcommands as builders of the test kit.
pub struct Ncplc;

impl Ncplc {
    /// `ncplc run MACHINE --no-watch` (no test wants the source watcher's thread), to be completed
    /// step by step: `Ncplc::run(m).virtual_time().program("PART1").until_end().output()`.
    pub fn run(machine: impl AsRef<OsStr>) -> Run {
        Run {
            args: [
                "run".into(),
                machine.as_ref().to_owned(),
                "--no-watch".into(),
            ]
            .into(),
        }
    }
}

/// An `ncplc run` command line; each step appends its flag in the order of the calls.
#[derive(Debug, Clone)]
#[must_use = "a Run does nothing until .command() or .output()"]
pub struct Run {
    args: Vec<OsString>,
}

impl Run {
    /// Appends `flag` and its value.
    fn flag(mut self, flag: &str, value: impl AsRef<OsStr>) -> Run {
        self.args.push(flag.into());
        self.args.push(value.as_ref().to_owned());
        self
    }

    /// Appends any further arguments.
    pub fn args<S: AsRef<OsStr>>(mut self, args: impl IntoIterator<Item = S>) -> Run {
        self.args
            .extend(args.into_iter().map(|a| a.as_ref().to_owned()));
        self
    }

    /// `--virtual-time`: ticks as fast as the machine computes them.
    pub fn virtual_time(self) -> Run {
        self.args(["--virtual-time"])
    }

    /// `--program NAME|PATH`: a part run.
    pub fn program(self, program: impl AsRef<OsStr>) -> Run {
        self.flag("--program", program)
    }

    /// `--mdi BLOCK` (repeatable).
    pub fn mdi(self, block: impl AsRef<OsStr>) -> Run {
        self.flag("--mdi", block)
    }

    /// `--ticks N`.
    pub fn ticks(self, ticks: u64) -> Run {
        self.flag("--ticks", ticks.to_string())
    }

    /// `--until-end`: stop at M02/M30 or a stopping alarm.
    pub fn until_end(self) -> Run {
        self.args(["--until-end"])
    }

    /// `--stats`.
    pub fn stats(self) -> Run {
        self.args(["--stats"])
    }

    /// `--engine jit|interp`.
    pub fn engine(self, engine: &str) -> Run {
        self.flag("--engine", engine)
    }

    /// `--dialect D`.
    pub fn dialect(self, dialect: &str) -> Run {
        self.flag("--dialect", dialect)
    }

    /// `--record FILE`.
    pub fn record(self, path: impl AsRef<OsStr>) -> Run {
        self.flag("--record", path)
    }

    /// `--trajectory FILE`.
    pub fn trajectory(self, path: impl AsRef<OsStr>) -> Run {
        self.flag("--trajectory", path)
    }

    /// The command, to spawn or to give more settings (stdio, environment).
    pub fn command(&self) -> Command {
        let mut c = Command::new(env!("CARGO_BIN_EXE_ncplc"));
        c.args(&self.args);
        c
    }

    /// Runs it to its end and collects its output.
    pub fn output(&self) -> Output {
        self.command().output().expect("ncplc runs")
    }
}

/// Copies the directory tree `from` into `to` (which exists).
pub fn copy_dir(from: &Path, to: &Path) {
    for e in std::fs::read_dir(from).expect("dir") {
        let e = e.expect("entry");
        let dst = to.join(e.file_name());
        if e.file_type().expect("type").is_dir() {
            std::fs::create_dir_all(&dst).expect("mkdir");
            copy_dir(&e.path(), &dst);
        } else {
            std::fs::copy(e.path(), &dst).expect("copy");
        }
    }
}

/// A copy of the bundled lathe whose `sim.toml` ends just before the line `marker` (the script's
/// later events dropped).
pub fn lathe_cut_at(marker: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let sim = dir.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    let cut = text
        .find(marker)
        .unwrap_or_else(|| panic!("the lathe's sim.toml has `{marker}`"));
    std::fs::write(&sim, &text[..cut]).expect("write sim.toml");
    dir
}

/// One real-time `ncplc run` with simulated devices at a time, across every module of the e2e
/// binary (they were separate binaries before, so `cargo test` never ran two of them at once): each
/// runs real-time scan and I/O threads, and on a 2-core machine several at once starve each other's
/// simulated devices (a virtual CANopen node then misses its 100 ms heartbeat, which is a correct
/// alarm but not what these tests are about). A panicking holder does not poison it for the others.
pub fn serial() -> std::sync::MutexGuard<'static, ()> {
    static RUNS: std::sync::Mutex<()> = std::sync::Mutex::new(());
    RUNS.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A child process, killed however the test ends.
pub struct Killed(pub std::process::Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Spawns `c` with its stderr piped and waits at most `secs` for a stderr line that `find` turns
/// into a value (a server's address, an endpoint); panics naming `what` and the lines seen.
pub fn spawn_until(
    c: &mut Command,
    secs: u64,
    what: &str,
    find: impl Fn(&str) -> Option<String>,
) -> (Killed, String) {
    use std::io::BufRead as _;
    use std::time::{Duration, Instant};
    let mut run = c
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("ncplc runs");
    let err = std::io::BufReader::new(run.stderr.take().expect("stderr"));
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in err.lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let run = Killed(run);
    let deadline = Instant::now() + Duration::from_secs(secs);
    let mut said = Vec::new();
    loop {
        let line = rx
            .recv_timeout(deadline.saturating_duration_since(Instant::now()))
            .unwrap_or_else(|_| panic!("no {what} in:\n{}", said.join("\n")));
        if let Some(v) = find(&line) {
            return (run, v);
        }
        said.push(line);
    }
}

/// Whether `python` can import `imports` (an independent peer such as pymodbus or asyncua);
/// without it the caller skips loudly, and under `CI=true` this fails instead (`.ci/run` installs
/// every peer). `what` names the package, `install` the command that installs it.
pub fn python_peer(python: &str, imports: &str, what: &str, install: &str) -> bool {
    let ok = Command::new(python)
        .args(["-c", imports])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "{what} is missing under CI ({install})"
        );
        eprintln!("SKIPPED: no {what} for {python}; {install}");
    }
    ok
}
