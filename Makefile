# DeepContact top-level driver. Every target installs what it needs first (idempotent),
# so `make bench` and `make test` work on a fresh Debian machine.
BUILD      ?= build
BUILD_TYPE ?= Release
JOBS       ?= $(shell nproc)
CMAKE_ARGS ?=
DC          = $(BUILD)/bin/deepcontact

.PHONY: all deps configure build test bench bench-quick results model sanitize fuzz clean

all: build

deps:
	./scripts/install-deps.sh

configure: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_ARGS)

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# The whole test suite (unit, relationship and CLI tests) through ctest.
test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# The main job: the default benchmark on the seed scene; the report lands in results/.
# One seed per core (--jobs): the figures equal a one-thread run's, the timings share the cores.
bench: build
	$(DC) bench --jobs $(JOBS) --out results

bench-quick: build
	$(DC) bench --quick --out results-quick

# Regenerates every figure the README and docs/ quote: docs/results/*.md, docs/results/results.json
# and the blocks between <!-- results:NAME --> markers (scripts/results/results.py; ~25 min on
# 2 cores with the shortened sizes, FULL=1 for the documented ones). One part alone:
# make results PART=bench|solvers|starters|cholmod|siconos|speed|build (comma-separated for several).
results: build
	/usr/bin/python3 scripts/results/results.py --build $(BUILD) $(if $(PART),--part $(PART)) $(if $(FULL),--full)

# Retrain the shipped default model (docs/learning.md gives the exact pipeline).
model: build
	./scripts/train-default-model.sh

# The test suite once under AddressSanitizer + UndefinedBehaviorSanitizer.
sanitize: deps
	# DC_NATIVE=OFF: the portable code paths (Conv2d's im2col + GEMM) run here under the
	# sanitizers, while `make test` (-march=native) covers the AVX-512 kernels.
	# -g1: line tables only. The sanitizers' stack traces (inlined frames included) are the
	# same as with -g, the code is the same, and it compiles ~20 % faster (DEVELOPERS.md);
	# for gdb: make sanitize CMAKE_ARGS='-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g -DNDEBUG"'.
	cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDC_SANITIZE=ON -DDC_NATIVE=OFF -DDC_BENCHMARKS=OFF \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" $(CMAKE_ARGS)
	cmake --build build-asan -j $(JOBS)
	# Two known defects inside libhdf5 1.10.8 are suppressed (tests/fuzz/*.supp, docs/robustness.md).
	cd build-asan && ASAN_OPTIONS=suppressions=$(CURDIR)/tests/fuzz/asan.supp \
	  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/fuzz/lsan-suite.supp ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD) build-asan
