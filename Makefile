# The two set-up commands of the README. Everything else is CMake presets.
PRESET ?= release
BUILD := build/$(PRESET)
SCENE ?= scenes/cornell-box/scene.xml
OUT ?= out/cornell-box.exr
JOBS ?= $(shell nproc)

.PHONY: deps configure build render test test-asan test-sanitize fuzz clean docs

deps:
	@scripts/install-deps.sh

configure: deps
	@test -f $(BUILD)/build.ninja || cmake --preset $(PRESET)

build: configure
	cmake --build --preset $(PRESET) -j $(JOBS)

render: build
	@mkdir -p $(dir $(OUT))
	$(BUILD)/bin/effigi render $(SCENE) -o $(OUT)

test: build
	ctest --preset $(PRESET)

test-asan:
	$(MAKE) test PRESET=asan

# The sanitizer subset of CI (tests labelled `sanitize`: loader, readers, conformance
# quick, a render per renderer), building only what those tests load.
test-sanitize: deps
	@test -f build/asan/build.ninja || cmake --preset asan
	cmake --build --preset asan -j $(JOBS) --target effigi_sanitize_subset
	ctest --preset asan -L sanitize

# libFuzzer on every reader (fuzz/, clang): FUZZ_SECONDS per target, one after the other.
# New inputs go to build/fuzz/corpus/<target>/ (seeded from fuzz/corpus/ and
# tests/data/regressions/), findings to build/fuzz/findings/<target>/, logs to build/fuzz/logs/.
# An input running past -timeout is a hang, i.e. a finding. Leaks are checked after each
# input (libFuzzer), not at exit: LeakSanitizer's exit check can crash on the worker threads
# (TBB, Embree) still alive then, which would count as a finding of an empty input.
FUZZ_SECONDS ?= 60
FUZZ_TARGETS ?= xml obj ply spd image serialized vol rib checkpoint
FUZZ_FLAGS ?= -timeout=10 -rss_limit_mb=2048
fuzz: deps
	@test -f build/fuzz/build.ninja || cmake --preset fuzz
	cmake --build --preset fuzz -j $(JOBS)
	@failed=; for t in $(FUZZ_TARGETS); do \
	  mkdir -p build/fuzz/corpus/$$t build/fuzz/findings/$$t build/fuzz/logs; \
	  dict=; test -f fuzz/$$t.dict && dict=-dict=fuzz/$$t.dict; \
	  echo "fuzz: $$t for $(FUZZ_SECONDS) s (log: build/fuzz/logs/$$t.log)"; \
	  ASAN_OPTIONS=leak_check_at_exit=0 UBSAN_OPTIONS=print_stacktrace=1 build/fuzz/bin/fuzz_$$t build/fuzz/corpus/$$t fuzz/corpus/$$t \
	    tests/data/regressions/$$t -max_total_time=$(FUZZ_SECONDS) $(FUZZ_FLAGS) $$dict \
	    -artifact_prefix=build/fuzz/findings/$$t/ -print_final_stats=1 > build/fuzz/logs/$$t.log 2>&1 \
	    || { failed="$$failed $$t"; tail -n 40 build/fuzz/logs/$$t.log; }; \
	  grep -E '^#[0-9]+[[:space:]]+(DONE|pulse|NEW|REDUCE|INITED)' build/fuzz/logs/$$t.log | tail -n 1; \
	done; \
	test -z "$$failed" || { echo "fuzz: findings in$$failed: build/fuzz/findings/"; exit 1; }

docs: build
	$(BUILD)/bin/effigi info --markdown > docs/components.md

clean:
	rm -rf build out
