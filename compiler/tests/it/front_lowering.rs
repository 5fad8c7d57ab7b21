//! Lowering details observable at run time: inline timers inside IF zones freeze with the zone,
//! counters, RETAIN variables and typed views, checked in the interpreter and the JIT alike.

use std::sync::Arc;

use compiler::{Engine, Interpreter, MachineContext, compile};
use packets::Signal;

fn run(src: &str, ticks: &[&[(&str, u8)]]) -> Vec<Vec<u8>> {
    let c = compile("t", src.as_bytes(), &MachineContext::lathe_like());
    assert!(
        c.diagnostics.iter().all(|d| !d.is_error()),
        "{:?}",
        c.diagnostics
    );
    let p = Arc::new(c.program.expect("compiles"));
    let mut interp = Interpreter::new(p.clone());
    let mut jit = compiler::jit::compile(&p).expect("JIT");
    let (mut a, mut b) = (p.new_image(), p.new_image());
    let mut out = Vec::new();
    for inputs in ticks {
        for (name, v) in *inputs {
            let s: Signal = name.parse().expect("signal");
            s.write(&mut a, *v);
            s.write(&mut b, *v);
        }
        interp.tick(&mut a);
        jit.tick(&mut b);
        assert_eq!(a, b, "interpreter and JIT disagree");
        out.push(a.clone());
    }
    out
}

fn bit(image: &[u8], name: &str) -> u8 {
    name.parse::<Signal>().expect("signal").read(image)
}

#[test]
fn an_inline_timer_in_a_false_if_zone_is_frozen() {
    // TON(30ms): Q at the 3rd execution after the one in which IN rose.
    let src = "IF I0A0 THEN\nU4A0 = TON(I0A1, 30ms)\nEND_IF";
    let on: &[(&str, u8)] = &[("I0A0", 1), ("I0A1", 1)];
    let freeze: &[(&str, u8)] = &[("I0A0", 0)];
    let go: &[(&str, u8)] = &[("I0A0", 1)];
    let images = run(src, &[on, &[], freeze, &[], &[], go, &[]]);
    let q: Vec<u8> = images.iter().map(|i| bit(i, "U4A0")).collect();
    // Executions 1, 2 run; ticks 3-5 frozen (coil keeps 0); execution 3 at tick 6 reaches 30 ms.
    assert_eq!(q, vec![0, 0, 0, 0, 0, 0, 1]);
}

#[test]
fn ctd_loads_and_counts_down_to_q() {
    let src =
        "DEF C : CTD(2)\nC.LD = I0A0\nC = I0A1\nU4A0 = C\nDEF V : BYTE AT W5A0\nV = BYTE(C.CV)";
    let load: &[(&str, u8)] = &[("I0A0", 1)];
    let unload: &[(&str, u8)] = &[("I0A0", 0)];
    let up: &[(&str, u8)] = &[("I0A1", 1)];
    let down: &[(&str, u8)] = &[("I0A1", 0)];
    let images = run(src, &[&[], load, unload, up, down, up, down]);
    let q: Vec<u8> = images.iter().map(|i| bit(i, "U4A0")).collect();
    let cv: Vec<u8> = images.iter().map(|i| bit(i, "W5A0")).collect();
    assert_eq!(q, vec![1, 0, 0, 0, 0, 1, 1], "an unloaded CTD reads Q = 1");
    assert_eq!(cv, vec![0, 2, 2, 1, 1, 0, 0]);
}

#[test]
fn retain_variables_and_views_are_laid_out() {
    let c = compile(
        "t",
        b"DEF PARTS : DINT RETAIN\nDEF COUNT : DINT := 7\nDEF DAC : WORD AT W4A2\nPARTS = PARTS + 1\nCOUNT = COUNT + 1\nDAC = WORD(COUNT)",
        &MachineContext::lathe_like(),
    );
    assert_eq!(c.diagnostics, vec![]);
    let p = c.program.expect("compiles");
    assert_eq!(p.vars.len(), 2);
    assert!(p.vars[0].retain && !p.vars[1].retain);
    assert!(p.retain_range().contains(&p.vars[0].offset));
    let image = p.new_image();
    assert_eq!(image[p.vars[1].offset], 7, "initial value written at start");
    assert_eq!(
        p.written_signals(),
        vec!["W4A2".parse().expect("sig"), "W4A3".parse().expect("sig")]
    );
}
