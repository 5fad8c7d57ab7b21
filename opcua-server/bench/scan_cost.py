#!/usr/bin/env python3
"""What the OPC UA server with a subscribed client costs the scan, and how late a tick's value
reaches the client: alternated real-time runs of `ncplc run MACHINE --ticks N --stats` without
the server (`off`) and with `--opcua` and an asyncua client holding 100 monitored items (Tick and
99 signal bytes) at a 10 ms publishing and sampling interval (`opcua`). Prints, per run, the scan
percentiles of `--stats` and the process's CPU time, for `opcua` the client's notifications and
its latency tick→client: receive time minus the value's server timestamp (the wall-clock time at
which the scan copied that tick's image; same machine, same clock); then the medians per variant.

Usage: scan_cost.py NCPLC MACHINE [--runs 3] [--ticks 2000]
"""

import argparse
import asyncio
import os
import re
import statistics
import subprocess
import sys
import threading
import time

SCAN = re.compile(r"scan time\s+p50\s+([\d.]+) µs\s+p99\s+([\d.]+) µs\s+p99.9\s+([\d.]+) µs\s+max\s+([\d.]+) µs")


async def client(url, seconds, out):
    from asyncua import Client

    class H:
        def __init__(self):
            self.lat = []
            self.seen = set()

        def datachange_notification(self, node, val, data):
            dv = data.monitored_item.Value
            # The first notification of an item is its current value, stamped when it last
            # changed (maybe seconds ago): not a latency.
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
        await sub.subscribe_data_change(nodes, queuesize=100, sampling_interval=10)
        await asyncio.sleep(seconds)
        await sub.delete()
        out["items"] = len(nodes)
        out["lat"] = h.lat


def one(args, variant):
    cmd = [args.ncplc, "run", args.machine, "--stats", "--no-watch", "--overrun-limit", "0",
           "--ticks", str(args.ticks)]
    if variant == "opcua":
        cmd += ["--opcua", "127.0.0.1:0"]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    got = {}
    if variant == "opcua":
        url = None
        for line in p.stderr:
            if line.startswith("opcua: "):
                url = line.split()[1]
                break
        threading.Thread(target=p.stderr.read, daemon=True).start()
        asyncio.run(client(url, args.ticks / 100 * 0.6, got))
    out = p.stdout.read()
    _, status, ru = os.wait4(p.pid, 0)
    m = SCAN.search(out)
    if not m:
        sys.exit(f"no --stats in the output of {' '.join(cmd)}:\n{out}")
    p50, p99, p999, mx = (float(x) for x in m.groups())
    r = {"variant": variant, "p50": p50, "p99": p99, "p999": p999, "max": mx,
         "cpu_s": ru.ru_utime + ru.ru_stime}
    if got.get("lat"):
        lat = sorted(got["lat"])
        r.update(items=got["items"], notes=len(lat), lat_p50_ms=1000 * lat[len(lat) // 2],
                 lat_p99_ms=1000 * lat[int(len(lat) * 0.99)], lat_max_ms=1000 * lat[-1])
    return r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ncplc")
    ap.add_argument("machine")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--ticks", type=int, default=2000)
    args = ap.parse_args()
    rows = []
    for i in range(args.runs):
        for v in ["off", "opcua"]:
            r = one(args, v)
            rows.append(r)
            print(r, flush=True)
    for v in ["off", "opcua"]:
        rs = [r for r in rows if r["variant"] == v]
        keys = [k for k in rs[0] if k != "variant"]
        print(v, {k: round(statistics.median(r[k] for r in rs), 3) for k in keys})


if __name__ == "__main__":
    main()
