//! The on-disk front-end cache: a second compile of the same source for the same machine returns
//! the stored program and warnings without compiling; another source or machine, or a source
//! with errors, is compiled (and errors are never stored).

use compiler::front_cache::compile_cached;
use compiler::jit::disk_cache::DiskCache;
use compiler::{MachineContext, synth::synthetic_program};

fn fronts(dir: &std::path::Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |rd| {
        rd.filter_map(Result::ok)
            .filter(|e| e.path().extension().is_some_and(|x| x == "front"))
            .count()
    })
}

#[test]
fn a_second_compile_returns_the_stored_program_and_warnings() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = DiskCache::new(dir.path());
    let ctx = MachineContext {
        spl: 256,
        ..MachineContext::lathe_like()
    };
    // `X` is never used: one warning.
    let src = format!("DEF X : DINT := 1\n{}", synthetic_program(200));
    let (first, hit) = compile_cached("PLCPRG", src.as_bytes(), &ctx, 1, Some(&cache));
    assert!(!hit);
    assert!(first.program.is_some());
    assert!(!first.diagnostics.is_empty(), "the unused X is reported");
    assert_eq!(fronts(dir.path()), 1);
    // An equal context built afresh (its interface map's hash tables in another order).
    let same = MachineContext {
        spl: 256,
        ..MachineContext::lathe_like()
    };
    let (second, hit) = compile_cached("PLCPRG", src.as_bytes(), &same, 1, Some(&cache));
    assert!(hit, "the same source for the same machine is found");
    assert_eq!(second.program, first.program);
    assert_eq!(second.diagnostics, first.diagnostics);
    assert_eq!(second.text, first.text);
    let (a, b) = (first.stats, second.stats);
    assert_eq!(
        (a.statements, a.symbolic_names, a.image_size, a.slow_slices),
        (b.statements, b.symbolic_names, b.image_size, b.slow_slices)
    );
    // Another machine (a different SPL), another file name or another source: compiled again.
    let other = MachineContext {
        spl: 300,
        ..ctx.clone()
    };
    assert!(!compile_cached("PLCPRG", src.as_bytes(), &other, 1, Some(&cache)).1);
    assert!(!compile_cached("OTHER", src.as_bytes(), &ctx, 1, Some(&cache)).1);
    let edited = src.replace("DEF X : DINT := 1", "DEF X : DINT := 2");
    assert!(!compile_cached("PLCPRG", edited.as_bytes(), &ctx, 1, Some(&cache)).1);
    assert_eq!(fronts(dir.path()), 4);
}

#[test]
fn a_source_with_errors_is_never_stored() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = DiskCache::new(dir.path());
    let ctx = MachineContext::lathe_like();
    let src = b"U4A0 = I0A0 *\n";
    for _ in 0..2 {
        let (c, hit) = compile_cached("PLCPRG", src, &ctx, 1, Some(&cache));
        assert!(!hit);
        assert!(c.program.is_none());
        assert!(diag::has_errors(&c.diagnostics));
    }
    assert_eq!(fronts(dir.path()), 0);
}

#[test]
fn a_damaged_entry_is_compiled_again() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = DiskCache::new(dir.path());
    let ctx = MachineContext::lathe_like();
    let src = b"U4A0 = I0A0 * I0A1\n";
    let (first, _) = compile_cached("PLCPRG", src, &ctx, 1, Some(&cache));
    for e in std::fs::read_dir(dir.path())
        .expect("dir")
        .filter_map(Result::ok)
    {
        std::fs::write(e.path(), b"garbage").expect("damage");
    }
    let (again, hit) = compile_cached("PLCPRG", src, &ctx, 1, Some(&cache));
    assert!(!hit);
    assert_eq!(again.program, first.program);
    assert!(
        compile_cached("PLCPRG", src, &ctx, 1, Some(&cache)).1,
        "stored again"
    );
}
