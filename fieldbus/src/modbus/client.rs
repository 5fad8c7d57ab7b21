//! The Modbus TCP remote-I/O client driver: one task per device, images exchanged lock-free.
//!
//! Each device gets its own tasks on the driver's private tokio runtime, each with its own connection
//! (`TCP_NODELAY`). The read task loops: read every input mapping, publish the input frame, wait
//! for the poll interval. Writes go over a connection of their own ([`ModbusDevice::write_connection`],
//! the default), so a write never waits behind a read already on the wire, and the scan thread
//! sends them itself when that connection is idle: one non-blocking `send` of the first changed
//! output mapping, with the write task reading the answer and doing everything that could wait
//! ([`crate::modbus::writer`]). With `write_connection = false` one task does both on one
//! connection, writing changed outputs before each read. Every request is timed out; any failure
//! drops that connection (a late answer would desynchronise the transaction ids) and reconnects
//! with exponential backoff. Outputs are written only from frames the scan published, so the device
//! never receives a value the logic did not command; after a reconnect the last commanded values
//! are written again.
//!
//! The scan side ([`ModbusIo`]) only touches triple buffers, atomics, a `try_lock` and at most one
//! non-blocking `send` per device and tick: [`PacketIo::latch_inputs`] copies each device's newest
//! consistent input frame (or its fail state while the device is lost, see [`crate::health`]; a
//! fault of either connection counts) and sets its healthy bit; [`PacketIo::publish_outputs`] hands
//! over changed outputs and puts the write on the wire or wakes the task that writes them.

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicU8, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use packets::{IoAlarm, PacketIo};
use tokio::sync::Notify;
use tokio_modbus::Slave;
use tokio_modbus::client::{Context, Reader, Writer};

use crate::exchange::{OutFrame, TripleReader, TripleWriter, triple};
use crate::health::{Fault, Health};
use crate::map::{ModbusArea, ModbusDevice, ModbusMapping};
use crate::modbus::writer::{WriteLink, WriteTask};
use crate::modbus::{bits_to_bytes, bytes_to_bits, bytes_to_regs, regs_to_bytes};
use crate::rt::IoThreads;
use crate::tick_io::{A_LEN, latch_device, queue_alarm, safe_image, take_changed_outputs};

/// One device's newest input image as the task read it.
#[derive(Debug, Clone)]
pub(crate) struct InFrame {
    /// Bumped after every complete, good read of all input mappings.
    pub seq: u64,
    /// Why the last exchange failed (`Fault::None` when it did not).
    pub fault: Fault,
    /// Packet A as far as this device's input mappings fill it.
    pub data: [u8; A_LEN],
}

struct DeviceSide {
    cfg: ModbusDevice,
    health: Health,
    inputs: TripleReader<InFrame>,
    outputs: TripleWriter<OutFrame>,
    wake: Arc<Notify>,
    acked: Arc<AtomicU64>,
    /// The write connection's fault ([`Fault::code`]); `Fault::None` in single-connection mode.
    write_fault: Arc<AtomicU8>,
    /// The write connection, shared with its task (None in single-connection mode).
    link: Option<Arc<WriteLink>>,
    out_seq: u64,
    last_out: [u8; A_LEN],
}

/// The Modbus TCP client driver (implements [`PacketIo`]).
pub struct ModbusIo {
    runtime: Option<tokio::runtime::Runtime>,
    threads: IoThreads,
    devices: Vec<DeviceSide>,
    alarms: Vec<IoAlarm>,
}

impl ModbusIo {
    /// Starts one task per device on a private runtime; fails only when the runtime cannot start.
    pub fn start(devices: &[ModbusDevice]) -> std::io::Result<ModbusIo> {
        ModbusIo::start_pinned(devices, &[])
    }

    /// As [`ModbusIo::start`], the runtime's threads pinned to `io_cpus` (empty = unpinned; a
    /// refusal by the kernel is warned about once and ignored).
    pub fn start_pinned(devices: &[ModbusDevice], io_cpus: &[usize]) -> std::io::Result<ModbusIo> {
        let threads = IoThreads::pinned(io_cpus);
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .thread_name("ncplc-modbus")
            .on_thread_start(threads.on_start())
            .on_thread_stop(threads.on_stop())
            .enable_all()
            .build()?;
        let mut sides = Vec::new();
        for cfg in devices {
            // Validation guarantees these; a hand-built config must not make the scan panic.
            let mut cfg = cfg.clone();
            cfg.inputs
                .retain(|m| m.range.len > 0 && m.range.end() <= A_LEN);
            cfg.outputs.retain(|m| {
                m.range.len > 0
                    && m.range.end() <= A_LEN
                    && matches!(m.area, ModbusArea::Coils | ModbusArea::HoldingRegisters)
            });
            let cfg = &cfg;
            let (in_tx, in_rx) = triple(InFrame {
                seq: 0,
                fault: Fault::None,
                data: [0; A_LEN],
            });
            let (out_tx, out_rx) = triple(OutFrame {
                seq: 0,
                data: [0; A_LEN],
            });
            let wake = Arc::new(Notify::new());
            let acked = Arc::new(AtomicU64::new(0));
            let write_fault = Arc::new(AtomicU8::new(Fault::None.code()));
            let (outputs, link) = if cfg.write_connection && !cfg.outputs.is_empty() {
                let link = Arc::new(WriteLink::new(cfg.outputs.len()));
                let writer = WriteTask {
                    cfg: cfg.clone(),
                    outputs: out_rx,
                    link: link.clone(),
                    wake: wake.clone(),
                    acked: acked.clone(),
                    fault: write_fault.clone(),
                };
                runtime.spawn(writer.run());
                (None, Some(link))
            } else {
                (Some(out_rx), None)
            };
            let task = DeviceTask {
                cfg: cfg.clone(),
                inputs: in_tx,
                outputs,
                wake: wake.clone(),
                acked: acked.clone(),
                seq: 0,
            };
            runtime.spawn(task.run());
            sides.push(DeviceSide {
                cfg: cfg.clone(),
                health: Health::new(&cfg.name, cfg.alarm_ticks),
                inputs: in_rx,
                outputs: out_tx,
                wake,
                acked,
                write_fault,
                link,
                out_seq: 0,
                last_out: [0; A_LEN],
            });
        }
        Ok(ModbusIo {
            runtime: Some(runtime),
            threads,
            devices: sides,
            alarms: Vec::new(),
        })
    }

    /// True while device `name` answers (as of the last latch).
    pub fn is_healthy(&self, name: &str) -> bool {
        self.devices
            .iter()
            .any(|d| d.cfg.name == name && d.health.healthy())
    }

    /// The `SCHED_FIFO` priority the driver's I/O thread took below a real-time scan thread
    /// (see [`crate::rt`]), once it did.
    pub fn io_priority(&self) -> Option<i32> {
        self.threads.priority()
    }

    /// Whether the I/O threads are pinned (`None`: no CPUs given; `Some(false)`: refused).
    pub fn io_pinned(&self) -> Option<bool> {
        self.threads.is_pinned()
    }

    /// True when every device not declared lost has acknowledged the newest outputs published.
    pub fn outputs_acknowledged(&self) -> bool {
        self.devices
            .iter()
            .all(|d| d.health.lost() || d.acked.load(Ordering::Acquire) >= d.out_seq)
    }

    /// How many output writes to device `name` the scan thread put on the wire itself (see
    /// [`crate::modbus::writer`]); 0 without a write connection.
    pub fn direct_writes(&self, name: &str) -> u64 {
        self.devices
            .iter()
            .filter(|d| d.cfg.name == name)
            .filter_map(|d| d.link.as_ref())
            .map(|l| l.direct_sends())
            .sum()
    }

    fn hand_over(&mut self, packets: &[u8], force: bool) {
        for d in &mut self.devices {
            let ranges = d.cfg.outputs.iter().map(|m| m.range);
            let changed =
                take_changed_outputs(ranges, packets, &mut d.last_out) || force || d.out_seq == 0;
            if changed {
                d.out_seq += 1;
                let buf = d.outputs.buf();
                buf.seq = d.out_seq;
                buf.data = d.last_out;
                d.outputs.publish();
                match &d.link {
                    Some(link) => link.push(&d.cfg, d.out_seq, &d.last_out, &d.wake, &d.acked),
                    None => d.wake.notify_one(),
                }
            }
        }
    }
}

impl Drop for ModbusIo {
    fn drop(&mut self) {
        if let Some(rt) = self.runtime.take() {
            rt.shutdown_background();
        }
    }
}

impl PacketIo for ModbusIo {
    fn name(&self) -> &str {
        "modbus"
    }

    fn latch_inputs(&mut self, _tick: u64, packets: &mut [u8]) {
        self.threads.follow_scan();
        for d in &mut self.devices {
            let (frame, _) = d.inputs.read();
            let fault = match frame.fault {
                Fault::None => Fault::from_code(d.write_fault.load(Ordering::Acquire)),
                f => f,
            };
            let inputs = d.cfg.inputs.iter().map(|m| (m.range, m.fail));
            let alarm = latch_device(
                &mut d.health,
                frame.seq,
                fault,
                &frame.data,
                inputs,
                d.cfg.healthy,
                packets,
            );
            queue_alarm(&mut self.alarms, alarm);
        }
    }

    fn publish_outputs(&mut self, _tick: u64, packets: &[u8]) {
        self.hand_over(packets, false);
    }

    fn take_alarms(&mut self) -> Vec<IoAlarm> {
        std::mem::take(&mut self.alarms)
    }

    /// Commands every output mapping's `safe` value and waits (at most 4 request timeouts) until the
    /// devices not declared lost have acknowledged it.
    fn safe_state(&mut self) {
        let outputs = self
            .devices
            .iter()
            .flat_map(|d| d.cfg.outputs.iter().map(|m| (m.range, m.fail)));
        let image = safe_image(outputs);
        self.hand_over(&image, true);
        let wait = self
            .devices
            .iter()
            .map(|d| d.cfg.timeout * 4)
            .max()
            .unwrap_or_default();
        let deadline = Instant::now() + wait;
        while Instant::now() < deadline && !self.outputs_acknowledged() {
            std::thread::sleep(Duration::from_micros(200));
        }
    }
}

/// The network side of one device: its reads, and its writes too without a write connection.
struct DeviceTask {
    cfg: ModbusDevice,
    inputs: TripleWriter<InFrame>,
    /// The commanded outputs when this task also writes them (single-connection mode).
    outputs: Option<TripleReader<OutFrame>>,
    wake: Arc<Notify>,
    acked: Arc<AtomicU64>,
    seq: u64,
}

impl DeviceTask {
    async fn run(mut self) {
        let mut backoff = self.cfg.reconnect_min;
        loop {
            let fault = match connect(self.cfg.address, self.cfg.unit, self.cfg.timeout).await {
                Ok(mut ctx) => {
                    let fault = self.serve(&mut ctx, &mut backoff).await;
                    // A best-effort goodbye; the connection is dropped either way.
                    let _ = tokio::time::timeout(
                        self.cfg.timeout,
                        tokio_modbus::client::Client::disconnect(&mut ctx),
                    )
                    .await;
                    fault
                }
                Err(f) => f,
            };
            self.report(fault);
            tokio::time::sleep(backoff).await;
            backoff = (backoff * 2).min(self.cfg.reconnect_max);
        }
    }

    fn report(&mut self, fault: Fault) {
        let buf = self.inputs.buf();
        buf.seq = self.seq;
        buf.fault = fault;
        self.inputs.publish();
    }

    /// Exchanges with a connected device until something fails; returns the fault.
    async fn serve(&mut self, ctx: &mut Context, backoff: &mut Duration) -> Fault {
        // What the device holds per output mapping, as far as we know (None: unknown, rewrite).
        let mut written: Vec<Option<Vec<u8>>> = vec![None; self.cfg.outputs.len()];
        let mut data = [0u8; A_LEN];
        loop {
            if let Err(fault) = self.cycle(ctx, &mut written, &mut data).await {
                return fault;
            }
            *backoff = self.cfg.reconnect_min;
            if self.cfg.poll.is_zero() {
                // Back-to-back polling: tokio timers round up to whole milliseconds, so a zero
                // sleep would cost up to 1 ms; yield instead (outputs are checked every cycle).
                tokio::task::yield_now().await;
            } else if self.outputs.is_none() {
                tokio::time::sleep(self.cfg.poll).await;
            } else {
                tokio::select! {
                    () = self.wake.notified() => {}
                    () = tokio::time::sleep(self.cfg.poll) => {}
                }
            }
        }
    }

    /// One exchange: changed outputs first, then every input mapping, then publish the inputs.
    async fn cycle(
        &mut self,
        ctx: &mut Context,
        written: &mut [Option<Vec<u8>>],
        data: &mut [u8; A_LEN],
    ) -> Result<(), Fault> {
        if let Some(outputs) = self.outputs.as_mut() {
            let (out, _) = outputs.read();
            let (out_seq, out_data) = (out.seq, out.data);
            if out_seq > 0 {
                write_changed(ctx, &self.cfg, &out_data, written).await?;
                self.acked.store(out_seq, Ordering::Release);
            }
        }
        for m in &self.cfg.inputs {
            read_mapping(
                ctx,
                m,
                &mut data[m.range.start..m.range.end()],
                self.cfg.timeout,
            )
            .await?;
        }
        self.seq += 1;
        let buf = self.inputs.buf();
        buf.seq = self.seq;
        buf.fault = Fault::None;
        buf.data = *data;
        self.inputs.publish();
        Ok(())
    }
}

/// Writes the output mappings whose bytes differ from what the device is known to hold.
async fn write_changed(
    ctx: &mut Context,
    cfg: &ModbusDevice,
    out: &[u8; A_LEN],
    written: &mut [Option<Vec<u8>>],
) -> Result<(), Fault> {
    for (i, m) in cfg.outputs.iter().enumerate() {
        let want = &out[m.range.start..m.range.end()];
        if written[i].as_deref() == Some(want) {
            continue;
        }
        // Unknown until the device acknowledges: a failure here means "rewrite after reconnect".
        written[i] = None;
        write_mapping(ctx, m, want, cfg.timeout).await?;
        written[i] = Some(want.to_vec());
    }
    Ok(())
}

async fn connect(addr: SocketAddr, unit: u8, timeout: Duration) -> Result<Context, Fault> {
    let stream = match tokio::time::timeout(timeout, tokio::net::TcpStream::connect(addr)).await {
        Ok(Ok(s)) => s,
        Ok(Err(_)) | Err(_) => return Err(Fault::Connect),
    };
    let _ = stream.set_nodelay(true);
    Ok(tokio_modbus::client::tcp::attach_slave(stream, Slave(unit)))
}

type Nested<T> = Result<tokio_modbus::Result<T>, tokio::time::error::Elapsed>;

fn flatten<T>(r: Nested<T>) -> Result<T, Fault> {
    match r {
        Err(_) => Err(Fault::Timeout),
        Ok(Err(tokio_modbus::Error::Transport(_))) => Err(Fault::Io),
        Ok(Err(tokio_modbus::Error::Protocol(_))) => Err(Fault::Protocol),
        Ok(Ok(Err(_))) => Err(Fault::Exception),
        Ok(Ok(Ok(v))) => Ok(v),
    }
}

async fn read_mapping(
    ctx: &mut Context,
    m: &ModbusMapping,
    out: &mut [u8],
    timeout: Duration,
) -> Result<(), Fault> {
    let n = m.area.items(out.len()) as u16;
    match m.area {
        ModbusArea::DiscreteInputs | ModbusArea::Coils => {
            let bits = if m.area == ModbusArea::Coils {
                flatten(tokio::time::timeout(timeout, ctx.read_coils(m.address, n)).await)?
            } else {
                flatten(
                    tokio::time::timeout(timeout, ctx.read_discrete_inputs(m.address, n)).await,
                )?
            };
            if bits.len() < usize::from(n) {
                return Err(Fault::Protocol);
            }
            bits_to_bytes(&bits, out);
        }
        ModbusArea::InputRegisters | ModbusArea::HoldingRegisters => {
            let regs = if m.area == ModbusArea::InputRegisters {
                flatten(
                    tokio::time::timeout(timeout, ctx.read_input_registers(m.address, n)).await,
                )?
            } else {
                flatten(
                    tokio::time::timeout(timeout, ctx.read_holding_registers(m.address, n)).await,
                )?
            };
            if regs.len() != usize::from(n) {
                return Err(Fault::Protocol);
            }
            regs_to_bytes(&regs, out);
        }
    }
    Ok(())
}

async fn write_mapping(
    ctx: &mut Context,
    m: &ModbusMapping,
    bytes: &[u8],
    timeout: Duration,
) -> Result<(), Fault> {
    match m.area {
        ModbusArea::Coils => flatten(
            tokio::time::timeout(
                timeout,
                ctx.write_multiple_coils(m.address, &bytes_to_bits(bytes)),
            )
            .await,
        ),
        ModbusArea::HoldingRegisters => flatten(
            tokio::time::timeout(
                timeout,
                ctx.write_multiple_registers(m.address, &bytes_to_regs(bytes)),
            )
            .await,
        ),
        // Validation rejects outputs to read-only tables.
        ModbusArea::DiscreteInputs | ModbusArea::InputRegisters => Err(Fault::Protocol),
    }
}
