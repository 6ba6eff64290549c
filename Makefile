# taylorode: every target but help first runs tools/setup.sh, which installs whatever is
# missing (gfortran, LAPACK/BLAS, fpm 0.12.0, the test-drive dev-dependency) and
# prints nothing when nothing is.
#
#   make run             the main job: the paper's Table 1 (fpm run --profile release)
#   make test            every test suite (fpm test, the accuracy suite in the release build);
#                        the last line is "N passed, N failed"
#   make test-checked    the tests with run-time checks and floating-point traps
#   make test-sanitize   the tests under AddressSanitizer and UBSan, with OpenMP (threads run in parallel)
#   make test-threads    the tests built with OpenMP: concurrent integrations really run in parallel
#   make ensemble        the ensemble command in an OpenMP release build: serial against threaded time
#   make test-mpi        the package in mpi/ (ensembles over MPI ranks) on 1 and 2 ranks; installs Open MPI
#   make test-petsc      the package in petsc/ (one system over ranks, PETSc) on 1 and 2 ranks; installs PETSc
#   make build           debug and release builds (the debug profile warns with -Wall -Wextra)
#   make floor           i-t-2's time per step on the paper's run against a hand-coded floor
#                        (FLOOR=path/to/it2_vdp.c, default ../shared/peers/floor/it2_vdp.c)
#   make install         the library (release) into PREFIX (default build/install): modules and the
#                        C header in include/, libtaylorode.a and .so and pkgconfig/taylorode.pc in lib/
#   make figures         every number and figure of the README regenerated with the machine's description
#                        (tools/figures.sh: out/, docs/*.png, README blocks; FULL=1 adds the full runs,
#                        PEERS=<peer harness> the peers in ROUNDS interleaved rounds, FLOOR=<it2_vdp.c>
#                        the floor; QUICK=1 checks the performance tooling in a few minutes)
#   make docs            the API documentation of src/ with FORD (installed into .venv if missing) in
#                        build/docs; fails on an undocumented public entity or a FORD warning
#
# ARGS is passed to the program: make test ARGS="schemes", make run ARGS="vdp --help".
# Each flag set builds in its own build/gfortran_<hash> directory.

SHELL := /bin/bash
FPM_VERSION := 0.12.0
VERSION := $(shell sed -n 's/^version = "\(.*\)"/\1/p' fpm.toml)
PREFIX ?= $(CURDIR)/build/install
# The interface tests build their C, F77 and Python programs against this installation
export TAYLORODE_PREFIX := $(CURDIR)/build/install

# Without fpm $(FPM_VERSION) on PATH, use the one tools/setup.sh installs into .venv.
ifneq ($(shell fpm --version 2>/dev/null | grep -cE 'Version: *$(FPM_VERSION)([^0-9.]|$$)'),1)
export PATH := $(CURDIR)/.venv/bin:$(PATH)
endif

# Added to the debug profile's flags (fpm's --flag replaces them unless --profile is given)
CHECKED_FLAGS := -fcheck=all -ffpe-trap=invalid,zero,overflow
SANITIZE_FLAGS := -fsanitize=address,undefined -fopenmp
THREADS_FLAGS := -fopenmp

args = $(if $(ARGS),-- $(ARGS))

# fpm test with options $(1); the test driver's "N passed, N failed" stays the last
# line of output even when fpm reports failed executions after it. If the test
# program stops before printing it, the line is made from the reported outcomes,
# counting the stopped run as one more failure.
define fpm_test
	@log="$$(mktemp)"; trap 'rm -f "$$log"' EXIT; \
	fpm test $(1) $(args) 2>&1 | tee "$$log"; status=$${PIPESTATUS[0]}; \
	summary="$$(grep -E '^[0-9]+ passed, [0-9]+ failed$$' "$$log" | tail -n 1)"; \
	if [ -z "$$summary" ]; then \
	  passed=$$(grep -cE '\[(PASSED|EXPECTED FAIL)\]$$' "$$log"); \
	  failed=$$(grep -cE '\[(FAILED|UNEXPECTED PASS)\]$$' "$$log"); \
	  echo "make: the test program stopped before its summary (exit status $$status)" >&2; \
	  echo "$$passed passed, $$((failed + 1)) failed"; \
	  [ "$$status" -ne 0 ] || status=1; \
	elif [ "$$(tail -n 1 "$$log")" != "$$summary" ]; then \
	  echo "$$summary"; \
	fi; \
	exit $$status
endef

.PHONY: help setup run test test-suites test-checked test-sanitize test-threads test-install build install floor docs figures \
	ensemble test-mpi test-petsc

help:
	@sed -n '/^#   make/s/^# *//p' Makefile

setup:
	@bash tools/setup.sh

run: setup
	@fpm run --profile release $(args)

# every suite: the debug build's, then the accuracy suite in the release build (its
# hundreds of integrations take 90 s in the debug build, 17 s in the release build);
# one summary line for both. With ARGS, the suite(s) asked for (accuracy in release).
test: setup test-install
ifeq ($(strip $(ARGS)),)
	@debug="$$(mktemp)"; release="$$(mktemp)"; trap 'rm -f "$$debug" "$$release"' EXIT; status=0; \
	$(MAKE) --no-print-directory test-suites 2>&1 | tee "$$debug"; [ "$${PIPESTATUS[0]}" -eq 0 ] || status=1; \
	$(MAKE) --no-print-directory test-suites ARGS=accuracy 2>&1 | tee "$$release"; \
	[ "$${PIPESTATUS[0]}" -eq 0 ] || status=1; \
	passed=0; failed=0; \
	for log in "$$debug" "$$release"; do \
	  line="$$(grep -E '^[0-9]+ passed, [0-9]+ failed$$' "$$log" | tail -n 1)"; \
	  [ -n "$$line" ] || line="0 passed, 1 failed"; \
	  set -- $$line; passed=$$((passed + $$1)); failed=$$((failed + $$3)); done; \
	echo "$$passed passed, $$failed failed"; \
	exit $$status
else
	@$(MAKE) --no-print-directory test-suites ARGS="$(ARGS)"
endif

# the suites in ARGS (default: all but accuracy) with fpm test; accuracy in the release build
test-suites:
	$(call fpm_test,$(if $(filter accuracy,$(firstword $(ARGS))),--profile release))

test-checked: setup test-install
	$(call fpm_test,--profile debug --flag "$(CHECKED_FLAGS)")

# gfortran 12 leaks the allocatable components of array-constructor temporaries (the
# test suites' lists of tests): LeakSanitizer is off unless ASAN_OPTIONS says otherwise.
# An allocation too large for any address space returns NULL (a status of the library's
# own; by default the sanitizer stops the program there).
test-sanitize: export ASAN_OPTIONS ?= detect_leaks=0:allocator_may_return_null=1
# an undefined-behaviour report stops the test program (a failure), not a line in the log
test-sanitize: export UBSAN_OPTIONS ?= halt_on_error=1:print_stacktrace=1
test-sanitize: setup test-install
	$(call fpm_test,--profile debug --flag "$(SANITIZE_FLAGS)" --c-flag "$(SANITIZE_FLAGS)" --link-flag "$(SANITIZE_FLAGS)")

test-threads: setup test-install
	$(call fpm_test,--profile debug --flag "$(THREADS_FLAGS)" --link-flag "$(THREADS_FLAGS)")

ensemble: setup
	@fpm run --profile release --flag "$(THREADS_FLAGS)" --link-flag "$(THREADS_FLAGS)" -- ensemble $(ARGS)

test-mpi: setup
	@bash tools/setup.sh mpi
	@bash tools/test-parallel.sh mpi

test-petsc: setup
	@bash tools/setup.sh petsc
	@bash tools/test-parallel.sh petsc

# the installation the interface tests build against (quiet unless it fails)
test-install:
	@$(MAKE) --no-print-directory install PREFIX="$(TAYLORODE_PREFIX)" > build/install.log 2>&1 || \
	  { cat build/install.log; echo "make: installing into $(TAYLORODE_PREFIX) failed" >&2; exit 1; }

install: setup
	fpm install --profile release --prefix "$(PREFIX)"
	@# fpm installs every module it built, the examples' and the app's too: only the library's stay
	@for module in $$(sed -n 's/^module \([a-z0-9_]*\).*/\1/p' example/*.f90 app/*.f90); do \
	  rm -f "$(PREFIX)/include/$$module.mod"; done
	install -m 644 include/taylorode.h "$(PREFIX)/include/"
	gfortran -shared -o "$(PREFIX)/lib/libtaylorode.so" -Wl,--whole-archive "$(PREFIX)/lib/libtaylorode.a" \
	  -Wl,--no-whole-archive -llapack -lblas
	mkdir -p "$(PREFIX)/lib/pkgconfig"
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(VERSION)|' tools/taylorode.pc.in > "$(PREFIX)/lib/pkgconfig/taylorode.pc"

build: setup
	fpm build
	fpm build --profile release

docs: setup
	@bash tools/docs.sh

figures: setup
	@bash tools/figures.sh

floor: setup
	@bash tools/floor.sh "$(FLOOR)"
