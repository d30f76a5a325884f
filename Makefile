# lever: the two commands.
#   make demo   set up, build, and check the lesson's arm model
#   make test   set up, build, and run every test
BUILD ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
LEVER = $(BUILD)/tools/lever/lever

.PHONY: all setup configure build demo test clean

all: build

setup:
	@scripts/setup.sh

configure: setup
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release > $(BUILD).configure.log || (cat $(BUILD).configure.log; exit 1)

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	$(LEVER) model models/arm2.xml

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD) $(BUILD).configure.log
