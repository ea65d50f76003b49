# hedra: the two commands everybody needs are `make demo` and `make test`.
BUILD      ?= build
ASAN_BUILD ?= build-asan
JOBS       ?= 2
CMAKE_ARGS ?=

BENCH_BUILD ?= build-bench
FUZZ_BUILD   ?= $(ASAN_BUILD)
FUZZ_SECONDS ?= 60
STRESS_CASES ?= 3000

.PHONY: all deps build demo test stress test-asan bench-build bench bench-quick fuzz-build fuzz clean

all: build

deps:
	@bash scripts/install-deps.sh

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_ARGS) > /dev/null
	cmake --build $(BUILD) -j$(JOBS)

demo: build
	./$(BUILD)/hedra demo

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

# The differential random tests (tests/differential) with STRESS_CASES seeded cases each
# (make test runs a few hundred in all); a failure prints its seed, HEDRA_STRESS_SEED reruns it.
stress: build
	cd $(BUILD) && HEDRA_STRESS_CASES=$(STRESS_CASES) ctest --output-on-failure -j$(JOBS) -R '^Differential\.'

# Second build with clang, AddressSanitizer + UBSan: every test again, and in the same build the
# libFuzzer targets of tests/fuzz (the libraries also carry -fsanitize=fuzzer-no-link), so the
# sanitizer tests and the fuzz runs share one compilation (CI runs both; .ci/run). No examples
# (nothing there to test) and no Python module (it would need a sanitized interpreter).
# A build directory configured earlier with GCC (as test-asan used to) gets a fresh CMake cache.
SANITIZE_CONFIGURE = if [ -f $(1)/CMakeCache.txt ] && ! grep -q '^CMAKE_CXX_COMPILER:.*clang' $(1)/CMakeCache.txt; then \
    echo "$(1): configured with another compiler; configuring it again with clang"; \
    rm -rf $(1)/CMakeCache.txt $(1)/CMakeFiles; fi; \
  cmake -S . -B $(1) -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" -DHEDRA_BUILD_FUZZ=ON \
  -DHEDRA_BUILD_EXAMPLES=OFF $(CMAKE_ARGS) > /dev/null

test-asan:
	bash scripts/install-deps.sh clang libclang-rt-14-dev
	$(call SANITIZE_CONFIGURE,$(ASAN_BUILD))
	cmake --build $(ASAN_BUILD) -j$(JOBS)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j$(JOBS)

# Benchmarks side by side with their peers; rewrites docs/benchmarks.md and the charts.
bench-build:
	bash scripts/install-deps.sh python3-matplotlib python3-numpy \
	  libocct-modeling-algorithms-dev libocct-modeling-data-dev libocct-foundation-dev
	cmake -S . -B $(BENCH_BUILD) -DCMAKE_BUILD_TYPE=Release -DHEDRA_BUILD_BENCH=ON -DHEDRA_BUILD_TESTS=OFF $(CMAKE_ARGS) > /dev/null
	cmake --build $(BENCH_BUILD) -j$(JOBS)

bench: bench-build
	bash scripts/run-bench.sh $(BENCH_BUILD)

bench-quick: bench-build
	HEDRA_BENCH_QUICK=1 bash scripts/run-bench.sh $(BENCH_BUILD)

# libFuzzer targets (clang, ASan + UBSan) for every reader and for scene -> commands, each run
# FUZZ_SECONDS on its seed corpus (tests/fuzz/corpus); fails on any finding. They live in the
# sanitizer build (FUZZ_BUILD defaults to ASAN_BUILD); fuzz-build compiles only what they need.
fuzz-build:
	bash scripts/install-deps.sh clang libclang-rt-14-dev
	$(call SANITIZE_CONFIGURE,$(FUZZ_BUILD))
	cmake --build $(FUZZ_BUILD) -j$(JOBS) --target hedra_fuzzers

fuzz: fuzz-build
	bash scripts/run-fuzz.sh $(FUZZ_BUILD) $(FUZZ_SECONDS)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(BENCH_BUILD) $(FUZZ_BUILD)
