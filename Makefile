# clearshape — the two commands of the README, plus benchmarks.
#   make run    install the Debian packages the main job needs, build the CLI only (Release),
#               run the main job (scripts/run-main.sh)
#   make test   install every Debian package, build everything (warnings are errors), run every
#               test through ctest
#   make bench  build and run the benchmarks side by side with their SciPy/NumPy peers
#   make test-sanitize  every test under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/)
#   make test-clean-root  the four .debs and the wheel, three users following the docs on a fresh Debian 12 root (debootstrap; root and
#               the network needed, so not part of make test: docs/package.md)
#   make fuzz   each libFuzzer target for FUZZ_SECONDS (clang, build-fuzz/; docs/data-safety.md)
# What each costs on a fresh two-core Debian 12: README.md, "Set-up: two commands".
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=
# -Werror on the project's own code (CMake option CLEARSHAPE_WERROR). The same value for run and
# test, so that switching between them never recompiles; `make run WERROR=OFF` for a compiler
# other than Debian 12's GCC 12.
WERROR ?= ON
# Precompiled headers (CMake option CLEARSHAPE_PCH): the tests' under UNITY, the CLI's and study's too
# without it; PCH=OFF to do without.
PCH ?= ON
# Unity build: each target's sources compile in batches of 8 (CMake option CLEARSHAPE_UNITY), about
# a third less compile CPU; UNITY=OFF to compile file by file.
UNITY ?= ON

# A quiet build: no "gmake[N]: Entering directory" lines from the makes that cmake --build runs
# (a build tree made with Unix Makefiles; a new tree uses Ninja, see configure below).
MAKEFLAGS += --no-print-directory

.PHONY: run test bench deps deps-run configure configure-run build build-run clean test-sanitize fuzz test-clean-root
FUZZ_SECONDS ?= 60

deps:
	@bash scripts/install-deps.sh

deps-run:
	@bash scripts/install-deps.sh --run

# cmake configure, its log in $(BUILD_DIR).configure.log (shown only when it fails). A new build
# tree uses Ninja (Debian's ninja-build: one progress line, and objects of a target compile while
# its dependencies link); an existing tree keeps the generator it was made with.
#   $(1): the options for this configure
define configure_tree
	@gen=""; if [ ! -f $(BUILD_DIR)/CMakeCache.txt ] && command -v ninja > /dev/null; then gen="-G Ninja"; fi; \
	echo "clearshape: configuring $(BUILD_DIR)/ (log: $(BUILD_DIR).configure.log)"; \
	cmake -S . -B $(BUILD_DIR) $$gen -DCMAKE_BUILD_TYPE=Release -DCLEARSHAPE_WERROR=$(WERROR) -DCLEARSHAPE_PCH=$(PCH) -DCLEARSHAPE_UNITY=$(UNITY) $(1) $(CMAKE_FLAGS) \
	  > $(BUILD_DIR).configure.log 2>&1 || { cat $(BUILD_DIR).configure.log; exit 1; }
endef

# Everything: library, CLI, Python module, firmware and its emulator, tests, examples, benchmarks.
configure: deps
	$(call configure_tree,-DCLEARSHAPE_BUILD_TESTS=ON -DCLEARSHAPE_BUILD_EXAMPLES=ON -DCLEARSHAPE_BUILD_BENCHMARKS=ON)

# The main job needs the CLI only. A new tree is configured without tests, examples and
# benchmarks (so GoogleTest and Google Benchmark need not be installed); an existing tree keeps
# its options (after `make test` they are on, which costs nothing here: only the CLI is built).
configure-run: deps-run
	$(call configure_tree,$(if $(wildcard $(BUILD_DIR)/CMakeCache.txt),,-DCLEARSHAPE_BUILD_TESTS=OFF -DCLEARSHAPE_BUILD_EXAMPLES=OFF -DCLEARSHAPE_BUILD_BENCHMARKS=OFF))

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

build-run: configure-run
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target clearshape_cli

run: build-run
	@bash scripts/run-main.sh $(BUILD_DIR)

test: build
	@ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

bench: build
	@bash scripts/run-bench.sh $(BUILD_DIR)

# Needs root and deb.debian.org; 3–6 min, most of it apt downloading (docs/package.md).
test-clean-root: build
	@bash scripts/test-clean-root.sh $(BUILD_DIR)

# The Python module is left out of the sanitizer trees: an ASan-built extension loads only into
# a Python started with libasan preloaded. So is the package suite (-LE package): it checks the
# shipped Release artifacts — a .deb that must hold that Python module, and a consumer project
# linked against the installed static libraries without the sanitizer runtime.
test-sanitize: deps
	@cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCLEARSHAPE_SANITIZE=ON \
	  -DCLEARSHAPE_BUILD_BENCHMARKS=OFF -DCLEARSHAPE_BUILD_PYTHON=OFF > build-asan.configure.log 2>&1 || (cat build-asan.configure.log; exit 1)
	@cmake --build build-asan -j $(JOBS)
	@ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --test-dir build-asan --output-on-failure -j $(JOBS) -LE package

fuzz: deps
	@bash scripts/install-deps.sh --fuzz
	@CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCLEARSHAPE_FUZZ=ON \
	  -DCLEARSHAPE_BUILD_TESTS=OFF -DCLEARSHAPE_BUILD_EXAMPLES=OFF -DCLEARSHAPE_BUILD_BENCHMARKS=OFF \
	  -DCLEARSHAPE_BUILD_PYTHON=OFF > build-fuzz.configure.log 2>&1 || (cat build-fuzz.configure.log; exit 1)
	@cmake --build build-fuzz -j $(JOBS) --target fuzz_csv fuzz_protocol fuzz_rig_config fuzz_impulses fuzz_modes
	@bash scripts/run-fuzz.sh build-fuzz $(FUZZ_SECONDS)

clean:
	@rm -rf $(BUILD_DIR) $(BUILD_DIR).configure.log build-asan build-fuzz build-asan.configure.log build-fuzz.configure.log
