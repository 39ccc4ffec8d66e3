# Makefile — builds the tocher core library, the CLI and the tests.
# `make` builds; `make test` runs every test; `make check` runs them under ASan+UBSan.

CC      ?= cc
BUILD   ?= build
OPT     ?= -O2
SAN     ?=
CFLAGS  ?=
LDFLAGS ?=

DEBIAN_PACKAGES := build-essential pkg-config libcjson-dev python3-scipy python3-matplotlib

CJSON_CFLAGS := $(shell pkg-config --cflags libcjson 2>/dev/null)
CJSON_LIBS   := $(shell pkg-config --libs libcjson 2>/dev/null || echo -lcjson)

WARN     := -Wall -Wextra -Werror -Wshadow -Wstrict-prototypes -Wmissing-prototypes -Wvla
ALL_CFLAGS = -std=c11 -D_POSIX_C_SOURCE=200809L $(OPT) -g $(SAN) $(WARN) \
             -Iinclude -Isrc $(CJSON_CFLAGS) -MMD -MP $(CFLAGS)
ALL_LDFLAGS = $(SAN) $(LDFLAGS)
LIBS     := $(CJSON_LIBS) -lm -lpthread

CORE_SRC := $(wildcard src/core/*.c)
IO_SRC   := $(wildcard src/io/*.c)
CLI_SRC  := $(wildcard src/cli/*.c)
TEST_SRC := tests/main.c $(wildcard tests/unit/*.c)

obj = $(patsubst %.c,$(BUILD)/obj/%.o,$(1))
LIB_OBJ  := $(call obj,$(CORE_SRC) $(IO_SRC))
CLI_OBJ  := $(call obj,$(CLI_SRC))
TEST_OBJ := $(call obj,$(TEST_SRC))

.PHONY: all deps test test-unit test-peers check run clean
.DEFAULT_GOAL := all

all: $(BUILD)/libtocher.a $(BUILD)/tocher

$(BUILD)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c $< -o $@

$(BUILD)/obj/tests/%.o: ALL_CFLAGS += -Itests

$(BUILD)/libtocher.a: $(LIB_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

$(BUILD)/tocher: $(CLI_OBJ) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(LIBS) -o $@

$(BUILD)/test_unit: $(TEST_OBJ) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(LIBS) -o $@

# Installs what the build and the tests need on Debian 12 (as root, or via sudo).
deps:
	@missing=""; for p in $(DEBIAN_PACKAGES); do \
	  dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  $$SUDO apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

test: deps
	@$(MAKE) --no-print-directory all $(BUILD)/test_unit
	@tests/run.sh $(BUILD)

test-unit: $(BUILD)/test_unit
	$(BUILD)/test_unit

check: deps
	@$(MAKE) --no-print-directory BUILD=build/san OPT=-O1 \
	  SAN="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all" \
	  all build/san/test_unit
	@ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 tests/run.sh build/san

run: deps all
	$(BUILD)/tocher eval api/examples/shadow-edges.json api/examples/points.json

clean:
	rm -rf build

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(TEST_OBJ:.o=.d)
