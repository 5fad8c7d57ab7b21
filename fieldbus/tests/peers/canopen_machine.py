"""Every CANopen node of ncplc's lathe, built on python-canopen LocalNodes, on one cannelloni link.

The independent peer of tests/e2e/drives_peer.rs: `ncplc run` of a copy of the lathe whose io.toml
says `transport = "cannelloni"` runs a part through its master against these nodes, in real time.

Usage:
  canopen_machine.py LOCAL_PORT REMOTE_PORT START_AT START_LEN
        prints "ready" once the nodes listen, serves the bus until stdin closes, then prints one
        JSON line per SYNC (what every RPDO carried, what every node answered) and a last line
        {"end": ...} with the totals.

The nodes (as plc-programs/lathe/io.toml declares them):
  node 2  the CiA 401 I/O module "dio1": object dictionary 1000h (000F0191h), 1017h, 6000h
          (8 input bytes, TPDO1 = 182h) and 6200h (8 output bytes, RPDO1 = 202h), both every SYNC.
          Its input terminals are the panel: the power-on contacts (I0A0, I0A1, I0A2, I0A7, I0A8,
          I1A0) from the first SYNC on, CYCLE START (I0A3) from SYNC START_AT for START_LEN SYNCs;
          the outputs (OU4, OU5) are logged as they are applied at each SYNC.
  node 3  X, node 4  Z: CiA 402 drives in cyclic synchronous position (the dictionary of
          canopen_peer.drive_od, which ncplc's master maps by SDO): this script's own power state
          machine; in Operation enabled the position actual follows the target of the same SYNC.
  node 5  S: a CiA 402 drive in cyclic synchronous velocity: its velocity actual (606Ch) follows
          the target with a ramp of ACCEL counts/s per SYNC (towards 0 while not enabled).

Each SYNC is answered at once, from the SYNC callback: the RPDOs received since the last SYNC are
applied and every node's TPDOs go out together in one datagram. Counting starts at SYNC 1.
A line: {"n": n, "X": [controlword, target, probe function, statusword, actual], "Z": [...],
"S": [controlword, target, statusword, actual], "io": [outputs applied (hex), inputs sent (hex)]};
an RPDO that did not come before the SYNC is null.
"""

import json
import os
import sys
import threading
import time

import canopen
from canopen import objectdictionary as odm

from canopen_peer import SW, CannelloniBus, drive_od, pdo_records, step, var

IO_NODE = 2
CSP = {"X": 3, "Z": 4}
CSV = {"S": 5}
# The panel's power-on contacts: I0A0, I0A1, I0A2, I0A7 (byte 0), I0A8 (byte 1), I1A0 (byte 4).
POWER = bytes([0x87, 0x01, 0, 0, 0x01, 0, 0, 0])
CYCLE_START = 0x08  # I0A3, byte 0
# The spindle drive's ramp: 300 counts/s per SYNC of 2 ms (4096 counts per revolution: about
# 2200 rev/min per second).
ACCEL = 300


class BatchBus(CannelloniBus):
    """A cannelloni bus that, while a SYNC is answered, collects that thread's frames into one
    datagram (other threads, the heartbeat producers, send at once)."""

    def __init__(self, local, remote):
        super().__init__(local, remote)
        self.batch = None
        self.holder = None

    def begin(self):
        self.batch, self.holder = [], threading.get_ident()

    def send(self, msg, timeout=None):
        if self.batch is not None and threading.get_ident() == self.holder:
            self.batch.append(msg)
        else:
            self.send_frames([msg])

    def flush(self):
        frames, self.batch, self.holder = self.batch, None, None
        if frames:
            self.send_frames(frames)


def io_od(node):
    """The CiA 401 module's dictionary: 8 input and 8 output bytes on PDO 1."""
    od = odm.ObjectDictionary()
    od.node_id = node
    od.add_object(var("Device type", 0x1000, 0, odm.UNSIGNED32, "ro", 0x000F0191))
    od.add_object(var("Producer heartbeat time", 0x1017, 0, odm.UNSIGNED16, "rw", 0))
    for index, name, access in ((0x6000, "Input", "ro"), (0x6200, "Output", "rw")):
        rec = odm.ODRecord(f"{name} bytes", index)
        rec.add_member(var("Highest sub-index", index, 0, odm.UNSIGNED8, "ro", 8))
        for i in range(1, 9):
            rec.add_member(var(f"{name} {i}", index, i, odm.UNSIGNED8, access))
        od.add_object(rec)
    pdo_records(od, 0x1400, 0x1600, 0x200 + node, [0x62000008 + (i << 8) for i in range(1, 9)])
    pdo_records(od, 0x1800, 0x1A00, 0x180 + node, [0x60000008 + (i << 8) for i in range(1, 9)])
    return od


class Machine:
    """The four LocalNodes and what each SYNC brought and was answered."""

    def __init__(self, network, bus, start_at, start_len):
        self.bus, self.start_at, self.start_len = bus, start_at, start_len
        self.lock = threading.Lock()
        self.nodes = {}
        for axis, node in {**CSP, **CSV}.items():
            self.nodes[axis] = canopen.LocalNode(node, drive_od(node))
        self.nodes["io"] = canopen.LocalNode(IO_NODE, io_od(IO_NODE))
        for n in self.nodes.values():
            network.add_node(n)
            n.nmt.state = "PRE-OPERATIONAL"
        self.state = {a: "SOD" for a in (*CSP, *CSV)}
        self.actual = {a: 0 for a in (*CSP, *CSV)}
        self.pending = {}
        self.mapped = set()
        self.outputs = bytes(8)
        self.syncs = 0
        self.log = []
        self.late = []  # per SYNC: µs from the SYNC callback's start to the answers' datagram
        for a in (*CSP, *CSV):
            self.nodes[a].sdo[0x6041].raw = SW["SOD"]
        network.subscribe(0x80, self.on_sync)
        network.subscribe(0, self.on_nmt)

    def on_nmt(self, can_id, data, timestamp):
        """NMT start: the master has mapped the PDOs by SDO; take the dictionary's configuration."""
        if len(data) < 2 or data[0] != 0x01:
            return
        with self.lock:
            for key, n in self.nodes.items():
                if data[1] not in (0, n.id) or key in self.mapped:
                    continue
                self.mapped.add(key)
                n.rpdo.read()
                n.tpdo.read()
                n.rpdo[1].add_callback(lambda pdo, key=key: self.on_rpdo(key, 1, pdo))
                if key in CSP:
                    n.rpdo[2].add_callback(lambda pdo, key=key: self.on_rpdo(key, 2, pdo))

    def on_rpdo(self, key, number, pdo):
        with self.lock:
            if key == "io":
                self.pending["io"] = bytes(pdo.data)
            elif number == 1:
                target = "Target position" if key in CSP else "Target velocity"
                self.pending[key] = (pdo["Controlword"].raw, pdo[target].raw)
            else:
                self.pending[key + "probe"] = pdo["Touch probe function"].raw

    def on_sync(self, can_id, data, timestamp):
        began = time.perf_counter()
        with self.lock:
            self.bus.begin()
            try:
                self.syncs += 1
                line = {"n": self.syncs}
                for axis in (*CSP, *CSV):
                    line[axis] = self.drive(axis)
                line["io"] = self.io()
                self.log.append(line)
            finally:
                self.bus.flush()
            self.late.append(int((time.perf_counter() - began) * 1e6))

    def drive(self, axis):
        node = self.nodes[axis]
        cw, target = self.pending.pop(axis, (None, None))
        if node.nmt.state != "OPERATIONAL":
            return [cw, target, None, None, None] if axis in CSP else [cw, target, None, None]
        if cw is not None:
            self.state[axis] = step(self.state[axis], cw)
        enabled = self.state[axis] == "OE"
        sw = SW[self.state[axis]]
        tpdo = node.tpdo[1]
        tpdo["Statusword"].raw = sw
        if axis in CSP:
            if enabled and target is not None:
                self.actual[axis] = target
            probe = self.pending.pop(axis + "probe", None)
            tpdo["Position actual value"].raw = self.actual[axis]
            tpdo.transmit()
            node.tpdo[2]["Touch probe status"].raw = (probe or 0) & 1
            node.tpdo[2]["Touch probe pos1 pos value"].raw = 0
            node.tpdo[2].transmit()
            node.tpdo[3]["Digital inputs"].raw = 0
            node.tpdo[3].transmit()
            return [cw, target, probe, sw, self.actual[axis]]
        want = target if enabled and target is not None else 0
        v = self.actual[axis]
        self.actual[axis] = v + max(-ACCEL, min(ACCEL, want - v))
        tpdo["Velocity actual value"].raw = self.actual[axis]
        tpdo.transmit()
        return [cw, target, sw, self.actual[axis]]

    def io(self):
        node = self.nodes["io"]
        applied = self.pending.pop("io", None)
        if applied is not None:
            self.outputs = applied
        inputs = bytearray(POWER)
        if self.start_at <= self.syncs < self.start_at + self.start_len:
            inputs[0] |= CYCLE_START
        if node.nmt.state != "OPERATIONAL":
            return [None if applied is None else applied.hex(), None]
        tpdo = node.tpdo[1]
        for i, b in enumerate(inputs):
            tpdo[i].raw = b
        tpdo.transmit()
        return [None if applied is None else applied.hex(), inputs.hex()]


def main():
    local, remote, start_at, start_len = (int(a) for a in sys.argv[1:5])
    # The nodes stand for devices with processors of their own: where permitted, the script
    # (every thread it starts) runs before the machine's other work — a shared machine's
    # compilers — at a low real-time priority (below ncplc's scan and I/O threads), else niced.
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(10))
        priority = "fifo 10"
    except (OSError, AttributeError):
        try:
            os.nice(-10)
        except OSError:
            pass
        priority = f"nice {os.nice(0)}"
    bus = BatchBus(local, remote)
    network = canopen.Network(bus)
    network.connect()
    machine = Machine(network, bus, start_at, start_len)
    print("ready", flush=True)
    try:
        sys.stdin.read()
    finally:
        with machine.lock:
            network.disconnect()
            log, late = list(machine.log), sorted(machine.late)
    for line in log:
        print(json.dumps(line))
    pct = (lambda q: late[min(len(late) - 1, int(q * len(late)))]) if late else (lambda q: None)
    print(json.dumps({"end": {"syncs": len(log), "priority": priority, "answer_us": {
        "p50": pct(0.5), "p99": pct(0.99), "max": late[-1] if late else None}}}), flush=True)


if __name__ == "__main__":
    main()
