# The two commands a new user types: `make demo` and `make test`.
# Both install missing Debian packages first (scripts/install-deps.sh).

# The MuJoCo to build against: 4.0.1 (default), 3.11.0 (the book's), or debian (2.2.2).
# Each engine other than the default builds in a folder of its own.
MUJOCO     ?= 4.0.1
DEFAULT_MUJOCO := 4.0.1
ifeq ($(MUJOCO),$(DEFAULT_MUJOCO))
BUILD      ?= build
ASAN_BUILD ?= build-asan
TSAN_BUILD ?= build-tsan
else
BUILD      ?= build-mujoco-$(MUJOCO)
ASAN_BUILD ?= build-asan-mujoco-$(MUJOCO)
TSAN_BUILD ?= build-tsan-mujoco-$(MUJOCO)
endif
# the other legs of the tested version matrix
MATRIX     ?= 3.11.0 debian
JOBS       ?= $(shell nproc)
# the robot corpus (scripts/fetch-robots.sh): tested on the default engine; CORPUS=off leaves
# it out (offline with an empty cache)
CORPUS     ?= on
PREFIX     ?= /usr/local
CMAKE_FLAGS ?=
PLUMB      := $(BUILD)/plumb
# the sanitizer legs keep line tables only (-g1: what their reports print; full debug
# information cost a sixth of the ASan build and two fifths of the TSan one with -O2)
ASAN_FLAGS := -DCMAKE_CXX_FLAGS_DEBUG=-g1 -DCMAKE_C_FLAGS_DEBUG=-g1
TSAN_FLAGS := "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"

.PHONY: all deps configure corpus build demo test test-release test-asan test-tsan test-norender test-fuzz test-matrix test-wheel wheel bench install format clean

all: build

deps:
	@scripts/install-deps.sh --mujoco $(MUJOCO)

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DPLUMB_WARNINGS_AS_ERRORS=ON -DPLUMB_MUJOCO=$(MUJOCO) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# the main job on the chapter's pendulum, with its report: builds only what it runs (the
# library and the plumb command); make test builds the rest
demo: configure
	@cmake --build $(BUILD) -j $(JOBS) --target plumb_cli
	@echo "== plumb verify models/pendulum.xml --set 'qpos[hinge]=0.7' --all --report $(BUILD)/pendulum-report.html"
	@$(PLUMB) verify models/pendulum.xml --set 'qpos[hinge]=0.7' --all --report $(BUILD)/pendulum-report.html
	@echo "== the report: $(abspath $(BUILD))/pendulum-report.html (open it in a browser; it needs no network)"

test: test-release test-asan

ifeq ($(CORPUS)$(MUJOCO),on$(DEFAULT_MUJOCO))
CORPUS_DEP := corpus
CTEST_ENV  := PLUMB_REQUIRE_CORPUS=1
CTEST_ARGS :=
else
CORPUS_DEP :=
CTEST_ENV  :=
# the other engines leave out, for time, what runs the same code on every engine: the crash
# tests (label crash: SIGKILLs of plumb's own writers), the reports in Chromium (label browser:
# the page's script and style), and the wire tests against Unitree's SDK and an independent CRC
# (message layouts and checksums), and the crosscheck against MuJoCo Warp and MJX (label engines:
# their environments pin MuJoCo 4.0.1); all of them run on the default engine
CTEST_ARGS := -LE 'corpus|crash|browser|engines' -E 'CliBridgeSdk2Test|UnitreeCrcMatchesAnIndependentImplementation'
endif

corpus:
	@scripts/fetch-robots.sh

test-release: build $(CORPUS_DEP)
	@cd $(BUILD) && $(CTEST_ENV) ctest --output-on-failure -j $(JOBS) $(CTEST_ARGS)

# the whole suite again under AddressSanitizer + UndefinedBehaviorSanitizer. Mesa's software
# rasteriser draws on one thread (LP_NUM_THREADS=0): LeakSanitizer's exit-time scan of the
# process can crash on llvmpipe's idle worker threads (not instrumented, still running)
test-asan: deps
	@cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DPLUMB_WARNINGS_AS_ERRORS=ON -DPLUMB_MUJOCO=$(MUJOCO) \
	  -DPLUMB_SANITIZE=address,undefined -DPLUMB_BUILD_BENCHMARKS=OFF -DPLUMB_WITH_MPI=OFF $(ASAN_FLAGS) $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(ASAN_BUILD) -j $(JOBS)
	@cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  LP_NUM_THREADS=0 ctest --output-on-failure -j $(JOBS)

# the threaded code (sweep's, rollout's and identify's worker pools, the stop flag, the CLI's
# streaming writers) under ThreadSanitizer; tests/tsan.supp says why the worker pool runs its
# chunks on std::threads here (Debian's oneTBB is not built with TSan). This build is also
# the one without the optional parts (PLUMB_WITH_RENDER=OFF, as on a machine without EGL or
# OSMesa; PLUMB_WITH_DDS=OFF, without CycloneDDS): render, the reports' pictures and the bridge
# must build, say so and exit 5 (make test-norender does that part alone)
TSAN_TARGETS := worker_pool_test stop_test sweep_test rollout_test run_test rollout_cli_test signals_cli_test budget_cli_test identify_test plumb_cli \
  render_test report_test render_cli_test exit_codes_cli_test
TSAN_TESTS   := ^(WorkerPoolTest|StopTimerTest|SweepTest|RolloutTest|RunTest|CliRolloutTest|CliSignalsTest|BudgetCliTest|IdentifyTest\.(TheSameForAnyNumberOfThreads|ThePendulumsDampingFromAFreeDecay)$$|RenderTest|RenderModelsTest|AllModels/RenderModelsTest|ReportTest|CliRenderTest|CliReportTest|ExitCodesTest\.AMissingBridgeIsFive$$)\.?
# the memory benchmarks among them (10^6 cases) take minutes under TSan and share no code
# path the others do not run
TSAN_SKIP    := SweepMemoryDoesNotGrowWithTheNumberOfCases|AHugeSweepSaysItsCost
test-tsan: deps
	@cmake -S . -B $(TSAN_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPLUMB_WARNINGS_AS_ERRORS=ON -DPLUMB_MUJOCO=$(MUJOCO) \
	  -DPLUMB_SANITIZE=thread -DPLUMB_WITH_RENDER=OFF -DPLUMB_WITH_DDS=OFF -DPLUMB_BUILD_BENCHMARKS=OFF -DPLUMB_BUILD_EXAMPLES=OFF -DPLUMB_WITH_MPI=OFF \
	  $(TSAN_FLAGS) $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(TSAN_BUILD) -j $(JOBS) --target $(TSAN_TARGETS)
	@cd $(TSAN_BUILD) && TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$(CURDIR)/tests/tsan.supp" \
	  ctest --output-on-failure -j $(JOBS) -R '$(TSAN_TESTS)' -E '$(TSAN_SKIP)'

# libFuzzer on every parser plumb owns (tests/fuzz), built with clang under ASan+UBSan;
# FUZZ_SECONDS per target (scripts/run-fuzzers.sh says what it found)
FUZZ_BUILD   ?= build-fuzz
FUZZ_SECONDS ?= 60
# -O1 and line tables, as libFuzzer's own documentation builds its targets
FUZZ_FLAGS   := "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG"
test-fuzz: deps
	@cmake -S . -B $(FUZZ_BUILD) -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPLUMB_MUJOCO=$(MUJOCO) -DPLUMB_FUZZ=ON $(FUZZ_FLAGS) \
	  -DPLUMB_SANITIZE=address,undefined -DPLUMB_WARNINGS_AS_ERRORS=OFF -DPLUMB_BUILD_TESTS=OFF \
	  -DPLUMB_BUILD_BENCHMARKS=OFF -DPLUMB_BUILD_EXAMPLES=OFF -DPLUMB_WITH_MPI=OFF \
	  -DPLUMB_WITH_RENDER=OFF $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(FUZZ_BUILD) -j $(JOBS) --target fuzz_paths fuzz_expressions fuzz_scenario \
	  fuzz_snapshot fuzz_robot_log fuzz_store $$(grep -q 'PLUMB_WITH_DDS:BOOL=ON' $(FUZZ_BUILD)/CMakeCache.txt && echo fuzz_bridge_config fuzz_dds fuzz_gamepad_script)
	@scripts/run-fuzzers.sh $(FUZZ_BUILD) $(FUZZ_SECONDS)

# a build without the renderer (PLUMB_WITH_RENDER=OFF, as on a machine without EGL or
# OSMesa): it must build, say so, and answer render and the reports' pictures with exit 5
NORENDER_BUILD ?= build-norender
NORENDER_TARGETS := plumb_cli render_test report_test render_cli_test exit_codes_cli_test
test-norender: deps
	@cmake -S . -B $(NORENDER_BUILD) -DCMAKE_BUILD_TYPE=Release -DPLUMB_WARNINGS_AS_ERRORS=ON -DPLUMB_MUJOCO=$(MUJOCO) \
	  -DPLUMB_WITH_RENDER=OFF -DPLUMB_WITH_DDS=OFF -DPLUMB_BUILD_BENCHMARKS=OFF -DPLUMB_BUILD_EXAMPLES=OFF -DPLUMB_WITH_MPI=OFF $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(NORENDER_BUILD) -j $(JOBS) --target $(NORENDER_TARGETS)
	@cd $(NORENDER_BUILD) && ctest --output-on-failure -j $(JOBS) -R '^(RenderTest|RenderModelsTest|AllModels/RenderModelsTest|ReportTest|CliRenderTest|CliReportTest|ExitCodesTest\.AMissingBridgeIsFive$$)\.?'

# the Release suite on every other MuJoCo of the matrix (3.11.0 and Debian's 2.2.2), without
# the benchmark programs (they build on the default engine), optimised at -O1: these legs
# test which MuJoCo plumb runs on, not what the optimiser does (-O3 on the default leg)
MATRIX_FLAGS := -DPLUMB_BUILD_BENCHMARKS=OFF '-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG' '-DCMAKE_C_FLAGS_RELEASE=-O1 -DNDEBUG'
test-matrix:
	@for v in $(MATRIX); do \
	  echo "== make test-release MUJOCO=$$v"; start=$$(date +%s); \
	  $(MAKE) --no-print-directory test-release MUJOCO=$$v CMAKE_FLAGS="$(MATRIX_FLAGS) $(CMAKE_FLAGS)" || exit 1; \
	  echo "== MUJOCO=$$v: $$(( $$(date +%s) - start )) s"; \
	done

# the pip wheel (plumb-mujoco): built by pip and scikit-build-core in build-wheel/ (kept: a
# second build compiles only what changed), repaired by auditwheel, written to build-wheel/dist
wheel: deps
	@scripts/build-wheel.sh

# the wheel's leg: the wheel installed into a fresh venv that holds only mujoco-core (with numpy)
# and pytest, and tested there (tests/wheel: the API, plumb on PATH, the pytest plugin)
test-wheel: deps
	@scripts/test-wheel.sh

bench: build
	@$(BUILD)/bench/run_overhead_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
	@$(BUILD)/bench/sweep_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
	@bench/callgrind_overhead.sh $(BUILD)

install: build
	@cmake --install $(BUILD) --prefix $(PREFIX)

format:
	@clang-format -i $$(git ls-files '*.h' '*.cc')

clean:
	@rm -rf build build-asan build-tsan build-norender build-fuzz build-mujoco-* build-asan-mujoco-* build-tsan-mujoco-* build-wheel
