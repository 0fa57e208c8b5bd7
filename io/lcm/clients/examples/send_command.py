#!/usr/bin/env python3
"""Sends saccaded one signed command:
python3 send_command.py URL KEY_FILE pause|resume|reset|fovea X Y Z (docs/LCM.md)."""
import sys
import time

from saccade import command_t
from saccade_lcm import Sender, read_key, sign

if len(sys.argv) < 4:
    sys.exit("usage: send_command.py URL KEY_FILE pause|resume|reset|fovea X Y Z")
url, key, kind = sys.argv[1], read_key(sys.argv[2]), sys.argv[3]
m = command_t()
m.utime = int(time.time() * 1e6)
m.sequence = 0  # a program sending several commands counts them: 0, 1, 2, ...
m.kind = {"pause": command_t.PAUSE, "resume": command_t.RESUME, "reset": command_t.RESET,
          "fovea": command_t.SET_FOVEA}[kind]
if kind == "fovea":
    m.fovea = [float(v) for v in sys.argv[4:7]]
Sender(url).publish("SACCADE_COMMAND", sign(m.encode(), key))
print("sent %s, signed" % kind)
