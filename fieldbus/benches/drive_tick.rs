//! The master's per-tick drive logic without I/O (`DriveSet`) for four axes and a spindle: the
//! RPDOs of one tick's commands (with the axes' RPDO2), the drives' TPDO answers (TPDO1–3 of an
//! axis, TPDO1 of the spindle), the after-SYNC checks (issue 21's budget
//! for kernel + drives is 20 µs p99 per tick; this is the drives' part, bus time excluded).

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use fieldbus::canopen::CanMsg;
use fieldbus::canopen::drive::{AxisId, DriveCommand, DriveSet};
use fieldbus::map::{CanDrive, DriveMode};
use tokio::time::Instant;

fn bench(c: &mut Criterion) {
    let drives: Vec<CanDrive> = [('X', 3), ('Y', 4), ('Z', 5), ('A', 6), ('S', 7)]
        .iter()
        .map(|&(axis, node_id)| CanDrive {
            process: 1,
            axis,
            node_id,
            counts_per_unit: 10_000.0,
            mode: if axis == 'S' {
                DriveMode::Csv
            } else {
                DriveMode::Csp
            },
            heartbeat: Duration::from_secs(3600),
            sdo: Vec::new(),
            simulate: Default::default(),
            span: 0..0,
            homing: true,
        })
        .collect();
    let mut set = DriveSet::new(&drives, Duration::from_millis(1));
    let now = Instant::now();
    set.started(now, &[0x0237; 5]);
    let axes: Vec<AxisId> = set.axes().collect();
    // TPDO1 of every drive; a `csp` drive also answers with TPDO2 (touch probe) and TPDO3
    // (digital inputs).
    let answers: Vec<CanMsg> = drives
        .iter()
        .flat_map(|d| {
            let id = u16::from(d.node_id);
            let mut v = vec![CanMsg::new(0x180 + id, &[0x37, 0x02, 1, 2, 3, 0])];
            if d.mode == DriveMode::Csp {
                v.push(CanMsg::new(0x280 + id, &[0; 6]));
                v.push(CanMsg::new(0x380 + id, &[0; 4]));
            }
            v
        })
        .collect();
    let mut n = 0.0f64;
    c.bench_function("drive_tick_5_drives", |b| {
        b.iter(|| {
            n += 0.001;
            for a in &axes {
                set.command(
                    *a,
                    DriveCommand {
                        set_point: n,
                        enable: true,
                        ..DriveCommand::default()
                    },
                );
            }
            let out = set.rpdos(now);
            for m in &answers {
                std::hint::black_box(set.on_frame(m, now));
            }
            set.after_sync(now);
            std::hint::black_box(out.len())
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
