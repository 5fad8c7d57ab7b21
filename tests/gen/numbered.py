#!/usr/bin/env python3
"""Numbered partprograms of a given size (issue 23: a program whose blocks carry `N` numbers), seeded.

Usage: tests/gen/numbered.py NC_DIR [MEGABYTES] [SEED]

Writes, in NC_DIR (e.g. the `nc/` folder of a copy of plc-programs/lathe):
  DENSEN.nc    MEFI `%1`, then blocks N1, N2, ... alternating `N<i> G01 X<a>. K1.` (K has no
               meaning in MEFI blocks: error 2038 on every other block) and a jump back
               `N<i> G73 L<1 + i/2 mod 5000>`; no M02/M30 (warning 2032)
  DENSENF.nc   Fanuc `O0001`, then `N<i> G01 X<a>. E1.` (address E is refused: error 2008 on
               every block)
  DENSEMF.nc   Fanuc `O0001`, then alternating a Macro B block `N<i> #1 = #1 + <k>` and
               `N<i> G01 X<a>. E1.` (2008 on every other block)
  VALIDN.nc    a valid MEFI lathe program: `%1`, `N1 G01 X0 Z0 F100.`, then
               `N<i> G01 X<a>. Z<b>.` and last `N<k> M30`
Each file is MEGABYTES (default 50) long (VALIDN.nc a block more); the same SEED (default 1)
gives the same bytes. Measure with `/usr/bin/time -v ncplc nc check MACHINE NC_DIR/DENSEN.nc`,
`... --dialect fanuc NC_DIR/DENSENF.nc` (and DENSEMF.nc) and `ncplc run MACHINE --program NC_DIR/<file> --ticks 10
--virtual-time`.
"""
import os
import random
import sys

nc = sys.argv[1]
size = int(float(sys.argv[2]) * 1_000_000) if len(sys.argv) > 2 else 50_000_000
SEED = int(sys.argv[3]) if len(sys.argv) > 3 else 1


def fill(path, head, block, tail=""):
    rng = random.Random(SEED)
    with open(path, "w", encoding="latin-1") as f:
        f.write(head)
        n, i = len(head), 1
        while n < size:
            text = block(rng, i)
            f.write(text)
            n += len(text)
            i += 1
        f.write(tail.format(i=i))


fill(os.path.join(nc, "DENSEN.nc"), "%1\n",
     lambda r, i: f"N{i} G01 X{r.randrange(100)}. K1.\n" if i % 2
     else f"N{i} G73 L{1 + (i // 2) % 5000}\n")
fill(os.path.join(nc, "DENSENF.nc"), "O0001\n",
     lambda r, i: f"N{i} G01 X{r.randrange(100)}. E1.\n")
fill(os.path.join(nc, "DENSEMF.nc"), "O0001\n",
     lambda r, i: f"N{i} #1 = #1 + {r.randrange(7)}\n" if i % 2
     else f"N{i} G01 X{r.randrange(100)}. E1.\n")
fill(os.path.join(nc, "VALIDN.nc"), "%1\n",
     lambda r, i: f"N{i} G01 X0 Z0 F100.\n" if i == 1
     else f"N{i} G01 X{r.randrange(100)}. Z{-r.randrange(100)}.\n",
     "N{i} M30\n")
