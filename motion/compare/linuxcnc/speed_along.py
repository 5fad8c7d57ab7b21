"""Compares the path speed of two runs of one program along the programmed path: for each
sampled point (one per 1 ms servo period / tick, `x y z` per line) the distance along the
programmed polyline of its nearest programmed segment, and the speed there; prints, per
window of the path (default 1 mm), the time each run spent in it and the lowest speed.
Usage: speed_along.py PROGRAM.ngc LINUXCNC.txt NCPLC.txt [WINDOW_MM]"""
import math
import sys


def program(path):
    pts = []
    for line in open(path):
        if line.startswith(("G0 ", "G1 ")):
            d = {}
            for w in line.split()[1:]:
                if w[0] in "XYZ":
                    d[w[0]] = float(w[1:])
            pts.append(tuple(d[k] for k in "XYZ"))
    return pts[1:]  # after the rapid to the start: the G1 path from pts[0]


def samples(path):
    s = [tuple(map(float, l.split())) for l in open(path) if l.strip()]
    moving = [i for i in range(1, len(s)) if s[i] != s[i - 1]]
    # the last stretch of motion (LinuxCNC: after the rapid and the 1 s dwell)
    start = prev = moving[0]
    for i in moving[1:]:
        if i - prev > 500:
            start = i
        prev = i
    return s[start - 1 : prev + 1]


def along(pts, s):
    """Arc length along the polyline of each sample (nearest segment, searched forward)."""
    cum = [0.0]
    for a, b in zip(pts, pts[1:]):
        cum.append(cum[-1] + math.dist(a, b))
    out, k = [], 0
    for p in s:
        best = None
        for j in range(max(0, k - 3), min(len(pts) - 1, k + 60)):
            a, b = pts[j], pts[j + 1]
            ab = [b[i] - a[i] for i in range(3)]
            n = sum(x * x for x in ab)
            t = 0.0 if n == 0 else max(0.0, min(1.0, sum(ab[i] * (p[i] - a[i]) for i in range(3)) / n))
            d = math.dist(p, [a[i] + t * ab[i] for i in range(3)])
            if best is None or d < best[0]:
                best = (d, j, cum[j] + t * math.sqrt(n))
        k = best[1]
        out.append(best[2])
    return out, cum[-1]


def main():
    pts = program(sys.argv[1])
    win = float(sys.argv[4]) if len(sys.argv) > 4 else 1.0
    runs = []
    for f in sys.argv[2:4]:
        s = samples(f)
        a, total = along(pts, s)
        v = [0.0] + [math.dist(s[i], s[i - 1]) / 0.001 for i in range(1, len(s))]
        runs.append((a, v))
    nwin = int(total / win) + 1
    stats = []
    for a, v in runs:
        t = [0] * nwin
        lo = [math.inf] * nwin
        for x, sp in zip(a, v):
            w = min(nwin - 1, int(x / win))
            t[w] += 1
            lo[w] = min(lo[w], sp)
        stats.append((t, lo))
    print(f"{'from mm':>8} {'lcnc ms':>8} {'ncplc ms':>8} {'diff':>6} {'lcnc vmin':>9} {'ncplc vmin':>10}")
    tot = [0, 0]
    for w in range(nwin):
        (t0, l0), (t1, l1) = stats[0], stats[1]
        tot[0] += t0[w]
        tot[1] += t1[w]
        print(f"{w * win:8.1f} {t0[w]:8d} {t1[w]:8d} {t1[w] - t0[w]:6d} {l0[w]:9.1f} {l1[w]:10.1f}")
    print(f"total ms: LinuxCNC {tot[0]}, ncplc {tot[1]}")


main()
