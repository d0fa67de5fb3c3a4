# napkin — top-level entry points. `make demo` and `make test` work on a fresh
# Debian 12 machine: they install missing Debian packages, configure and build.
SHELL := /bin/bash
JOBS ?= $(shell nproc)
# CTest runs one test more than there are processors: many tests spend much of their time waiting
# (on napkin processes they start, Chromium, the Slurm daemons, settle and lock timeouts).
TEST_JOBS ?= $(shell echo $$(( $$(nproc) + 1 )))
BUILD_RELEASE ?= build/release
BUILD_TEST ?= build/test
BUILD_BENCH ?= build/bench
BUILD_FUZZ ?= build/fuzz
BUILD_TIDY ?= build/tidy
BUILD_PACKAGE ?= build/package
# What the program needs (make demo): Boost.Math for compare's t distribution,
# dygraphs embedded into the binary for report's charts, Boost.Beast and Boost.Asio (headers in
# libboost1.74-dev) for `napkin serve`'s HTTP server. What the tests and benchmarks add: cpp-httplib
# is their HTTP client of `napkin serve`; Chromium opens the HTML report headless; time
# (/usr/bin/time -v) gives bench/run_memory.sh the peak memory of `napkin run`; Slurm and munge run
# the reprocess test on a private single-node cluster (tests/slurm).
# The Python module (python/, docs/python.md) and its pytest suites; pandas for query_frame; mypy
# checks its type stubs (python/tests/test_typing.py).
PYTHON_PACKAGES := pybind11-dev python3-dev python3-numpy python3-pytest python3-pandas mypy
# An independent implementation of compare's statistics for its tests (python/tests/
# test_compare_statistics.py): scipy's t distributions, statsmodels' TOST and power.
STATISTICS_TEST_PACKAGES := python3-scipy python3-statsmodels
PROGRAM_PACKAGES := cmake g++ make pkg-config libeigen3-dev libtbb-dev libspdlog-dev \
  nlohmann-json3-dev libcli11-dev libsqlite3-dev sqlite3 libboost-math-dev libboost1.74-dev libjs-dygraphs \
  libzip-dev
DEBIAN_PACKAGES := $(PROGRAM_PACKAGES) libgtest-dev libgmock-dev libbenchmark-dev libcpp-httplib-dev clang-format \
  chromium time slurm-wlm munge $(PYTHON_PACKAGES) $(STATISTICS_TEST_PACKAGES)
# What `make fuzz` adds to the program's packages: clang and its libFuzzer runtime.
FUZZ_PACKAGES := $(PROGRAM_PACKAGES) clang libclang-rt-14-dev
# What `make tidy` adds: clang-tidy and clang (its configuration's compiler), and the headers of
# the tests, benchmarks and Python module, as the sources include them.
TIDY_PACKAGES := $(PROGRAM_PACKAGES) libgtest-dev libgmock-dev libbenchmark-dev libcpp-httplib-dev pybind11-dev \
  python3-dev clang-tidy clang
# What `make package` adds: the Python module's build and tests; help2man writes the man page;
# dpkg-dev's dpkg-shlibdeps and file give CPack the package's Depends; man-db renders the man page;
# lintian checks the package and systemd-analyze (Debian systemd) its service unit (make package-check).
PACKAGE_PACKAGES := $(PROGRAM_PACKAGES) $(PYTHON_PACKAGES) help2man dpkg-dev file man-db lintian systemd

.PHONY: deps program-deps fuzz-deps tidy-deps package-deps demo test build release bench fuzz tidy format format-check \
  package package-check clean

deps: PACKAGES = $(DEBIAN_PACKAGES)
program-deps: PACKAGES = $(PROGRAM_PACKAGES)
fuzz-deps: PACKAGES = $(FUZZ_PACKAGES)
tidy-deps: PACKAGES = $(TIDY_PACKAGES)
package-deps: PACKAGES = $(PACKAGE_PACKAGES)
deps program-deps fuzz-deps tidy-deps package-deps:
	@missing=""; for p in $(PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "napkin: installing missing Debian packages:$$missing"; \
	  SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi

# The program alone: no GoogleTest, no Google Benchmark.
$(BUILD_RELEASE)/CMakeCache.txt: | program-deps
	cmake -S . -B $(BUILD_RELEASE) -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DNAPKIN_BUILD_BENCH=OFF

release: program-deps $(BUILD_RELEASE)/CMakeCache.txt
	cmake --build $(BUILD_RELEASE) -j$(JOBS) --target napkin

# The test build: warnings are errors, address and undefined-behaviour sanitizers on napkin's code
# (its libraries, the program and the Python module; the test files have the address sanitizer
# only, tests/CMakeLists.txt says why). napkin is compiled with -Og, GCC's level for debugging (half
# the compile time of -O1 under the sanitizers), its numeric libraries (engine/, synth/, where the
# tests spend their time) with -O1, all with line tables (-g1) for the sanitizers' reports; the
# test files with -O0 and no debug information: optimising GoogleTest's
# macros under the sanitizers was most of the build's time (cmake/NapkinHelpers.cmake), and their
# failures name file and line themselves. GCC collects its garbage only past 1 GiB
# (--param ggc-min-heapsize, ggc-min-expand): about a tenth of the build's time on this 2-core
# virtual machine, where each page the collector frees and takes again costs a fault, for at most
# 3 GiB per compiler. Each library and test program is compiled in batches of files
# (NAPKIN_UNITY_BUILD): the headers' inline code is generated once a batch. The benchmarks are not
# part of it: `make bench` builds them as they are meant to run (Release, no sanitizers).
$(BUILD_TEST)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_TEST) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-Og -g1 -DNDEBUG" \
	  -DCMAKE_CXX_FLAGS="--param=ggc-min-expand=100 --param=ggc-min-heapsize=1048576" \
	  -DNAPKIN_NUMERIC_CODE_OPTIONS="-O1" -DNAPKIN_TEST_CODE_OPTIONS="-O0;-g0" -DNAPKIN_WERROR=ON -DNAPKIN_SANITIZE=ON -DNAPKIN_BUILD_BENCH=OFF \
	  -DNAPKIN_UNITY_BUILD=ON -DNAPKIN_BUILD_PYTHON=ON

build: deps $(BUILD_TEST)/CMakeCache.txt
	cmake --build $(BUILD_TEST) -j$(JOBS)

# Every source file is clang-format clean (.clang-format); `make format` fixes them.
FORMAT_SOURCES = $(shell git ls-files '*.cpp' '*.h' 2>/dev/null || find . -path ./build -prune -o \( -name '*.cpp' -o -name '*.h' \) -print)

format:
	clang-format -i $(FORMAT_SOURCES)

format-check: deps
	@echo "clang-format --dry-run --Werror: every .cpp and .h file"
	@clang-format --dry-run --Werror $(FORMAT_SOURCES)

test: build format-check
	cd $(BUILD_TEST) && ctest --output-on-failure -j$(TEST_JOBS) --timeout 1800

demo: release
	$(BUILD_RELEASE)/cli/napkin demo

$(BUILD_BENCH)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_BENCH) -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DNAPKIN_BUILD_BENCH=ON

bench: deps $(BUILD_BENCH)/CMakeCache.txt
	cmake --build $(BUILD_BENCH) -j$(JOBS)
	$(BUILD_BENCH)/bench/napkin_bench

# Coverage-guided fuzzing of the parsers (fuzz/, docs/architecture.md "Fuzzing"), not part of
# `make test`: a clang build with libFuzzer and the sanitizers, each target run for FUZZ_SECONDS on
# a corpus kept in $(BUILD_FUZZ)/corpus/<target>, seeded from fuzz/seeds/<target>. A finding
# leaves its input in $(BUILD_FUZZ)/artifacts/<target>/: fix it, then add the input to
# fuzz/regressions/<target>/, which `make test` runs through the same target.
FUZZ_SECONDS ?= 60
# Every target has its seed folder (tests/fuzz/ checks it): the targets are the folders of fuzz/seeds/.
FUZZ_TARGETS ?= $(notdir $(patsubst %/,%,$(wildcard fuzz/seeds/*/)))

$(BUILD_FUZZ)/CMakeCache.txt: | fuzz-deps
	cmake -S . -B $(BUILD_FUZZ) -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DBUILD_TESTING=OFF -DNAPKIN_BUILD_BENCH=OFF -DNAPKIN_BUILD_FUZZ=ON

fuzz: fuzz-deps $(BUILD_FUZZ)/CMakeCache.txt
	cmake --build $(BUILD_FUZZ) -j$(JOBS) --target napkin_fuzzers
	@failed=""; for t in $(FUZZ_TARGETS); do \
	  mkdir -p $(BUILD_FUZZ)/corpus/$$t $(BUILD_FUZZ)/artifacts/$$t $(BUILD_FUZZ)/logs $(BUILD_FUZZ)/tmp; \
	  echo "napkin fuzz: $$t for $(FUZZ_SECONDS) s (log $(BUILD_FUZZ)/logs/$$t.log)"; \
	  TMPDIR=$(abspath $(BUILD_FUZZ))/tmp $(BUILD_FUZZ)/fuzz/$${t}_fuzzer -max_total_time=$(FUZZ_SECONDS) \
	    -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix=$(BUILD_FUZZ)/artifacts/$$t/ \
	    $(BUILD_FUZZ)/corpus/$$t fuzz/seeds/$$t > $(BUILD_FUZZ)/logs/$$t.log 2>&1 || failed="$$failed $$t"; \
	  grep -E '^(Done|stat::number_of_executed_units|stat::peak_rss_mb)|^#[0-9]+.*DONE' $(BUILD_FUZZ)/logs/$$t.log; \
	done; \
	if [ -n "$$failed" ]; then \
	  echo "napkin fuzz: findings in:$$failed (inputs in $(BUILD_FUZZ)/artifacts/<target>/, details in the logs)"; \
	  exit 1; \
	fi

# clang-tidy with the checks of .clang-tidy (bug-prone, performance, naming), warnings as errors.
# `make tidy` checks every C++ source file git tracks; `make tidy TIDY_BASE=main` (or any
# revision) only those changed since its merge base with HEAD. The compile commands come from a
# configuration of their own, which has every source file in it: the tests, the benchmarks, the
# Python module and, as in `make fuzz`, clang with the libFuzzer targets (fuzz_main.cpp is
# compiled once a target, with NAPKIN_FUZZ_TARGET naming it). Nothing is compiled there; only the
# generated fragments the sources include (the embedded migrations and report files) are written.
TIDY_BASE ?=
TIDY_SOURCES = $(if $(TIDY_BASE),$(shell git diff --name-only --diff-filter=d $$(git merge-base $(TIDY_BASE) HEAD) -- '*.cpp'),$(shell git ls-files '*.cpp'))

# Reconfigured when this Makefile changes, so an older tidy configuration takes the options above.
$(BUILD_TIDY)/CMakeCache.txt: Makefile | tidy-deps
	cmake -S . -B $(BUILD_TIDY) -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
	  -DNAPKIN_BUILD_BENCH=ON -DNAPKIN_BUILD_FUZZ=ON -DNAPKIN_BUILD_PYTHON=ON

tidy: tidy-deps $(BUILD_TIDY)/CMakeCache.txt
	cmake --build $(BUILD_TIDY) --target napkin_embedded_migrations napkin_embedded_report_assets
	@if [ -z "$(strip $(TIDY_SOURCES))" ]; then echo "napkin tidy: no C++ source changed since $(TIDY_BASE)"; else \
	  echo "napkin tidy: clang-tidy over $(words $(TIDY_SOURCES)) files (log $(BUILD_TIDY)/tidy.log)"; \
	  printf '%s\n' $(TIDY_SOURCES) | xargs -P $(JOBS) -n 4 clang-tidy -p $(BUILD_TIDY) --quiet \
	    --warnings-as-errors='*' --header-filter='^$(CURDIR)/[a-z]+/' > $(BUILD_TIDY)/tidy.log 2>&1; \
	  status=$$?; grep -E '(warning|error):' $(BUILD_TIDY)/tidy.log | sort -u; \
	  if [ $$status = 0 ]; then echo "napkin tidy: clean"; else echo "napkin tidy: findings above"; exit 1; fi; fi

# The Debian package (cmake/Packaging.cmake, packaging/): a Release build of its own with the
# Python module, no tests or benchmarks, installed under /usr; CPack writes
# $(BUILD_PACKAGE)/napkin_<version>_<arch>.deb. `make package-check` checks it as installed
# (packaging/package_check.sh); .ci/run runs it after `make test`.
$(BUILD_PACKAGE)/CMakeCache.txt: | package-deps
	cmake -S . -B $(BUILD_PACKAGE) -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DNAPKIN_BUILD_BENCH=OFF \
	  -DNAPKIN_BUILD_PYTHON=ON -DNAPKIN_BUILD_PACKAGE=ON -DCMAKE_INSTALL_PREFIX=/usr

package: package-deps $(BUILD_PACKAGE)/CMakeCache.txt
	cmake --build $(BUILD_PACKAGE) -j$(JOBS)
	rm -f $(BUILD_PACKAGE)/napkin_*.deb
	cd $(BUILD_PACKAGE) && cpack -G DEB
	@ls $(BUILD_PACKAGE)/napkin_*.deb

package-check: package
	packaging/package_check.sh $(BUILD_PACKAGE)

clean:
	rm -rf build
