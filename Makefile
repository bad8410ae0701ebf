# volguide — entry points (see docs/interface.md). Every target installs what is missing first.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
# Debian packages. DEMO_PACKAGES: what the CLI needs to build and run (`make demo` installs only
# these). TEST_PACKAGES: the rest, for the test suite, the benchmarks and their report — GoogleTest and
# Google Benchmark; python3-matplotlib and chromium: the benchmark report, its plots and the headless
# check of its HTML page, exercised by the bench_harness test; python3-pybind11, python3-numpy,
# python3-pytest: the Python module and its tests; python3-venv, python3-pip, python3-setuptools and
# python3-wheel: the pip_install test (`pip install --no-build-isolation .` into a venv, offline);
# slurm-wlm and munge: the single-node Slurm cluster of
# the slurm_array test, docs/distributed.md; clang and libclang-rt-14-dev: libFuzzer and the sanitizers
# of `make fuzz`, docs/reliability.md. Keep in sync with CMakeLists.txt.
DEMO_PACKAGES := build-essential cmake pkg-config libembree-dev libtbb-dev libopenexr-dev \
  libpugixml-dev libtinyobjloader-dev libfmt-dev libcli11-dev nlohmann-json3-dev libstb-dev \
  libopenvdb-dev libboost-iostreams-dev zlib1g-dev libpng-dev libjpeg62-turbo-dev libhwy-dev ninja-build
TEST_PACKAGES := libgtest-dev libgmock-dev libbenchmark-dev python3 python3-matplotlib chromium \
  python3-dev python3-pybind11 python3-numpy python3-pytest python3-venv python3-pip python3-setuptools \
  python3-wheel slurm-wlm munge \
  clang libclang-rt-14-dev
APT_PACKAGES := $(DEMO_PACKAGES) $(TEST_PACKAGES)
# What a full build configures (tests, benchmarks, the Python module, the Open PGL peer) and what the
# demo's build leaves out of a build directory it creates (it builds only the CLI).
FULL_OPTIONS := -DVOLGUIDE_BUILD_TESTS=ON -DVOLGUIDE_BUILD_BENCH=ON -DVOLGUIDE_BUILD_PYTHON=ON \
  -DVOLGUIDE_WITH_OPENPGL=ON
DEMO_OPTIONS := -DVOLGUIDE_BUILD_TESTS=OFF -DVOLGUIDE_BUILD_BENCH=OFF -DVOLGUIDE_BUILD_PYTHON=OFF \
  -DVOLGUIDE_WITH_OPENPGL=OFF
# make bench QUICK=1: the reduced budget; TIME=seconds per render; BENCH_ARGS: any run_bench.py option.
QUICK ?=
TIME ?=
BENCH_ARGS ?=
# CTest label expression for `make test`; CI runs everything.
TEST_ARGS ?=

.PHONY: deps deps-demo configure build build-openpgl08 python test install demo bench bench-micro bench-distributed clean format fuzz test-sanitize

deps:
	@scripts/install-deps.sh $(APT_PACKAGES)

deps-demo:
	@scripts/install-deps.sh $(DEMO_PACKAGES)

# Configures a new build directory with everything; a directory the demo made (CLI only, marked
# VOLGUIDE_DEMO_ONLY) is reconfigured with everything; any other is left with its own settings.
configure: deps
	@if [ ! -f $(BUILD_DIR)/CMakeCache.txt ] || grep -q '^VOLGUIDE_DEMO_ONLY:BOOL=ON' $(BUILD_DIR)/CMakeCache.txt; then \
	  cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(FULL_OPTIONS) -DVOLGUIDE_DEMO_ONLY=OFF; fi

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# The Python module into $(BUILD_DIR)/python (use it with PYTHONPATH=$(BUILD_DIR)/python; docs/python.md).
python: configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target python

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) $(TEST_ARGS)

# make install PREFIX=DIR: the guiding core library, its API headers and the CMake package
# (find_package(volguide) -> volguide::volguide; docs/guiding-api.md).
PREFIX ?=
ifneq ($(filter install,$(MAKECMDGOALS)),)
ifeq ($(PREFIX),)
$(error usage: make install PREFIX=DIR)
endif
endif
install: build
	cmake --install $(BUILD_DIR) --prefix $(PREFIX)

# The demo installs and builds only what the CLI needs (in a build directory of its own making, with
# Ninja, which schedules the compile jobs tighter than make: no tests, benchmarks, Python module or
# Open PGL; an existing build directory is used as it is), then renders both methods side by side.
demo: deps-demo
	@[ -f $(BUILD_DIR)/CMakeCache.txt ] || cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release $(DEMO_OPTIONS) \
	  -DVOLGUIDE_DEMO_ONLY=ON
	cmake --build $(BUILD_DIR) -j $(JOBS) --target volguide_cli
	@scripts/demo.sh $(BUILD_DIR)

# The VSPG peer's binary (issue 37): the CLI linking Open PGL 0.8 in a build directory of its own (one
# build links one Open PGL); `make bench BENCH_ARGS="--openpgl08-build-dir build-pgl08"` runs its row.
OPENPGL08_BUILD_DIR ?= build-pgl08
build-openpgl08: deps-demo
	@[ -f $(OPENPGL08_BUILD_DIR)/CMakeCache.txt ] || cmake -S . -B $(OPENPGL08_BUILD_DIR) -DCMAKE_BUILD_TYPE=Release \
	  $(filter-out -DVOLGUIDE_WITH_OPENPGL=OFF,$(DEMO_OPTIONS)) -DVOLGUIDE_WITH_OPENPGL=ON -DVOLGUIDE_OPENPGL_SOURCE=0.8
	cmake --build $(OPENPGL08_BUILD_DIR) -j $(JOBS) --target volguide_cli

bench: build
	@scripts/bench.sh $(BUILD_DIR) $(if $(QUICK),--quick) $(if $(TIME),--time $(TIME)) $(BENCH_ARGS)

# The Google Benchmark micro-benchmarks (kernels, whole-render throughput).
bench-micro: build
	@scripts/bench-micro.sh $(BUILD_DIR)

# Distributed rendering on this machine: chunk processes vs one process, merge time (docs/distributed.md).
bench-distributed: build
	@bench/distributed_bench.sh $(BUILD_DIR)

# make fuzz FUZZ_SECONDS=N: every reader's libFuzzer target for N seconds each, built with clang into
# FUZZ_BUILD_DIR (docs/reliability.md). Exit 1 when a target finds a crash, hang or sanitizer report.
# FUZZ_TARGETS: a subset (default all: scene vol vdb field obj ply exr_part serialized image checkpoint). FUZZ_SEED=N (environment):
# libFuzzer's seed, for a run that explores the same inputs every time (CI's smoke run uses 1).
# FUZZ_RUNS=M (environment): also stop each target after M executions (the long runs: 10000000).
# FUZZ_JOBS=N (environment): targets run at once (default JOBS; each fuzzer uses one core).
FUZZ_SECONDS ?= 60
FUZZ_BUILD_DIR ?= build-fuzz
FUZZ_TARGETS ?=
fuzz: deps
	@JOBS=$(JOBS) scripts/fuzz.sh $(FUZZ_SECONDS) $(FUZZ_BUILD_DIR) $(FUZZ_TARGETS)

# The unit, stat and fast integration tests under ASan + UBSan (build-asan), the render loop, photon
# pass, render checkpoint and determinism tests under TSan (build-tsan); docs/reliability.md. CPU heavy: two more builds.
# SANITIZE_STAGES, SANITIZE_LABELS, SANITIZE_ASAN_BUILD (environment): scripts/test-sanitize.sh;
# SANITIZE_ASAN_BUILD=fuzz runs the ASan + UBSan stage in FUZZ_BUILD_DIR's clang build (CI, .ci/run).
test-sanitize: deps
	@JOBS=$(JOBS) FUZZ_BUILD_DIR=$(FUZZ_BUILD_DIR) scripts/test-sanitize.sh build-asan build-tsan

format:
	clang-format -i $$(git ls-files '*.cpp' '*.h')

clean:
	rm -rf $(BUILD_DIR) out
