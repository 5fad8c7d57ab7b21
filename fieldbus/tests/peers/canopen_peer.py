"""Independent CANopen peer for fieldbus/tests/python_canopen.rs: python-canopen over cannelloni UDP.

Usage:
  canopen_peer.py master LOCAL_PORT REMOTE_PORT NODE   python-canopen's BaseNode402 drives the
        drive at NODE (ncplc's simulated CiA 402 drive) through the state machine and CSP targets;
        prints one JSON line with what it saw.
  canopen_peer.py node LOCAL_PORT REMOTE_PORT NODE SYNCS   a drive built on python-canopen's
        LocalNode (its SDO server and PDO handling; this script's own small state machine) that
        ncplc's master configures and drives; after SYNCS SYNCs prints one JSON line with the
        (controlword, target) of each SYNC.

The cannelloni format (version 2, DATA) is written here from its description, like the Rust side.
"""

import collections
import json
import socket
import struct
import sys
import threading
import time

import can
import canopen
from canopen import objectdictionary as odm


class CannelloniBus(can.BusABC):
    """A python-can bus exchanging cannelloni datagrams with one UDP peer on loopback."""

    def __init__(self, local_port, remote_port, **kwargs):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", local_port))
        self.remote = ("127.0.0.1", remote_port)
        self.seq = 0
        self.pending = collections.deque()
        self.lock = threading.Lock()
        super().__init__(channel="cannelloni", **kwargs)

    def send(self, msg, timeout=None):
        self.send_frames([msg])

    def send_frames(self, msgs):
        """Sends `msgs` in one datagram (the format carries any number of frames)."""
        body = b""
        for msg in msgs:
            cid = msg.arbitration_id
            if msg.is_extended_id:
                cid |= 0x80000000
            if msg.is_remote_frame:
                cid |= 0x40000000
            data = b"" if msg.is_remote_frame else bytes(msg.data)
            body += struct.pack(">IB", cid, msg.dlc if msg.is_remote_frame else len(data)) + data
        with self.lock:
            head = struct.pack(">BBBH", 2, 0, self.seq, len(msgs))
            self.seq = (self.seq + 1) & 0xFF
        self.sock.sendto(head + body, self.remote)

    def _recv_internal(self, timeout):
        if not self.pending:
            self.sock.settimeout(timeout)
            try:
                dgram, addr = self.sock.recvfrom(2048)
            except (socket.timeout, OSError):
                return None, False
            if addr != self.remote or len(dgram) < 5 or dgram[0] != 2 or dgram[1] != 0:
                return None, False
            count = struct.unpack(">H", dgram[3:5])[0]
            at = 5
            for _ in range(count):
                cid, n = struct.unpack(">IB", dgram[at:at + 5])
                at += 5
                if n & 0x80:
                    at += 1
                n &= 0x7F
                rtr = bool(cid & 0x40000000)
                data = b"" if rtr else dgram[at:at + n]
                at += 0 if rtr else n
                self.pending.append(can.Message(
                    arbitration_id=cid & 0x1FFFFFFF, is_extended_id=bool(cid & 0x80000000),
                    is_remote_frame=rtr, dlc=n, data=data, timestamp=time.time()))
        if not self.pending:
            return None, False
        return self.pending.popleft(), False

    def shutdown(self):
        super().shutdown()
        self.sock.close()


def var(name, index, sub, dtype, access="rw", default=0):
    v = odm.ODVariable(name, index, sub)
    v.data_type = dtype
    v.access_type = access
    v.default = default
    return v


def pdo_records(od, comm, mapping, cob, maps):
    rec = odm.ODRecord(f"PDO comm {comm:04X}", comm)
    rec.add_member(var("Highest sub-index", comm, 0, odm.UNSIGNED8, "ro", 2))
    rec.add_member(var("COB-ID", comm, 1, odm.UNSIGNED32, "rw", cob))
    rec.add_member(var("Transmission type", comm, 2, odm.UNSIGNED8, "rw", 1))
    od.add_object(rec)
    rec = odm.ODRecord(f"PDO map {mapping:04X}", mapping)
    rec.add_member(var("Number of entries", mapping, 0, odm.UNSIGNED8, "rw", len(maps)))
    for i in range(1, 9):
        rec.add_member(var(f"Entry {i}", mapping, i, odm.UNSIGNED32, "rw", maps[i - 1] if i <= len(maps) else 0))
    od.add_object(rec)


def drive_od(node):
    """A CiA 402 drive's dictionary: the objects ncplc's master configures and maps."""
    od = odm.ObjectDictionary()
    od.node_id = node
    od.add_object(var("Device type", 0x1000, 0, odm.UNSIGNED32, "ro", 0x00020192))
    od.add_object(var("Producer heartbeat time", 0x1017, 0, odm.UNSIGNED16, "rw", 0))
    pdo_records(od, 0x1400, 0x1600, 0x200 + node, [0x60400010, 0x607A0020])
    pdo_records(od, 0x1800, 0x1A00, 0x180 + node, [0x60410010, 0x60640020])
    # The homing PDOs, disabled until the master maps and enables them.
    pdo_records(od, 0x1401, 0x1601, 0x80000300 + node, [])
    pdo_records(od, 0x1801, 0x1A01, 0x80000280 + node, [])
    pdo_records(od, 0x1802, 0x1A02, 0x80000380 + node, [])
    od.add_object(var("Touch probe function", 0x60B8, 0, odm.UNSIGNED16, "rw"))
    od.add_object(var("Touch probe status", 0x60B9, 0, odm.UNSIGNED16, "ro"))
    od.add_object(var("Touch probe pos1 pos value", 0x60BA, 0, odm.INTEGER32, "ro"))
    od.add_object(var("Digital inputs", 0x60FD, 0, odm.UNSIGNED32, "ro"))
    od.add_object(var("Error code", 0x603F, 0, odm.UNSIGNED16, "ro"))
    od.add_object(var("Controlword", 0x6040, 0, odm.UNSIGNED16, "rw"))
    od.add_object(var("Statusword", 0x6041, 0, odm.UNSIGNED16, "ro", 0x0240))
    od.add_object(var("Modes of operation", 0x6060, 0, odm.INTEGER8, "rw"))
    od.add_object(var("Modes of operation display", 0x6061, 0, odm.INTEGER8, "ro"))
    od.add_object(var("Position actual value", 0x6064, 0, odm.INTEGER32, "ro"))
    od.add_object(var("Velocity actual value", 0x606C, 0, odm.INTEGER32, "ro"))
    od.add_object(var("Target position", 0x607A, 0, odm.INTEGER32, "rw"))
    od.add_object(var("Target velocity", 0x60FF, 0, odm.INTEGER32, "rw"))
    rec = odm.ODRecord("Interpolation time period", 0x60C2)
    rec.add_member(var("Highest sub-index", 0x60C2, 0, odm.UNSIGNED8, "ro", 2))
    rec.add_member(var("Time period units", 0x60C2, 1, odm.UNSIGNED8, "rw", 1))
    rec.add_member(var("Time index", 0x60C2, 2, odm.INTEGER8, "rw", -3))
    od.add_object(rec)
    return od


def wait_until(cond, seconds, what):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if cond():
            return
        time.sleep(0.005)
    raise RuntimeError(f"timeout waiting for {what}")


def master(local, remote, node_id):
    bus = CannelloniBus(local, remote)
    network = canopen.Network(bus)
    network.connect()
    node = canopen.BaseNode402(node_id, drive_od(node_id))
    network.add_node(node)
    out = {}
    try:
        node.nmt.send_command(0x80)  # enter pre-operational
        time.sleep(0.05)
        node.sdo[0x6060].raw = 8  # cyclic synchronous position
        node.sdo[0x1017].raw = 50
        node.nmt.state = "PRE-OPERATIONAL"
        node.setup_402_state_machine()
        network.sync.start(0.01)
        node.rpdo[1].start(0.01)
        node.nmt.state = "OPERATIONAL"
        node.rpdo[1]["Target position"].raw = 0
        node.check_statusword(0.5)
        out["start"] = node.state
        node.state = "OPERATION ENABLED"
        out["enabled"] = node.state
        positions = []
        for target in (1000, 2500, -4000):
            node.rpdo[1]["Target position"].raw = target
            wait_until(lambda: node.tpdo_values.get(0x6064) == target, 1.0, f"position {target}")
            positions.append(node.tpdo_values[0x6064])
        out["positions"] = positions
        node.state = "SWITCHED ON"
        out["disabled"] = node.state
        out["mode"] = node.sdo[0x6061].raw
    finally:
        network.sync.stop()
        node.rpdo[1].stop()
        network.disconnect()
    print(json.dumps(out))


# This script's own CiA 402 state machine for the LocalNode drive: (statusword bits of a state).
SW = {"SOD": 0x0240, "RTSO": 0x0221, "SO": 0x0223, "OE": 0x0227, "QSA": 0x0207, "FAULT": 0x0208}


def step(state, cw):
    if state == "FAULT":
        return state
    if cw & 0x02 == 0:
        return "SOD"
    if state == "SOD":
        return "RTSO" if cw & 0x07 == 0x06 else state
    if state == "OE" and cw & 0x04 == 0:
        return "QSA"
    if cw & 0x04 == 0:
        return "SOD"
    if cw & 0x07 == 0x06:
        return "RTSO"
    if state == "RTSO" and cw & 0x07 == 0x07:
        return "SO"
    if state == "SO" and cw & 0x0F == 0x0F:
        return "OE"
    if state == "OE" and cw & 0x0F == 0x07:
        return "SO"
    return state


def node(local, remote, node_id, syncs):
    bus = CannelloniBus(local, remote)
    network = canopen.Network(bus)
    network.connect()
    drive = canopen.LocalNode(node_id, drive_od(node_id))
    network.add_node(drive)
    lock = threading.Lock()
    st = {"state": "SOD", "pending": None, "syncs": 0, "seen": [], "position": 0, "pdo": False,
          "probe": 0, "probes": []}
    drive.sdo[0x6041].raw = SW["SOD"]
    done = threading.Event()

    def on_rpdo(pdo):
        with lock:
            st["pending"] = (pdo["Controlword"].raw, pdo["Target position"].raw)

    def on_rpdo2(pdo):
        with lock:
            st["probe"] = pdo["Touch probe function"].raw

    def on_sync(can_id, data, timestamp):
        with lock:
            if drive.nmt.state != "OPERATIONAL":
                return
            st["syncs"] += 1
            cw, target = st["pending"] if st["pending"] else (None, None)
            st["seen"].append([cw, target])
            if cw is not None:
                st["state"] = step(st["state"], cw)
                if st["state"] == "OE":
                    st["position"] = target
            drive.tpdo[1]["Statusword"].raw = SW[st["state"]]
            drive.tpdo[1]["Position actual value"].raw = st["position"]
            drive.tpdo[1].transmit()
            # The touch probe as far as this drive has one: enabled (status bit 0) while armed.
            st["probes"].append(st["probe"])
            drive.tpdo[2]["Touch probe status"].raw = st["probe"] & 1
            drive.tpdo[2]["Touch probe pos1 pos value"].raw = 0
            drive.tpdo[2].transmit()
            drive.tpdo[3]["Digital inputs"].raw = 0
            drive.tpdo[3].transmit()
            if st["syncs"] >= syncs:
                done.set()

    def on_nmt(can_id, data, timestamp):
        # NMT start: the master has mapped the PDOs by SDO; take our own dictionary's new
        # configuration (LocalNode's PDO handling reads it through its SDO server).
        if len(data) >= 2 and data[0] == 0x01 and data[1] in (0, node_id):
            with lock:
                drive.rpdo.read()
                drive.tpdo.read()
                drive.rpdo[1].add_callback(on_rpdo)
                drive.rpdo[2].add_callback(on_rpdo2)
                st["pdo"] = True

    network.subscribe(0x80, on_sync)
    network.subscribe(0, on_nmt)
    drive.nmt.state = "PRE-OPERATIONAL"
    print("ready", flush=True)
    try:
        if not done.wait(20):
            raise RuntimeError(f"only {st['syncs']} SYNCs arrived")
        print(json.dumps({
            "seen": st["seen"],
            "state": st["state"],
            "mode": drive.sdo[0x6060].raw,
            "period": [drive.sdo[0x60C2][1].raw, drive.sdo[0x60C2][2].raw],
            "heartbeat": drive.sdo[0x1017].raw,
            "rpdo": [drive.sdo[0x1600][i].raw for i in range(0, 3)],
            "tpdo": [drive.sdo[0x1A00][i].raw for i in range(0, 3)],
            "pdo2": [[drive.sdo[c][1].raw, drive.sdo[c][2].raw] for c in (0x1401, 0x1801, 0x1802)],
            "rpdo2": [drive.sdo[0x1601][i].raw for i in range(0, 2)],
            "tpdo2": [drive.sdo[0x1A01][i].raw for i in range(0, 3)],
            "tpdo3": [drive.sdo[0x1A02][i].raw for i in range(0, 2)],
            "probes": st["probes"],
        }))
    finally:
        network.disconnect()


if __name__ == "__main__":
    mode, local, remote, node_id = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
    if mode == "master":
        master(local, remote, node_id)
    else:
        node(local, remote, node_id, int(sys.argv[5]))
