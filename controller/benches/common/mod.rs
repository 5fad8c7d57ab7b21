//! Shared by the part-run benchmarks: a scheduler running a planned partprogram on a machine's
//! CNC kernel, logic and plant in virtual time.

use std::sync::{Arc, Mutex};

use cnc::{Command, Mode};
use controller::machine::Machine;
use controller::part_run::make_interp;
use packets::PacketIo;
use runtime::clock::VirtualClock;
use runtime::compiled::EngineKind;
use runtime::image::Image;
use runtime::machine_facts::Facts;
use runtime::scheduler::{Scheduler, Settings};
use sim::kernel::{KernelIo, KernelSetup};
use sim::part::plan_text;

/// A scheduler running `text` (named `name`) on `m` with AUTO selected (the part script presses
/// START); `wrap` may put the kernel I/O inside another `PacketIo`.
pub fn part_scheduler(
    m: &Machine,
    name: &str,
    text: &str,
    wrap: impl FnOnce(KernelIo) -> Box<dyn PacketIo>,
) -> (Scheduler, Arc<Mutex<cnc::Cnc>>) {
    let blocks = plan_text(&m.dir, name, text, None, false).unwrap_or_else(|e| panic!("{e}"));
    let facts = Facts::load(&m.dir).unwrap_or_else(|e| panic!("{e}"));
    let axcfil = &facts.machine.axcfil;
    let complex = sim::machine_view::complex_speed(&m.dir).unwrap_or_else(|e| panic!("{e}"));
    let interp = |cfg: &cnc::ProcessConfig, start: &[f64]| make_interp(axcfil, complex, cfg, start);
    let setup = KernelSetup {
        axcfil,
        iocfil: facts.machine.iocfil.as_ref(),
        interface: &m.interface,
        a_inputs: &m.config.a_inputs,
        tick_ms: m.config.tick_ms,
        make_interp: &interp,
    };
    let (io, cnc) = KernelIo::new(&setup, m.script.clone()).unwrap_or_else(|e| panic!("{e}"));
    {
        let mut c = cnc.lock().unwrap_or_else(|e| panic!("{e}"));
        let p = c.process_mut(1).unwrap_or_else(|e| panic!("{e}"));
        p.load(name, blocks).unwrap_or_else(|e| panic!("{e}"));
        p.command(Command::SetMode(Mode::Auto));
    }
    let compile = m.compile_fn(EngineKind::Jit, m.config.tick_ms);
    let loaded = compile(&m.read_source().unwrap_or_else(|e| panic!("{e}")))
        .unwrap_or_else(|e| panic!("{e}"));
    let mut image = Image::new(loaded.meta.image_len(), &m.config.t_init);
    loaded.meta.init_image(image.bytes_mut());
    let settings = Settings {
        tick_ns: u64::from(m.config.tick_ms) * 1_000_000,
        overrun_limit: 0,
    };
    let s = Scheduler::new(
        image,
        loaded,
        wrap(io),
        Box::new(VirtualClock::new()),
        settings,
    );
    (s, cnc)
}

/// The session token of the HMI benches' server (a viewer: the benches only watch).
#[allow(dead_code)]
pub const BENCH_TOKEN: &str = "bench-token-0123456789";

/// The HMI benches' link: an HMI server on an ephemeral loopback port over the CNC kernel `cnc`
/// running `text` as PART1 on `m` (PLC source `source`).
#[allow(dead_code)] // the part-run benches include this module without serving an HMI
pub fn hmi_link(
    m: &Machine,
    source: &[u8],
    text: &str,
    cnc: Arc<Mutex<cnc::Cnc>>,
) -> controller::hmi_link::HmiLink {
    use controller::hmi_link::image_cnc::ImageCnc;
    use controller::hmi_link::kernel_cnc::KernelCnc;
    let image = ImageCnc::new(&m.interface, &[1], None);
    let kernel = KernelCnc::new(cnc, image, &[("PART1".into(), text.to_string())]);
    let config = hmi::ServerConfig {
        addr: "127.0.0.1:0".parse().unwrap_or_else(|e| panic!("{e}")),
        tokens: hmi::Tokens::single(BENCH_TOKEN.into(), hmi::Role::Viewer),
        readonly: false,
        allow_hosts: Vec::new(),
        allow_origins: Vec::new(),
        tls: None,
        limits: hmi::security::limits::Limits::default(),
    };
    controller::hmi_link::HmiLink::start(
        config,
        controller::hmi_link::catalog::build(m, source),
        Box::new(kernel),
        m.config.tick_ms,
        None,
    )
    .unwrap_or_else(|e| panic!("{e}"))
}
