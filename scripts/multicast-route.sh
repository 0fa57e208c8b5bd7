#!/usr/bin/env bash
# LCM's default URL (udpm://239.255.76.67:7667?ttl=0) needs a route for multicast. On a robot
# the LAN's route does; on a build machine without one, route multicast through loopback.
# Idempotent; needs root only when the route is missing.
set -euo pipefail
if ip route get 239.255.76.67 >/dev/null 2>&1 && ip route show 224.0.0.0/4 | grep -q .; then
  exit 0
fi
if ! ip route show 224.0.0.0/4 | grep -q .; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "saccade: no multicast route; as root run: ip route add 224.0.0.0/4 dev lo" >&2
    exit 1
  fi
  ip route add 224.0.0.0/4 dev lo
  echo "saccade: added the multicast route 224.0.0.0/4 dev lo (for LCM with ttl=0)" >&2
fi
