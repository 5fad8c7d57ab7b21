#!/usr/bin/env python3
"""Error-dense inputs that are well formed line by line (issue 23, item 4), seeded.

Usage: tests/gen/error_dense.py MACHINE_COPY [MEGABYTES] [SEED]

Overwrites, in the machine directory MACHINE_COPY (a copy of plc-programs/lathe):
  MP0/AXCFIL       its own records, then valid and unknown records alternating (`NAS=X` /
                   `QZQ<n>=1`) in section 3 up to MEGABYTES
  MP0/PGCFIL       its own records, then a duplicated `MAS=XZ` (101) and an instruction section 6
                   does not allow (`QZQ<n>=1`, 6) alternating
  MP0/IOCFIL       its own records, then a duplicated `T01=<n>` (101) and `QZQ<n>=1` (6)
                   alternating in section 4
  nc/DENSE.nc      a partprogram alternating two lines of words (`G01 X.. F100.`, `G01 Q..`);
                   they carry no `N`, so in MEFI every word is error 2004 (outside a block)
  nc/DENSEF.nc     a Fanuc partprogram `O0001` then two lines alternating: two MEFI declarations
                   `R<n>=1.` (2033 each) and `N-<n> O1.5` (2009, 2003); no line makes a block
  MP0/PLCPRG.dense the PLC program followed by lines alternating a valid and an undefined name
Each file is MEGABYTES (default 50) long; the same SEED (default 1) gives the same bytes.
Measure with `/usr/bin/time -v ncplc check MACHINE_COPY --max-errors 100` (the characterization
files; AXCFIL is read first, so to measure PGCFIL or IOCFIL alone put the lathe's own AXCFIL
back), `ncplc nc check MACHINE_COPY nc/DENSE.nc`, `ncplc nc check MACHINE_COPY nc/DENSEF.nc
--dialect fanuc`, `ncplc build MACHINE_COPY --plc MP0/PLCPRG.dense`.
"""
import os
import random
import sys


def fill(path, head, pair, size):
    rng = random.Random(SEED)
    with open(path, "w", encoding="latin-1") as f:
        f.write(head)
        n = len(head)
        while n < size:
            text = pair(rng)
            f.write(text)
            n += len(text)


machine = sys.argv[1]
size = int(float(sys.argv[2]) * 1_000_000) if len(sys.argv) > 2 else 50_000_000
SEED = int(sys.argv[3]) if len(sys.argv) > 3 else 1

ax = os.path.join(machine, "MP0", "AXCFIL")
with open(ax, encoding="latin-1") as f:
    base = f.read()
fill(ax, base.rstrip("\n") + "\n",
     lambda r: f"NAS=X\nQZQ{r.randrange(10)}=1\n", size)

pg = os.path.join(machine, "MP0", "PGCFIL")
with open(pg, encoding="latin-1") as f:
    base = f.read()
fill(pg, base.rstrip("\n") + "\n",
     lambda r: f"MAS=XZ\nQZQ{r.randrange(10)}=1\n", size)

io = os.path.join(machine, "MP0", "IOCFIL")
with open(io, encoding="latin-1") as f:
    base = f.read()
fill(io, base.rstrip("\n") + "\n",
     lambda r: f"T01={r.randrange(10, 100)}\nQZQ{r.randrange(10)}=1\n", size)

fill(os.path.join(machine, "nc", "DENSEF.nc"), "O0001\n",
     lambda r: f"R{r.randrange(1, 10)}=1. R{r.randrange(1, 10)}=2.\nN-{r.randrange(1, 100)} O1.5\n", size)

fill(os.path.join(machine, "nc", "DENSE.nc"), "%\n",
     lambda r: f"G01 X{r.randrange(100)}. F100.\nG01 Q{r.randrange(100)}.\n", size)

plc = os.path.join(machine, "MP0", "PLCPRG")
with open(plc, encoding="latin-1") as f:
    base = f.read()
fill(plc + ".dense", base.rstrip("\n") + "\n",
     lambda r: f"P1 = I0A0\nP1 = NOSUCH{r.randrange(1000)}\n", size)
