# msm_sim developer entry points. The repository root is the catkin package; it is built in a
# catkin workspace under build/ws (ignored by git).
#
#   make demo   install dependencies, build, run the robot demo headless, print a summary and
#               plot it (build/demo/demo.png)
#   make lab    the same, then the materials lab on a default block
#   make test   install dependencies, build, run every gtest and rostest, fail on any failure
#   make bench  build and run the Google Benchmarks and the Python ones (bench/)
#   make validate  the accuracy and speed checks, written to docs/validation.md with figures
#   make soak   10 simulated minutes of random pushes on two objects (not part of `make test`)
#   make test-sanitize  the core and lab gtests under AddressSanitizer and UBSan (build/ws-sanitize)
#   make fuzz   libFuzzer on the mesh and model-file readers, FUZZ_SECONDS each (build/fuzz, clang)

SHELL := /bin/bash
ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
WS := $(ROOT)/build/ws
# Debian's catkin and genmsg need Debian's python3; a pyenv python3 earlier in PATH breaks them.
export PATH := /usr/bin:/bin:$(PATH)
CATKIN_MAKE := catkin_make -C $(WS) -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3
JOBS ?= -j2

.PHONY: deps workspace build demo lab test test-sanitize soak fuzz bench validate format clean

deps:
	@$(ROOT)/scripts/install_dependencies.sh

# src/msm_sim mirrors the package's top-level entries as symlinks, all but build/: a symlink to
# the whole repository would contain the workspace itself and loop tools that walk the package
# directory (rosrun, roslaunch's find).
# $(call link_package,<workspace>): the symlink layout, for build/ws and build/ws-sanitize.
define link_package
	@if [ -L $(1)/src/msm_sim ]; then rm $(1)/src/msm_sim; fi
	@mkdir -p $(1)/src/msm_sim
	@for entry in $(ROOT)/*; do \
	  name=$$(basename "$$entry"); \
	  if [ "$$name" != build ]; then ln -sfn "$$entry" "$(1)/src/msm_sim/$$name"; fi; \
	done
	@find $(1)/src/msm_sim -maxdepth 1 -xtype l -delete
endef

workspace:
	$(call link_package,$(WS))

build: deps workspace
	$(CATKIN_MAKE) $(JOBS)

# The robot demo, headless for 10 s: a finger presses into the default soft block and drags
# across it; prints the node count, the peak fingertip force, the real-time factor and the final
# energy, and writes build/demo/demo.csv and build/demo/demo.png (force and real-time factor
# against time). run_demo.py ends the launch once the summary is done (exit 0).
DEMO_DURATION ?= 10
demo: build
	source $(WS)/devel/setup.bash && rosrun msm_sim run_demo.py duration:=$(DEMO_DURATION) \
	  output_dir:=$(ROOT)/build/demo

# The materials lab on a default block (what `make demo` ran before the node existed).
lab: build
	source $(WS)/devel/setup.bash && rosrun msm_sim msm_lab compression --model cubic \
	  --size 2 1 1 --spacing 0.0625 --youngs 1e5 --poisson 0.25 --density 1100

# The accuracy and speed checks (scripts/validate.py): every figure of docs/validation.md and
# docs/figures/validation/, stamped with the commit, the date and the machine.
validate: build
	/usr/bin/python3 $(ROOT)/scripts/validate.py --lab $(WS)/devel/lib/msm_sim/msm_lab \
	  --bullet $(WS)/devel/lib/msm_sim/msm_sim_bullet_benchmark --out $(ROOT)/docs/validation.md

# Tests run one at a time: the rostests pace nodes to ROS time, and two of them sharing the two
# cores let a node fall behind the clock (it then drops simulated time and is not the
# simulation the test expects; the robot drag test failed that way under -j2).
test: build
	rm -rf $(WS)/build/test_results
	$(CATKIN_MAKE) -j1 run_tests
	catkin_test_results --verbose $(WS)/build/test_results

# The core and lab gtests built with AddressSanitizer and UndefinedBehaviorSanitizer
# (MSM_SIM_SANITIZE, RelWithDebInfo) in their own workspace, run one after another. Every
# sanitizer report goes to a file under $(SAN_LOGS) (forked children and msm_lab runs included,
# whose exit codes the tests check), and the target fails when any test fails or any report
# was written. A sanitizer error exits with code 86, never with a code a test expects.
SAN_WS := $(ROOT)/build/ws-sanitize
SAN_LOGS := $(SAN_WS)/sanitizer-reports
SAN_TESTS := test_core_units test_dynamics test_calibration test_lab_cli
SAN_ENV := ASAN_OPTIONS=exitcode=86:detect_leaks=1:log_path=$(SAN_LOGS)/asan \
  LSAN_OPTIONS=suppressions=$(ROOT)/test/fuzz/lsan_suppressions.txt \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:log_path=$(SAN_LOGS)/ubsan
test-sanitize: deps
	$(call link_package,$(SAN_WS))
	catkin_make -C $(SAN_WS) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMSM_SIM_SANITIZE=ON \
	  -DPYTHON_EXECUTABLE=/usr/bin/python3 $(JOBS) $(SAN_TESTS) msm_lab
	rm -rf $(SAN_LOGS) && mkdir -p $(SAN_LOGS)
	status=0; for t in $(SAN_TESTS); do \
	  echo "== $$t"; \
	  $(SAN_ENV) $(SAN_WS)/devel/lib/msm_sim/$$t || { echo "FAILED: $$t"; status=1; }; \
	done; \
	if [ -n "$$(ls -A $(SAN_LOGS))" ]; then \
	  echo "sanitizer reports:"; cat $(SAN_LOGS)/*; status=1; fi; \
	exit $$status

# libFuzzer targets for the readers of untrusted files (test/fuzz/, built with clang and ASan +
# UBSan in build/fuzz, outside the catkin workspace): each runs FUZZ_SECONDS from a seed corpus
# (the test cube in every mesh format, a small model file), 5 s and 1 GB per input at most, and
# the target fails on any crash, hang, leak, sanitizer report or unexpected exception; the
# offending input is kept in build/fuzz/ (crash-*, timeout-*, oom-*).
FUZZ_DIR := $(ROOT)/build/fuzz
FUZZ_SECONDS ?= 60
fuzz: deps
	cmake -S $(ROOT)/test/fuzz -B $(FUZZ_DIR) -DCMAKE_CXX_COMPILER=clang++ \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo
	cmake --build $(FUZZ_DIR) $(JOBS)
	rm -rf $(FUZZ_DIR)/corpus && mkdir -p $(FUZZ_DIR)/corpus/mesh $(FUZZ_DIR)/corpus/model
	$(FUZZ_DIR)/write_seed_corpus $(FUZZ_DIR)/corpus/mesh $(FUZZ_DIR)/corpus/model
	for target in mesh_import:mesh model_file:model; do \
	  LSAN_OPTIONS=suppressions=$(ROOT)/test/fuzz/lsan_suppressions.txt \
	  $(FUZZ_DIR)/$${target%%:*}_fuzzer -seed=1 -max_total_time=$(FUZZ_SECONDS) -timeout=5 \
	    -rss_limit_mb=1024 -print_final_stats=1 -artifact_prefix=$(FUZZ_DIR)/ \
	    $(FUZZ_DIR)/corpus/$${target##*:} || exit 1; \
	done

# The Bullet comparison is built when libbullet-dev is present (the dependency script installs it).
bench: build
	$(WS)/devel/lib/msm_sim/msm_sim_benchmarks
	if [ -x $(WS)/devel/lib/msm_sim/msm_sim_bullet_benchmark ]; then \
	  $(WS)/devel/lib/msm_sim/msm_sim_bullet_benchmark; fi
	source $(WS)/devel/setup.bash && \
	  python3 $(ROOT)/bench/python_step_benchmark.py $(WS)/devel/lib/msm_sim/msm_world_reference && \
	  python3 $(ROOT)/bench/sweep_scaling_benchmark.py

format:
	clang-format -i $$(git -C $(ROOT) ls-files '*.cpp' '*.h')

clean:
	rm -rf $(ROOT)/build

# Issue "Hardening": the core World under 10 simulated minutes of random pushes up to 100 object
# weights, on the default block and a random-lattice bean; prints the figures (a few minutes).
soak: build
	$(CATKIN_MAKE) -j1 test_soak
	$(WS)/devel/lib/msm_sim/test_soak
