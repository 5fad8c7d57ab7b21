//! The JIT's on-disk code cache: a second compile of the same program in a cache directory maps
//! the stored code (same bytes, same behaviour as the interpreter), a changed program or a
//! damaged entry is compiled again.

use std::sync::Arc;

use compiler::jit::JitOptions;
use compiler::jit::disk_cache::{self, DiskCache};
use compiler::{Engine, Interpreter, MachineContext, compile, synth::synthetic_program};

fn program(statements: usize) -> compiler::ir::Program {
    let ctx = MachineContext {
        spl: 256,
        ..MachineContext::lathe_like()
    };
    compile("disk", synthetic_program(statements).as_bytes(), &ctx)
        .program
        .expect("the program compiles")
}

fn entries(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .map(|rd| rd.filter_map(Result::ok).map(|e| e.path()).collect())
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn a_second_compile_maps_the_stored_code_and_runs_like_the_interpreter() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = DiskCache::new(dir.path().join("code"));
    let p = program(300);
    let opts = JitOptions::default();
    let (first, hit) = disk_cache::compile(&p, &opts, Some(&cache)).expect("compiles");
    assert!(!hit, "an empty cache holds nothing");
    assert_eq!(entries(cache.dir()).len(), 1);
    let (mut second, hit) = disk_cache::compile(&p, &opts, Some(&cache)).expect("loads");
    assert!(hit, "the same program is found");
    assert_eq!(first.machine_code(), second.machine_code());
    assert_eq!(first.function_count(), second.function_count());
    let p = Arc::new(p);
    let mut interp = Interpreter::new(p.clone());
    let (mut a, mut b) = (p.new_image(), p.new_image());
    for t in 0..200u32 {
        for image in [&mut a, &mut b] {
            image[128 + (t as usize * 7) % 1024] ^= (t % 251) as u8;
        }
        interp.tick(&mut a);
        second.tick(&mut b);
        assert!(a == b, "tick {t}");
    }
}

#[test]
fn another_program_options_or_a_damaged_entry_are_compiled_again() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = DiskCache::new(dir.path());
    let opts = JitOptions::default();
    let (p, q) = (program(200), program(260));
    assert!(!disk_cache::compile(&p, &opts, Some(&cache)).expect("p").1);
    assert!(!disk_cache::compile(&q, &opts, Some(&cache)).expect("q").1);
    let speed = JitOptions {
        opt_level: "speed",
        ..JitOptions::default()
    };
    assert!(
        !disk_cache::compile(&p, &speed, Some(&cache))
            .expect("p speed")
            .1
    );
    assert_eq!(entries(dir.path()).len(), 3);
    assert!(
        disk_cache::compile(&q, &opts, Some(&cache))
            .expect("q again")
            .1
    );
    // Damage every entry: each is compiled (and stored) again.
    for e in entries(dir.path()) {
        std::fs::write(&e, b"not a cache entry").expect("damage");
    }
    assert!(
        !disk_cache::compile(&p, &opts, Some(&cache))
            .expect("p again")
            .1
    );
    assert!(
        disk_cache::compile(&p, &opts, Some(&cache))
            .expect("p stored again")
            .1
    );
    // Threads do not change the code: a 2-thread compile finds the 1-thread one.
    let two = JitOptions {
        threads: 2,
        ..JitOptions::default()
    };
    assert!(
        disk_cache::compile(&p, &two, Some(&cache))
            .expect("p 2 threads")
            .1
    );
}

#[test]
fn lookup_finds_only_what_a_compile_stored() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = DiskCache::new(dir.path());
    let p = program(100);
    let opts = JitOptions::default();
    assert!(disk_cache::lookup(&p, &opts, &cache).is_none());
    let (compiled, _) = disk_cache::compile(&p, &opts, Some(&cache)).expect("compiles");
    let found = disk_cache::lookup(&p, &opts, &cache).expect("stored");
    assert_eq!(compiled.machine_code(), found.machine_code());
}

/// After `ncplc run` mapped a program's code from the disk cache, the first online change
/// compiles only the functions it changed: the mapped functions fill the in-memory cache.
#[test]
fn an_online_change_after_a_mapped_start_compiles_only_the_changed_function() {
    use compiler::jit::{CodeCache, compile_cached, compile_with};
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = DiskCache::new(dir.path());
    let opts = JitOptions::default();
    let p = program(300);
    let (built, _) = disk_cache::compile(&p, &opts, Some(&cache)).expect("compiles");
    let mut memory = CodeCache::new();
    let mapped = disk_cache::lookup_cached(&p, &opts, &cache, &mut memory).expect("mapped");
    assert_eq!(mapped.machine_code(), built.machine_code());
    let functions = mapped.function_count();
    assert!(functions >= 3, "FAST and SLOW functions: {functions}");
    assert_eq!(memory.len(), functions);
    // Swapping the first two FAST statements changes the first function only (no chunk boundary
    // can move: the accumulated cost is unchanged past them).
    let mut edited = p.clone();
    assert_ne!(edited.fast[0], edited.fast[1]);
    edited.fast.swap(0, 1);
    let changed = compile_cached(&edited, &opts, &mut memory).expect("online change");
    assert_eq!(memory.compiled(), 1);
    assert_eq!(memory.reused(), functions - 1);
    assert_eq!(
        changed.machine_code(),
        compile_with(&edited, &opts)
            .expect("uncached")
            .machine_code()
    );
    // Without the mapped functions, the same change compiles every function.
    let mut empty = CodeCache::new();
    compile_cached(&edited, &opts, &mut empty).expect("compiles");
    assert_eq!(empty.compiled(), functions);
}
