# lever: the two commands.
#   make demo   set up, build, and check the lesson's arm model
#   make test   set up, build, and run every test
BUILD ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
LEVER = $(BUILD)/tools/lever/lever

.PHONY: all setup configure build demo test clean

all: build

setup:
	@scripts/setup.sh

configure: setup
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release > $(BUILD).configure.log || (cat $(BUILD).configure.log; exit 1)

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# make demo builds only what it runs: the lever command and the libraries it links (make test
# builds the rest: the tests, the benchmarks' smoke tests, the Python package)
demo: configure
	@cmake --build $(BUILD) -j $(JOBS) --target lever_cli
	$(LEVER) check models/arm2.xml

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

# make test-asan: the whole suite again in a Debug build (assertions on, Eigen's bounds checks
# included; -O1, as ASan recommends, so that the MuJoCo comparisons run in minutes) with
# AddressSanitizer and UndefinedBehaviorSanitizer (-fno-sanitize-recover=all: any finding fails
# its test). -g1: line tables only, which is what the sanitizers' reports print (file:line);
# with full debug info the instrumented build took twice as long. The test code itself is built
# at -O0 (LEVER_TEST_COMPILE_OPTIONS; the libraries under test keep -O1): the largest test file
# took 800 s with -g -O1, 370 s with -g1 -O1 and 215 s with -g1 -O0 (a loaded machine). Eigen's
# eigensolver and SVDs, the heaviest templates the tests use, are compiled once in
# tests/support/spectra_*.cpp. The benchmarks are left out (make bench measures them; their smoke
# tests run in make test). MuJoCo, KDL
# and tinyxml2 are Debian's prebuilt libraries, not instrumented. .ci/run runs it after make test.
# The Python package is left out: an instrumented extension cannot load into Debian's
# uninstrumented python3 (the sanitizer runtime must come first in the process). So are the
# browser tests: their engine is the WebAssembly build, which the sanitizers do not reach.
# The tests that draw random states or run for seconds draw a quarter of them under the sanitizers
# (tests/support/sampling.hpp): the same code paths, at a quarter of the time; make test draws all.
ASAN_BUILD ?= build-asan
# Left out under the sanitizers, to keep .ci/run within its 30 minutes: the slowest end-to-end
# tests (each 40-260 s instrumented), whose every code path a lighter test of the same run also
# takes (lever check on arm2 and panda7 section by section; identification on clean data, whose
# every identify() call runs the physical fit too, where the recorded Panda's 88 s instrumented
# are Eigen's QR and SVD of a large regressor; one step of each integrator at random states; the
# derivatives against MuJoCo; the elliptic cones' lockstep runs for the Newton solver, whose
# random-state comparison mostly times MuJoCo's own solver, uninstrumented). make test runs them.
# The packaging tests are not built (tests/packaging/CMakeLists.txt says why).
ASAN_SKIP = a real Panda that MuJoCo recorded|elliptic cones agree with MuJoCo at random states|how far MuJoCo's default tolerance moves its answer|every model loads, exits 0 or 1|noisy data, estimates within|lever identify says when the estimate is not physical|servos in sections|spectral radii, timesteps|noisy torques, an estimate|RK4 conserves energy|singular values, manipulability|A and B match central differences of step|lockstep trajectories, one RK4|lockstep trajectories, one implicit
.PHONY: test-asan
test-asan: setup
	@cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g1 -O1" \
	  -DLEVER_SANITIZE="address;undefined" -DLEVER_BUILD_PYTHON=OFF -DLEVER_WEB_TESTS=OFF \
	  -DLEVER_BUILD_BENCH=OFF -DLEVER_TEST_COMPILE_OPTIONS=-O0 \
	  > $(ASAN_BUILD).configure.log || (cat $(ASAN_BUILD).configure.log; exit 1)
	@cmake --build $(ASAN_BUILD) -j $(JOBS)
	ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --test-dir $(ASAN_BUILD) --output-on-failure -j $(JOBS) -E "$(ASAN_SKIP)"

clean:
	rm -rf $(BUILD) $(BUILD).configure.log

# make test-ray: tests/python/test_ray.py, a real local Ray cluster (a head and two worker nodes on
# 127.0.0.1) against the single-process BatchRunner. Not part of make test: pip's ray is some 360 MB
# and took 67 s to install (once, into $(BUILD)/venv-ray), the cluster about 10 s to start.
.PHONY: test-ray
test-ray: configure
	@cmake --build $(BUILD) -j $(JOBS) --target lever_python lever_cli
	tests/python/venv.sh wheel $(BUILD) .
	tests/python/venv.sh ray $(BUILD)
	cd tests/python && PYTHONDONTWRITEBYTECODE=1 $(abspath $(BUILD))/venv-ray/bin/python -m pytest -q -p no:cacheprovider test_ray.py

# make bench: lever against MuJoCo 2.2.2, Orocos KDL and Pinocchio (pip's pin, installed into
# $(BENCH_BUILD)/venv-pinocchio; without it the benchmarks run without Pinocchio and say so)
# (bench/), built in Release in its own folder, run with repetitions and random interleaving, then every operation's instructions per
# call counted by callgrind (bench/instructions.py, about two minutes); writes docs/performance.md.
# Run it on a quiet machine (`uptime`): the time ratios are only as good as the load allows (the
# instruction counts do not depend on it).
# make bench-instructions: the instruction counts alone (any load), into $(BENCH_BUILD)/
# instructions.json; docs/performance.md is rewritten with them if a timing run is there.
BENCH_BUILD ?= build-bench
BENCH_REPETITIONS ?= 10
BENCH_MIN_TIME ?= 0.05
BENCH_FLAGS ?=
BENCH_ITERATIONS ?= 1000
LEVER_COMMIT = $(shell git rev-parse --short HEAD 2>/dev/null || echo unknown)$(shell git diff --quiet HEAD -- engine 2>/dev/null || echo +uncommitted-engine-changes)
# the report from whatever measurements are there: times (needed), instruction counts, the
# browser peer (make web-bench); written to a temporary file first, so that a failure leaves
# the document as it was
define bench_report
args="$(BENCH_BUILD)/bench.json --check $(BENCH_BUILD)/bench-check.md"; \
  [ -f $(BENCH_BUILD)/instructions.json ] && args="$$args --instructions $(BENCH_BUILD)/instructions.json"; \
  [ -f $(WEB_BUILD)/web-bench.json ] && args="$$args --web $(WEB_BUILD)/web-bench.json"; \
  if $(BENCH_BUILD)/bench/lever_bench_report $$args > docs/performance.md.part; then \
    mv docs/performance.md.part docs/performance.md && echo "wrote docs/performance.md"; \
  else rm -f docs/performance.md.part; exit 1; fi
endef
.PHONY: bench bench-build bench-instructions
bench-build: setup
	@scripts/setup.sh bench
	@cmake -S . -B $(BENCH_BUILD) -DCMAKE_BUILD_TYPE=Release -DLEVER_BUILD_BENCH=ON -DLEVER_BENCH_PINOCCHIO=ON > $(BENCH_BUILD).configure.log || (cat $(BENCH_BUILD).configure.log; exit 1)
	@grep "Pinocchio" $(BENCH_BUILD).configure.log || true
	@cmake --build $(BENCH_BUILD) -j $(JOBS) --target lever_bench lever_bench_report lever_bench_profile
bench: bench-build
	@$(BENCH_BUILD)/bench/lever_bench --check > $(BENCH_BUILD)/bench-check.md || (cat $(BENCH_BUILD)/bench-check.md; exit 1)
	$(BENCH_BUILD)/bench/lever_bench --benchmark_repetitions=$(BENCH_REPETITIONS) \
	  --benchmark_min_time=$(BENCH_MIN_TIME) --benchmark_enable_random_interleaving=true \
	  --benchmark_display_aggregates_only=true \
	  --benchmark_out=$(BENCH_BUILD)/bench.json --benchmark_out_format=json \
	  --benchmark_context=lever_commit=$(LEVER_COMMIT) \
	  $(BENCH_FLAGS)
	bench/instructions.py --profile $(BENCH_BUILD)/bench/lever_bench_profile \
	  --iterations $(BENCH_ITERATIONS) --commit $(LEVER_COMMIT) \
	  --out $(BENCH_BUILD)/instructions.json models/*.xml tests/models/sensors.xml bench/scenes/*.xml
	@$(bench_report)
bench-instructions: bench-build
	bench/instructions.py --profile $(BENCH_BUILD)/bench/lever_bench_profile \
	  --iterations $(BENCH_ITERATIONS) --commit $(LEVER_COMMIT) \
	  --out $(BENCH_BUILD)/instructions.json models/*.xml tests/models/sensors.xml bench/scenes/*.xml
	@if [ -f $(BENCH_BUILD)/bench.json ] && [ -f $(BENCH_BUILD)/bench-check.md ]; then $(bench_report); \
	  else echo "bench-instructions: no timing run in $(BENCH_BUILD) (make bench): docs/performance.md left as it is"; fi

# make agreement: lever against MuJoCo 2.2.2 on every model (random states, lockstep trajectories,
# free runs); writes docs/agreement.md. Quantities beyond the 1e-12 bound are written into the
# document as FAIL without stopping it (lever diff exits 1); a model that cannot be loaded stops it.
.PHONY: agreement
agreement: configure
	@cmake --build $(BUILD) -j $(JOBS) --target lever_cli
	@$(LEVER) diff --markdown models/*.xml tests/models/*.xml > docs/agreement.md; status=$$?; \
	  [ $$status -le 1 ] || exit $$status; \
	  echo "wrote docs/agreement.md (lever diff: exit status $$status)"

# make fuzz: the libFuzzer targets (fuzz/) built with clang++-14 under ASan+UBSan in build-fuzz,
# each run for FUZZ_SECONDS (default 60) from a seed corpus made from the models; prints the
# executions and findings of each, and fails on a finding. Needs clang-14 and libclang-rt-14-dev
# (installed by scripts/setup.sh fuzz when missing).
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 60
.PHONY: fuzz fuzz-build
fuzz-build:
	@scripts/setup.sh fuzz
	@CXX=clang++-14 cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLEVER_FUZZ=ON \
	  -DLEVER_SANITIZE="address;undefined" -DLEVER_BUILD_TESTS=OFF -DLEVER_BUILD_TOOLS=OFF \
	  -DLEVER_BUILD_BENCH=OFF -DLEVER_WITH_MUJOCO=OFF > $(FUZZ_BUILD).configure.log || (cat $(FUZZ_BUILD).configure.log; exit 1)
	@cmake --build $(FUZZ_BUILD) -j $(JOBS) --target fuzz_mjcf fuzz_engine fuzz_dict
fuzz: fuzz-build
	@BUILD=$(FUZZ_BUILD) FUZZ_SECONDS=$(FUZZ_SECONDS) fuzz/run.sh

# make lint: clang-tidy (.clang-tidy) and cppcheck over lever's own code: engine/, mjcf_lite/,
# tools/, tests/, examples/, fuzz/, bench/. Uses the compile commands of $(BUILD).
# make format-check: clang-format (.clang-format) would change no file; make format rewrites them.
LINT_SOURCES = $(shell git ls-files 'engine/*.cpp' 'mjcf_lite/*.cpp' 'plot/*.cpp' 'io/*.cpp' 'check/*.cpp' 'lab/*.cpp' 'identify/*.cpp' 'harness/*.cpp' 'tools/*.cpp' 'tests/*.cpp' 'examples/*.cpp' 'fuzz/*.cpp' 'bench/*.cpp')
FORMAT_FILES = $(shell git ls-files '*.cpp' '*.hpp' '*.h')
.PHONY: lint format format-check
lint: build
	@scripts/setup.sh lint
	run-clang-tidy-14 -p $(BUILD) -quiet -j $(JOBS) $(addprefix $(CURDIR)/,$(filter-out fuzz/fuzz_%.cpp,$(LINT_SOURCES)))
	cppcheck --std=c++20 --language=c++ --enable=warning,performance,portability --inline-suppr \
	  --suppress=missingIncludeSystem --suppress=missingInclude --quiet -j $(JOBS) --error-exitcode=1 \
	  -I engine/include -I mjcf_lite/include -I plot/include -I io/include -I check/include -I lab/include -I identify/include -I tools/diff/include \
	  -I harness/include \
	  -I tests/support -I fuzz "-DTEST_CASE(...)=void test_case()" "-DSECTION(...)=if (true)" \
	  "-DDYNAMIC_SECTION(...)=if (true)" $(LINT_SOURCES)
format-check:
	@scripts/setup.sh lint
	@clang-format-14 --dry-run --Werror $(FORMAT_FILES) && echo "format-check: $(words $(FORMAT_FILES)) files formatted"
format:
	@scripts/setup.sh lint
	clang-format-14 -i $(FORMAT_FILES)

# make web: lever compiled to WebAssembly with Emscripten (emcmake; tests, tools and benchmarks off)
# into build-web/: build-web/web/wasm/lever_wasm.{js,wasm}, the lab's engine (web/wasm). Emscripten's
# JS optimizer needs Debian's node-acorn on NODE_PATH.
# make lab: builds it and serves the lab (web/) on 127.0.0.1, printing the page's URL (LAB_PORT=0:
# a free port).
# make web-bench: one lab step (forward + step) timed natively and in WebAssembly; then lever's
# WebAssembly lab step against MuJoCo's official WebAssembly build (npm mujoco-js, pinned by
# web/bench/package-lock.json, installed into $(WEB_BUILD)/web-bench-peer by this target only) in
# one node process (web/bench/peer_step_time.mjs), into $(WEB_BUILD)/web-bench.json; docs/
# performance.md is rewritten with it if a `make bench` run is there.
WEB_BUILD ?= build-web
WEB_PEER = $(WEB_BUILD)/web-bench-peer
WEB_BENCH_MODELS ?= models/arm2.xml models/panda7.xml
LAB_PORT ?= 0
WEB_ENV = NODE_PATH=/usr/share/nodejs
.PHONY: web lab web-bench
web: setup
	@$(WEB_ENV) emcmake cmake -S . -B $(WEB_BUILD) -DCMAKE_BUILD_TYPE=Release -DLEVER_BUILD_TESTS=OFF \
	  -DLEVER_BUILD_TOOLS=OFF -DLEVER_BUILD_BENCH=OFF -DLEVER_WITH_MUJOCO=OFF \
	  > $(WEB_BUILD).configure.log || (cat $(WEB_BUILD).configure.log; exit 1)
	@$(WEB_ENV) cmake --build $(WEB_BUILD) -j $(JOBS) --target lever_wasm
	@ls -l $(WEB_BUILD)/web/wasm/lever_wasm.wasm $(WEB_BUILD)/web/wasm/lever_wasm.js
lab: web
	/usr/bin/python3 web/serve.py --port $(LAB_PORT) --build $(WEB_BUILD)/web/wasm
$(WEB_PEER)/node_modules/mujoco-js/package.json: web/bench/package.json web/bench/package-lock.json
	@scripts/setup.sh web-bench
	@mkdir -p $(WEB_PEER)
	@cp web/bench/package.json web/bench/package-lock.json $(WEB_PEER)/
	cd $(WEB_PEER) && npm ci --ignore-scripts --no-audit --no-fund
	@touch $@
web-bench: web build $(WEB_PEER)/node_modules/mujoco-js/package.json
	@$(WEB_ENV) cmake --build $(WEB_BUILD) -j $(JOBS) --target lever_step_time
	$(BUILD)/web/bench/lever_step_time models/arm2.xml
	node $(WEB_BUILD)/web/bench/lever_step_time.js models/arm2.xml
	node web/bench/js_step_time.js $(WEB_BUILD)/web/wasm models/arm2.xml
	node web/bench/peer_step_time.mjs --lever $(WEB_BUILD)/web/wasm \
	  --mujoco $(WEB_PEER)/node_modules/mujoco-js --commit $(LEVER_COMMIT) \
	  --out $(WEB_BUILD)/web-bench.json $(WEB_BENCH_MODELS)
	@if [ -f $(BENCH_BUILD)/bench.json ] && [ -f $(BENCH_BUILD)/bench-check.md ] && \
	  [ -x $(BENCH_BUILD)/bench/lever_bench_report ]; then $(bench_report); \
	  else echo "web-bench: no make bench run in $(BENCH_BUILD): docs/performance.md left as it is"; fi
