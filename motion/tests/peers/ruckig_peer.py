#!/usr/bin/env python3
"""The reference Ruckig (PyPI `ruckig`) behind the same point-to-point semantics as
motion::PtpAxis, for motion/tests/it/ruckig_peer.rs.

stdin, one case per line:  v a j dt p0 ticks cmd...   (j = inf: no jerk limit)
  cmd = TICK:to:TARGET:V   move to TARGET at no more than V (capped by v)
      | TICK:jog:DIR:V     jog in direction DIR (-1, 0, 1) at V (capped); DIR 0 stops
stdout, one line per case: the position after every tick, as repr() floats.
"""
import math, sys

from ruckig import ControlInterface, InputParameter, OutputParameter, Result, Ruckig


def run(v, a, j, dt, p0, ticks, cmds):
    otg = Ruckig(1, dt)
    inp, out = InputParameter(1), OutputParameter(1)
    inp.current_position = [p0]
    inp.current_velocity = [0.0]
    inp.current_acceleration = [0.0]
    inp.max_velocity = [v]
    inp.max_acceleration = [a]
    inp.max_jerk = [j]
    goal = ("idle",)
    positions = []
    for t in range(ticks):
        for (at, kind, x, s) in cmds:
            if at != t:
                continue
            if kind == "to":
                inp.control_interface = ControlInterface.Position
                inp.target_position = [x]
                inp.target_velocity = [0.0]
                inp.target_acceleration = [0.0]
                inp.max_velocity = [min(abs(s), v)]
                goal = ("to", x)
            else:
                speed = math.copysign(1.0, x) * min(abs(s), v) if x != 0 else 0.0
                inp.control_interface = ControlInterface.Velocity
                inp.target_velocity = [speed]
                inp.target_acceleration = [0.0]
                inp.max_velocity = [v]
                goal = ("stop",) if speed == 0.0 else ("jog", speed)
        if goal[0] != "idle":
            try:
                r = otg.update(inp, out)
            except Exception:
                r = None
            if r == Result.Working:
                out.pass_to_input(inp)
            elif r == Result.Finished:
                out.pass_to_input(inp)
                if goal[0] == "to":
                    inp.current_position = [goal[1]]
                if goal[0] != "jog":
                    inp.current_velocity = [0.0]
                    inp.current_acceleration = [0.0]
                    goal = ("idle",)
            else:
                inp.current_velocity = [0.0]
                inp.current_acceleration = [0.0]
                goal = ("idle",)
        positions.append(inp.current_position[0])
    return positions


for line in sys.stdin:
    f = line.split()
    if not f:
        continue
    v, a, j, dt, p0 = (float(x) for x in f[:5])
    ticks = int(f[5])
    cmds = []
    for c in f[6:]:
        at, kind, x, s = c.split(":")
        cmds.append((int(at), kind, float(x), float(s)))
    print(" ".join(repr(p) for p in run(v, a, j, dt, p0, ticks, cmds)), flush=True)
