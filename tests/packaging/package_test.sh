#!/usr/bin/env bash
# The .deb as a user gets it (issue 19): built by CPack from BUILD_DIR, installed with dpkg,
# the unit checked by systemd-analyze, the daemon run from its installed paths as the user the
# package creates, the message types found by another CMake project, and the package purged.
# Needs root (dpkg); exits 77 (skipped) without it. It installs into the real /usr and /etc:
# the package is purged at the end, whatever happened.
set -euo pipefail
build_dir=$(cd "$1" && pwd)
fail() { echo "package test: $*" >&2; exit 1; }
[ "$(id -u)" = 0 ] || { echo "package test: needs root for dpkg; skipped" >&2; exit 77; }
# A machine where saccade is installed for real (a robot) keeps it: the test would purge it.
if dpkg-query -W -f='${Status}' saccade 2>/dev/null | grep -q "ok installed"; then
  echo "package test: saccade is installed on this machine; skipped, not to remove it" >&2
  exit 77
fi
work=$(mktemp -d)
trap 'dpkg --purge saccade >/dev/null 2>&1 || true; rm -rf "$work"' EXIT

(cd "$build_dir" && cpack -G DEB -B "$work" -D CPACK_OUTPUT_FILE_PREFIX="$work/packages" \
   >"$work/cpack.log" 2>&1) ||
  { cat "$work/cpack.log"; fail "cpack failed"; }
deb=$(ls "$work"/packages/saccade_*.deb)
dpkg -i "$deb" >"$work/dpkg.log" 2>&1 || { cat "$work/dpkg.log"; fail "dpkg -i failed"; }

# What postinst made: the user, in the camera groups, and the models' folder it owns.
id -nG saccade | grep -qw video || fail "user saccade is not in group video: $(id saccade)"
[ "$(stat -c %U /var/lib/saccade/models)" = saccade ] || fail "/var/lib/saccade/models not saccade's"
[ -f /etc/saccade/saccaded.yaml ] || fail "/etc/saccade/saccaded.yaml missing"
dpkg-query -W -f='${Conffiles}\n' saccade | grep -q /etc/saccade/saccaded.yaml ||
  fail "/etc/saccade/saccaded.yaml is not a conffile"

unit=/usr/lib/systemd/system/saccaded.service
grep -q '^ExecStart=/usr/bin/saccaded --config /etc/saccade/saccaded.yaml$' "$unit" ||
  fail "the unit's ExecStart: $(grep ExecStart "$unit")"
systemd-analyze verify "$unit" >"$work/verify.log" 2>&1 ||
  { cat "$work/verify.log"; fail "systemd-analyze verify $unit"; }

# The installed daemon, as the service runs it: the installed config, user saccade.
/usr/bin/saccaded --version | grep -q "^saccaded " || fail "saccaded --version"
runuser -u saccade -- /usr/bin/saccaded --config /etc/saccade/saccaded.yaml \
  --source 'synthetic:static?frames=12&rate=0' --model synthetic:target \
  --lcm-url 'udpm://239.255.76.67:7699?ttl=0' >"$work/run.out" 2>"$work/run.err" ||
  { cat "$work/run.err"; fail "the installed saccaded failed"; }
grep -q "run: 12 frames processed" "$work/run.err" || { cat "$work/run.err"; fail "not 12 frames"; }

# The installed viewer finds its installed page (it refuses to start without one) and listens.
[ -f /usr/share/saccade/web/vendor/three.module.js ] || fail "the viewer's three.js is not installed"
timeout -s INT 3 /usr/bin/saccade view --port 0 --lcm-url 'udpm://239.255.76.67:7699?ttl=0' \
  >"$work/view.out" 2>"$work/view.err" || true
grep -q "^saccade view: open http://127.0.0.1:" "$work/view.out" ||
  { cat "$work/view.err"; fail "the installed saccade view did not start"; }

# Another project finds the message types.
mkdir -p "$work/client"
cat >"$work/client/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(client CXX)
find_package(saccade REQUIRED)
add_executable(client client.cc)
target_link_libraries(client PRIVATE saccade::lcmtypes)
CMAKE
cat >"$work/client/client.cc" <<'CC'
#include <saccade/detections_t.hpp>
int main() {
  saccade::detections_t d{};
  return d.getEncodedSize() > 0 ? 0 : 1;
}
CC
(cmake -S "$work/client" -B "$work/client/build" && cmake --build "$work/client/build" &&
   "$work/client/build/client") >"$work/client.log" 2>&1 ||
  { cat "$work/client.log"; fail "find_package(saccade) did not give the types"; }

dpkg --purge saccade >"$work/purge.log" 2>&1 || { cat "$work/purge.log"; fail "dpkg --purge"; }
[ ! -e /usr/bin/saccaded ] || fail "/usr/bin/saccaded left after purge"
echo "package test: $(basename "$deb") installed, verified, ran 12 frames as saccade, purged"
