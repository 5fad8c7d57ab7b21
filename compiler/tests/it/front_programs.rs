//! The example machines' PLC programs behave as their comments say, in the interpreter and in
//! the JIT (tick for tick the same image).

use std::sync::Arc;

use compiler::{Engine, Interpreter, MachineContext, compile};
use packets::Signal;

fn ctx(inputs: &[u16], outputs: &[u16]) -> MachineContext {
    MachineContext {
        a_inputs: inputs.to_vec(),
        a_outputs: outputs.to_vec(),
        spl: 400,
        ..MachineContext::lathe_like()
    }
}

struct Rig {
    interp: Interpreter,
    jit: compiler::JitProgram,
    a: Vec<u8>,
    b: Vec<u8>,
}

impl Rig {
    fn new(src: &[u8], ctx: &MachineContext) -> Self {
        let c = compile("PLCPRG", src, ctx);
        assert_eq!(c.diagnostics, vec![]);
        let p = Arc::new(c.program.expect("compiles"));
        let a = p.new_image();
        let b = p.new_image();
        let jit = compiler::jit::compile(&p).expect("JIT compiles");
        Rig {
            interp: Interpreter::new(p),
            jit,
            a,
            b,
        }
    }
    fn set(&mut self, name: &str, v: u8) {
        let s: Signal = name.parse().expect("signal");
        s.write(&mut self.a, v);
        s.write(&mut self.b, v);
    }
    fn get(&self, name: &str) -> u8 {
        let s: Signal = name.parse().expect("signal");
        s.read(&self.a)
    }
    fn tick(&mut self, n: usize) {
        for _ in 0..n {
            self.interp.tick(&mut self.a);
            self.jit.tick(&mut self.b);
            assert_eq!(self.a, self.b, "interpreter and JIT disagree");
        }
    }
}

#[test]
fn lathe_m03_waits_for_at_speed_then_finishes_the_handshake() {
    let mut r = Rig::new(
        include_bytes!("../../../plc-programs/lathe/MP0/PLCPRG"),
        &ctx(&[0, 1], &[4, 5]),
    );
    for s in ["I0K2", "I0A0", "I0A1", "I0A2", "I1A0", "I0A7", "I0A8"] {
        r.set(s, 1);
    }
    r.tick(1);
    assert_eq!(
        (
            r.get("U11K4"),
            r.get("U10K8"),
            r.get("U10K9"),
            r.get("U4A4")
        ),
        (1, 1, 1, 1),
        "ESTOP released, X/Z enabled"
    );
    r.set("W3K0", 0x03);
    r.tick(1);
    r.set("I1K0", 1); // MSTB
    r.tick(1);
    assert_eq!(
        (r.get("U4A0"), r.get("U11K0")),
        (1, 0),
        "spindle CW on, no MFIN before at-speed"
    );
    r.set("I0A5", 1); // at speed
    r.tick(20);
    assert_eq!(r.get("U11K0"), 0, "at-speed must hold 200 ms");
    r.tick(1);
    assert_eq!(r.get("U11K0"), 1, "MFIN after 200 ms at speed");
    r.set("I1K0", 0);
    r.tick(1);
    assert_eq!(
        (r.get("U11K0"), r.get("U4A0")),
        (0, 1),
        "FIN drops with the strobe, spindle keeps running"
    );
    // Opening the emergency-stop chain stops everything.
    r.set("I0A0", 0);
    r.tick(1);
    assert_eq!((r.get("U11K4"), r.get("U4A0"), r.get("U10K8")), (0, 0, 0));
}

#[test]
fn lathe_lubrication_alarm_latches_until_reset() {
    let mut r = Rig::new(
        include_bytes!("../../../plc-programs/lathe/MP0/PLCPRG"),
        &ctx(&[0, 1], &[4, 5]),
    );
    for s in ["I0K2", "I0A0", "I0A1", "I1A0", "I0A7"] {
        r.set(s, 1);
    }
    r.tick(1);
    assert_eq!(
        r.get("U4A3"),
        1,
        "a lubrication shot when the process becomes ready"
    );
    r.set("I0A7", 0); // level low
    r.tick(220);
    assert_eq!(r.get("U5A2"), 1, "alarm lamp after 2 s low level");
    r.set("I0A7", 1);
    r.tick(10);
    assert_eq!(r.get("U5A2"), 1, "latched");
    r.set("I0K1", 1); // RESET
    r.tick(10);
    assert_eq!(r.get("U5A2"), 0, "cleared by RESET once refilled");
}

/// The mill's context: its connectors and its interface map (process 2's signals).
fn mill_ctx() -> MachineContext {
    let o = compiler::InterfaceMap::parse(
        "interface.toml",
        include_str!("../../../plc-programs/mill/interface.toml"),
    )
    .expect("the mill's map parses");
    MachineContext {
        interface: compiler::InterfaceMap::builtin()
            .with_overrides(o)
            .expect("no clash"),
        ..ctx(&[0, 1, 2], &[4, 5, 6])
    }
}

#[test]
fn mill_m06_runs_the_tool_change_sequence() {
    let mut r = Rig::new(
        include_bytes!("../../../plc-programs/mill/MP0/PLCPRG"),
        &mill_ctx(),
    );
    for s in [
        "I0K2", "I0A0", "I0A1", "I0A2", "I1A0", "I0A7", "I2A0", "I2A2",
    ] {
        r.set(s, 1);
    }
    // T12: TCODE is BCD.
    r.set("W5K0", 0x12);
    r.tick(1);
    r.set("I1K2", 1);
    r.tick(1);
    assert_eq!(r.get("U11K2"), 1, "TFIN");
    r.set("I1K2", 0);
    r.set("W3K0", 0x06);
    r.tick(1);
    r.set("I1K0", 1); // MSTB with M06
    r.tick(1);
    assert_eq!((r.get("U6A0"), r.get("U6A1")), (1, 0), "orient first");
    r.set("I0A6", 1);
    r.set("I2A4", 1);
    r.tick(1);
    assert_eq!(r.get("U6A1"), 1, "unclamp once oriented at zero speed");
    r.set("I2A0", 0);
    r.set("I2A1", 1);
    r.tick(1);
    assert_eq!(r.get("U6A2"), 1, "swap once unclamped");
    r.set("I2A2", 0);
    r.set("I2A3", 1);
    r.tick(1);
    assert_eq!((r.get("U6A1"), r.get("U6A2")), (0, 0), "clamp and return");
    r.set("I2A1", 0);
    r.set("I2A0", 1);
    r.set("I2A2", 1);
    r.set("I2A3", 0);
    r.tick(1);
    r.tick(1);
    assert_eq!(r.get("U11K0"), 1, "MFIN after the change");
    r.set("I1K0", 0);
    r.tick(2);
    assert_eq!((r.get("U11K0"), r.get("U6A0")), (0, 0));
}

#[test]
fn mill_process_2_m30_waits_for_the_tool_change_and_m00_does_not() {
    let mut r = Rig::new(
        include_bytes!("../../../plc-programs/mill/MP0/PLCPRG"),
        &mill_ctx(),
    );
    for s in ["I0A0", "I0A1", "I0A2", "I1A0", "I0A7", "I2A0", "I2A2"] {
        r.set(s, 1);
    }
    r.tick(1);
    assert_eq!(r.get("U30K8"), 0, "RABI_T off while process 2 is not ready");
    r.set("I6K2", 1); // CONP_T
    r.tick(1);
    assert_eq!(r.get("U30K8"), 1, "RABI_T");
    // M06 on process 1 starts the tool change.
    r.set("W3K0", 0x06);
    r.set("I1K0", 1);
    r.tick(1);
    assert_eq!(r.get("U6A0"), 1, "orienting");
    // M30 on process 2 (MCODE_T W7K0, MSTB_T I6K0) waits while the change runs.
    r.set("W7K0", 0x30);
    r.set("I6K0", 1);
    r.tick(3);
    assert_eq!(r.get("U30K0"), 0, "no MFIN_T during the tool change");
    // The change ends (RESET clears it), and M30 finishes.
    r.set("I1K0", 0);
    r.set("I0K1", 1);
    r.tick(1);
    assert_eq!((r.get("U6A0"), r.get("U30K0")), (0, 1), "MFIN_T");
    r.set("I0K1", 0);
    r.set("I6K0", 0);
    r.tick(1);
    assert_eq!(r.get("U30K0"), 0, "MFIN_T follows the strobe down");
    // M00 finishes at once, even during a tool change.
    r.set("W3K0", 0x06);
    r.set("I1K0", 1);
    r.tick(1);
    r.set("W7K0", 0x00);
    r.set("I6K0", 1);
    r.tick(1);
    assert_eq!(r.get("U30K0"), 1, "M00 at once");
    // The e-stop chain opening drops the magazine axis enable.
    r.set("I0A0", 0);
    r.tick(1);
    assert_eq!(r.get("U30K8"), 0);
}
