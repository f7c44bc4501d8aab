# Convenience front end over CMake. `make run` renders the default scene,
# `make test` builds and runs the whole test suite.
BUILD ?= build
JOBS  ?= $(shell nproc 2>/dev/null || echo 2)

.PHONY: all build run test clean deps

all: build

$(BUILD)/CMakeCache.txt:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo

build: $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

deps:
	scripts/install-deps.sh

run: build
	mkdir -p out
	$(BUILD)/rtgi render --shadow pcss --size 512x512 --out out/cornell.pfm --png out/cornell.png --timings

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD) out
