# napkin — top-level entry points. `make demo` and `make test` work on a fresh
# Debian 12 machine: they install missing Debian packages, configure and build.
SHELL := /bin/bash
JOBS ?= $(shell nproc)
BUILD_RELEASE ?= build/release
BUILD_TEST ?= build/test
DEBIAN_PACKAGES := cmake g++ make pkg-config libeigen3-dev libtbb-dev libspdlog-dev \
  nlohmann-json3-dev libcli11-dev libsqlite3-dev sqlite3 libgtest-dev libgmock-dev \
  libbenchmark-dev

.PHONY: deps demo test build release bench clean

deps:
	@missing=""; for p in $(DEBIAN_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "napkin: installing missing Debian packages:$$missing"; \
	  SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi

$(BUILD_RELEASE)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_RELEASE) -DCMAKE_BUILD_TYPE=Release

release: deps $(BUILD_RELEASE)/CMakeCache.txt
	cmake --build $(BUILD_RELEASE) -j$(JOBS)

# The test build: warnings are errors, address and undefined-behaviour sanitizers on.
$(BUILD_TEST)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_TEST) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNAPKIN_WERROR=ON -DNAPKIN_SANITIZE=ON

build: deps $(BUILD_TEST)/CMakeCache.txt
	cmake --build $(BUILD_TEST) -j$(JOBS)

test: build
	cd $(BUILD_TEST) && ctest --output-on-failure -j$(JOBS) --timeout 1800

demo: release
	$(BUILD_RELEASE)/cli/napkin demo

bench: release
	$(BUILD_RELEASE)/bench/napkin_bench

clean:
	rm -rf build
