# Convenience front end over CMake. `make run` renders the default scene,
# `make test` builds and runs the whole test suite.
BUILD ?= build
JOBS  ?= $(shell nproc 2>/dev/null || echo 2)
SHELL := /bin/bash

.PHONY: all build run test clean deps test-asan fuzz-build fuzz-smoke

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

# The suite under AddressSanitizer + UndefinedBehaviorSanitizer, in its own
# build directory. LeakSanitizer reports are suppressed only for the GL
# driver's own allocations (tests/lsan.supp names them; the preloaded
# tests/nodlclose.c keeps the driver mapped so that they have a name).
# intercept_tls_get_addr=0: ASan's tracking of dynamic TLS recorded a bogus
# range (0xe07-0x1800001f09) for the dlopen'ed driver, and LeakSanitizer's
# tracer crashed scanning it (signal 11; GCC 12, glibc 2.36) in whichever
# test the JIT layout put it: test_radiometry, then test_direct. Static TLS
# and every thread's stack are still scanned.
ASAN_BUILD ?= build-asan
SAN_ENV = LD_PRELOAD=$(CURDIR)/$(ASAN_BUILD)/tests/librtgi_nodlclose.so \
          ASAN_OPTIONS=detect_leaks=1:verify_asan_link_order=0:detect_odr_violation=0:allocator_may_return_null=1:intercept_tls_get_addr=0 \
          LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 \
          UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

$(ASAN_BUILD)/CMakeCache.txt:
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRTGI_SANITIZE=ON

# The programs that exercise memory: parsers and loaders, images, the CLI
# and its failure paths, object lifetimes, metrics. The render-fidelity
# programs run once, in `make test`: their GL work checks nothing more under
# a sanitizer, and running them twice took CI past 10 minutes.
RTGI_ASAN_TESTS ?= test_math test_metrics test_settings test_badinput test_image_io test_cli test_lifetime test_compare_masks test_gl_layer test_layout
empty :=
space := $(empty) $(empty)

test-asan: $(ASAN_BUILD)/CMakeCache.txt
	cmake --build $(ASAN_BUILD) -j $(JOBS) --target rtgi alloc_failure_shim rtgi_nodlclose $(RTGI_ASAN_TESTS)
	cd $(ASAN_BUILD) && $(SAN_ENV) ctest --output-on-failure -j $(JOBS) -R '^($(subst $(space),|,$(strip $(RTGI_ASAN_TESTS))))(_[0-9]+of[0-9]+)?$$'


# libFuzzer targets (fuzz/, clang only) and a bounded run of each on its
# seed corpus: FUZZ_SECONDS per target; findings go to $(FUZZ_BUILD)/artifacts.
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 20

$(FUZZ_BUILD)/CMakeCache.txt:
	cmake -S . -B $(FUZZ_BUILD) -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRTGI_FUZZ=ON -DBUILD_TESTING=OFF

fuzz-build: $(FUZZ_BUILD)/CMakeCache.txt
	cmake --build $(FUZZ_BUILD) -j $(JOBS) --target fuzz_scene fuzz_mesh fuzz_image

fuzz-smoke: fuzz-build
	mkdir -p $(FUZZ_BUILD)/artifacts
	for t in scene mesh image; do \
	  mkdir -p $(FUZZ_BUILD)/corpus/$$t && \
	  ASAN_OPTIONS=detect_leaks=0 $(FUZZ_BUILD)/fuzz/fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -timeout=30 \
	    -rss_limit_mb=4096 -dict=fuzz/$$t.dict -artifact_prefix=$(FUZZ_BUILD)/artifacts/$$t- \
	    $(FUZZ_BUILD)/corpus/$$t fuzz/corpus/$$t 2>&1 | grep -E '^#[0-9]+[[:space:]]+(INITED|DONE)|ERROR|SUMMARY' ; \
	  test $${PIPESTATUS[0]} -eq 0 || exit 1; \
	done

clean:
	rm -rf $(BUILD) out
