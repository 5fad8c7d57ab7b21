#!/usr/bin/env python3
"""What a WebSocket client reading the HMI at 20 Hz costs the scan: alternated real-time runs of
`ncplc run MACHINE --program PART --until-end --stats` without the HMI (`off`), with the HMI and
no client (`idle`) and with the HMI and ws_client.py reading /ws at 20 Hz (`20hz`). Prints, per
run, the scan-time percentiles of `--stats` and the process's CPU time (every thread: scan,
server, render), then the medians per variant.

Usage: scan_cost.py NCPLC MACHINE [--program PART1] [--runs 3] [--port 18950] [--ticks N]

The figure for the issue's target is the scan time (`--stats`: from waking to the end of the
tick's latch, scan and publish), which a client can only slow through the other threads on the
same cores; the scan thread's own part of a publish is a copy measured separately (callgrind, see
the README row).
"""

import argparse
import os
import re
import signal
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SCAN = re.compile(r"scan time\s+p50\s+([\d.]+) µs\s+p99\s+([\d.]+) µs\s+p99.9\s+([\d.]+) µs\s+max\s+([\d.]+) µs")
TICKS = re.compile(r"ticks (\d+)\s+overruns (\d+)")


def one(args, variant, port):
    # No trip on overruns (a loaded machine overruns now and then: the run must go on), and a
    # cap on the ticks in case the part does not end.
    cmd = [args.ncplc, "run", args.machine, "--program", args.program, "--stats", "--no-watch",
           "--overrun-limit", "0"]
    cmd += ["--ticks", str(args.ticks)] if args.ticks else ["--until-end", "--ticks", "8000"]
    if variant != "off":
        cmd += ["--hmi", f"127.0.0.1:{port}"]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    client = None
    if variant == "20hz":
        client = subprocess.Popen(
            [sys.executable, os.path.join(HERE, "ws_client.py"), f"127.0.0.1:{port}", "--hz", "20", "--ack"],
            stdout=subprocess.PIPE, text=True)
    out = p.stdout.read()
    _, status, ru = os.wait4(p.pid, 0)
    frames = ""
    if client:
        # The socket may still hold frames the client has not read: stop it now.
        client.send_signal(signal.SIGTERM)
        frames = client.communicate(timeout=30)[0].strip()
    m, t = SCAN.search(out), TICKS.search(out)
    if not m or not t:
        sys.exit(f"no --stats in the output of {' '.join(cmd)}:\n{out}")
    p50, p99, p999, mx = (float(x) for x in m.groups())
    return {
        "variant": variant,
        "ticks": int(t.group(1)),
        "overruns": int(t.group(2)),
        "p50": p50, "p99": p99, "p999": p999, "max": mx,
        "cpu_s": ru.ru_utime + ru.ru_stime,
        "client": frames,
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ncplc")
    ap.add_argument("machine")
    ap.add_argument("--program", default="PART1")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--port", type=int, default=18950)
    ap.add_argument("--ticks", type=int, default=0, help="0: until the part ends")
    args = ap.parse_args()
    rows = []
    for k in range(args.runs):
        for variant in ("off", "idle", "20hz"):
            r = one(args, variant, args.port + len(rows))
            rows.append(r)
            print(f"{variant:5} ticks {r['ticks']} overruns {r['overruns']} scan p50 {r['p50']:.2f} "
                  f"p99 {r['p99']:.2f} p99.9 {r['p999']:.2f} max {r['max']:.2f} µs  cpu {r['cpu_s']:.2f} s  {r['client']}",
                  flush=True)
            time.sleep(1)
    print("median per variant:")
    for variant in ("off", "idle", "20hz"):
        v = [r for r in rows if r["variant"] == variant]
        med = lambda key: statistics.median(r[key] for r in v)
        print(f"{variant:5} scan p50 {med('p50'):.2f} µs  p99 {med('p99'):.2f} µs  p99.9 {med('p999'):.2f} µs  "
              f"cpu {med('cpu_s'):.2f} s")


if __name__ == "__main__":
    main()
