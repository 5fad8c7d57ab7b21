//! The runtime's side of the web HMI (`ncplc run --hmi`): starts the `hmi` server, answers its
//! requests at tick boundaries (writes and forces go into the scheduler's [`crate::force::Forces`],
//! commands to the [`hmi::Cnc`]) and publishes a [`Snapshot`] at most every 25 ms (≥ 20 Hz) into a
//! latest-value channel, so the scan never waits for a browser.

pub mod alarms;
pub mod catalog;
pub mod image_cnc;
pub mod kernel_cnc;

use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

use hmi::{Cnc, Command, Envelope, Request, ScanStats, ServerConfig, SharedSnapshot, Snapshot};
use tokio::sync::watch;

use self::alarms::AlarmList;
use crate::online::Note;
use crate::scheduler::{Event, Scheduler};

/// How often a snapshot is published (40 Hz).
pub const PUBLISH_EVERY: Duration = Duration::from_millis(25);

/// A running HMI and what the scan keeps for it.
pub struct HmiLink {
    /// The server.
    pub running: hmi::Running,
    snapshots: watch::Sender<SharedSnapshot>,
    requests: mpsc::Receiver<Envelope>,
    cnc: Box<dyn Cnc>,
    last_publish: Option<Instant>,
    tick_ms: u32,
    alarms: AlarmList,
    process_alarms: Vec<(u8, AlarmList)>,
    online: String,
}

impl HmiLink {
    /// Starts the server for `catalog`, with `cnc` behind the Machine page.
    pub fn start(
        config: ServerConfig,
        catalog: hmi::Catalog,
        cnc: Box<dyn Cnc>,
        tick_ms: u32,
    ) -> Result<HmiLink, hmi::StartError> {
        let (snap_tx, snap_rx) = watch::channel(Arc::new(Snapshot::default()));
        let (req_tx, req_rx) = mpsc::channel();
        let running = hmi::start(config, catalog, snap_rx, req_tx)?;
        Ok(HmiLink {
            running,
            snapshots: snap_tx,
            requests: req_rx,
            cnc,
            last_publish: None,
            tick_ms,
            alarms: AlarmList::default(),
            process_alarms: Vec::new(),
            online: "running".into(),
        })
    }

    /// Keeps the machine-wide alarm list and the online-change status up to date (`tick`: the
    /// tick the event happened at).
    pub fn on_event(&mut self, ev: &Event, tick: u64) {
        match ev {
            Event::Alarm(a) if self.cnc.owns_alarm(a) => {}
            Event::Alarm(a) => self.alarms.raise(a, tick),
            Event::Cleared(a) => self.alarms.clear(a),
            Event::Swapped { tick, .. } => self.online = format!("running since tick {tick}"),
        }
    }

    /// Keeps the online-change status up to date.
    pub fn on_note(&mut self, note: &Note) {
        self.online = match note {
            Note::Compiled { .. } => "compiled; swapping at the next tick".into(),
            Note::Rejected { diagnostics } => format!("edit refused:\n{diagnostics}"),
            Note::Error(e) => format!("online change: {e}"),
        };
    }

    /// At a tick boundary: applies the pending requests, then publishes when due.
    pub fn service(&mut self, sched: &mut Scheduler) {
        let applied_at = sched.tick_count();
        let pending: Vec<Envelope> = self.requests.try_iter().collect();
        for env in pending {
            let forces = sched.forces_mut();
            let reply = match &env.request {
                Request::Write(s, v) => {
                    forces.write_once(*s, *v);
                    Ok(applied_at)
                }
                Request::Force(s, v) => {
                    forces.force(*s, *v);
                    Ok(applied_at)
                }
                Request::Unforce(s) => {
                    if forces.unforce(s) {
                        Ok(applied_at)
                    } else {
                        Err(format!("{s} is not forced"))
                    }
                }
                Request::UnforceAll => {
                    forces.unforce_all();
                    Ok(applied_at)
                }
                Request::Command {
                    process,
                    command: Command::Ack,
                } => {
                    self.acknowledge(*process);
                    Ok(applied_at)
                }
                Request::Command { process, command } => {
                    self.cnc.command(*process, command).map(|()| applied_at)
                }
            };
            let _ = env.reply.send(reply);
        }
        self.cnc
            .after_tick(&sched.image().bytes()[..packets::PACKETS_LEN]);
        let due = self
            .last_publish
            .is_none_or(|t| t.elapsed() >= PUBLISH_EVERY);
        if due {
            self.last_publish = Some(Instant::now());
            self.publish(sched);
        }
    }

    /// Acknowledges the alarms of `process` (0: every process and the machine-wide ones); see
    /// [`alarms`] for what that means.
    fn acknowledge(&mut self, process: u8) {
        if process == 0 {
            self.alarms.acknowledge();
        }
        for (p, list) in &mut self.process_alarms {
            if process == 0 || *p == process {
                list.acknowledge();
            }
        }
    }

    /// Publishes the current state now.
    pub fn publish(&mut self, sched: &Scheduler) {
        let image = &sched.image().bytes()[..packets::PACKETS_LEN];
        let tick = sched.tick_count();
        let mut machine = self.cnc.status(image);
        for ps in &mut machine.processes {
            let active: Vec<String> = ps.alarms.drain(..).map(|a| a.text).collect();
            let list = match self
                .process_alarms
                .iter_mut()
                .position(|(p, _)| *p == ps.process)
            {
                Some(i) => &mut self.process_alarms[i].1,
                None => {
                    self.process_alarms.push((ps.process, AlarmList::default()));
                    let last = self.process_alarms.len() - 1;
                    &mut self.process_alarms[last].1
                }
            };
            list.sync(&active, tick);
            ps.alarms = list.entries().to_vec();
        }
        let snap = Snapshot {
            tick: sched.tick_count(),
            engine: sched.engine_name().to_string(),
            tick_ms: self.tick_ms,
            scan: ScanStats {
                scan_p50_us: sched.stats.scan.value_at_quantile(0.5) as f64 / 1e3,
                scan_max_us: sched.stats.scan.max() as f64 / 1e3,
                overruns: sched.stats.overruns,
            },
            image: image.to_vec(),
            forced: sched.forces().forced().to_vec(),
            alarms: self.alarms.entries().to_vec(),
            online: self.online.clone(),
            machine,
            tripped: sched.tripped(),
            toolpaths: self.cnc.toolpaths(),
        };
        self.snapshots.send_replace(Arc::new(snap));
    }
}
