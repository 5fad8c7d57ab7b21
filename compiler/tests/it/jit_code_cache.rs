//! The JIT's code cache (online change): a recompile reuses the machine code of every function
//! whose cranelift IR is unchanged, an edit recompiles only the functions around it, and the
//! program runs bit for bit like one compiled without the cache and like the interpreter.

use std::collections::HashSet;
use std::sync::Arc;

use compiler::ir::Program;
use compiler::jit::{self, CodeCache, JitOptions};
use compiler::{Engine, Interpreter, MachineContext, compile, synth::synthetic_program};

fn program(src: &str) -> Arc<Program> {
    let ctx = MachineContext {
        spl: 5000,
        ..MachineContext::lathe_like()
    };
    let c = compile("cache", src.as_bytes(), &ctx);
    Arc::new(c.program.expect("the program compiles"))
}

/// The distinct function bodies of `p` as `ncplc build --emit clif` prints them, without the
/// label comment and the function's name (which holds its number).
fn function_texts(p: &Program) -> HashSet<String> {
    let clif = jit::emit_clif(p).expect("clif");
    clif.split("\n; ")
        .map(|f| {
            let mut lines = f.lines();
            let (label, header) = (lines.next(), lines.next());
            assert!(
                label.is_some_and(|l| l.contains("function part")),
                "{label:?}"
            );
            assert!(
                header.is_some_and(|h| h.starts_with("function u0:")),
                "{header:?}"
            );
            lines.collect::<Vec<_>>().join("\n")
        })
        .collect()
}

/// Runs the engines side by side for 40 ticks with pseudo-random input bytes; every image must
/// equal the first engine's after every tick.
fn assert_same_behaviour(p: &Program, engines: &mut [&mut dyn Engine]) {
    let mut images: Vec<Vec<u8>> = engines.iter().map(|_| p.new_image()).collect();
    let mut x: u32 = 12345;
    for tick in 0..40 {
        for _ in 0..16 {
            x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
            let at = (x >> 8) as usize % 600;
            let v = (x >> 24) as u8;
            for image in &mut images {
                image[at] = v;
            }
        }
        for (e, image) in engines.iter_mut().zip(&mut images) {
            e.tick(image);
        }
        for (i, image) in images.iter().enumerate().skip(1) {
            assert!(*image == images[0], "tick {tick}: engine {i} differs");
        }
    }
}

#[test]
fn recompiling_the_same_program_reuses_every_function() {
    let p = program(&synthetic_program(1500));
    let opts = JitOptions::default();
    let mut cache = CodeCache::new();
    let mut first = jit::compile_cached(&p, &opts, &mut cache).expect("jit");
    let n = first.function_count();
    assert_eq!((cache.reused(), cache.compiled()), (0, n));
    assert_eq!(cache.len(), n);
    let mut second = jit::compile_cached(&p, &opts, &mut cache).expect("jit");
    assert_eq!((cache.reused(), cache.compiled()), (n, 0));
    assert_eq!(cache.reused_by_statements(), n);
    // Other settings make other code: nothing is reused across them.
    let speed = JitOptions {
        opt_level: "speed",
        ..JitOptions::default()
    };
    let mut third = jit::compile_cached(&p, &speed, &mut cache).expect("jit");
    assert_eq!((cache.reused(), cache.compiled()), (0, n));
    let mut plain = jit::compile_with(&p, &opts).expect("jit");
    let mut interp = Interpreter::new(p.clone());
    assert_same_behaviour(
        &p,
        &mut [&mut interp, &mut first, &mut second, &mut third, &mut plain],
    );
}

#[test]
fn an_edit_recompiles_only_the_functions_it_changes() {
    let src = synthetic_program(3000);
    // One statement more in the middle of the FAST part: the chunks after it shift.
    let mut lines: Vec<&str> = src.lines().collect();
    let at = lines.len() / 3;
    lines.insert(at, "V7 = V7 + 1");
    let edited = lines.join("\n") + "\n";
    let (old, new) = (program(&src), program(&edited));
    let opts = JitOptions::default();
    let mut cache = CodeCache::new();
    jit::compile_cached(&old, &opts, &mut cache).expect("jit");
    let mut jit_new = jit::compile_cached(&new, &opts, &mut cache).expect("jit");
    let (old_f, new_f) = (function_texts(&old), function_texts(&new));
    let changed = new_f.difference(&old_f).count();
    eprintln!(
        "{changed} of {} changed, {} cached",
        new_f.len(),
        cache.len()
    );
    assert_eq!(cache.compiled(), changed);
    assert_eq!(cache.reused(), jit_new.function_count() - changed);
    // The declarations are unchanged (an inline timer's name moved with its line, but names do
    // not count): every unchanged function is found by its statements.
    assert_eq!(cache.reused_by_statements(), cache.reused());
    // Content-defined chunk boundaries resynchronise right after the edit.
    assert!(
        (1..=3).contains(&changed),
        "{changed} of {} functions changed",
        new_f.len()
    );
    let mut plain = jit::compile_with(&new, &opts).expect("jit");
    let mut interp = Interpreter::new(new.clone());
    assert_same_behaviour(&new, &mut [&mut interp, &mut jit_new, &mut plain]);
}

#[test]
fn a_changed_constant_recompiles_its_function() {
    let src = synthetic_program(3000);
    let mut lines: Vec<String> = src.lines().map(str::to_string).collect();
    let at = (lines.len() / 3..lines.len())
        .find(|&i| lines[i].starts_with("IF [V"))
        .expect("an IF zone");
    let (head, tail) = lines[at].split_once("> ").expect("a comparison");
    let (k, rest) = tail.split_once(']').expect("closing bracket");
    let k: u32 = k.parse().expect("a constant");
    lines[at] = format!("{head}> {}]{rest}", k + 1);
    let edited = lines.join("\n") + "\n";
    let (old, new) = (program(&src), program(&edited));
    let opts = JitOptions::default();
    let mut cache = CodeCache::new();
    jit::compile_cached(&old, &opts, &mut cache).expect("jit");
    let mut jit_new = jit::compile_cached(&new, &opts, &mut cache).expect("jit");
    let changed = function_texts(&new)
        .difference(&function_texts(&old))
        .count();
    assert_eq!(changed, 1);
    assert_eq!(
        (cache.compiled(), cache.reused()),
        (1, jit_new.function_count() - 1)
    );
    let mut plain = jit::compile_with(&new, &opts).expect("jit");
    let mut interp = Interpreter::new(new.clone());
    assert_same_behaviour(&new, &mut [&mut interp, &mut jit_new, &mut plain]);
}

#[test]
fn a_new_initial_value_reuses_every_function() {
    let src = synthetic_program(3000);
    // A new initial value: the declarations differ, the layout and so every function's IR stay
    // the same (the initial values are the image's, not the code's).
    let edited = src.replacen("DEF V0 : DINT := 0\n", "DEF V0 : DINT := 77\n", 1);
    let (old, new) = (program(&src), program(&edited));
    assert_ne!(old.vars[0].init, new.vars[0].init);
    let opts = JitOptions::default();
    let mut cache = CodeCache::new();
    jit::compile_cached(&old, &opts, &mut cache).expect("jit");
    let mut jit_new = jit::compile_cached(&new, &opts, &mut cache).expect("jit");
    let changed = function_texts(&new)
        .difference(&function_texts(&old))
        .count();
    assert_eq!(
        (cache.compiled(), cache.reused()),
        (changed, jit_new.function_count() - changed)
    );
    // The declarations differ, so nothing is found by its statements, all by the IR.
    assert_eq!(cache.reused_by_statements(), 0);
    assert_eq!(changed, 0);
    let mut plain = jit::compile_with(&new, &opts).expect("jit");
    let mut interp = Interpreter::new(new.clone());
    assert_same_behaviour(&new, &mut [&mut interp, &mut jit_new, &mut plain]);
}
