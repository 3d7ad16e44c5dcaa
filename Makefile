# The two commands a new user types: `make demo` and `make test`.
# Both install missing Debian packages first (scripts/install-deps.sh).

BUILD      ?= build
ASAN_BUILD ?= build-asan
JOBS       ?= $(shell nproc)
PREFIX     ?= /usr/local
CMAKE_FLAGS ?=
PLUMB      := $(BUILD)/plumb

.PHONY: all deps build demo test test-release test-asan bench install format clean

all: build

deps:
	@scripts/install-deps.sh

build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DPLUMB_WARNINGS_AS_ERRORS=ON $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)

# the main job on the chapter's pendulum
demo: build
	@echo "== plumb verify models/pendulum.xml --set 'qpos[hinge]=0.7' --all"
	@$(PLUMB) verify models/pendulum.xml --set 'qpos[hinge]=0.7' --all

test: test-release test-asan

test-release: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# the whole suite again under AddressSanitizer + UndefinedBehaviorSanitizer
test-asan: deps
	@cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DPLUMB_WARNINGS_AS_ERRORS=ON \
	  -DPLUMB_SANITIZE=address,undefined -DPLUMB_BUILD_BENCHMARKS=OFF -DPLUMB_WITH_MPI=OFF $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(ASAN_BUILD) -j $(JOBS)
	@cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure -j $(JOBS)

bench: build
	@$(BUILD)/bench/run_overhead_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
	@$(BUILD)/bench/sweep_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
	@bench/callgrind_overhead.sh $(BUILD)

install: build
	@cmake --install $(BUILD) --prefix $(PREFIX)

format:
	@clang-format -i $$(git ls-files '*.h' '*.cc')

clean:
	@rm -rf $(BUILD) $(ASAN_BUILD)
