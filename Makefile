# Makefile - a thin wrapper over CMake. `make render` and `make test` are README's quick start.
BUILD ?= build
ASAN_BUILD ?= build-asan
JOBS ?= 2
CTEST_FLAGS ?= --output-on-failure -j$(JOBS)

.PHONY: all setup build render test test-release test-sanitize bench clean

all: build

setup:
	sh scripts/setup.sh

build: setup
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo
	cmake --build $(BUILD) -j$(JOBS)

# Render the built-in default scene to brume.png.
render: build
	./$(BUILD)/brume render -o brume.png

# The whole suite: optimized build, then under AddressSanitizer + UndefinedBehaviorSanitizer.
test: test-release test-sanitize

test-release: build
	cd $(BUILD) && ctest $(CTEST_FLAGS)

test-sanitize: setup
	# the fuzz targets are built with ASan + UBSan already: they run in test-release only
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRUME_SANITIZE=ON -DBRUME_FUZZ_TESTS=OFF
	cmake --build $(ASAN_BUILD) -j$(JOBS)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest $(CTEST_FLAGS)

bench: build
	cmake --build $(BUILD) --target bench -j$(JOBS)
	@for b in $(BUILD)/bench/bench_*; do echo "== $$b"; $$b; done

clean:
	rm -rf $(BUILD) $(ASAN_BUILD)
