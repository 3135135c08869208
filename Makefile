# woven: the two commands of the README, plus the pieces they are made of.
BUILD      ?= build
ASAN_BUILD ?= build-asan
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 60
JOBS       ?= $(shell nproc)
CMAKE_GEN  := -G Ninja

# `make demo` builds only the `woven` binary (build-demo); `make build` and `make test` build the
# rest: the test suite, the fuzz replays and the Python module (python/).
.PHONY: all deps build build-demo build-asan build-fuzz demo test test-release test-asan fuzz bench clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) $(CMAKE_GEN) -DCMAKE_BUILD_TYPE=Release

build: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

build-demo: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS) --target woven

$(ASAN_BUILD)/build.ninja:
	cmake -S . -B $(ASAN_BUILD) $(CMAKE_GEN) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWOVEN_SANITIZE=ON

build-asan: deps $(ASAN_BUILD)/build.ninja
	cmake --build $(ASAN_BUILD) -j $(JOBS)

# The paper's cube drape with cotton: out/drape.obj, out/drape.ply, out/drape.glb, out/drape.png,
# out/report.json. Builds the binary alone, not the test suite.
demo: build-demo
	$(BUILD)/woven drape --out out

test-release: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

test-asan: build-asan
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
		ctest --output-on-failure -j $(JOBS) -LE no_sanitize

test: deps
	$(MAKE) test-release
	$(MAKE) test-asan

# libFuzzer targets of the parsers, built with clang (ASan + UBSan) in $(FUZZ_BUILD); each runs
# FUZZ_SECONDS on fuzz/corpus/<target> and the built-in files. `make test` replays the corpus.
$(FUZZ_BUILD)/build.ninja:
	cmake -S . -B $(FUZZ_BUILD) $(CMAKE_GEN) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
		-DWOVEN_FUZZ=ON -DWOVEN_TESTS=OFF -DWOVEN_PYTHON=OFF "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG" \
		"-DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
		-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined

build-fuzz: deps $(FUZZ_BUILD)/build.ninja
	cmake --build $(FUZZ_BUILD) -j $(JOBS) --target fuzz_fabric fuzz_scene fuzz_obj fuzz_gltf fuzz_values fuzz_corner_map fuzz_output_set fuzz_output_json fuzz_sweep_plan fuzz_glb_check fuzz_start fuzz_shadow

fuzz: build-fuzz
	bash fuzz/run.sh $(FUZZ_BUILD) $(FUZZ_SECONDS)

bench: deps
	cmake -S . -B $(BUILD) $(CMAKE_GEN) -DCMAKE_BUILD_TYPE=Release -DWOVEN_BENCH=ON
	cmake --build $(BUILD) -j $(JOBS)
	bash bench/run.sh $(BUILD)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(FUZZ_BUILD)
