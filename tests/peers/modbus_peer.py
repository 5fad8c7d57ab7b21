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


if __name__ == "__main__":
    if sys.argv[1:2] == ["device"]:
        sys.exit(asyncio.run(device()))
    if sys.argv[1:2] == ["client"] and len(sys.argv) == 4:
        sys.exit(client(sys.argv[2], int(sys.argv[3])))
    sys.exit(__doc__)
