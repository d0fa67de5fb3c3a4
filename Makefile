# napkin — top-level entry points. `make demo` and `make test` work on a fresh
# Debian 12 machine: they install missing Debian packages, configure and build.
SHELL := /bin/bash
JOBS ?= $(shell nproc)
BUILD_RELEASE ?= build/release
BUILD_TEST ?= build/test
BUILD_BENCH ?= build/bench
# What the program needs (make demo): Boost.Math for compare's t distribution,
# dygraphs embedded into the binary for report's charts. What the tests and
# benchmarks add: Chromium opens the HTML report headless.
PROGRAM_PACKAGES := cmake g++ make pkg-config libeigen3-dev libtbb-dev libspdlog-dev \
  nlohmann-json3-dev libcli11-dev libsqlite3-dev sqlite3 libboost-math-dev libjs-dygraphs libzip-dev
DEBIAN_PACKAGES := $(PROGRAM_PACKAGES) libgtest-dev libgmock-dev libbenchmark-dev clang-format \
  chromium

.PHONY: deps program-deps demo test build release bench format format-check clean

deps: PACKAGES = $(DEBIAN_PACKAGES)
program-deps: PACKAGES = $(PROGRAM_PACKAGES)
deps program-deps:
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

# The test build: warnings are errors, address and undefined-behaviour sanitizers on.
$(BUILD_TEST)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_TEST) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNAPKIN_WERROR=ON -DNAPKIN_SANITIZE=ON

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
	cd $(BUILD_TEST) && ctest --output-on-failure -j$(JOBS) --timeout 1800

demo: release
	$(BUILD_RELEASE)/cli/napkin demo

$(BUILD_BENCH)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_BENCH) -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DNAPKIN_BUILD_BENCH=ON

bench: deps $(BUILD_BENCH)/CMakeCache.txt
	cmake --build $(BUILD_BENCH) -j$(JOBS)
	$(BUILD_BENCH)/bench/napkin_bench

clean:
	rm -rf build
