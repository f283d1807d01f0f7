# clearshape — the two commands of the README, plus benchmarks.
#   make run    install missing Debian packages, build (Release), run the main job
#   make test   install missing Debian packages, build, run every test through ctest
#   make bench  build and run the benchmarks side by side with their SciPy/NumPy peers
#   make test-sanitize  every test under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/)
#   make fuzz   each libFuzzer target for FUZZ_SECONDS (clang, build-fuzz/; docs/data-safety.md)
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: run test bench deps configure build clean test-sanitize fuzz
FUZZ_SECONDS ?= 60

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > $(BUILD_DIR).configure.log 2>&1 \
	  || (cat $(BUILD_DIR).configure.log; exit 1)

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

run: build
	@bash scripts/run-main.sh $(BUILD_DIR)

test: build
	@ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

bench: build
	@bash scripts/run-bench.sh $(BUILD_DIR)

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
