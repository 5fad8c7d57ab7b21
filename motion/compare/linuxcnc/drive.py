#!/usr/bin/python3
"""LinuxCNC display stand-in: homes, runs $LCNC_PROG in auto mode and records every servo
period's joint positions (HAL sampler) to $LCNC_OUT, then turns the machine off."""
import os
import subprocess
import sys
import time

import linuxcnc

prog, out = os.environ["LCNC_PROG"], os.environ["LCNC_OUT"]
s, c, e = linuxcnc.stat(), linuxcnc.command(), linuxcnc.error_channel()
c.state(linuxcnc.STATE_ESTOP_RESET); c.wait_complete(10)
c.state(linuxcnc.STATE_ON); c.wait_complete(10)
c.mode(linuxcnc.MODE_MANUAL); c.wait_complete(10)
c.teleop_enable(0); c.wait_complete(10)
c.home(-1); c.wait_complete(10)
for _ in range(500):
    s.poll()
    if all(s.homed[i] for i in range(3)):
        break
    time.sleep(0.01)
c.mode(linuxcnc.MODE_AUTO); c.wait_complete(10)
with open(out, "w") as f:
    sampler = subprocess.Popen(["halsampler", "-c", "0"], stdout=f)
    c.program_open(prog); c.wait_complete(10)
    c.auto(linuxcnc.AUTO_RUN, 0)
    time.sleep(0.5)
    while True:
        s.poll()
        err = e.poll()
        if err:
            print("linuxcnc error:", err, file=sys.stderr)
        if s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0 and s.current_vel == 0:
            break
        time.sleep(0.05)
    time.sleep(0.3)
    sampler.terminate()
    sampler.wait()
c.state(linuxcnc.STATE_OFF)
