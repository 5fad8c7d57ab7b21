#!/usr/bin/env python3
"""Whether Nagle's algorithm holds the server's PublishResponses back: one real-time run of
`ncplc run MACHINE --ticks 1000 --opcua` with the asyncua client of scan_cost.py (100 items at
10 ms) for 6 s, captured on the loopback (dumpcap: apt-get install tshark, root or CAP_NET_RAW);
counts the PublishResponses that reached the wire more than 5 ms after their PublishTime, and how
many of them left within 0.5 ms after a pure ACK (no payload) of the client — the signature of
Nagle waiting for the ACK of the previous segment.

Usage (from the repository root): opcua-server/bench/nagle.py NCPLC [MACHINE]
"""
import asyncio
import os
import subprocess
import sys
import tempfile
import threading

sys.dont_write_bytecode = True  # no __pycache__ beside the scripts
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scan_cost as sc  # noqa: E402


def main():
    binary = sys.argv[1]
    machine = sys.argv[2] if len(sys.argv) > 2 else "plc-programs/lathe"
    p = subprocess.Popen([binary, "run", machine, "--no-watch", "--overrun-limit", "0", "--ticks", "1000",
                          "--opcua", "127.0.0.1:0"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    for line in p.stderr:
        if line.startswith("opcua: "):
            url = line.split()[1]
            break
    threading.Thread(target=p.stderr.read, daemon=True).start()
    port = int(url.rstrip("/").rsplit(":", 1)[1])
    fd, path = tempfile.mkstemp(suffix=".pcapng")
    os.close(fd)
    cap = sc.start_capture(port, path)
    got = {}
    asyncio.run(sc.asyncua_client(url, 6, got))
    p.wait(); cap.terminate(); cap.wait()
    r = subprocess.run(["tshark", "-r", path, "-d", f"tcp.port=={port},opcua", "-T", "fields",
                        "-e", "frame.time_epoch", "-e", "tcp.srcport", "-e", "tcp.len",
                        "-e", "opcua.PublishTime", "-E", "occurrence=f", "-t", "ud"],
                       capture_output=True, text=True)
    rows = []
    for l in r.stdout.splitlines():
        c = l.split("\t")
        rows.append((float(c[0]), c[1] == str(port), int(c[2] or 0), c[3]))
    late = after_ack = 0
    for i, (t, from_srv, n, pub) in enumerate(rows):
        if from_srv and pub and n > 0:
            gap = t - sc.parse_abs(pub)
            if gap > 0.005:
                late += 1
                prev = rows[i - 1]
                if not prev[1] and prev[2] == 0 and t - prev[0] < 0.0005:
                    after_ack += 1
    print(f"responses sent >5 ms after their PublishTime: {late}; of them right after (<0.5 ms) a pure ACK of the client: {after_ack}")
    os.unlink(path)


if __name__ == "__main__":
    main()
