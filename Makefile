# The two front-door commands: `make demo` and `make test`. Both install the Debian
# packages they need, build the package in a catkin workspace inside the repository
# (.ws/, git-ignored) and run with Debian's python3 (the pyenv one on PATH cannot see ROS).
SHELL := /bin/bash
.SHELLFLAGS := -eo pipefail -c

PKG := ohm_mirror_detector3d
WS := $(CURDIR)/.ws
export PATH := /usr/bin:/bin:$(PATH)
export ROS_HOME := $(WS)/.ros
export ROS_HOSTNAME := 127.0.0.1
export ROS_LOG_DIR := $(WS)/.ros/log
BUILD_TYPE ?= Release
# Extra CMake arguments of the build (`make bench` adds -DOHM_BUILD_BENCH=ON).
CMAKE_EXTRA ?=

APT_PACKAGES := build-essential cmake ros-base-dev librosbag-dev libyaml-cpp-dev libpcl-dev libpcl-conversions-dev \
  libtf2-ros-dev libtf2-eigen-dev python3-rostest python3-dynamic-reconfigure \
  python3-sensor-msgs python3-geometry-msgs python3-visualization-msgs python3-tf2-ros python3-tf2-msgs \
  python3-numpy python3-matplotlib python3-pytest libgtest-dev rosbash tf2-tools \
  libtopic-tools-dev python3-genpy pybind11-dev python3-pybind11 python3-dev python3-yaml python3-venv \
  libdiagnostic-updater-dev python3-diagnostic-msgs rviz xvfb xauth imagemagick xdotool catkin-lint

SOURCE_WS := source $(WS)/devel/setup.bash

.PHONY: all deps build test demo bench evaluate evaluate-moving test-compat print-apt-packages clean fuzz fuzz-build test-sanitize soak
all: build

# Installs only what is missing, so a prepared machine pays one dpkg-query.
deps:
	@missing=$$(for p in $(APT_PACKAGES); do \
	    dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:" $$missing; \
	  sudo=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$sudo apt-get update -qq; \
	  DEBIAN_FRONTEND=noninteractive $$sudo apt-get install -y -qq --no-install-recommends $$missing; \
	fi

build: deps
	@mkdir -p $(WS)/src $(WS)/devel/lib/python3/dist-packages $(ROS_LOG_DIR)
	@# The package in the workspace is a folder of links to the repository's entries, all but
	@# the workspace itself: a link to the whole repository would contain .ws again, and
	@# rosrun's `find -L` would walk that loop and find every executable many times.
	@if [ -L $(WS)/src/$(PKG) ]; then rm $(WS)/src/$(PKG); fi
	@mkdir -p $(WS)/src/$(PKG)
	@find $(WS)/src/$(PKG) -maxdepth 1 -type l ! -exec test -e {} \; -delete
	@for entry in $(CURDIR)/* $(CURDIR)/.ci; do \
	  case "$${entry##*/}" in .ws|demo_output) ;; *) ln -sfn "$$entry" $(WS)/src/$(PKG)/ ;; esac; done
	cd $(WS) && catkin_make all tests -j2 -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) \
	  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
	  -DCATKIN_ENABLE_TESTING=ON $(CMAKE_EXTRA) > $(WS)/build.log 2>&1 || { tail -n 60 $(WS)/build.log; exit 1; }
	@echo "built $(PKG) in $(WS) (log: $(WS)/build.log)"

# ctest, not `catkin_make run_tests`: the latter exits 0 when tests fail. Two tests at a time:
# half the serial time on 2 cores (CMakeLists.txt says which test runs alone and which start first).
test: build
	$(SOURCE_WS) && cd $(WS)/build && ctest -j2 --output-on-failure

# With Xvfb, rviz runs on a virtual screen and its picture is saved as demo_output/rviz.png.
demo: build
	$(SOURCE_WS) && port=$$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])') && \
	  export ROS_MASTER_URI=http://127.0.0.1:$$port && \
	  if command -v xvfb-run >/dev/null && command -v Xvfb >/dev/null; then \
	    xvfb-run -a -s "-screen 0 1024x768x24" roslaunch -p $$port --screen $(PKG) demo.launch \
	      out:=$(CURDIR)/demo_output rviz:=true screenshot:=$(CURDIR)/demo_output/rviz.png; \
	  else \
	    echo "no Xvfb: the demo runs without rviz"; \
	    roslaunch -p $$port --screen $(PKG) demo.launch out:=$(CURDIR)/demo_output; \
	  fi

# Not part of `make test`: a Release build with the bench binary, then the measurements
# (table on stdout, bench/results.json): 8 sweeps x 22 runs of our pipeline, the PCL baseline on
# the same sweeps (slow: a few runs), resident set after 10,000 sweeps, and the latency of the
# real nodelet in a nodelet manager, with the driver in the same manager and in another process
# (own masters on free ports). About ten minutes.
# Then issue 14's frames (bench/side_by_side.py: 1080 x 400 with objects, a 64 x 600 dual-return frame
# through filter_dual_return), beside another build's when BENCH_OTHER names its dist-packages
# (e.g. BENCH_OTHER=/path/to/main/.ws/devel/lib/python3/dist-packages).
BENCH_OTHER ?=
bench:
	$(MAKE) build BUILD_TYPE=Release CMAKE_EXTRA=-DOHM_BUILD_BENCH=ON
	$(SOURCE_WS) && /usr/bin/python3 bench/run_bench.py --binary $(WS)/devel/lib/$(PKG)/bench_pipeline \
	  --output $(CURDIR)/bench/results.json
	$(SOURCE_WS) && /usr/bin/python3 bench/side_by_side.py $(if $(BENCH_OTHER),--other $(BENCH_OTHER))

# Not part of `make test`: the filter (the Python bindings, no master) on EVALUATE_SCENES random scenes per
# sensor family of SENSORS.md plus the named scenes, realistic physics, scored against the ground truth
# with issue 14's targets beside the figures: table on stdout, EVALUATE_OUT/evaluation.md and .json.
# EVALUATE_ARGS adds options, e.g. --params launch/rotating_hokuyo_params.yaml --families hokuyo --seed 100.
EVALUATE_SCENES ?= 50
EVALUATE_OUT ?= $(CURDIR)/evaluation/latest
EVALUATE_ARGS ?=
evaluate:
	$(MAKE) build BUILD_TYPE=Release
	$(SOURCE_WS) && nice /usr/bin/python3 -m ohm_mirror_detector3d.scene_evaluation --scenes $(EVALUATE_SCENES) \
	  --out $(EVALUATE_OUT) $(EVALUATE_ARGS)

# Not part of `make test` nor of `make evaluate` (about 15-25 min here): the filter over the sweeps of a
# moving sensor (src/ohm_mirror_detector3d/moving_evaluation.py): MOVING_SCENES random walks of
# MOVING_SWEEPS sweeps per sensor family plus the passes of experiment 2's glass door, a wall mirror
# and a mirror facing open space; table on stdout, MOVING_OUT/moving.md and .json. MOVING_ARGS adds
# options, e.g. --pass-pose (a pipeline that takes each sweep's pose).
MOVING_SCENES ?= 5
MOVING_SWEEPS ?= 8
MOVING_OUT ?= $(CURDIR)/evaluation/moving_latest
MOVING_ARGS ?=
evaluate-moving:
	$(MAKE) build BUILD_TYPE=Release
	$(SOURCE_WS) && nice /usr/bin/python3 -m ohm_mirror_detector3d.moving_evaluation --scenes $(MOVING_SCENES) \
	  --sweeps $(MOVING_SWEEPS) --out $(MOVING_OUT) $(MOVING_ARGS)

# Not part of `make test`: build and ctest in a Debian 11 (bullseye) chroot, the toolchain closest
# to ROS Noetic robots (gcc 10, PCL 1.11, Python 3.9), plus vermin for Python 3.8. The chroot
# lives in .compat/ (git-ignored, ~4 GB) and is reused; the first run took 18 min here
# (packages, build), later ones 2.5 min (6 min when CMakeLists.txt or package.xml changed).
test-compat:
	@missing=$$(for p in debootstrap python3-venv; do \
	    dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  sudo=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$sudo apt-get update -qq; \
	  DEBIAN_FRONTEND=noninteractive $$sudo apt-get install -y -qq --no-install-recommends $$missing; \
	fi
	test/compat/run_compat.sh

# For test/compat/run_compat.sh, which installs the same list inside the chroot.
print-apt-packages:
	@echo $(APT_PACKAGES)

# The core gtests, the ROS input-conversion gtests and the fuzz corpus replay built with
# -fsanitize=address,undefined in .ws/sanitize (the catkin build stays as it is) and run.
test-sanitize: build
	$(SOURCE_WS) && test/run_sanitized_tests.sh $(CURDIR) $(WS) $(WS)/sanitize

# Not part of `make test`: SOAK_SWEEPS small sweeps through the real nodelet in a manager, lockstep;
# fails when the manager's RSS grows by more than 1 MB between sweep 100 and the last. A few minutes.
SOAK_SWEEPS ?= 10000
soak: build
	$(SOURCE_WS) && rostest --text $(CURDIR)/test/soak/soak.test sweeps:=$(SOAK_SWEEPS)

# Not part of `make test`: the libFuzzer target (test/fuzz/fuzz_entry.h) built with clang outside
# catkin into .ws/fuzz, run for FUZZ_SECONDS on one core. New inputs go to .ws/fuzz/corpus; the
# committed seeds (test/fuzz/corpus) and grown corpus (test/fuzz/corpus_grown) are read. A crash
# leaves its reproducer in .ws/fuzz/artifacts (copy it to test/fuzz/crashes: `make test` replays
# all three folders).
FUZZ_SECONDS ?= 60
FUZZ_DIR := $(WS)/fuzz
FUZZ_PACKAGES := clang libclang-rt-14-dev libfuzzer-14-dev
fuzz-build: build
	$(MAKE) deps APT_PACKAGES="$(FUZZ_PACKAGES)"
	test/fuzz/build_fuzz.sh $(CURDIR) $(WS) $(FUZZ_DIR)

fuzz: fuzz-build
	mkdir -p $(FUZZ_DIR)/corpus $(FUZZ_DIR)/artifacts
	$(SOURCE_WS) && UBSAN_OPTIONS=print_stacktrace=1 $(FUZZ_DIR)/fuzz_prefilter $(FUZZ_DIR)/corpus $(CURDIR)/test/fuzz/corpus $(CURDIR)/test/fuzz/corpus_grown \
	  -max_total_time=$(FUZZ_SECONDS) -max_len=8192 -rss_limit_mb=2048 -timeout=120 -print_final_stats=1 \
	  -artifact_prefix=$(FUZZ_DIR)/artifacts/ 2>&1 | tee $(FUZZ_DIR)/last_run.log

clean:
	rm -rf $(WS)
