# A thin wrapper over CMake. `make demo` and `make test` install missing Debian packages first.
MAKEFLAGS += --no-print-directory
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release -DSACCADE_WERROR=ON

.PHONY: all deps configure build package install demo test bench bench-stages bench-daemon bench-track bench-peer eval-xcap \
        eval-xcap-search eval-xcap-ppf fuzz asan-build test-asan soak clean

all: build

deps:
	@./scripts/install-deps.sh

configure: deps
	@[ -f $(BUILD_DIR)/CMakeCache.txt ] || echo "saccade: first build: it installs what is" \
	  "missing from Debian and builds Saccade, about 15 minutes on 2 cores" >&2
	@cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS) > $(BUILD_DIR).configure.log 2>&1 || \
	  (cat $(BUILD_DIR).configure.log; exit 1)

build: configure
	@./scripts/build.sh $(BUILD_DIR) $(JOBS)

# A .deb of the programs, configs, unit, docs and message types (build/packages/); see
# "Run it as a service" in the README.
package: build
	@cd $(BUILD_DIR) && cpack -G DEB > cpack.log 2>&1 || (cat cpack.log; exit 1)
	@ls $(BUILD_DIR)/packages/*.deb

install: build
	@cmake --install $(BUILD_DIR)

# saccaded on the synthetic Kinect: a target that moves, hides and comes back, over LCM, with
# saccade view beside it (the address is printed; DEMO_PORT=N for another port than 8080).
demo: build
	@./scripts/multicast-route.sh
	@./scripts/demo.sh $(BUILD_DIR)

# One line per test as it ends; the output of a failing one; the count at the end.
test: build
	@cd $(BUILD_DIR) && ctest --progress --output-on-failure -j $(JOBS)

# Speed on the real milk scene (needs ../shared/data); see docs/BENCHMARKS.md.
bench: build
	@./scripts/bench.sh $(BUILD_DIR)

# Google Benchmark over the hot stages on the synthetic Kinect (no data needed).
bench-stages: build
	@OMP_WAIT_POLICY=passive $(BUILD_DIR)/tests/bench/saccade_stage_bench

# saccaded against a 30 Hz virtual OpenNI2 camera; see docs/BENCHMARKS.md.
bench-daemon: build
	@./scripts/bench-daemon.sh $(BUILD_DIR)

# Tracking on every sequence (synthetic, and real captures re-rendered when ../shared/data is
# there) at 30 Hz: tracked share, re-acquisition, drops; JSON lines last. docs/BENCHMARKS.md.
bench-track: build
	@./scripts/bench-track.sh $(BUILD_DIR)

# ViSP's model-based tracker (installed from Debian when missing) beside Saccade's on the ViSP
# cube's real frames: error and time per frame of each. docs/BENCHMARKS.md.
bench-peer: build
	@./scripts/bench-peer.sh $(BUILD_DIR)

# The cross-capture benchmark (needs ../shared/data/mosd_xcap), all three protocols, with the
# stock PCL peer: writes eval-xcap/report.md, the tables of docs/RESULTS.md (about 20 minutes).
eval-xcap: build
	@OMP_WAIT_POLICY=passive $(BUILD_DIR)/daemon/saccade eval \
	  --cases ../shared/data/mosd_xcap/cases_with_pose.yaml --data ../shared/data \
	  --configs configs/xcap-configs.yaml --protocols a,b,c --reference saccade --out eval-xcap

# Issue 34's search against the paper's on the same benchmark, protocols a, b, c, with colour
# (eval-xcap-search/colour) and without (eval-xcap-search/no-colour): docs/RESULTS.md, "Finding
# it anywhere" (about 20 minutes).
eval-xcap-search: build
	@OMP_WAIT_POLICY=passive $(BUILD_DIR)/daemon/saccade eval \
	  --cases ../shared/data/mosd_xcap/cases_with_pose.yaml --data ../shared/data \
	  --configs configs/xcap-search-configs.yaml --protocols a,b,c --out eval-xcap-search/colour
	@OMP_WAIT_POLICY=passive $(BUILD_DIR)/daemon/saccade eval \
	  --cases ../shared/data/mosd_xcap/cases_with_pose.yaml --data ../shared/data \
	  --configs configs/xcap-search-configs.yaml --protocols a,b,c --no-colour \
	  --out eval-xcap-search/no-colour

# OpenCV's PPF matcher on every 4th case of the same benchmark: it trains each model for about
# 16 s and matches a scene in about 2 s, 238 cases would take over an hour (about 20 minutes).
eval-xcap-ppf: build
	@OMP_WAIT_POLICY=passive $(BUILD_DIR)/daemon/saccade eval \
	  --cases ../shared/data/mosd_xcap/cases_with_pose.yaml --data ../shared/data \
	  --configs configs/xcap-peer-configs.yaml --every 4 --out eval-xcap-ppf

# libFuzzer on the PCD check and the LCM command decoder, FUZZ_SECONDS (60) each; see
# docs/RELIABILITY.md. Installs Debian's clang-14 and libfuzzer-14-dev when missing.
fuzz: build
	@./scripts/fuzz.sh $(BUILD_DIR)

# Every target under AddressSanitizer, LeakSanitizer and UBSan, in its own folder; see
# docs/RELIABILITY.md (the first build takes about 25 minutes on 2 cores).
ASAN_BUILD_DIR ?= build-asan
asan-build: deps
	@cmake -S . -B $(ASAN_BUILD_DIR) -DCMAKE_BUILD_TYPE=Release -DSACCADE_SANITIZE=ON \
	  > $(ASAN_BUILD_DIR).configure.log 2>&1 || (cat $(ASAN_BUILD_DIR).configure.log; exit 1)
	@cmake --build $(ASAN_BUILD_DIR) -j $(JOBS)

# The whole suite on the sanitized build; any report fails the test that ran into it.
test-asan: asan-build
	@./scripts/multicast-route.sh
	@./scripts/test-asan.sh $(ASAN_BUILD_DIR)

# saccaded under ASan/LSan on a looping real capture for MINUTES (10): the memory's slope and
# any leak at exit (needs ../shared/data); see docs/RELIABILITY.md.
MINUTES ?= 10
soak: asan-build
	@./scripts/multicast-route.sh
	@MINUTES=$(MINUTES) ./scripts/soak.sh $(ASAN_BUILD_DIR)

clean:
	@rm -rf $(BUILD_DIR) $(BUILD_DIR).configure.log $(ASAN_BUILD_DIR) $(ASAN_BUILD_DIR).configure.log
