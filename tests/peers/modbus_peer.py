#!/usr/bin/python3
"""pymodbus as the peer of ncplc's Modbus TCP code (tests/e2e/modbus_peer.rs drives it).

  modbus_peer.py device
      A remote-I/O coupler served by pymodbus: 64 discrete inputs (0 and 1, the lathe's e-stop
      chain, closed), 64 coils. Prints `listening PORT`; once ncplc energises coil 4 (DRIVES_ON)
      it opens discrete input 0 (an e-stop button) and waits for coil 4 to drop. Prints one JSON
      line with what it saw and exits 0, or exits 1 after 20 s.
  modbus_peer.py client HOST PORT
      A SCADA client (pymodbus ModbusTcpClient) against ncplc's HMI server: reads discrete
      inputs, coils and input registers, writes a holding register of the window and one outside
      it, writes a coil, and prints one JSON line with every answer (values or exception codes).
  modbus_peer.py hostile HOST PORT LIMIT CONNECTIONS
      A hostile client of ncplc's HMI server, whose io.toml allows LIMIT requests per second per
      connection and CONNECTIONS connections: a flood of 50 pipelined requests on one connection,
      a wrong unit id, one connection more than allowed, a half-open connection (3 bytes of a
      header, then silence), malformed MBAP headers (protocol id 0x1234, length 0), a write
      outside the window; prints one JSON line with what each got.
"""
import asyncio, json, socket, sys, time

from pymodbus.client import ModbusTcpClient
from pymodbus.datastore import ModbusSequentialDataBlock, ModbusServerContext, ModbusSlaveContext
from pymodbus.server import StartAsyncTcpServer


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


async def device():
    store = ModbusSlaveContext(
        di=ModbusSequentialDataBlock(0, [1, 1] + [0] * 62),
        co=ModbusSequentialDataBlock(0, [0] * 64),
        hr=ModbusSequentialDataBlock(0, [0] * 8),
        ir=ModbusSequentialDataBlock(0, [0] * 8),
        zero_mode=True,
    )
    context = ModbusServerContext(slaves={1: store}, single=False)
    port = free_port()
    server = await StartAsyncTcpServer(context, address=("127.0.0.1", port), defer_start=True)
    task = asyncio.create_task(server.serve_forever())
    print(f"listening {port}", flush=True)
    seen = {"energised": False, "dropped": False}
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        coil4 = store.getValues(1, 4, 1)[0]
        if not seen["energised"] and coil4:
            seen["energised"] = True
            seen["coils_when_energised"] = [i for i, v in enumerate(store.getValues(1, 0, 64)) if v]
            store.setValues(2, 0, [0])  # the e-stop button is pressed
        elif seen["energised"] and not coil4:
            seen["dropped"] = True
            seen["coils_when_dropped"] = [i for i, v in enumerate(store.getValues(1, 0, 64)) if v]
            break
        await asyncio.sleep(0.005)
    print(json.dumps(seen), flush=True)
    await server.shutdown()
    task.cancel()
    return 0 if seen["dropped"] else 1


def answer(r):
    """The values of a response, or its exception code."""
    if r.isError():
        return {"exception": getattr(r, "exception_code", None)}
    if hasattr(r, "bits"):
        return {"bits": [int(b) for b in r.bits]}
    if hasattr(r, "registers"):
        return {"registers": list(r.registers)}
    return {"ok": True}


def client(host, port):
    c = ModbusTcpClient(host, port=port, timeout=3)
    if not c.connect():
        print(json.dumps({"error": "no connection"}))
        return 1
    out = {}
    out["inputs_0_16"] = answer(c.read_discrete_inputs(0, 16, slave=1))
    out["inputs_of_an_output_connector"] = answer(c.read_discrete_inputs(128, 1, slave=1))
    out["coils_128_136"] = answer(c.read_coils(128, 8, slave=1))
    out["write_window"] = answer(c.write_register(400, 0x1234, slave=1))
    time.sleep(0.3)  # a few ticks: the write reaches the image at the next latch
    out["window_read_back"] = answer(c.read_input_registers(400, 2, slave=1))
    out["holding_read_back"] = answer(c.read_holding_registers(400, 1, slave=1))
    out["write_outside_window"] = answer(c.write_register(0, 7, slave=1))
    out["write_coil"] = answer(c.write_coil(128, True, slave=1))
    out["registers_past_the_table"] = answer(c.read_input_registers(1024, 1, slave=1))
    c.close()
    print(json.dumps(out, sort_keys=True), flush=True)
    return 0


def mbap(tid, unit, pdu, protocol=0, length=None):
    """One Modbus TCP frame (MBAP header + PDU)."""
    n = len(pdu) + 1 if length is None else length
    return tid.to_bytes(2, "big") + protocol.to_bytes(2, "big") + n.to_bytes(2, "big") + bytes([unit]) + pdu


def read_regs(tid, unit=1):
    """Read input registers 0..1 (function 04)."""
    return mbap(tid, unit, bytes([4, 0, 0, 0, 2]))


def frames(sock, n, wait=5.0):
    """Reads up to n response frames: a list of (function, exception or None)."""
    sock.settimeout(wait)
    buf, out = b"", []
    while len(out) < n:
        while len(buf) >= 7 and len(buf) >= 6 + int.from_bytes(buf[4:6], "big"):
            size = 6 + int.from_bytes(buf[4:6], "big")
            frame, buf = buf[:size], buf[size:]
            fc = frame[7]
            out.append((fc, frame[8] if fc & 0x80 else None))
        if len(out) >= n:
            break
        try:
            chunk = sock.recv(4096)
        except OSError:
            break
        if not chunk:
            break
        buf += chunk
    return out


def closed_within(sock, wait):
    """Seconds until the server closes `sock` without answering, or None if it answers or stays."""
    sock.settimeout(wait)
    t0 = time.monotonic()
    try:
        data = sock.recv(1024)
    except ConnectionResetError:
        data = b""  # closed with unread bytes: a reset
    except OSError:
        return None  # the wait ran out
    return round(time.monotonic() - t0, 3) if not data else None


def hostile(host, port, limit, connections):
    out = {}
    # Pymodbus itself with a wrong unit id, and a write outside the window.
    c = ModbusTcpClient(host, port=port, timeout=3)
    c.connect()
    out["wrong_unit"] = answer(c.read_input_registers(0, 1, slave=7))
    out["write_outside_window"] = answer(c.write_register(0, 7, slave=1))
    c.close()
    # A flood: 50 requests in one write on a fresh connection.
    s = socket.create_connection((host, port))
    s.sendall(b"".join(read_regs(i) for i in range(50)))
    got = frames(s, 50)
    out["flood_served"] = sum(1 for fc, e in got if e is None)
    out["flood_busy"] = sum(1 for fc, e in got if e == 6)
    out["flood_answers"] = len(got)
    s.close()
    time.sleep(0.2)
    # The connection cap: CONNECTIONS answered, one more closed at once, room again after one goes.
    held = []
    for i in range(connections):
        k = socket.create_connection((host, port))
        k.sendall(read_regs(i))
        held.append((k, frames(k, 1)))
    out["held_answered"] = sum(1 for _, f in held if f and f[0][1] is None)
    extra = socket.create_connection((host, port))
    extra.sendall(read_regs(99))
    out["over_cap_closed"] = closed_within(extra, 5.0) is not None
    extra.close()
    held[0][0].close()
    time.sleep(0.3)
    again = socket.create_connection((host, port))
    again.sendall(read_regs(100))
    out["after_one_left"] = [e for _, e in frames(again, 1)]
    again.close()
    for k, _ in held[1:]:
        k.close()
    time.sleep(0.3)
    # Half open: three bytes of a header, then nothing; the idle timeout closes it.
    h = socket.create_connection((host, port))
    h.sendall(read_regs(1)[:3])
    out["half_open_closed_after_s"] = closed_within(h, 10.0)
    h.close()
    # Malformed MBAP headers: the connection is closed without an answer.
    for name, frame in [
        ("bad_protocol", mbap(1, 1, bytes([4, 0, 0, 0, 1]), protocol=0x1234)),
        ("zero_length", mbap(1, 1, b"", length=0)),
    ]:
        m = socket.create_connection((host, port))
        m.sendall(frame)
        out[name + "_closed"] = closed_within(m, 5.0) is not None
        m.close()
    # The server still serves a well-behaved client.
    c = ModbusTcpClient(host, port=port, timeout=3)
    c.connect()
    out["still_serving"] = answer(c.read_input_registers(400, 1, slave=1))
    c.close()
    print(json.dumps(out, sort_keys=True), flush=True)
    return 0


if __name__ == "__main__":
    if sys.argv[1:2] == ["hostile"] and len(sys.argv) == 6:
        sys.exit(hostile(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])))
    if sys.argv[1:2] == ["device"]:
        sys.exit(asyncio.run(device()))
    if sys.argv[1:2] == ["client"] and len(sys.argv) == 4:
        sys.exit(client(sys.argv[2], int(sys.argv[3])))
    sys.exit(__doc__)
