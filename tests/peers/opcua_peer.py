"""asyncua (PyPI, the most used open OPC UA stack in Python) as an independent client of
`ncplc run --opcua`, driven by tests/e2e/opcua.rs. Prints one JSON object with what it saw.

Usage: opcua_peer.py signals URL SECONDS
       opcua_peer.py model URL
       opcua_peer.py secure URL CERT_DIR USER:PASSWORD:ROLE...
       opcua_peer.py methods URL MACHINE USER PASSWORD
       opcua_peer.py variables URL SECONDS
       opcua_peer.py start_part URL MACHINE
"""
import asyncio
import json
import sys

from asyncua import Client, ua

NS_SIGNALS = "urn:ncplc"


def stamp(dv):
    """A data value as [value, source timestamp in µs since the epoch]."""
    v = dv.Value.Value
    if isinstance(v, bool):
        v = int(v)
    ts = dv.SourceTimestamp
    return [v, int(ts.timestamp() * 1_000_000) if ts else None]


class Collect:
    def __init__(self):
        self.got = []

    def datachange_notification(self, node, val, data):
        self.got.append([node.nodeid.Identifier] + stamp(data.monitored_item.Value))


async def write(node, variant):
    try:
        await node.write_value(ua.DataValue(variant))
        return "Good"
    except ua.UaStatusCodeError as e:
        return ua.StatusCode(e.code).name


async def signals(url, seconds):
    out = {}
    async with Client(url) as c:
        ns = await c.get_namespace_index(NS_SIGNALS)
        objects = c.nodes.objects

        def path(*names):
            return objects.get_child([f"{ns}:{n}" for n in names])

        sig = await path("Signals")
        out["packets"] = sorted([(await n.read_browse_name()).Name for n in await sig.get_children()])
        mcode = await path("Signals", "K", "3", "MCODE")
        mfin = await path("Signals", "K", "11", "MFIN")
        start = await path("Signals", "A", "0", "START_PB")
        tick = await path("Signals", "Tick")
        tick_ms = await (await path("Signals", "TickMs")).read_value()
        out["tick_ms"] = tick_ms
        out["mcode_description"] = (await mcode.read_description()).Text
        out["mcode_address"] = await (await mcode.get_child([f"{ns}:Address"])).read_value()
        out["start_description"] = (await start.read_description()).Text
        out["mfin_type"] = (await mfin.read_data_type_as_variant_type()).name
        # One read of several values with their ticks: the tick variable gives the origin.
        dvs = await c.read_attributes([tick, mcode, mfin, start])
        out["read"] = [stamp(d) for d in dvs]
        # Subscribe at the logic tick.
        h = Collect()
        sub = await c.create_subscription(tick_ms, h)
        await sub.subscribe_data_change([tick, mcode, mfin, start], queuesize=1000, sampling_interval=tick_ms)
        await asyncio.sleep(seconds / 2)
        # Writes: inside the window (W200K0 = 0x5A), outside (MCODE), of the wrong type (W200K1).
        w200 = await path("Signals", "K", "200", "W200K0")
        out["write_window"] = await write(w200, ua.Variant(0x5A, ua.VariantType.Byte))
        out["write_outside"] = await write(mcode, ua.Variant(7, ua.VariantType.Byte))
        w201 = await path("Signals", "K", "200", "W200K1")
        out["write_wrong_type"] = await write(w201, ua.Variant(7, ua.VariantType.Int32))
        out["write_bit_as_byte"] = await write(w201, ua.Variant(True, ua.VariantType.Boolean))
        out["access_window"] = (await w200.get_user_access_level()) and sorted(
            a.name for a in await w200.get_user_access_level())
        await asyncio.sleep(seconds / 2)
        out["w200k0_read_back"] = await w200.read_value()
        out["w200k1_read_back"] = await w201.read_value()
        await sub.delete()
        out["notifications"] = h.got
    print(json.dumps(out))


class Events:
    def __init__(self):
        self.got = []

    def event_notification(self, event):
        ts = event.Time
        self.got.append([event.Message.Text, event.Severity, int(ts.timestamp() * 1_000_000), event.SourceName])

    def datachange_notification(self, node, val, data):
        pass


async def model(url, name, seconds):
    out = {}
    async with Client(url) as c:
        ns = await c.get_namespace_index(NS_SIGNALS)
        mt = await c.get_namespace_index("http://opcfoundation.org/UA/MachineTool/")
        mach = await c.get_namespace_index("http://opcfoundation.org/UA/Machinery/")
        di = await c.get_namespace_index("http://opcfoundation.org/UA/DI/")
        ia = await c.get_namespace_index("http://opcfoundation.org/UA/IA/")
        objects = c.nodes.objects
        m = await objects.get_child([f"{mach}:Machines", f"{ns}:{name}"])
        ty = c.get_node(await m.read_type_definition())
        out["type"] = (await ty.read_browse_name()).Name
        out["type_children"] = sorted([(await n.read_browse_name()).Name for n in await ty.get_children()])
        ident = await m.get_child([f"{di}:Identification"])
        out["identification_type"] = (await c.get_node(await ident.read_type_definition()).read_browse_name()).Name
        for bn in [f"{di}:Manufacturer", f"{di}:Model", f"{di}:SerialNumber", f"{mach}:YearOfConstruction"]:
            v = await (await ident.get_child([bn])).read_value()
            out[bn.split(":")[1]] = v.Text if hasattr(v, "Text") else v
        ch = await m.get_child([f"{mt}:Monitoring", f"{mt}:Channel1"])
        state = await ch.get_child([f"{mt}:ChannelState"])
        mode = await ch.get_child([f"{mt}:ChannelMode"])
        fov = await ch.get_child([f"{mt}:FeedOverride"])
        out["channel_state_type"] = (await c.get_node(await state.read_data_type()).read_browse_name()).Name
        lamp = await m.get_child([f"{mt}:Monitoring", f"{mt}:Stacklight", f"{ns}:Lamp0"])
        lamp_on = await lamp.get_child([f"{ia}:SignalOn"])
        out["lamp0_color"] = await (await lamp.get_child([f"{ia}:SignalColor"])).read_value()
        prog = await m.get_child([f"{mt}:Production", f"{mt}:ActiveProgram"])
        out["program"] = await (await prog.get_child([f"{mt}:Name"])).read_value()
        cur = await prog.get_child([f"{mt}:State", "0:CurrentState"])
        tick = await objects.get_child([f"{ns}:Signals", f"{ns}:Tick"])
        dvs = await c.read_attributes([tick])
        out["tick"] = stamp(dvs[0])
        h = Collect()
        sub = await c.create_subscription(10, h)
        await sub.subscribe_data_change([state, mode, fov, lamp_on, cur], queuesize=1000, sampling_interval=10)
        ev = Events()
        esub = await c.create_subscription(10, ev)
        messages = await m.get_child([f"{mt}:Notification", f"{mt}:Messages"])
        await esub.subscribe_events(messages)
        await asyncio.sleep(seconds)
        await sub.delete()
        await esub.delete()
        out["notifications"] = [[n[0], n[1].Text if hasattr(n[1], "Text") else n[1], n[2]] for n in h.got]
        out["events"] = ev.got
    print(json.dumps(out, default=str))


async def limits(url):
    """Past the server's limits (opcua-server/src/limits.rs): the 9th session, the 5001st monitored
    item of a subscription, a Read of 5001 nodes; and the server still serves a client after it."""
    out = {}
    clients = []
    for i in range(9):
        c = Client(url, timeout=10)
        try:
            await c.connect()
            clients.append(c)
            out[f"session{i + 1}"] = "Good"
        except ua.UaStatusCodeError as e:
            out[f"session{i + 1}"] = ua.StatusCode(e.code).name
    for c in clients[1:]:
        await c.disconnect()
    c = clients[0]
    ns = await c.get_namespace_index(NS_SIGNALS)
    tick = await c.nodes.objects.get_child([f"{ns}:Signals", f"{ns}:Tick"])
    # A constant byte (packet T), so that 5000 items do not flood the client every tick.
    const = await c.nodes.objects.get_child([f"{ns}:Signals", f"{ns}:T", f"{ns}:15", f"{ns}:W15T3"])
    sub = await c.create_subscription(10, Collect())
    try:
        await sub.subscribe_data_change([const] * 5001, queuesize=1, sampling_interval=10)
        out["items_5001_in_one_call"] = "Good"
    except ua.UaStatusCodeError as e:
        out["items_5001_in_one_call"] = ua.StatusCode(e.code).name
    res = await sub.subscribe_data_change([const] * 5000, queuesize=1, sampling_interval=10)
    codes = [r.name if isinstance(r, ua.StatusCode) else "Good" for r in res]
    try:
        more = await sub.subscribe_data_change([const], queuesize=1, sampling_interval=10)
        codes += [r.name if isinstance(r, ua.StatusCode) else "Good" for r in more]
    except ua.UaStatusCodeError as e:
        codes.append(ua.StatusCode(e.code).name)
    out["items_good"] = codes.count("Good")
    out["items_refused"] = sorted(set(x for x in codes if x != "Good"))
    await sub.delete()
    try:
        await c.read_attributes([tick] * 5001)
        out["read_5001"] = "Good"
    except ua.UaStatusCodeError as e:
        out["read_5001"] = ua.StatusCode(e.code).name
    out["read_after"] = (await tick.read_data_value()).StatusCode.name
    await c.disconnect()
    print(json.dumps(out))


async def events(url, name, seconds):
    """The alarm events of Notification/Messages while SECONDS pass."""
    out = {}
    async with Client(url) as c:
        ns = await c.get_namespace_index(NS_SIGNALS)
        mt = await c.get_namespace_index("http://opcfoundation.org/UA/MachineTool/")
        mach = await c.get_namespace_index("http://opcfoundation.org/UA/Machinery/")
        m = await c.nodes.objects.get_child([f"{mach}:Machines", f"{ns}:{name}"])
        messages = await m.get_child([f"{mt}:Notification", f"{mt}:Messages"])
        tick = await c.nodes.objects.get_child([f"{ns}:Signals", f"{ns}:Tick"])
        out["tick"] = stamp((await c.read_attributes([tick]))[0])
        ev = Events()
        sub = await c.create_subscription(10, ev)
        await sub.subscribe_events(messages)
        await asyncio.sleep(seconds)
        await sub.delete()
        out["events"] = ev.got
    print(json.dumps(out))


async def call(obj, method):
    """A method call: ["Good", outputs] or [status name, None]."""
    try:
        out = await obj.call_method(method)
        return ["Good", out]
    except ua.UaStatusCodeError as e:
        return [ua.StatusCode(e.code).name, None]


async def wait_for(got, node_id, value, seconds):
    """Waits until the notifications of NODE_ID include VALUE (GOT: a function giving them);
    False on time-out."""
    for _ in range(int(seconds * 100)):
        if any(n[0] == node_id and n[1] == value for n in got()):
            return True
        await asyncio.sleep(0.01)
    return False


async def methods(url, name, user, password):
    """START, HOLD and RESET of Channel1: refused to an anonymous viewer, called by an operator
    while the program state, channel state, spindle and block count are subscribed."""
    out = {}

    async def channel_of(c):
        ns = await c.get_namespace_index(NS_SIGNALS)
        mt = await c.get_namespace_index("http://opcfoundation.org/UA/MachineTool/")
        mach = await c.get_namespace_index("http://opcfoundation.org/UA/Machinery/")
        m = await c.nodes.objects.get_child([f"{mach}:Machines", f"{ns}:{name}"])
        ch = await m.get_child([f"{mt}:Monitoring", f"{mt}:Channel1"])
        return ns, mt, m, ch

    async with Client(url) as c:
        ns, mt, m, ch = await channel_of(c)
        out["viewer_start"] = (await call(ch, f"{ns}:Start"))[0]
        # A viewer may not write anywhere: outside the window the node is not writable at all.
        mcode = await c.nodes.objects.get_child([f"{ns}:Signals", f"{ns}:K", f"{ns}:3", f"{ns}:MCODE"])
        w200 = await c.nodes.objects.get_child([f"{ns}:Signals", f"{ns}:K", f"{ns}:200", f"{ns}:W200K0"])
        out["viewer_write_outside"] = await write(mcode, ua.Variant(7, ua.VariantType.Byte))
        out["viewer_write_window"] = await write(w200, ua.Variant(7, ua.VariantType.Byte))
    c = Client(url)
    c.set_user(user)
    c.set_password(password)
    async with c:
        ns, mt, m, ch = await channel_of(c)
        prog = await m.get_child([f"{mt}:Production", f"{mt}:ActiveProgram"])
        cur = await prog.get_child([f"{mt}:State", "0:CurrentState"])
        state = await ch.get_child([f"{mt}:ChannelState"])
        tick = await c.nodes.objects.get_child([f"{ns}:Signals", f"{ns}:Tick"])
        out["tick"] = stamp((await c.read_attributes([tick]))[0])
        out["methods"] = sorted([(await n.read_browse_name()).Name
                                 for n in await ch.get_methods()])
        h = Collect()
        sub = await c.create_subscription(10, h)
        blocks = await prog.get_child([f"{ns}:BlocksExecuted"])
        sp = await m.get_child([f"{mt}:Monitoring", f"{mt}:Spindle1"])
        out["spindle_type"] = (await c.get_node(await sp.read_type_definition()).read_browse_name()).Name
        spindle = [await sp.get_child([f"{mt}:Override"]), await sp.get_child([f"{mt}:IsRotating"]),
                   await sp.get_child([f"{ns}:ActualSpeed"]), await sp.get_child([f"{ns}:CommandedSpeed"])]
        await sub.subscribe_data_change([cur, state, blocks] + spindle, queuesize=1000,
                                        sampling_interval=10)
        await asyncio.sleep(0.5)
        out["hold_idle"] = (await call(ch, f"{ns}:Hold"))[0]
        status, ticks = await call(ch, f"{ns}:Start")
        out["start"] = [status, ticks]
        got = lambda: [[n[0], n[1].Text if hasattr(n[1], "Text") else n[1], n[2]] for n in h.got]
        cur_id = cur.nodeid.Identifier
        out["running"] = await wait_for(got, cur_id, "Running", 20)
        out["hold"] = await call(ch, f"{ns}:Hold")
        out["interrupted"] = await wait_for(got, cur_id, "Interrupted", 5)
        out["resume"] = await call(ch, f"{ns}:Start")
        out["ended"] = await wait_for(got, cur_id, "Ended", 20)
        out["reset"] = await call(ch, f"{ns}:Reset")
        await asyncio.sleep(0.3)
        await sub.delete()
        out["notifications"] = got()
    print(json.dumps(out, default=str))


async def variables(url, seconds):
    """The PLC program's variables: the folder, a type and description, a refused write, and the
    notifications of CHAIN_OK, HOLD_REQ and the blinker until HOLD_REQ fell (at most SECONDS)."""
    out = {}
    async with Client(url) as c:
        ns = await c.get_namespace_index(NS_SIGNALS)
        folder = await c.nodes.objects.get_child([f"{ns}:Variables"])
        out["names"] = sorted([(await n.read_browse_name()).Name for n in await folder.get_children()])
        chain = await folder.get_child([f"{ns}:CHAIN_OK"])
        hold = await folder.get_child([f"{ns}:HOLD_REQ"])
        out["chain_type"] = (await chain.read_data_type_as_variant_type()).name
        out["chain_description"] = (await chain.read_description()).Text
        out["write"] = await write(chain, ua.Variant(False, ua.VariantType.Boolean))
        tick = await c.nodes.objects.get_child([f"{ns}:Signals", f"{ns}:Tick"])
        out["tick"] = stamp((await c.read_attributes([tick]))[0])
        h = Collect()
        sub = await c.create_subscription(10, h)
        blink = [await folder.get_child([f"{ns}:BLINK_ON.Q"]), await folder.get_child([f"{ns}:BLINK_ON.ET"])]
        out["blink_description"] = (await blink[1].read_description()).Text
        await sub.subscribe_data_change([chain, hold] + blink, queuesize=1000, sampling_interval=10)
        # Watch until HOLD_REQ has risen and fallen and at least 4 s have passed (three blinks),
        # at most SECONDS: a client slow to subscribe under load still sees the scripted hold.
        loop = asyncio.get_running_loop()
        start = loop.time()
        while loop.time() - start < seconds:
            await asyncio.sleep(0.1)
            held = [n[1] for n in h.got if n[0] == "Variables/HOLD_REQ"]
            fell = any(a == 1 and b == 0 for a, b in zip(held, held[1:]))
            if fell and loop.time() - start >= 4:
                break
        await sub.delete()
        out["notifications"] = h.got
    print(json.dumps(out))


async def start_part(url, name):
    """START of Channel1 (anonymous: an integrator on loopback without a users file), then the
    active program's states until it has ended."""
    out = {}
    async with Client(url) as c:
        ns = await c.get_namespace_index(NS_SIGNALS)
        mt = await c.get_namespace_index("http://opcfoundation.org/UA/MachineTool/")
        mach = await c.get_namespace_index("http://opcfoundation.org/UA/Machinery/")
        m = await c.nodes.objects.get_child([f"{mach}:Machines", f"{ns}:{name}"])
        ch = await m.get_child([f"{mt}:Monitoring", f"{mt}:Channel1"])
        prog = await m.get_child([f"{mt}:Production", f"{mt}:ActiveProgram"])
        cur = await prog.get_child([f"{mt}:State", "0:CurrentState"])
        out["program"] = await (await prog.get_child([f"{mt}:Name"])).read_value()
        h = Collect()
        sub = await c.create_subscription(10, h)
        await sub.subscribe_data_change([cur], queuesize=1000, sampling_interval=10)
        await asyncio.sleep(0.3)
        out["start"] = await call(ch, f"{ns}:Start")
        got = lambda: [[n[0], n[1].Text if hasattr(n[1], "Text") else n[1]] for n in h.got]
        out["ended"] = await wait_for(got, cur.nodeid.Identifier, "Ended", 60)
        await sub.delete()
        out["states"] = [n[1] for n in got()]
    print(json.dumps(out, default=str))


APP_URI = "urn:ncplc:test-client"


async def client_cert(cert_dir):
    """The client's certificate and key, made once in CERT_DIR."""
    from pathlib import Path
    from asyncua.crypto.cert_gen import setup_self_signed_certificate
    from cryptography.x509.oid import ExtendedKeyUsageOID
    d = Path(cert_dir)
    cert, key = d / "client-cert.der", d / "client-key.pem"
    await setup_self_signed_certificate(
        key, cert, APP_URI, "localhost", [ExtendedKeyUsageOID.CLIENT_AUTH],
        {"countryName": "DE", "organizationName": "ncplc tests", "commonName": "ncplc-test-client"})
    return cert, key


async def attempt(url, cert, key, mode, user=None, password=None, action=None):
    """One session: the status it ended with, and what `action` returned."""
    from asyncua.crypto.security_policies import SecurityPolicyBasic256Sha256
    c = Client(url, timeout=10)
    c.application_uri = APP_URI
    if mode is not None:
        await c.set_security(SecurityPolicyBasic256Sha256, certificate=str(cert), private_key=str(key), mode=mode)
    if user is not None:
        c.set_user(user)
        c.set_password(password)
    try:
        await c.connect()
    except ua.UaStatusCodeError as e:
        return ua.StatusCode(e.code).name, None
    except Exception as e:  # a refused session surfaces as the stack's own error types too
        code = getattr(e, "code", None)
        return (ua.StatusCode(code).name if code is not None else type(e).__name__ + ": " + str(e)), None
    try:
        result = await action(c) if action else None
        return "Good", result
    finally:
        await c.disconnect()


async def secure(url, cert_dir, users):
    cert, key = await client_cert(cert_dir)
    out = {}
    sae = ua.MessageSecurityMode.SignAndEncrypt

    async def read_and_write(c):
        ns = await c.get_namespace_index(NS_SIGNALS)
        objects = c.nodes.objects
        mcode = await objects.get_child([f"{ns}:Signals", f"{ns}:K", f"{ns}:3", f"{ns}:MCODE"])
        w200 = await objects.get_child([f"{ns}:Signals", f"{ns}:K", f"{ns}:200", f"{ns}:W200K0"])
        return {
            "mcode_read": (await mcode.read_data_value()).StatusCode.name,
            "write": await write(w200, ua.Variant(0x21, ua.VariantType.Byte)),
        }

    out["endpoints"] = sorted(
        f"{e.SecurityPolicyUri.rsplit('#', 1)[-1]} {e.SecurityMode.name}"
        for e in await Client(url).connect_and_get_server_endpoints())
    out["anonymous"] = (await attempt(url, cert, key, sae))[0]
    out["none_policy"] = (await attempt(url, cert, key, None))[0]
    for spec in users:
        user, password, role = spec.split(":")
        out[f"{role}_wrong_password"] = (await attempt(url, cert, key, sae, user, password + "x"))[0]
        status, result = await attempt(url, cert, key, sae, user, password, read_and_write)
        out[role] = {"session": status, **(result or {})}
        sign = ua.MessageSecurityMode.Sign
        out[f"{role}_sign"] = (await attempt(url, cert, key, sign, user, password))[0]
    print(json.dumps(out))


async def untrusted(url, cert_dir, user, password):
    cert, key = await client_cert(cert_dir)
    status, _ = await attempt(url, cert, key, ua.MessageSecurityMode.SignAndEncrypt, user, password)
    print(json.dumps({"first": status}))


def main():
    mode = sys.argv[1]
    if mode == "signals":
        asyncio.run(signals(sys.argv[2], float(sys.argv[3])))
    elif mode == "events":
        asyncio.run(events(sys.argv[2], sys.argv[3], float(sys.argv[4])))
    elif mode == "limits":
        asyncio.run(limits(sys.argv[2]))
    elif mode == "model":
        asyncio.run(model(sys.argv[2], sys.argv[3], float(sys.argv[4])))
    elif mode == "secure":
        asyncio.run(secure(sys.argv[2], sys.argv[3], sys.argv[4:]))
    elif mode == "start_part":
        asyncio.run(start_part(sys.argv[2], sys.argv[3]))
    elif mode == "variables":
        asyncio.run(variables(sys.argv[2], float(sys.argv[3])))
    elif mode == "methods":
        asyncio.run(methods(sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5]))
    elif mode == "untrusted":
        asyncio.run(untrusted(sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5]))
    else:
        sys.exit(f"unknown mode {mode}")


if __name__ == "__main__":
    main()
