# The two set-up commands of the README. Everything else is CMake presets.
PRESET ?= release
BUILD := build/$(PRESET)
SCENE ?= scenes/cornell-box/scene.xml
OUT ?= out/cornell-box.exr
JOBS ?= $(shell nproc)

.PHONY: deps configure build render test test-asan clean docs

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

docs: build
	$(BUILD)/bin/effigi info --markdown > docs/components.md

clean:
	rm -rf build out
