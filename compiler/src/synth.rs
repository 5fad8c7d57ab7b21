//! A deterministic generator of large, valid PLC programs, for benchmarks and stress tests.
//!
//! [`synthetic_program`] mixes the statement kinds a real machine program has: boolean rungs with
//! self-latches and byte comparisons, arithmetic on DINT variables, named and inline timers,
//! counters, one-shots, SET/RES and `IF` zones, with a FAST and a SLOW part. It compiles without
//! errors for [`MachineContext::lathe_like`](crate::MachineContext::lathe_like) with `spl` ≥ 200.

use std::fmt::Write;

/// A program of about `statements` executable statements (the first 80 % FAST, the rest SLOW).
pub fn synthetic_program(statements: usize) -> String {
    let mut s = String::with_capacity(statements * 40);
    s.push_str("; synthetic program for benchmarks\n");
    for i in 0..100 {
        let _ = writeln!(s, "DEF V{i} : DINT := {i}");
    }
    for i in 0..50 {
        let _ = writeln!(s, "DEF T{i} : TON({}ms)", 10 * (i + 1));
    }
    for i in 0..20 {
        let _ = writeln!(s, "DEF C{i} : CTU({})", i + 2);
    }
    let mut n = 0;
    let mut k = 0usize;
    let (mut timers, mut counters, mut pulses) = (0, 0, 0);
    let mut slow = false;
    while n < statements {
        if !slow && n >= statements * 4 / 5 {
            s.push_str("$\n");
            slow = true;
        }
        let c = 100 + k % 150;
        let b = k % 32;
        let (c2, b2) = (100 + (k * 7) % 150, (k * 3) % 32);
        match k % 10 {
            5 => {
                let _ = writeln!(
                    s,
                    "V{} = V{} + DINT(W{}K{}) * 3 - V{}",
                    k % 100,
                    (k + 1) % 100,
                    c2,
                    k % 4,
                    (k + 2) % 100
                );
            }
            6 if timers < 50 => {
                let _ = writeln!(s, "T{timers} = I{c2}K{b2} + U{c}N{b}");
                timers += 1;
            }
            6 => {
                let _ = writeln!(
                    s,
                    "U{c}N{b} = TON(I{c2}N{b2} * /I{c}K{b}, {}ms)",
                    10 * (k % 30)
                );
            }
            7 => {
                let _ = writeln!(
                    s,
                    "IF [V{} > {}] THEN\nU{c}K{b} = I{c2}K{b2} + T{}\nEND_IF",
                    k % 100,
                    k % 1000,
                    k % 50
                );
                n += 1;
            }
            8 if pulses < 1024 && !slow => {
                let _ = writeln!(
                    s,
                    "P{pulses} = I{c2}N{b2}\nU{c}K{b} = P{pulses} + C{}",
                    k % 20
                );
                pulses += 1;
                n += 1;
            }
            9 if counters < 20 => {
                let _ = writeln!(s, "C{counters} = I{c2}K{b2}\nC{counters}.R = I{c}N{b}");
                counters += 1;
                n += 1;
            }
            9 => {
                let _ = writeln!(
                    s,
                    "SET U{c}N{b} = I{c2}K{b2} * [W3K0 = {:03X}H]\nRES U{c}N{b} = I0K1",
                    k % 256
                );
                n += 1;
            }
            _ => {
                let _ = writeln!(
                    s,
                    "U{c}K{b} = I{c2}K{b2} * /U{c}K{b} + I0A{} * [W3K0 = {}H] + U{c}K{b} * /I1A{}",
                    k % 32,
                    k % 90 + 10,
                    (k * 5) % 32
                );
            }
        }
        n += 1;
        k += 1;
    }
    s
}
