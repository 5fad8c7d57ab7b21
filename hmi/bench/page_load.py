#!/usr/bin/env python3
"""Page load of the web HMI in a real browser (Debian chromium + chromedriver), stdlib only.

Starts `ncplc run <machine> --hmi 127.0.0.1:0` (or uses --url), drives chromedriver over its
W3C WebDriver HTTP API and loads the HMI N times in a fresh tab each. For every load it reads,
from the page's own clock (performance.now(), ms since navigation start):
  dom   - DOMContentLoaded end,
  load  - the load event end (HTML, CSS, JS, uPlot),
  live  - the first live frame on screen (the status line carries a tick from /ws).
Prints one line per load and the median/max of each. The issue's target: page load < 1 s.

usage: hmi/bench/page_load.py [--ncplc PATH] [--machine DIR] [--runs N] [--extra "ARGS"]
"""
import argparse, json, os, re, shlex, socket, statistics, subprocess, sys, time, urllib.request

def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]

def wd(base, method, path, body=None):
    data = json.dumps(body).encode() if body is not None else None
    req = urllib.request.Request(base + path, data=data, method=method,
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=60) as r:
        return json.loads(r.read())["value"]

LIVE = """
const done = arguments[arguments.length - 1];
function probe() {
  const st = document.getElementById('status');
  if (st && st.dataset.tick) {
    const nav = performance.getEntriesByType('navigation')[0];
    done({dom: nav.domContentLoadedEventEnd, load: nav.loadEventEnd, live: performance.now()});
  } else setTimeout(probe, 1);
}
probe();
"""

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ncplc", default="target/release/ncplc")
    ap.add_argument("--machine", default="plc-programs/lathe")
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--extra", default="--program PART1")
    a = ap.parse_args()
    run = subprocess.Popen([a.ncplc, "run", a.machine, "--hmi", "127.0.0.1:0", "--no-watch",
                            "--overrun-limit", "0"] + shlex.split(a.extra),
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    url = None
    for line in run.stderr:
        m = re.match(r"hmi: (http://[^/\s]+/)", line)
        if m:
            url = m.group(1)
            break
    if not url:
        sys.exit("ncplc did not print its HMI address")
    port = free_port()
    drv = subprocess.Popen(["/usr/bin/chromedriver", f"--port={port}"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    base = f"http://127.0.0.1:{port}"
    try:
        for _ in range(300):
            try:
                wd(base, "GET", "/status"); break
            except OSError:
                time.sleep(0.1)
        caps = {"capabilities": {"alwaysMatch": {"goog:chromeOptions": {"args": [
            "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            "--no-first-run", "--window-size=1280,900"]}}}}
        sid = wd(base, "POST", "/session", caps)["sessionId"]
        wd(base, "POST", f"/session/{sid}/timeouts", {"script": 30000})
        rows = []
        for i in range(a.runs):
            wd(base, "POST", f"/session/{sid}/url", {"url": "about:blank"})
            wd(base, "POST", f"/session/{sid}/url", {"url": url})
            r = wd(base, "POST", f"/session/{sid}/execute/async", {"script": LIVE, "args": []})
            rows.append(r)
            print(f"load {i + 1}: dom {r['dom']:.1f} ms, load {r['load']:.1f} ms, live {r['live']:.1f} ms")
        for k in ("dom", "load", "live"):
            v = [r[k] for r in rows]
            print(f"{k}: median {statistics.median(v):.1f} ms, max {max(v):.1f} ms")
        wd(base, "DELETE", f"/session/{sid}")
    finally:
        drv.kill(); run.kill(); run.wait()

if __name__ == "__main__":
    main()
