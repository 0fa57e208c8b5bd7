#!/usr/bin/env python3
"""Prints where saccaded sees each instance: python3 print_instances.py [URL] [FRAMES]"""
import sys

from saccade import detections_t
from saccade_lcm import DEFAULT_URL, Receiver

url = sys.argv[1] if len(sys.argv) > 1 else DEFAULT_URL
frames = int(sys.argv[2]) if len(sys.argv) > 2 else 0  # 0: until Ctrl-C
seen = 0
for channel, data in Receiver(url).messages({"SACCADE_DETECTIONS"}):
    d = detections_t.decode(data)
    for i in d.instances:
        x, y, z = i.centroid  # where the object is (trans is the model's origin)
        print("%s at (%.3f, %.3f, %.3f) m in %s, confidence %.2f"
              % (i.model_name, x, y, z, d.frame, i.confidence))
    seen += d.num_instances > 0
    if frames and seen >= frames:
        break
