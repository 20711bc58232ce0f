# Makefile - a thin wrapper over CMake. `make render` and `make test` are README's quick start.
# The developer builds here (build, test) turn -Werror on (BRUME_WERROR); `make render`, the
# user's first command, and a plain `cmake` build do not: a new compiler's new warning must
# not stop a user's first picture.
BUILD ?= build
ASAN_BUILD ?= build-asan
O3_BUILD ?= build-o3
CLANG_BUILD ?= build-clang
JOBS ?= 2
CTEST_FLAGS ?= --output-on-failure -j$(JOBS)

.PHONY: all setup setup-render build render test test-release test-sanitize build-o3 build-clang install bench clean

all: build

setup:
	sh scripts/setup.sh

CONFIGURE = cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRUME_WERROR=ON

build: setup
	$(CONFIGURE)
	cmake --build $(BUILD) -j$(JOBS)

# Render the built-in default scene to brume.png: 15 s of rendering, denoised (README). Only
# the library and the tool are built (target brume_cli) and only their packages installed
# (`setup.sh render`): the first picture does not wait for the tests.
setup-render:
	sh scripts/setup.sh render

render: setup-render
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRUME_WERROR=OFF
	cmake --build $(BUILD) -j$(JOBS) --target brume_cli
	./$(BUILD)/brume render --time 15 --denoise -o brume.png
	@echo "brume.png: the default scene after 15 s of rendering, denoised (before denoising: brume-raw.png)."
	@echo "The converged picture (3 % noise in every pixel, minutes): ./$(BUILD)/brume render -o brume-converged.png"

# The whole suite: optimized build, then under AddressSanitizer + UndefinedBehaviorSanitizer,
# then the library and the tool as a Release (-O3) build must compile without a warning.
test: test-release test-sanitize build-o3

test-release: build
	cd $(BUILD) && ctest $(CTEST_FLAGS)

test-sanitize: setup
	# the fuzz targets are built with ASan + UBSan already: they run in test-release only.
	# ASan's shadow rules out the OpenVDB reader's RLIMIT_AS, so one hostile .vdb could have the
	# reader touch gigabytes: ASan's own allocation cap stands in for it (a child that hits it dies,
	# which brume reports as a refused file). 1536 MiB refuses the 2 GiB that a count of 0x7fffffff
	# asks for (sparse.hostile_vdb_huge_counts), as RLIMIT_AS does in the release build: at 2048 the
	# child zero-filled 2 GiB, 10 s each under ASan and past the sandbox's wall limit under load.
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRUME_SANITIZE=ON -DBRUME_FUZZ_TESTS=OFF -DBRUME_WERROR=ON
	cmake --build $(ASAN_BUILD) -j$(JOBS)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:max_allocation_size_mb=1536 UBSAN_OPTIONS=print_stacktrace=1 ctest $(CTEST_FLAGS)

# What a user's `cmake -DCMAKE_BUILD_TYPE=Release` builds (gcc -O3), warnings as errors (the C
# code; the one C++ file, grid_vdb.cpp, is left out to keep CI short).
build-o3: setup
	cmake -S . -B $(O3_BUILD) -DCMAKE_BUILD_TYPE=Release -DBRUME_WERROR=ON -DBRUME_FUZZ_TESTS=OFF -DBRUME_WITH_OPENVDB=OFF
	cmake --build $(O3_BUILD) -j$(JOBS) --target brume_shared brume_cli

# The same with clang (not part of `make test`, to keep CI short).
build-clang: setup
	CC=clang CXX=clang++ cmake -S . -B $(CLANG_BUILD) -DCMAKE_BUILD_TYPE=Release -DBRUME_WERROR=ON -DBRUME_FUZZ_TESTS=OFF
	cmake --build $(CLANG_BUILD) -j$(JOBS) --target brume_shared brume_cli

# Installs under PREFIX (default /usr/local): header, libraries, tool, brume.pc, CMake
# package, Python package.
PREFIX ?= /usr/local
install: build
	cmake --install $(BUILD) --prefix $(PREFIX)

bench: build
	cmake --build $(BUILD) --target bench -j$(JOBS)
	@for b in $(BUILD)/bench/bench_*; do echo "== $$b"; $$b; done

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(O3_BUILD) $(CLANG_BUILD)
