# Makefile — builds the tocher core library, the CLI (tocher), the daemon (tocherd), the image
# plugin (libtocher_image.so), the tests and the benchmarks (build/report, build/bench_perf).
# `make` builds; `make test` runs every test; `make check` runs them under ASan+UBSan, built
# with -Wconversion and the core's assertions on; `make report` / `make bench` measure
# (docs/report.md, docs/performance.md); `make numfmt-full` runs the number printing tests at the
# issue's 10^7 size; `make torture` attacks the daemon at full size;
# `make fuzz` builds the libFuzzer target (tests/fuzz/); `make cross` builds for aarch64 and runs
# the unit tests of its per-architecture code under qemu.

CC      ?= cc
BUILD   ?= build
OPT     ?= -O2
SAN     ?=
# -DTC_DEBUG turns on the core's TC_ASSERTs (src/core/assert.h); `make check` sets it.
ASSERTS ?=
CFLAGS  ?=
LDFLAGS ?=

DEBIAN_PACKAGES := build-essential pkg-config libcjson-dev libmicrohttpd-dev libopenimageio-dev \
                   openimageio-tools python3-openimageio python3-scipy python3-matplotlib python3-yaml \
                   python3-jsonschema python3-numpy curl wrk chromium libhiredis-dev libzstd-dev redis-server \
                   nginx-light

CJSON_CFLAGS := $(shell pkg-config --cflags libcjson 2>/dev/null)
CJSON_LIBS   := $(shell pkg-config --libs libcjson 2>/dev/null || echo -lcjson)
MHD_CFLAGS   := $(shell pkg-config --cflags libmicrohttpd 2>/dev/null)
MHD_LIBS     := $(shell pkg-config --libs libmicrohttpd 2>/dev/null || echo -lmicrohttpd)
# The Redis mesh store (src/io/store_redis.c): hiredis, and zstd for large values.
HIREDIS_LIBS := $(shell pkg-config --libs hiredis 2>/dev/null || echo -lhiredis)
ZSTD_LIBS    := $(shell pkg-config --libs libzstd 2>/dev/null || echo -lzstd)
OIIO_CFLAGS  := $(shell pkg-config --cflags OpenImageIO 2>/dev/null)
OIIO_LIBS    := $(shell pkg-config --libs OpenImageIO 2>/dev/null || echo -lOpenImageIO -lOpenImageIO_Util)
CXX     ?= c++
PYTHON  ?= /usr/bin/python3

WARN     := -Wall -Wextra -Werror -Wshadow -Wstrict-prototypes -Wmissing-prototypes -Wvla
# More warnings for one build: `make check` sets WARN_EXTRA=-Wconversion (in C it also
# turns on -Wsign-conversion); a plain `make` leaves it empty.
WARN_EXTRA ?=
ALL_CFLAGS = -std=c11 -D_POSIX_C_SOURCE=200809L $(OPT) -g $(SAN) $(ASSERTS) $(WARN) $(WARN_EXTRA) \
             -Iinclude -Isrc $(CJSON_CFLAGS) -MMD -MP $(CFLAGS)
ALL_LDFLAGS = $(SAN) $(LDFLAGS)
LIBS     := $(CJSON_LIBS) $(HIREDIS_LIBS) $(ZSTD_LIBS) -lm -lpthread -ldl
# The one C++ file: OpenImageIO behind a C interface, built as a plugin that
# src/image/plugin.c opens on the first encode (non-image work never loads it).
ALL_CXXFLAGS = -std=c++17 $(OPT) -g $(SAN) -fPIC -Wall -Wextra -Werror -Iinclude -Isrc $(OIIO_CFLAGS) $(CXXFLAGS)

CORE_SRC := $(wildcard src/core/*.c)
IO_SRC   := $(wildcard src/io/*.c) $(wildcard src/image/*.c) $(wildcard src/scenes/*.c)
CLI_SRC  := $(wildcard src/cli/*.c)
SRV_SRC  := $(wildcard src/server/*.c)
# tests/support: the C helpers the unit and stability suites share (test meshes, property
# checks), beside tests/pylib, their Python counterpart.
TEST_SRC := tests/main.c $(wildcard tests/support/*.c) $(wildcard tests/unit/*.c) $(wildcard tests/stability/*.c)

obj = $(patsubst %.c,$(BUILD)/obj/%.o,$(1))
# raster_cover.c twice on x86: portable, and with AVX2 and FMA (raster.c picks by the CPU);
# elsewhere (aarch64) the portable build alone (src/core/cpu.h).
TARGET_ARCH_X86 := $(filter x86_64-% i386-% i486-% i586-% i686-%,$(shell $(CC) -dumpmachine 2>/dev/null))
COVER_AVX2 := $(if $(TARGET_ARCH_X86),$(BUILD)/obj/src/core/raster_cover_avx2.o)
LIB_OBJ  := $(call obj,$(CORE_SRC) $(IO_SRC)) $(COVER_AVX2)
CLI_OBJ  := $(call obj,$(CLI_SRC))
SRV_OBJ  := $(call obj,$(SRV_SRC))
BENCH_OBJ := $(call obj,$(wildcard bench/*.c))
# The benchmark programs' objects (each linked on its own below): listed so that their
# dependency files are read, or a changed header (a field added to tc_options) leaves them stale.
PERF_OBJ := $(call obj,$(wildcard bench/perf/*.c))
TEST_OBJ := $(call obj,$(TEST_SRC))

.PHONY: all deps test test-unit numfmt-full check torture run clean report report-quick bench fuzz fuzz-deps cross cross-deps cluster cluster-stop
.DEFAULT_GOAL := all

all: $(BUILD)/libtocher.a $(BUILD)/tocher $(BUILD)/tocherd $(BUILD)/libtocher_image.so

$(BUILD)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c $< -o $@

ifneq ($(COVER_AVX2),)
$(COVER_AVX2): src/core/raster_cover.c
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -mavx2 -mfma -DTC_COVER_AVX2 -c $< -o $@
endif

$(BUILD)/obj/tests/%.o: ALL_CFLAGS += -Itests -Itests/support
$(BUILD)/obj/src/server/%.o: ALL_CFLAGS += $(MHD_CFLAGS)
# GCC notes that 32-byte vectors passed by value change the ABI without AVX: they pass only
# between always-inline functions of one build, never across a call (ct_span.c, ct_fast.h,
# ct_points.c, raster_cover.c; bench_scaling includes ct_fast.h for tc__raster_force_generic).
$(BUILD)/obj/src/core/ct_span.o $(BUILD)/obj/src/core/ct_fast.o $(BUILD)/obj/src/core/raster_cover.o $(COVER_AVX2) \
  $(BUILD)/obj/src/core/raster.o $(BUILD)/obj/src/core/ct_points.o $(BUILD)/obj/tests/unit/test_raster.o \
  $(BUILD)/obj/bench/perf/scaling.o: ALL_CFLAGS += -Wno-psabi
# The render loop is worth -O3 (unrolling, +17% Mpixel/s per thread measured on a 1024² tile of
# 8192 triangles); only where the build is optimized anyway (`make check` keeps its -O1).
$(BUILD)/obj/src/core/raster_cover.o $(COVER_AVX2): ALL_CFLAGS += $(if $(filter -O2,$(OPT)),-O3)
# The viewer page is assembled into viewer.o (.incbin), which -MMD does not see.
$(BUILD)/obj/src/server/viewer.o: src/server/viewer.html

$(BUILD)/libtocher_image.so: src/image/encode.cpp src/image/image.h src/image/format.h
	@mkdir -p $(dir $@)
	$(CXX) $(ALL_CXXFLAGS) -shared $< $(OIIO_LIBS) -o $@

$(BUILD)/libtocher.a: $(LIB_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

$(BUILD)/tocher: $(CLI_OBJ) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(LIBS) -o $@

$(BUILD)/tocherd: $(SRV_OBJ) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(MHD_LIBS) $(LIBS) -o $@

# drain.c: the one server piece the unit tests call (no libmicrohttpd in it).
$(BUILD)/test_unit: $(TEST_OBJ) $(call obj,src/server/drain.c) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(LIBS) -o $@

# The error-against-run-time report (bench/): build/report measures, in C, into a data
# directory (CSV, PNG, run.json); bench/report.py writes the page and its plots from it.
$(BUILD)/report: $(BENCH_OBJ) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(LIBS) -o $@

# The performance comparison with scipy and matplotlib: docs/performance.md (bench/perf/).
$(BUILD)/bench_perf: $(call obj,bench/perf/perf.c) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(LIBS) -o $@

# Validation against build, at n and 4n and per thread count (issue 17): bench/perf/validate.c.
$(BUILD)/bench_validate: $(call obj,bench/perf/validate.c) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(LIBS) -o $@

# Scattered points (issue 17 §3): the batch path against the one it replaced (bench/perf/points.py).
$(BUILD)/bench_points: $(call obj,bench/perf/points.c) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(LIBS) -o $@

# Number printing (issue 17): tc_fmt_double against the cascade it replaced and printf.
$(BUILD)/obj/bench/perf/%.o: ALL_CFLAGS += -Ibench/perf
$(BUILD)/bench_numfmt: $(call obj,bench/perf/numfmt.c bench/perf/numfmt_cascade.c) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(LIBS) -o $@

# Tile throughput per thread and thread scaling (issue 17 §3): no daemon, no image plugin, so the
# binary can be carried to a machine with more cores (`device`; docs/performance.md says which).
# Linked with cJSON alone (the store's objects are not pulled from the archive): carry it and
# libcjson.so.1, nothing else.
$(BUILD)/bench_scaling: $(call obj,bench/perf/scaling.c) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(CJSON_LIBS) -lm -lpthread -ldl -o $@
# The core's clock with 1..N threads busy (bench/perf/clockprobe.c): carried with bench_scaling.
$(BUILD)/bench_clockprobe: $(call obj,bench/perf/clockprobe.c)
	$(CC) $(ALL_LDFLAGS) $^ -lm -lpthread -o $@
# A tile's pixels against /v1/evaluate's values and owners (bench/perf/tile_error.c).
$(BUILD)/bench_tile_error: $(call obj,bench/perf/tile_error.c) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(CJSON_LIBS) -lm -lpthread -ldl -o $@

# Where a build's time goes per loop and between loops, per thread count (bench/perf/phases.c);
# built and carried like bench_scaling.
$(BUILD)/bench_phases: $(call obj,bench/perf/phases.c) $(BUILD)/libtocher.a
	$(CC) $(ALL_LDFLAGS) $^ $(CJSON_LIBS) -lm -lpthread -ldl -o $@

bench: deps
	@$(MAKE) --no-print-directory all $(BUILD)/bench_perf $(BUILD)/bench_numfmt $(BUILD)/bench_scaling \
	  $(BUILD)/bench_validate $(BUILD)/bench_phases $(BUILD)/bench_points
	bench/perf/run.sh $(BUILD)

# docs/report.md and docs/report/ (about 5 minutes on 2 cores).
report: deps
	@$(MAKE) --no-print-directory all $(BUILD)/report
	$(BUILD)/report --out docs/report
	$(PYTHON) bench/report.py docs/report docs/report.md

# The same on one scene, small meshes and every realistic surface, into $(BUILD)/report-quick/
# (docs/ untouched): a minute or less, what CI runs to keep bench/ and the script working.
QUICK := $(BUILD)/report-quick
report-quick: deps
	@$(MAKE) --no-print-directory all $(BUILD)/report
	rm -rf $(QUICK)
	$(BUILD)/report --out $(QUICK)/report --scenes penumbra --max-density 8 --min-threshold 0.1
	$(PYTHON) bench/report.py $(QUICK)/report $(QUICK)/report.md

# $(call apt_install,PACKAGES[,FIRST]): the Debian packages of the list not installed yet, with
# apt-get (as root, or via sudo), after the shell command FIRST if any ($$SUDO set for it). A name
# installed for two architectures (libcjson-dev after `make cross`) is ambiguous to dpkg -s
# unless qualified: then the machine's own architecture's is asked for.
apt_install = arch=$$(dpkg --print-architecture); missing=""; for p in $(1); do \
	  dpkg -s $$p >/dev/null 2>&1 || dpkg -s $$p:$$arch >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  $(if $(2),$(2);) \
	  $$SUDO apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing >/dev/null; \
	fi

# Installs what the build and the tests need on Debian 12.
deps:
	@$(call apt_install,$(DEBIAN_PACKAGES))

test: deps
	@$(MAKE) --no-print-directory all $(BUILD)/test_unit
	@tests/run.sh $(BUILD)

test-unit: $(BUILD)/test_unit
	$(BUILD)/test_unit

# tc_fmt_double at the issue's full size: 10^7 random doubles read back, 2 * 10^5 (and
# every edge case) against the shortest-digits reference; about a minute.
numfmt-full: $(BUILD)/test_unit
	TC_NUMFMT_FULL=1 $(BUILD)/test_unit numfmt

check: deps
	@$(MAKE) --no-print-directory BUILD=build/san OPT=-O1 ASSERTS=-DTC_DEBUG WARN_EXTRA=-Wconversion \
	  SAN="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all" \
	  all build/san/test_unit build/san/report build/san/bench_perf build/san/bench_numfmt build/san/bench_scaling \
	  build/san/bench_phases build/san/bench_points \
	  build/san/bench_validate
	@ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 tests/run.sh build/san

# The libFuzzer target over the JSON API's request -> response functions (tests/fuzz/):
# the library rebuilt with clang and ASan+UBSan (assertions on) in build/fuzz/, the
# target linked with -fsanitize=fuzzer (clang, unlike gcc, warns on `(T){first}`
# compound literals, hence -Wno-missing-field-initializers). Only this needs clang, so `make test` does not
# install it. Run: build/fuzz/fuzz_api -dict=tests/fuzz/json.dict NEW_DIR tests/fuzz/corpus
# FUZZ_ASSERTS= FUZZ_BUILD=build/fuzz-na: the same without the assertions, to fuzz past a
# known invariant failure with only the sanitizers watching.
FUZZ_SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
FUZZ_BUILD ?= build/fuzz
FUZZ_ASSERTS ?= -DTC_DEBUG
fuzz: deps fuzz-deps
	@$(MAKE) --no-print-directory CC=clang BUILD=$(FUZZ_BUILD) OPT=-O1 ASSERTS="$(FUZZ_ASSERTS)" \
	  CFLAGS="-Wno-missing-field-initializers $(CFLAGS)" \
	  SAN="$(FUZZ_SAN) -fsanitize=fuzzer-no-link" FUZZ_LINK="$(FUZZ_SAN) -fsanitize=fuzzer" \
	  $(FUZZ_BUILD)/fuzz_api

fuzz-deps:
	@$(call apt_install,clang)

$(BUILD)/fuzz_api: $(call obj,tests/fuzz/fuzz_api.c) $(BUILD)/libtocher.a
	$(CC) $(FUZZ_LINK) $(LDFLAGS) $^ $(LIBS) -o $@

# The portable build on another architecture (src/core/cpu.h: the AVX2 variants are x86's only):
# the library and the unit tests cross-built for aarch64 in build/aarch64/ (every warning an
# error) and the tests of the code that has per-architecture paths (CROSS_TESTS: the covering of
# tiles, scattered points, spans, the locator, fmax/fmin, number reading and printing, typed arrays) run
# under qemu-user against the arm64 glibc and libraries (Debian multiarch). The image plugin
# (OpenImageIO, C++) is not cross-built. A few minutes; .ci/run runs it.
CROSS_PACKAGES := gcc-aarch64-linux-gnu libc6-dev-arm64-cross qemu-user-static libc6:arm64 libcjson-dev:arm64 \
                  libhiredis-dev:arm64 libzstd-dev:arm64
CROSS_TESTS := raster points span locate minmax numfmt strtod typed base64 request_fast
cross: cross-deps
	@$(MAKE) --no-print-directory CC=aarch64-linux-gnu-gcc BUILD=build/aarch64 build/aarch64/libtocher.a \
	  build/aarch64/test_unit
	@for t in $(CROSS_TESTS); do \
	  out=$$(qemu-aarch64-static -L / build/aarch64/test_unit $$t 2>&1) || { echo "$$out" | grep FAIL; exit 1; }; \
	  printf 'aarch64 %-13s %s\n' "$$t:" "$$(echo "$$out" | tail -n 1)"; done

cross-deps:
	@$(call apt_install,$(CROSS_PACKAGES),dpkg --print-foreign-architectures | grep -qx arm64 || $$SUDO dpkg --add-architecture arm64)

# The daemon under hostile load at full size (slow clients, floods, huge bodies): every
# tests/torture/*.py against the daemon in $(BUILD); minutes, not run by CI. Their short
# forms run in `make test` (tests/endpoint/).
torture: deps
	@$(MAKE) --no-print-directory all
	@set -e; for t in tests/torture/*.py; do [ -e "$$t" ] || continue; \
	  echo "== $$t"; $(PYTHON) "$$t" $(BUILD); done

# Starts the daemon in the foreground on 127.0.0.1:8080 (TOCHER_LISTEN etc. override).
run: deps
	@$(MAKE) --no-print-directory all
	@echo
	@echo "Try, from any directory:"
	@echo "  curl -s -H 'Content-Type: application/json' --data-binary @$(CURDIR)/api/examples/square-light.json http://127.0.0.1:8080/v1/ordinates"
	@echo "  curl -s -H 'Content-Type: application/json' --data-binary @$(CURDIR)/api/examples/render.json http://127.0.0.1:8080/v1/render -o tile.png"
	@echo
	exec $(BUILD)/tocherd

# A cluster on this machine, on loopback (deploy/cluster.py): redis-server, CLUSTER_REPLICAS
# tocherd replicas sharing it (--store redis://) on CLUSTER_PORT+1.., nginx with
# deploy/nginx/tocher.conf on CLUSTER_PORT; pid files and logs in $(BUILD)/cluster/.
# It keeps running after make returns; `make cluster-stop` stops it.
CLUSTER_PORT ?= 8090
CLUSTER_REDIS_PORT ?= 6390
CLUSTER_REPLICAS ?= 3
CLUSTER_STORE ?= redis
cluster: deps
	@$(MAKE) --no-print-directory all
	@$(PYTHON) deploy/cluster.py start --build $(BUILD) --run $(BUILD)/cluster --port $(CLUSTER_PORT) \
	  --redis-port $(CLUSTER_REDIS_PORT) --replicas $(CLUSTER_REPLICAS) --store $(CLUSTER_STORE)

cluster-stop:
	@$(PYTHON) deploy/cluster.py stop --run $(BUILD)/cluster

clean:
	rm -rf build

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(SRV_OBJ:.o=.d) $(TEST_OBJ:.o=.d) $(BENCH_OBJ:.o=.d) $(PERF_OBJ:.o=.d) $(BUILD)/obj/tests/fuzz/fuzz_api.d
