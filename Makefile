# mscgs — build, run, test, bench, install.
#
#   make            build every service and the mscgs tool into build/
#   make run        install missing packages, build, run the default exercise
#   make test       install missing packages, build under ASan+UBSan, run every test
#   make test-systemd  only the units under a real systemd in a container
#   make check-layers  no service includes or links another service's code
#   make bench      build optimised, run the benchmarks
#   make bench-multicast  the bus over multicast against tcp, and under loss (root)
#   make bench-translators  the gateway's CPU at 1,000 vehicles, DIS alone and with
#                   STANAG 4607 and Cursor on Target on
#   make bench-record  mscgs record at 1,000 vehicles, 10x: messages/s, CPU, MB per hour
#   make bench-replay REC=FILE  mscgs replay of a recording at 50x: wall time, messages/s
#   make bench-video  imagerd's live video: frame rate, CPU, entity update to the wire,
#                   glass to glass on the map
#   make montecarlo whole scenes in lockstep: every scenario family, the table
#                   (MC_RUNS, MC_SEED, MC_JOBS, MC_FAMILIES)
#   make validate-lockstep  the lockstep against the live system, 20 seeds
#   make validate-sar  SAR chips that hold the designated target, live, 8 seeds
#   make soak       long fault injection: 30+ trials a service, a long exercise
#   make install    install binaries, the page, systemd units, configs (PREFIX, DESTDIR)
#   make install-built  the same, of a build already made (O=...), building nothing
#   make clean      remove build/
#   make format     clang-format every C, C++ and header file
#
#   RENDER=osmesa|egl  imagerd's OpenGL context: OSMesa (default) or EGL
#                      surfaceless (Mesa 25.1 and later have no OSMesa)
#
# Out-of-tree: objects, generated protobuf-c code and binaries go under $(O).

PREFIX  ?= /usr/local
DESTDIR ?=
SYSCONFDIR ?= /etc
UNITDIR ?= $(PREFIX)/lib/systemd/system
O       ?= build
SAN     ?= 0
# FAULT=1 compiles in the debug-only fault channel (common/cgs_fault.h); the
# sanitizer build the tests use has it, release builds do not.
FAULT   ?= $(if $(filter 1,$(SAN)),1,0)

CC      ?= cc
CXX     ?= c++
PKGS     = libzmq libsodium libprotobuf-c geographiclib gdal inih libsystemd zlib libzstd fftw3 gsl libpng json-c libxml-2.0 libavcodec libavformat libavutil libswscale librsvg-2.0
# GDAL's include flags go only to the files that use GDAL (GDAL_SRCS, below);
# every program links it.
PKG_CFLAGS := $(shell pkg-config --cflags $(filter-out gdal,$(PKGS)) 2>/dev/null)
GDAL_CFLAGS := $(shell pkg-config --cflags gdal 2>/dev/null)
PKG_LIBS   := $(shell pkg-config --libs $(PKGS) 2>/dev/null)
CMOCKA_LIBS := $(shell pkg-config --libs cmocka 2>/dev/null)

WARN     = -Wall -Wextra -Werror -Wno-format-truncation  # snprintf truncation is intended
CPPFLAGS = -D_GNU_SOURCE -Icommon -I$(O)/gen $(PKG_CFLAGS) -MMD -MP
# The folders a source may include from besides common/: a service's files
# see their own service's folder only, so no service can include another's
# code; the mscgs tool (its lockstep engine drives every service's adapter)
# and the tests see every service's.
ALL_SVC_INC = $(addprefix -I,$(wildcard services/*) $(wildcard services/mscgs/*/))
src_inc = $(if $(filter services/mscgs/% tests/%,$(1)),$(ALL_SVC_INC),$(if $(filter services/%,$(1)),-Iservices/$(word 2,$(subst /, ,$(1)))))
CFLAGS   = -std=c11 $(WARN) -g
CXXFLAGS = -std=c++17 $(WARN) -g
LDLIBS   = $(PKG_LIBS) -lcivetweb -lstdc++ -lm -lpthread

ifeq ($(SAN),fuzz)
  WARN    += -Wno-unknown-warning-option
  SANFLAGS = -fsanitize=address,undefined,fuzzer-no-link -fno-omit-frame-pointer
  CFLAGS   += -O1 $(SANFLAGS)
  CXXFLAGS += -O1 $(SANFLAGS)
else ifeq ($(SAN),1)
  SANFLAGS = -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
  CFLAGS   += -O1 $(SANFLAGS)
  CXXFLAGS += -O1 $(SANFLAGS)
  LDFLAGS  += $(SANFLAGS)
else
  CFLAGS   += -O2
  CXXFLAGS += -O2
endif
ifeq ($(FAULT),1)
  CPPFLAGS += -DCGS_FAULT
endif

# Compilers may be overridden from the environment; "cc" default is fine on Debian.
ifeq ($(origin CC),default)
  CC = cc
endif
ifeq ($(origin CXX),default)
  CXX = g++
endif

PROTOS      := $(wildcard proto/*.proto)
PROTO_C     := $(patsubst proto/%.proto,$(O)/gen/%.pb-c.c,$(PROTOS))
PROTO_H     := $(PROTO_C:.c=.h)
COMMON_C    := $(wildcard common/*.c)
COMMON_CXX  := $(wildcard common/*.cpp)
FDS_C       := $(O)/gen/cgs_fds.c
LIB_OBJS    := $(patsubst %.c,$(O)/obj/%.o,$(COMMON_C)) \
               $(patsubst %.cpp,$(O)/obj/%.o,$(COMMON_CXX)) \
               $(patsubst $(O)/gen/%.c,$(O)/obj/gen/%.o,$(PROTO_C) $(FDS_C))
LIB         := $(O)/lib/libcgs.a

SERVICES    := $(patsubst services/%/main.c,%,$(wildcard services/*/main.c))
BINS        := $(addprefix $(O)/bin/,$(SERVICES))

UNIT_SRCS   := $(wildcard tests/unit/test_*.c)
UNIT_BINS   := $(patsubst tests/unit/%.c,$(O)/tests/unit/%,$(UNIT_SRCS))
INTEG_SRCS  := $(wildcard tests/integration/*.c)
INTEG_BINS  := $(patsubst tests/integration/%.c,$(O)/tests/integration/%,$(INTEG_SRCS))
FAULT_SRCS  := $(wildcard tests/fault/*.c)
FAULT_BINS  := $(patsubst tests/fault/%.c,$(O)/tests/fault/%,$(FAULT_SRCS))
BENCH_SRCS  := $(wildcard tests/bench/*.c)
BENCH_BINS  := $(patsubst tests/bench/%.c,$(O)/bench/%,$(BENCH_SRCS))
FUZZ_SRCS   := $(wildcard tests/fuzz/fuzz_*.c)
FUZZ_BINS   := $(patsubst tests/fuzz/%.c,$(O)/fuzz/%,$(FUZZ_SRCS))
FUZZ_SECONDS ?= 60

# Each service's core objects: every .c in its folder but main.c, linked into
# the service and into the unit tests. The mscgs tool's subfolders
# (lockstep/) are part of its core; imagerd's ctx/ holds one backend per build.
MSCGS_SUB_C   := $(wildcard services/mscgs/*/*.c)
SVC_CORE_C    := $(filter-out services/%/main.c,$(wildcard services/*/*.c)) $(MSCGS_SUB_C)
SVC_CORE_OBJS := $(patsubst %.c,$(O)/obj/%.o,$(SVC_CORE_C))
SVC_LIB       := $(if $(SVC_CORE_OBJS),$(O)/lib/libcgs_services.a)

# imagerd's render context: one backend per binary (services/imagerd/ctx/).
RENDER  ?= osmesa
ifeq ($(filter $(RENDER),osmesa egl),)
  $(error RENDER must be osmesa or egl, not '$(RENDER)')
endif
GL_LIBS_osmesa := $(shell pkg-config --libs osmesa 2>/dev/null || echo -lOSMesa)
GL_LIBS_egl    := $(shell pkg-config --libs egl opengl 2>/dev/null || echo -lEGL -lOpenGL)
CTX_OBJ_osmesa := $(O)/obj/services/imagerd/ctx/im_ctx_osmesa.o
CTX_OBJ_egl    := $(O)/obj/services/imagerd/ctx/im_ctx_egl.o
# The other backend, built and tested too: its render test and an imagerd.
ALT_RENDER     := $(if $(filter osmesa,$(RENDER)),egl,osmesa)
ALT_BINS       := $(O)/bin-$(ALT_RENDER)/imagerd $(O)/tests/unit/test_im_render@$(ALT_RENDER)

# stationd's page: its own files (the script is ES modules in web/js, no
# bundler), and OpenLayers, milsymbol and mpegts.js (the live video's
# player) from the npm packages its lock file names (scripts/install-deps
# runs npm ci), copied into $(O)/web, which stationd serves (no CDN: it
# works on a lab network).
WEB_DIR    := services/stationd/web
WEB_NPM    := $(WEB_DIR)/node_modules
WEB_OWN    := $(addprefix $(O)/web/,index.html style.css)
WEB_JS     := $(patsubst $(WEB_DIR)/%,$(O)/web/%,$(wildcard $(WEB_DIR)/js/*.js))
WEB_VENDOR := $(addprefix $(O)/web/vendor/,ol.js ol.css milsymbol.js mpegts.js)
WEB_FILES  := $(WEB_OWN) $(WEB_JS) $(WEB_VENDOR)

JOBS    ?= $(shell nproc 2>/dev/null || echo 2)

# Keep objects that pattern chains would otherwise delete as intermediates.
.SECONDARY:

.PHONY: all run test test-systemd test-build check-layers bench bench-multicast bench-translators bench-video bench-record bench-replay montecarlo validate-lockstep validate-sar soak fault-build fuzz fuzz-build install install-built clean format deps help
.DEFAULT_GOAL := all

all: $(BINS) $(WEB_FILES)

help:
	@sed -n '2,21p' Makefile | sed 's/^# \{0,1\}//'

deps:
	@scripts/install-deps

# The default exercise at RUN_SPEED times real time, so the intercept ends
# within about three minutes (its 95th percentile in lockstep is about 650 s
# of simulation after the designation at 120 s); --duration stops it in any
# case after RUN_DURATION s of simulation. RUN_SPEED=1 runs it at real time.
RUN_SPEED ?= 5
RUN_DURATION ?= 900
run: deps
	@$(MAKE) --no-print-directory -j$(JOBS) all
	$(O)/bin/mscgs run --exercise deploy/exercises/default.ini --out $(O)/run --speed $(RUN_SPEED) \
	    --duration $(RUN_DURATION) --stop-after-intercept 20 $(RUN_ARGS)

# The test build lives in its own folder so it never mixes with release objects.
# The systemd test runs the release build in a container (tests/systemd/).
test: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/asan SAN=1 test-build
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 all
	@$(MAKE) --no-print-directory O=build/asan check-layers
	@CGS_RELEASE_BUILD=build/release CGS_MAKE_CACHE=1 tests/run build/asan

# Only the systemd container test (makes its cached image when there is none).
test-systemd: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 all
	@CGS_RELEASE_BUILD=build/release CGS_MAKE_CACHE=1 tests/run build/asan systemd

# No service includes or links another service's code (the tool and the
# tests may): over the tree, and over this build's binaries.
check-layers: $(BINS)
	@scripts/check-layering . $(O) && echo "check-layers: no service includes or links another's code"

test-build: $(BINS) $(WEB_FILES) $(UNIT_BINS) $(INTEG_BINS) $(FAULT_BINS) $(ALT_BINS)

bench: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 all $(addprefix build/release/bench/,$(notdir $(BENCH_BINS)))
	@tests/bench/run build/release

# The bus over UDP multicast against TCP, and under loss, between network
# namespaces (root): opt-in, about 4 minutes.
bench-translators: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 all
	@tests/bench/translators.sh build/release

# imagerd's live video: frame rate, CPU, entity update to the wire, glass to
# glass on the map in Chromium (about 3 minutes).
bench-video: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 all
	@tests/bench/video.sh build/release

bench-record: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 all
	@tests/bench/record.sh build/release

# A recording replayed at SPEED (default 50) into a bus a listener records.
bench-replay: deps
	@test -n "$(REC)" || { echo "make bench-replay REC=FILE [EX=EXERCISE] [SPEED=50]: a recording (mscgs run --record --duration 3600 makes a one-hour one)"; exit 2; }
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 all
	@tests/bench/replay.sh build/release $(REC) $(or $(EX),deploy/exercises/default.ini) $(or $(SPEED),50)

bench-multicast: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 all build/release/bench/bench_mcast
	@tests/bench/multicast.sh build/release

# Whole scenes in lockstep (opt-in): every scenario family of
# deploy/scenarios/, MC_RUNS runs each, the table of imaged rates and
# tracking metrics (MC_RUNS, MC_SEED, MC_JOBS, MC_FAMILIES).
MC_RUNS ?= 200
MC_SEED ?= 1
MC_JOBS ?= $(JOBS)
MC_FAMILIES ?= default convoy crossing notch stop-go masked dense
montecarlo: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 build/release/bin/mscgs
	@scripts/montecarlo-table build/release $(MC_RUNS) $(MC_SEED) $(MC_JOBS) $(MC_FAMILIES)

# The lockstep against the live system (opt-in, about ten minutes): the
# default exercise over 20 seeds, live at 20x and in lockstep.
validate-lockstep: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 all
	@tests/lockstep/validate.sh build/release 20 20

validate-sar: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/release SAN=0 all
	@tests/measure/sar.sh build/release 8 4 360

# Long fault injection (opt-in: not part of `make test`): at least 30 trials
# of each service, then a long exercise that checks memory and message loss
# (tests/fault/soak; SOAK_MINUTES, SOAK_SCALE, FAULT_TRIALS, SOAK_SERVICES).
# Optimised, without sanitizers, with the fault channel.
soak: deps
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/soak SAN=0 FAULT=1 fault-build
	@tests/fault/soak build/soak

fault-build: $(BINS) $(WEB_FILES) $(INTEG_BINS) $(FAULT_BINS)

# Coverage-guided fuzzing of the parsers (opt-in: not part of `make test`).
fuzz:
	@scripts/install-deps --fuzz
	@$(MAKE) --no-print-directory -j$(JOBS) O=build/fuzz SAN=fuzz CC=clang CXX=clang++ fuzz-build
	@set -e; for f in $(patsubst tests/fuzz/%.c,build/fuzz/fuzz/%,$(FUZZ_SRCS)); do \
	    mkdir -p build/fuzz/corpus/$$(basename $$f); \
	    echo "fuzzing $$(basename $$f) for $(FUZZ_SECONDS) s"; \
	    $$f -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 build/fuzz/corpus/$$(basename $$f) \
	        $$(ls -d tests/fuzz/corpus/$$(basename $$f) 2>/dev/null) 2>&1 | tail -5; \
	done

fuzz-build: $(FUZZ_BINS)

install: all
	@$(MAKE) --no-print-directory install-built

# What install copies, without building first: the tests install the build
# they were given (a build from sources edited since would not be the one
# under test).
install-built:
	@for b in $(BINS); do [ -x $$b ] || { echo "install-built: $$b is not built (make O=$(O) SAN=$(SAN) all)" >&2; exit 1; }; done
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/share/mscgs
	install -m 0755 $(BINS) $(DESTDIR)$(PREFIX)/bin/
	install -d $(DESTDIR)$(PREFIX)/share/mscgs/web/js $(DESTDIR)$(PREFIX)/share/mscgs/web/vendor
	install -m 0644 $(WEB_OWN) $(DESTDIR)$(PREFIX)/share/mscgs/web/
	install -m 0644 $(WEB_JS) $(DESTDIR)$(PREFIX)/share/mscgs/web/js/
	install -m 0644 $(WEB_VENDOR) $(DESTDIR)$(PREFIX)/share/mscgs/web/vendor/
	install -d $(DESTDIR)$(UNITDIR) $(DESTDIR)$(SYSCONFDIR)/mscgs $(DESTDIR)$(PREFIX)/share/doc/mscgs
	for f in deploy/systemd/*; do \
	    sed -e 's|@BINDIR@|$(PREFIX)/bin|g' -e 's|@DATADIR@|$(PREFIX)/share|g' -e 's|@SYSCONFDIR@|$(SYSCONFDIR)|g' $$f \
	        >$(DESTDIR)$(UNITDIR)/$$(basename $$f) && chmod 0644 $(DESTDIR)$(UNITDIR)/$$(basename $$f); \
	done
	@# The lab exercise becomes /etc/mscgs/exercise.ini, and its gateway's
	@# parameters (DIS on the lab network's interface) /etc/mscgs/gateway.ini,
	@# never over an admin's own.
	if [ -e $(DESTDIR)$(SYSCONFDIR)/mscgs/exercise.ini ]; then \
	    echo "install: $(DESTDIR)$(SYSCONFDIR)/mscgs/exercise.ini exists: left as it is"; \
	else \
	    sed -e 's|@DATADIR@|$(PREFIX)/share|g' -e 's|@SYSCONFDIR@|$(SYSCONFDIR)|g' deploy/exercises/lab.ini.in \
	        >$(DESTDIR)$(SYSCONFDIR)/mscgs/exercise.ini; \
	fi
	if [ -e $(DESTDIR)$(SYSCONFDIR)/mscgs/gateway.ini ]; then \
	    echo "install: $(DESTDIR)$(SYSCONFDIR)/mscgs/gateway.ini exists: left as it is"; \
	else \
	    install -m 0644 deploy/params/gateway-lab.ini $(DESTDIR)$(SYSCONFDIR)/mscgs/gateway.ini; \
	fi
	install -m 0644 README.md $(DESTDIR)$(PREFIX)/share/doc/mscgs/
	cp -r deploy/. $(DESTDIR)$(PREFIX)/share/mscgs/

clean:
	rm -rf build

format:
	clang-format -i $$(git ls-files '*.c' '*.h' '*.cpp')

# --- stationd's page ---------------------------------------------------------------
$(O)/web/%: $(WEB_DIR)/%
	@mkdir -p $(@D)
	cp $< $@

$(WEB_NPM)/%:
	@echo "$@ is missing: run scripts/install-deps (npm ci in $(WEB_DIR))" >&2; exit 1

$(O)/web/vendor/ol.js: $(WEB_NPM)/ol/dist/ol.js
$(O)/web/vendor/ol.css: $(WEB_NPM)/ol/ol.css
$(O)/web/vendor/milsymbol.js: $(WEB_NPM)/milsymbol/dist/milsymbol.js
$(O)/web/vendor/mpegts.js: $(WEB_NPM)/mpegts.js/dist/mpegts.js
$(WEB_VENDOR):
	@mkdir -p $(@D)
	cp $< $@

# --- generated protobuf-c code -------------------------------------------------
# One protoc-c run makes every file; the stamp keeps parallel builds from
# running it once per output.
$(O)/gen/.stamp: $(PROTOS)
	@mkdir -p $(O)/gen
	protoc-c --proto_path=proto --c_out=$(O)/gen $(PROTOS)
	@touch $@

$(PROTO_C) $(PROTO_H): $(O)/gen/.stamp ;

# Every message's schema as a google.protobuf.FileDescriptorSet (what MCAP
# recordings carry, so other tools decode them: cgs_schemas.h).
$(FDS_C): $(PROTOS)
	@mkdir -p $(O)/gen
	protoc --proto_path=proto --include_imports --descriptor_set_out=$(O)/gen/cgs_fds.bin $(PROTOS)
	cd $(O)/gen && xxd -i cgs_fds.bin >cgs_fds.c.tmp && mv cgs_fds.c.tmp cgs_fds.c

# --- objects -------------------------------------------------------------------
$(O)/obj/gen/%.o: $(O)/gen/%.c | $(O)/gen/.stamp
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

# The only sources that include GDAL's headers: the terrain's DEM import,
# stationd's relief, imagerd's SAR GeoTIFF, and their tests.
GDAL_SRCS := common/cgs_terrain_dem.c services/stationd/st_relief.c \
             services/imagerd/im_geotiff.c \
             tests/unit/test_terrain.c tests/unit/test_st_relief.c tests/unit/test_im_geotiff.c
$(patsubst %.c,$(O)/obj/%.o,$(GDAL_SRCS)): CPPFLAGS += $(GDAL_CFLAGS)

$(O)/obj/%.o: %.c | $(O)/gen/.stamp
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(call src_inc,$<) $(CFLAGS) -c $< -o $@

$(O)/obj/%.o: %.cpp | $(O)/gen/.stamp
	@mkdir -p $(dir $@)
	$(CXX) $(CPPFLAGS) $(call src_inc,$<) $(CXXFLAGS) -c $< -o $@

$(LIB): $(LIB_OBJS)
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

ifneq ($(SVC_LIB),)
$(SVC_LIB): $(SVC_CORE_OBJS)
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^
endif

# --- binaries ------------------------------------------------------------------
.SECONDEXPANSION:
# A service links its own objects and common/ only; the mscgs tool also
# every service's core ($(SVC_LIB), after its own objects), for its
# lockstep engine.
$(O)/bin/%: $$(foreach f,$$(wildcard services/$$*/*.c) $$(if $$(filter mscgs,$$*),$(MSCGS_SUB_C)),$(O)/obj/$$(basename $$(f)).o) $$(if $$(filter mscgs,$$*),$(SVC_LIB)) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $^ -o $@ $(LDLIBS)

# imagerd and its render test: the chosen backend; the other one beside them.
$(O)/bin/imagerd: $(CTX_OBJ_$(RENDER))
$(O)/bin/imagerd: LDLIBS += $(GL_LIBS_$(RENDER))
# (the archive again after the context object, which calls into it)
$(O)/tests/unit/test_im_render: $(CTX_OBJ_$(RENDER))
$(O)/tests/unit/test_im_render: LDLIBS := $(SVC_LIB) $(LDLIBS) $(GL_LIBS_$(RENDER))
$(O)/bench/bench_imagerd: $(CTX_OBJ_$(RENDER))
$(O)/bench/bench_imagerd: LDLIBS := $(SVC_LIB) $(LDLIBS) $(GL_LIBS_$(RENDER))

$(O)/bin-$(ALT_RENDER)/imagerd: $(foreach f,$(wildcard services/imagerd/*.c),$(O)/obj/$(basename $(f)).o) $(CTX_OBJ_$(ALT_RENDER)) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $^ -o $@ $(LDLIBS) $(GL_LIBS_$(ALT_RENDER))

$(O)/tests/unit/test_im_render@$(ALT_RENDER): $(O)/obj/tests/unit/test_im_render.o $(CTX_OBJ_$(ALT_RENDER)) $(SVC_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $^ -o $@ $(CMOCKA_LIBS) $(LDLIBS) $(GL_LIBS_$(ALT_RENDER))

$(O)/tests/unit/%: $(O)/obj/tests/unit/%.o $(SVC_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $^ -o $@ $(CMOCKA_LIBS) $(LDLIBS)

$(O)/tests/integration/%: $(O)/obj/tests/integration/%.o $(SVC_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $^ -o $@ $(LDLIBS)

$(O)/tests/fault/%: $(O)/obj/tests/fault/%.o $(SVC_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $^ -o $@ $(LDLIBS)

$(O)/bench/%: $(O)/obj/tests/bench/%.o $(SVC_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $^ -o $@ $(LDLIBS)

$(O)/fuzz/%: $(O)/obj/tests/fuzz/%.o $(SVC_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CXX) $(LDFLAGS) -fsanitize=address,undefined,fuzzer $^ -o $@ $(LDLIBS)

-include $(shell find $(O)/obj -name '*.d' 2>/dev/null)
