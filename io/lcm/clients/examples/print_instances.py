#!/usr/bin/env python3
"""Prints where saccaded sees each instance, and each track's state changes:
python3 print_instances.py [URL] [FRAMES]. Act on TRACKING and RE-ACQUIRED only (docs/LCM.md)."""
import os
import sys

from saccade import detections_t
from saccade_lcm import DEFAULT_URL, Receiver


def short_name(model_name):
    """mug for /var/lib/saccade/models/mug.pcd; a spec such as synthetic:target as it is."""
    return os.path.splitext(os.path.basename(model_name))[0] or model_name


url = sys.argv[1] if len(sys.argv) > 1 else DEFAULT_URL
frames = int(sys.argv[2]) if len(sys.argv) > 2 else 0  # 0: until Ctrl-C
seen = 0
states = {}  # track id -> its last state
for channel, data in Receiver(url).messages({"SACCADE_DETECTIONS"}):
    d = detections_t.decode(data)
    for i in d.instances:
        name = short_name(i.model_name)
        if i.track_id >= 0 and states.get(i.track_id) != i.track_state_name:
            print("%s #%d: %s -> %s" % (name, i.track_id, states.get(i.track_id, "NEW"),
                                        i.track_state_name))
            states[i.track_id] = i.track_state_name
        x, y, z = i.centroid  # where the object is (trans is the model's origin)
        print("%s #%d %s at (%.3f, %.3f, %.3f) m in %s, confidence %.2f"
              % (name, i.track_id, i.track_state_name, x, y, z, d.frame, i.confidence))
    sys.stdout.flush()
    seen += d.num_instances > 0
    if frames and seen >= frames:
        break
