//! End to end: homing (MCZ) on CiA 402 drives (issue 21). A copy of the lathe without absolute
//! encoders (`sim.toml [cnc] referenced = false`) homes X and Z on simulated drives through the
//! CLI (`--io canopen`): HOME, START, the MCZ cycle reading the home switch from the drive's
//! digital inputs `60FDh` and the reference mark from the drive's touch probe (`60B8h`..`60BAh`),
//! then PART1 when the operator presses START again; the run replays exactly from its trace.

use std::path::Path;

use crate::e2e_common;
use e2e_common::{Ncplc, copy_dir, ncplc, root};

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// A copy of the lathe that must home: X starts at machine −50 with its switch edge at 13.7, Z
/// at −100 with its edge at 27 (both MCZ direction 0: the switch is pressed from its edge up);
/// the operator presses START again at tick 1500, after homing.
fn unreferenced_lathe() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let sim = dir.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    assert!(text.contains("referenced = true"));
    let text = text.replace("referenced = true", "referenced = false")
        + "\n[[axis]]\nname = \"X\"\nstart = -50\nhome_switch = 13.7\n\
           \n[[axis]]\nname = \"Z\"\nstart = -100\nhome_switch = 27\n\
           \n[[part.at]]\ntick = 1500\nset = { I0A3 = 1 }\n\
           \n[[part.at]]\ntick = 1505\nset = { I0A3 = 0 }\n";
    std::fs::write(&sim, text).expect("write");
    dir
}

/// One drive sample of a trace record: (last actual value, `60FDh`, probe status, latched value).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Sample {
    last: f64,
    inputs: u64,
    probe_status: u64,
    probe: Option<f64>,
}

/// Per record (tick, the kernel's positions when recorded, the drive samples by axis letter).
type Record = (u64, Vec<(String, f64)>, Vec<(char, Sample)>);

fn records(trace: &str) -> Vec<Record> {
    let bits = |v: &serde_json::Value| f64::from_bits(v.as_u64().expect("bits"));
    trace
        .lines()
        .skip(1)
        .map(|l| {
            let r: serde_json::Value = serde_json::from_str(l).expect("json");
            let pos = r
                .get("pos")
                .and_then(|p| p.as_object())
                .map(|o| {
                    o.iter()
                        .map(|(a, h)| {
                            let h = u64::from_str_radix(h.as_str().expect("hex"), 16);
                            (a.clone(), f64::from_bits(h.expect("hex")))
                        })
                        .collect()
                })
                .unwrap_or_default();
            let drives = r
                .get("drives")
                .and_then(|d| d.as_array())
                .map(|d| {
                    d.iter()
                        .filter_map(|d| {
                            let axis = d["axis"]["axis"].as_str()?.chars().next()?;
                            let last = d["values"].as_array()?.last()?;
                            Some((
                                axis,
                                Sample {
                                    last: last.as_u64().map_or(f64::NAN, f64::from_bits),
                                    inputs: d.get("inputs").and_then(|v| v.as_u64()).unwrap_or(0),
                                    probe_status: d
                                        .get("probe_status")
                                        .and_then(|v| v.as_u64())
                                        .unwrap_or(0),
                                    probe: d.get("probe").map(bits),
                                },
                            ))
                        })
                        .collect()
                })
                .unwrap_or_default();
            (r["t"].as_u64().expect("t"), pos, drives)
        })
        .collect()
}

/// Homing X and Z on drives, hand-derived. The search goes up (MCZ direction 0) at MAN 2000
/// until the drive's `60FDh` bit 2 reports the switch, then back at the MCZ speed; once the
/// switch is left the touch probe is armed, and the next reference mark below the edge on the
/// PAS pitch is latched: X (pitch 5) leaves 13.7 and meets the mark at machine 10, drive
/// position 10 − (−50) = 60 mm; Z (pitch 10) leaves 27 and meets machine 20, drive position
/// 20 − (−100) = 120 mm. The marks crossed during the search (X at machine 0, 5, 10) are not
/// latched: the probe is not armed then. That drive position becomes coordinate 0, so after
/// homing every kernel position is the drive's position − 60 (X) and − 120 (Z), exactly; the
/// axes stand just below the mark, 2 interpolation ticks' travel at the MCZ speed. Then PART1
/// runs its cycle as on the plant, and the replay is exact.
#[test]
fn the_lathe_homes_x_and_z_on_drives_from_the_switch_and_the_touch_probe() {
    let _serial = e2e_common::serial();
    let m = unreferenced_lathe();
    let trace = m.path().join("home.jsonl");
    let out = Ncplc::run(m.path())
        .args(["--io", "canopen"])
        .virtual_time()
        .program("PART1")
        .until_end()
        .record(&trace)
        .output();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("cycle time 41.44 s (ticks 1503..5647), ended\n"),
        "{text}"
    );
    assert!(!text.contains("alarm: process"), "{text}");
    let t = std::fs::read_to_string(&trace).expect("trace");
    let recs = records(&t);
    for (axis, edge_counts, mark, letter) in
        [('X', 637_000, 60.0, "1X"), ('Z', 1_270_000, 120.0, "1Z")]
    {
        let samples: Vec<(u64, Sample)> = recs
            .iter()
            .filter_map(|(t, _, d)| d.iter().find(|(a, _)| *a == axis).map(|(_, s)| (*t, *s)))
            .filter(|(_, s)| !s.last.is_nan())
            .collect();
        // 60FDh bit 2 is the switch: set exactly while the drive stands at or above the edge
        // (machine 13.7 = drive 63.7 mm; 27 = drive 127 mm), until homing moves the axis off.
        let pressed: Vec<u64> = samples
            .iter()
            .filter(|(_, s)| s.inputs & 4 != 0)
            .map(|(t, _)| *t)
            .collect();
        assert!(!pressed.is_empty(), "{axis}: the switch was never pressed");
        for (t, s) in &samples {
            let counts = (s.last * 10_000.0).round() as i64;
            assert_eq!(
                s.inputs & 4 != 0,
                counts >= edge_counts,
                "{axis} at tick {t}: {s:?}"
            );
        }
        // The probe stored exactly the mark's drive position, once, after the switch was left.
        let stored: Vec<&(u64, Sample)> = samples
            .iter()
            .filter(|(_, s)| s.probe_status & 2 != 0)
            .collect();
        assert_eq!(stored.len(), 1, "{axis}: {stored:?}");
        let (at, latch) = *stored[0];
        assert_eq!(latch.probe, Some(mark), "{axis}");
        assert_eq!(latch.probe_status, 3, "{axis}");
        assert!(at > *pressed.last().expect("pressed"), "{axis}");
        // Armed (status 1) from leaving the switch until the latch, disarmed after it.
        let armed = samples
            .iter()
            .filter(|(t, s)| s.probe_status == 1 && *t < at)
            .count();
        assert!(armed > 0, "{axis}");
        assert!(samples.iter().all(|(t, s)| *t <= at || s.probe_status == 0));
        // After homing every recorded kernel position is the drive's − the mark, exactly.
        let homed: Vec<(u64, f64, f64)> = recs
            .iter()
            .filter(|(t, _, _)| *t > at + 1 && *t < 1500)
            .filter_map(|(t, p, d)| {
                let pos = p.iter().find(|(a, _)| a == letter)?.1;
                let drive = d.iter().find(|(a, _)| *a == axis)?.1.last;
                Some((*t, pos, drive))
            })
            .collect();
        assert!(!homed.is_empty(), "{axis}");
        for (t, pos, drive) in &homed {
            assert_eq!(*pos, drive - mark, "{axis} at tick {t}");
        }
        // At rest just below the mark: 2 interpolation ticks of 2 ms at the MCZ speed, 200
        // mm/min of Z's slide, 400 of X's diameter (0.0133 and 0.0067 per tick), ± a count.
        let (_, rest, _) = *homed.last().expect("homed");
        let want = if axis == 'X' { -0.1333 } else { -0.0667 };
        assert!((rest - want).abs() < 1.5e-4, "{axis} rests at {rest}");
    }
    // The replay gives the recorded switch and probe to its kernel: identical, no bus.
    let out = ncplc(&["replay", s(m.path()), s(&trace)]);
    let r =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{r}");
    assert!(
        r.contains("outputs identical, kernel signals and axis positions identical"),
        "{r}"
    );
}
