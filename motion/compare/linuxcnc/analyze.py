"""Motion time of each LinuxCNC run (servo periods from the first to the last moving sample of
the program, after the rapid and the 1 s dwell), its ratio to issue 10's lower bound, the peak
axis speed/acceleration (finite differences) and the tolerance checks (largest distance of a
sample from the programmed polyline; largest distance of a programmed corner from the sampled
path), beside ncplc's time from the same programs."""
import math
import re
import sys

work = sys.argv[1]
DT = 0.001
ours = {}
for line in open(f"{work}/ncplc.txt"):
    name, t, lb = line.split()
    ours[name] = (float(t), float(lb))


def program(name):
    pts = []
    for line in open(f"{work}/{name}.ngc"):
        if line.startswith(("G0 ", "G1 ")):
            d = dict(re.findall(r"([XYZ])(-?[0-9.]+)", line))
            pts.append(tuple(float(d[k]) for k in "XYZ"))
    return pts


def dseg(p, a, b):
    ab = [b[i] - a[i] for i in range(3)]
    ap = [p[i] - a[i] for i in range(3)]
    n = sum(x * x for x in ab)
    t = 0.0 if n == 0 else max(0.0, min(1.0, sum(ab[i] * ap[i] for i in range(3)) / n))
    return math.sqrt(sum((ap[i] - t * ab[i]) ** 2 for i in range(3)))


def last_motion(samples):
    moving = [i for i in range(1, len(samples)) if samples[i] != samples[i - 1]]
    start = prev = moving[0]
    for i in moving[1:]:
        if i - prev > 500:
            start = i
        prev = i
    return samples[start - 1 : prev + 1]


for name in ours:
    s = last_motion([tuple(map(float, l.split())) for l in open(f"{work}/{name}.txt") if l.strip()])
    t = (len(s) - 1) * DT
    v = max(abs(s[i][k] - s[i - 1][k]) / DT for i in range(1, len(s)) for k in range(3))
    a = max(abs(s[i + 1][k] - 2 * s[i][k] + s[i - 1][k]) / DT / DT for i in range(1, len(s) - 1) for k in range(3))
    dev = corner = float("nan")
    if name != "circles":  # polylines only
        p = program(name)
        j, dev = 0, 0.0
        for q in s:
            best, bj = min((dseg(q, p[k], p[k + 1]), k) for k in range(max(0, j - 3), min(len(p) - 1, j + 60)))
            j, dev = bj, max(dev, best)
        i0, corner = 0, 0.0
        for vtx in p[1:-1]:
            i = i0
            while i < len(s) and math.dist(s[i], vtx) > 0.2:
                i += 1
            best, bi = min((dseg(vtx, s[k], s[k + 1]), k) for k in range(max(0, i - 1), min(len(s) - 1, i + 200)))
            i0, corner = bi, max(corner, best)
    ot, lb = ours[name]
    print(f"{name:>12}: LinuxCNC {t:7.3f} s = {t / lb:.4f} x bound (peak v {v:.1f} mm/s, a {a:.0f} mm/s2, "
          f"deviation {dev * 1000:.2f} um, corner miss {corner * 1000:.2f} um) | ncplc {ot:7.3f} s = {ot / lb:.4f} | bound {lb:.3f} s")
