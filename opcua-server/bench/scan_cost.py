#!/usr/bin/env python3
"""What the OPC UA server with a subscribed client costs the scan, and how late a tick's value
reaches the client, taken apart by stage.

Alternated real-time runs of `ncplc run MACHINE --ticks N --stats` without the server (`off`), with
`--opcua` and the asyncua client (`asyncua`), and with `--opcua` and async-opcua's own client
(`rust`, examples/opcua_latency.rs: `cargo build --release -p opcua-server --example
opcua_latency`). Both clients hold 100 monitored items (Tick and 99 signal bytes of packet K) at a
10 ms publishing and sampling interval and queue size 100. Prints, per run, the scan percentiles
of `--stats` and the process's CPU time (`client_cpu_s`: the client's), and for the served runs the latency of every notified
value, in ms, p50/p99/max, by stage (all clocks are this host's wall clock; the first
notification of each item is its current value, stamped when it last changed, and not counted):

  apply  the publisher set the value (and the stack queued it in its monitored items) − the
         scan's copy; only from a binary built with `--features opcua-server/latency`
  srv    the notification message's PublishTime − the value's server timestamp (the scan's
         copy of that tick): the server's part up to the publish cycle that took the value
  sock   the PublishResponse's last TCP segment on the loopback (tshark, `--tshark`) − the
         server timestamp: the server's whole part (with `waited_pct`, the share of data
         responses sent within 1 ms of their Publish request's arrival: those values waited
         for the client to ask)
  own    sock for the values of the other responses: the server's part when the client had a
         Publish request waiting
  recv   the client has decoded the PublishResponse − the server timestamp (asyncua: its
         subscription's publish callback; rust: the subscription callback)
  lat    the value reaches the client's data-change handler − the server timestamp (asyncua's
         handler runs as a task scheduled by the publish callback; rust: = recv)

`--tshark` captures the loopback with dumpcap (apt-get install tshark; root or CAP_NET_RAW).
Then the medians per variant. Usage:
  scan_cost.py NCPLC MACHINE [--runs 3] [--ticks 2000] [--clients asyncua,rust]
               [--rust-client target/release/examples/opcua_latency] [--tshark]
"""

import argparse
import asyncio
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time

SCAN = re.compile(r"scan time\s+p50\s+([\d.]+) µs\s+p99\s+([\d.]+) µs\s+p99.9\s+([\d.]+) µs\s+max\s+([\d.]+) µs")
APPLY = re.compile(r"opcua: latency apply: (\d+) frames, p50 ([\d.]+) ms, p99 ([\d.]+) ms, max ([\d.]+) ms")


def pct(values):
    """p50, p99, max in ms of seconds (index n/2 and ⌊0.99 n⌋ of the sorted values)."""
    v = sorted(values)
    if not v:
        return None
    return {"p50": round(1000 * v[len(v) // 2], 2), "p99": round(1000 * v[int(len(v) * 0.99)], 2),
            "max": round(1000 * v[-1], 2)}


async def asyncua_client(url, seconds, out):
    from asyncua import Client, ua

    class H:
        def __init__(self):
            self.lat = []
            self.seen = set()

        def datachange_notification(self, node, val, data):
            dv = data.monitored_item.Value
            if node.nodeid not in self.seen:
                self.seen.add(node.nodeid)
                return
            if dv.ServerTimestamp:
                self.lat.append(time.time() - dv.ServerTimestamp.timestamp())

    async with Client(url) as c:
        ns = await c.get_namespace_index("urn:ncplc")
        objects = c.nodes.objects
        nodes = [await objects.get_child([f"{ns}:Signals", f"{ns}:Tick"])]
        for conn in range(0, 25):
            for b in range(4):
                if len(nodes) < 100:
                    nodes.append(await objects.get_child(
                        [f"{ns}:Signals", f"{ns}:K", f"{ns}:{conn}", f"{ns}:W{conn}K{b}"]))
        h = H()
        sub = await c.create_subscription(10, h)
        # The publish loop's callback for this subscription, wrapped: the time the decoded
        # PublishResponse reaches the subscription, and the message's PublishTime.
        callbacks = c.uaclient.session._subscription_callbacks
        inner = callbacks[sub.subscription_id]
        recv, srv, seen = [], [], set()

        def wrapped(result):
            now = time.time()
            msg = result.NotificationMessage
            published = msg.PublishTime.timestamp() if msg.PublishTime else None
            for n in msg.NotificationData or []:
                if not isinstance(n, ua.DataChangeNotification):
                    continue
                for item in n.MonitoredItems:
                    if item.ClientHandle not in seen:
                        seen.add(item.ClientHandle)
                        continue
                    ts = item.Value.ServerTimestamp
                    if ts:
                        recv.append(now - ts.timestamp())
                        if published:
                            srv.append(published - ts.timestamp())
            return inner(result)

        callbacks[sub.subscription_id] = wrapped
        await sub.subscribe_data_change(nodes, queuesize=100, sampling_interval=10)
        await asyncio.sleep(seconds)
        await sub.delete()
        out["items"] = len(nodes)
        out["stages"] = {"srv": pct(srv), "recv": pct(recv), "lat": pct(h.lat)}
        out["notes"] = len(h.lat)


def rust_client(binary, url, seconds, out):
    r = subprocess.run([binary, url, str(seconds)], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{binary}: {r.stderr}")
    got = json.loads(r.stdout)
    out["items"] = got["items"]
    out["notes"] = got["notes"]
    out["stages"] = {"srv": got["srv"], "recv": got["lat"], "lat": got["lat"]}


def start_capture(port, path):
    """dumpcap on the loopback, server port only; None without tshark."""
    if not shutil.which("dumpcap"):
        return None
    p = subprocess.Popen(["dumpcap", "-q", "-i", "lo", "-f", f"tcp port {port}", "-w", path],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(1.0)
    return p


def socket_stage(port, path):
    """From the capture: per value of every PublishResponse the server sent, its frame time − its
    server timestamp (the first value of each client handle skipped, as the clients skip it), the
    same for the responses not sent on their request's arrival, and the share of data responses sent within 1 ms of their Publish request's arrival (the
    subscription had notifications but no request: the value waited for the client)."""
    fields = ["frame.time_epoch", "tcp.srcport", "opcua.servicenodeid.numeric",
              "opcua.RequestHandle", "opcua.ClientHandle", "opcua.datavalue.ServerTimestamp"]
    cmd = ["tshark", "-r", path, "-d", f"tcp.port=={port},opcua", "-Y", "opcua", "-T", "fields",
           "-E", "occurrence=a", "-E", "aggregator=;", "-t", "ud"]
    for f in fields:
        cmd += ["-e", f]
    r = subprocess.run(cmd, capture_output=True, text=True)
    out, own, seen, asked, data, waited = [], [], set(), {}, 0, 0
    for line in r.stdout.splitlines():
        cols = line.split("\t")
        if len(cols) < 6:
            continue
        t = float(cols[0])
        service = cols[2].split(";")[0]
        handle = cols[3].split(";")[0]
        if cols[1] != str(port):
            if service == "826":  # PublishRequest
                asked[handle] = t
            continue
        if service != "829" or not cols[5]:  # PublishResponse with values
            continue
        data += 1
        on_arrival = handle in asked and t - asked[handle] < 0.001
        waited += on_arrival
        for h, s in zip(cols[4].split(";"), cols[5].split(";")):
            if h not in seen:
                seen.add(h)
                continue
            out.append(t - parse_abs(s))
            if not on_arrival:
                own.append(t - parse_abs(s))
    return pct(out), pct(own), round(100 * waited / max(data, 1), 1)


def parse_abs(text):
    """tshark's absolute time in UTC ("2026-11-28 22:40:01.123456789" with -t ud, or
    "Nov 28, 2026 22:40:01.123456789 UTC")."""
    text = text.strip().removesuffix(" UTC")
    for fmt in ("%Y-%m-%d %H:%M:%S", "%b %d, %Y %H:%M:%S", "%Y-%m-%dT%H:%M:%S"):
        head, _, frac = text.partition(".")
        try:
            base = time.mktime(time.strptime(head, fmt)) - time.timezone
        except ValueError:
            continue
        return base + float("0." + (frac.rstrip("Z") or "0"))
    raise ValueError(f"tshark time {text!r}")


def one(args, variant):
    cmd = [args.ncplc, "run", args.machine, "--stats", "--no-watch", "--overrun-limit", "0",
           "--ticks", str(args.ticks)]
    if variant != "off":
        cmd += ["--opcua", "127.0.0.1:0"]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    got, err = {}, []
    cap = None
    if variant != "off":
        url = None
        for line in p.stderr:
            if line.startswith("opcua: "):
                url = line.split()[1]
                break
        port = int(url.rstrip("/").rsplit(":", 1)[1])
        threading.Thread(target=lambda: err.extend(p.stderr), daemon=True).start()
        if args.tshark:
            fd, path = tempfile.mkstemp(suffix=".pcapng")
            os.close(fd)
            cap = start_capture(port, path)
        seconds = args.ticks / 100 * 0.6
        # The client's CPU time: this process's for asyncua, the reaped child's for rust.
        cpu = lambda who: (lambda u: u.ru_utime + u.ru_stime)(resource.getrusage(who))
        who = resource.RUSAGE_SELF if variant == "asyncua" else resource.RUSAGE_CHILDREN
        before = cpu(who)
        if variant == "asyncua":
            asyncio.run(asyncua_client(url, seconds, got))
        else:
            rust_client(args.rust_client, url, seconds, got)
        got["client_cpu_s"] = round(cpu(who) - before, 2)
    out = p.stdout.read()
    _, status, ru = os.wait4(p.pid, 0)
    m = SCAN.search(out)
    if not m:
        sys.exit(f"no --stats in the output of {' '.join(cmd)}:\n{out}")
    p50, p99, p999, mx = (float(x) for x in m.groups())
    r = {"variant": variant, "p50": p50, "p99": p99, "p999": p999, "max": mx,
         "cpu_s": round(ru.ru_utime + ru.ru_stime, 2)}
    if variant != "off":
        stages = got["stages"]
        time.sleep(0.2)
        a = APPLY.search("".join(err))
        if a:
            stages["apply"] = {"p50": float(a.group(2)), "p99": float(a.group(3)),
                               "max": float(a.group(4))}
        if cap:
            cap.terminate()
            cap.wait()
            stages["sock"], stages["own"], r["waited_pct"] = socket_stage(port, path)
            os.unlink(path)
        r.update(items=got["items"], notes=got["notes"], client_cpu_s=got["client_cpu_s"])
        for stage in ["apply", "srv", "sock", "own", "recv", "lat"]:
            if stages.get(stage):
                for k, v in stages[stage].items():
                    r[f"{stage}_{k}"] = v
    return r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ncplc")
    ap.add_argument("machine")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--ticks", type=int, default=2000)
    ap.add_argument("--clients", default="asyncua,rust")
    ap.add_argument("--rust-client", default="target/release/examples/opcua_latency")
    ap.add_argument("--tshark", action="store_true")
    args = ap.parse_args()
    variants = ["off"] + [c for c in args.clients.split(",") if c]
    unknown = [v for v in variants if v not in ("off", "asyncua", "rust")]
    if unknown:
        sys.exit(f"--clients: unknown {', '.join(unknown)} (asyncua, rust)")
    if "rust" in variants and not os.access(args.rust_client, os.X_OK):
        sys.exit(f"{args.rust_client} is missing: cargo build --release -p opcua-server "
                 "--features latency --example opcua_latency (or --clients asyncua)")
    if args.tshark and not shutil.which("dumpcap"):
        sys.exit("--tshark: dumpcap is missing (apt-get install tshark)")
    rows = []
    for _ in range(args.runs):
        for v in variants:
            r = one(args, v)
            rows.append(r)
            print(r, flush=True)
    for v in variants:
        rs = [r for r in rows if r["variant"] == v]
        keys = [k for k in rs[0] if k != "variant" and all(k in r for r in rs)]
        print(v, {k: round(statistics.median(r[k] for r in rs), 3) for k in keys})


if __name__ == "__main__":
    main()
