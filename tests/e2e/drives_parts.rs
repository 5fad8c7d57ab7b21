//! End to end: more of the bundled parts on CiA 402 drives (issue 21's "every bundled part runs
//! with `--io canopen` to M30 and replays identically"). PART1 of both machines is in `drives::`;
//! here a G96 facing (the spindle's speed follows X on its `csv` drive), a G84 thread (the feed
//! follows the spindle's revolutions from the drive's `606Ch`) and a Fanuc mill program with tool
//! changes run on the plant and on the drives in virtual time, end at the same positions, and the
//! bus run replays exactly without the bus. (Every other bundled part was run the same way when
//! this test was written: docs/drives.md lists them; the long ones stay out of the suite's time.)

use crate::drives::{final_positions, run_to_end as run, text};
use crate::e2e_common::{ncplc, root};

#[test]
fn a_g96_facing_a_thread_and_a_fanuc_mill_part_run_on_drives_and_replay_exactly() {
    let _serial = crate::e2e_common::serial();
    // The cycles on the plant and on the bus: a tick later on the bus (the panel's CYCLE START
    // comes over the I/O node) and a tick longer per wait for the spindle at speed (its drive's
    // answer reaches the kernel at the next tick).
    for (machine, part, plant_cycle, bus_cycle) in [
        (
            "lathe",
            "FACE96",
            "cycle time 10.78 s (ticks 12..1090), ended",
            "cycle time 10.82 s (ticks 13..1095), ended",
        ),
        (
            "lathe",
            "G84THREAD",
            "cycle time 19.79 s (ticks 12..1991), ended",
            "cycle time 19.79 s (ticks 13..1992), ended",
        ),
        (
            "mill",
            "O00050.nc",
            "cycle time 26.48 s (ticks 12..2660), ended",
            "cycle time 26.55 s (ticks 13..2668), ended",
        ),
    ] {
        let m = root().join("plc-programs").join(machine);
        let dir = tempfile::tempdir().expect("tempdir");
        let (plant, plant_trace, ok) = run(&m, part, "sim", dir.path());
        assert!(ok, "{plant}");
        let (bus, bus_trace, ok) = run(&m, part, "canopen", dir.path());
        assert!(ok, "{bus}");
        assert!(plant.contains(plant_cycle), "{machine} {part}: {plant}");
        assert!(bus.contains(bus_cycle), "{machine} {part}: {bus}");
        assert!(!bus.contains("alarm: process"), "{bus}");
        let end = final_positions(&bus_trace);
        assert!(end.len() >= 2, "{machine} {part}: {end:?}");
        assert_eq!(end, final_positions(&plant_trace), "{machine} {part}");
        let trace = dir.path().join("canopen.jsonl");
        let out = ncplc(&[
            "replay",
            m.to_str().expect("utf-8"),
            trace.to_str().expect("utf-8"),
        ]);
        let r = text(&out);
        assert!(out.status.success(), "{r}");
        assert!(
            r.contains("outputs identical, kernel signals and axis positions identical"),
            "{machine} {part}: {r}"
        );
    }
}
