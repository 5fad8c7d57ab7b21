//! End to end: the servo loop as the manual defines it (issue 21). A new user's lathe — both
//! axes at 12 m/min rapid with KV 20 (a steady lag of v/KV = 10 mm without feed-forward) and
//! `SRV=.5,2,10` — runs PART1 in AUTO to M30 without a following-error alarm: programmed moves run
//! with velocity feed-forward (Kvff 1) and are checked against SRV's VFF limit (2 mm). The same
//! axis jogged at that speed in MANU has no feed-forward and is checked against the no-VFF limit.

use std::path::Path;

use crate::e2e_common;
use e2e_common::{copy_dir, ncplc, root};

/// A copy of the lathe with `edits` (from, to) applied to the bytes of its AXCFIL (not UTF-8:
/// its comments are in the Russian code page).
fn lathe_with_axcfil(edits: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let path = dir.path().join("MP0/AXCFIL");
    let mut bytes = std::fs::read(&path).expect("AXCFIL");
    for (from, to) in edits {
        let at = bytes
            .windows(from.len())
            .position(|w| w == from.as_bytes())
            .unwrap_or_else(|| panic!("AXCFIL has {from:?}"));
        bytes.splice(at..at + from.len(), to.bytes());
    }
    std::fs::write(&path, bytes).expect("write AXCFIL");
    dir
}

/// X at Z's rapid: RAP 12 000 mm/min, GM0 12 000 mm/min at KV 20; both keep `SRV=.5,2,10`.
const NEW_USER: &[(&str, &str)] = &[
    ("RAP=10000,800\r\n", "RAP=12000,800\r\n"),
    ("GM0=10000,7.5,20,,\r\n", "GM0=12000,7.5,20,,\r\n"),
];

fn part1(machine: &Path) -> (Option<i32>, String) {
    let out = ncplc(&[
        "run".as_ref(),
        machine.as_os_str(),
        "--virtual-time".as_ref(),
        "--no-watch".as_ref(),
        "--program".as_ref(),
        "PART1".as_ref(),
        "--until-end".as_ref(),
        "--stats".as_ref(),
    ]);
    (
        out.status.code(),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    )
}

/// The summary's per-axis following error: `(axis, mm, limit text)`.
fn peaks(text: &str) -> Vec<(char, f64, String)> {
    let line = text
        .lines()
        .find(|l| l.starts_with("process 1:"))
        .expect("process 1 summary");
    let list = line
        .split("largest following error ")
        .nth(1)
        .expect("following error");
    list.split(", ")
        .map(|item| {
            let (axis, rest) = item.split_once(' ').expect("axis");
            let (mm, limit) = rest.split_once(" mm (").expect("mm");
            (
                axis.chars().next().expect("letter"),
                mm.parse().expect("number"),
                limit.trim_end_matches(')').to_string(),
            )
        })
        .collect()
}

#[test]
fn a_new_users_lathe_at_12_m_min_and_kv_20_runs_part1_without_a_false_alarm() {
    let m = lathe_with_axcfil(NEW_USER);
    let (code, text) = part1(m.path());
    assert_eq!(code, Some(0), "{text}");
    assert!(!text.contains("alarm"), "{text}");
    assert!(text.contains("cycle time "), "{text}");
    // Kvff 1, no FQF: the drives follow the set points exactly (e∞ = (s − Kvff·s)/KV = 0).
    assert_eq!(
        peaks(&text),
        [
            ('X', 0.0, "SRV stand-by 0.5 mm".to_string()),
            ('Z', 0.0, "SRV stand-by 0.5 mm".to_string())
        ],
        "{text}"
    );
}

#[test]
fn with_fqf_the_acceleration_lag_stays_below_a_tenth_of_v_over_kv() {
    // FQF 20 Hz on both axes: while accelerating at 800 mm/s² the filtered feed-forward lags by
    // at most a·dt·p/(1 − p) = 5.600 mm/s (p = e^(−2π·20·0.002)), so e ≤ 5.600/20 = 0.280 mm,
    // against the VFF limit 2 mm; the target is 0.1 × v/KV = 1 mm. X is a diameter axis:
    // its set points and errors are diameters, twice the slide's: ≤ 0.560 mm.
    let edits: Vec<(&str, &str)> = NEW_USER
        .iter()
        .copied()
        .chain([
            (
                "GM0=12000,7.5,20,,\r\nLO1=5,-180,2",
                "GM0=12000,7.5,20,,\r\nFQF=20\r\nLO1=5,-180,2",
            ),
            (
                "GM0=12000,7.5,20,,\r\nLO1=5,-600,2",
                "GM0=12000,7.5,20,,\r\nFQF=20\r\nLO1=5,-600,2",
            ),
        ])
        .collect();
    let m = lathe_with_axcfil(&edits);
    let (code, text) = part1(m.path());
    assert_eq!(code, Some(0), "{text}");
    assert!(!text.contains("alarm"), "{text}");
    for (axis, mm, limit) in peaks(&text) {
        let bound = if axis == 'X' { 0.560 } else { 0.280 };
        assert!(mm > 0.0 && mm <= bound, "{axis} {mm}: {text}");
        assert_eq!(limit, "SRV VFF 2 mm", "{axis}: {text}");
    }
}

#[test]
fn with_uep_1_the_same_part_lags_v_over_kv_and_stops_at_the_no_vff_limit() {
    // PGCFIL ASS=UEP,1: no feed-forward; the rapids lag up to 10 mm (v/KV), which the no-VFF
    // limit lowered to 9 mm does not allow.
    let m = lathe_with_axcfil(&[
        NEW_USER[0],
        NEW_USER[1],
        ("SRV=.5,2,10\r\n", "SRV=.5,2,9\r\n"),
        ("SRV=.5,2,10\r\n", "SRV=.5,2,9\r\n"),
    ]);
    let pg = m.path().join("MP0/PGCFIL");
    let text = std::fs::read(&pg).expect("PGCFIL");
    let at = text
        .windows(10)
        .position(|w| w == b"ASS=USO,1\n")
        .expect("section 4's ASS=USO")
        + 10;
    std::fs::write(&pg, [&text[..at], b"ASS=UEP,1\n", &text[at..]].concat()).expect("write");
    let (code, out) = part1(m.path());
    assert_eq!(code, Some(1), "{out}");
    // Z's rapid accelerates at 800 mm/s²: the lag's target s/KV grows by 800·0.002/20 = 0.08 mm
    // per tick, so the first tick beyond 9 mm shows at most 9.08 mm: 9.033.
    assert!(
        out.contains(
            "alarm: process 1: following error of axis Z: 9.033 mm exceeds SRV no-VFF limit 9 mm (moving without feed-forward)\n"
        ),
        "{out}"
    );
}

#[test]
fn a_jog_at_12_m_min_has_no_feed_forward_and_alarms_beyond_the_no_vff_limit() {
    // Z jogs at MAN 12 000 mm/min (acceleration 200 mm/s²): its lag s/KV rises towards
    // 200/20 = 10 mm, beyond the no-VFF limit lowered to 9.5 mm. The panel switch I1A1 selects
    // MANU (MODEREQ 4) and holds JOGM2 once the MDI block has ended. At 200 mm/s² the lag's
    // target s/KV grows by 200·0.002/20 = 0.02 mm per 2 ms tick, so the first tick beyond 9.5 mm
    // shows at most 9.52 mm: 9.506.
    let m = lathe_with_axcfil(&[
        NEW_USER[0],
        NEW_USER[1],
        (
            "SRV=.5,2,10\r\nMAN=2000,200\r\nGM0=12000,7.5,20,,\r\nLO1=5,-600,2",
            "SRV=.5,2,9.5\r\nMAN=12000,200\r\nGM0=12000,7.5,20,,\r\nLO1=5,-600,2",
        ),
    ]);
    let plc = m.path().join("MP0/PLCPRG");
    let text = std::fs::read_to_string(&plc).expect("PLCPRG");
    let end = text.rfind('$').expect("the closing $");
    std::fs::write(
        &plc,
        format!(
            "{}IF I1A1 THEN\n  MODEREQ = 4\nEND_IF\nJOGM2 = I1A1\n{}",
            &text[..end],
            &text[end..]
        ),
    )
    .expect("write PLCPRG");
    let sim = m.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    std::fs::write(
        &sim,
        text + "\n[[part.at]]\ntick = 300\nset = { I1A1 = 1 }\n",
    )
    .expect("write");
    let out = ncplc(&[
        "run".as_ref(),
        m.path().as_os_str(),
        "--virtual-time".as_ref(),
        "--no-watch".as_ref(),
        "--mdi".as_ref(),
        "N1 G00 X-10 Z-5".as_ref(),
        "--ticks".as_ref(),
        "700".as_ref(),
    ]);
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("alarm: process 1: following error of axis Z: 9.506 mm exceeds SRV no-VFF limit 9.5 mm (moving without feed-forward)\n"),
        "{text}"
    );
}
