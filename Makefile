# vito's set-up, build and test commands (see README.md).
#   make demo       install missing Debian packages, build, solve the default problem
#   make test       install missing Debian packages, run the test suite (optimised build), then
#                   the Python package's (pytest, tests/python/) in .venv
#   make python     the Python package (`import vito`) built into .venv (maturin), with pytest
#   make test-wheel the Python wheel (`pip wheel ./python`) installed into a fresh venv, solving
#   make test-slow  the slow tests (#[ignore]d by default)
#   make lint       rustfmt and clippy, as CI checks them
#   make test-slurm a sweep through `sbatch --array` on a private single-node Slurm (root, apt)
#   make robots-table  docs/robots.md: every URDF of example-robot-data (PyPI, into .venv)
#                   through vito inspect, init and check, beside Pinocchio's verdict
#   make pages      the pages and strips under results/ (results/pages.txt) redrawn by this build
#   make bench      the timing harnesses in benches/ (print figures)
#   make bench-casadi  `vito bench` beside the independent CasADi implementation (CasADi 3.8.2
#                   from PyPI into .venv-casadi; nothing else needs it)
#   make fuzz       1,000,000 generated and mutated inputs (problems, URDFs, expressions, chains, attributes, trajectory CSVs, names) through loading, the CSV readers and the writers of names (FUZZ_COUNT, FUZZ_SEED)
#   make fuzz-python 100,000 generated Python values through vito.Problem, the solve options, paths and pickles (FUZZ_PYTHON_COUNT)
#   make test-debian13  `make demo` and `make test` in a fresh Debian 13 chroot (Ipopt 3.14; root)

CARGO ?= cargo
PROBLEM ?= problems/hopper_2d.toml
OUT ?= out/hopper_2d

# MUMPS calls OpenBLAS on small dense blocks, where its threads only add overhead (and the
# solve lock already gives one solve per process); parallel work uses processes.
export OPENBLAS_NUM_THREADS ?= 1

.PHONY: deps build demo python test test-python test-wheel test-slow test-slurm lint pages bench bench-casadi robustness ladders fuzz fuzz-python test-debian13 robots-table

deps:
	bash vendor-config/install-deps.sh

build: deps
	$(CARGO) build --release

demo: build
	$(CARGO) run --release -- solve $(PROBLEM) --out $(OUT)

# The Python package in the project's virtual environment .venv (vendor-config/install-python.sh:
# python3 -m venv, maturin, numpy, pandas, matplotlib and pytest from PyPI, `maturin develop
# --release`, .venv/bin/vito linked to target/release/vito).
python: deps
	bash vendor-config/install-python.sh

# Solving tests need the optimised profile; `--release` is the default test run. Then the Python
# package's tests; pytest's exit 5 (no test collected) is a failure with its own message.
test: deps
	$(CARGO) test --release
	$(MAKE) --no-print-directory test-python

test-python: python
	.venv/bin/python -m pytest -q -m "not wheel" tests/python; status=$$?; \
	if [ $$status -eq 5 ]; then echo "test-python: pytest collected no test in tests/python" >&2; fi; \
	exit $$status

test-slow: deps
	$(CARGO) test --release -- --ignored --skip cli::sweep_slurm

# `pip wheel ./python`, installed into a fresh venv (numpy from PyPI), solving the hopper
# (tests/python/test_wheel.py; a few minutes: a wheel build and a new environment).
test-wheel: python
	.venv/bin/python -m pytest -q -m wheel tests/python

# Installs Slurm if missing (root, apt), starts it under /tmp/vito-slurm-ci, stops it after;
# skips with a message where it cannot be installed. See tools/slurm-ci.sh.
test-slurm: deps
	$(CARGO) test --release --test integration cli::sweep_slurm -- --ignored --nocapture

lint:
	$(CARGO) fmt --check
	$(CARGO) clippy --all-targets -- -D warnings

# The example-robot-data table (tools/robots_table.py, the package from vendor-config/install-python.sh).
robots-table: python
	.venv/bin/python tools/robots_table.py --vito target/release/vito --out docs/robots.md

# Every page, strip and sweep plot results/pages.txt lists, redrawn from the committed
# trajectories (`cargo test --release --test integration view::committed_pages` checks that
# the committed files are what this build draws). `sweep report` exits 1 for a grid with
# unsolved points; its plot is written all the same.
pages: build
	grep -v '^#' results/pages.txt | while read -r kind a b c d; do \
		case "$$kind" in \
		page) ./target/release/vito view "$$a" ;; \
		strip) ./target/release/vito view "$$b" --strip "$$a" --svg "$$c" $${d:+--problem "$$d"} ;; \
		report) ./target/release/vito sweep report "$$a" --metric "$$b" >/dev/null || test $$? -eq 1 ;; \
		esac || exit 1; \
	done

bench: deps
	$(CARGO) bench

# The reference problems solved by vito and by tools/independent/spec_casadi.py, one after the
# other, in one table (BENCHMARKS.md). CasADi comes from PyPI into a private venv, once.
CASADI_VENV ?= .venv-casadi
bench-casadi: build
	test -x $(CASADI_VENV)/bin/python || python3 -m venv $(CASADI_VENV)
	$(CASADI_VENV)/bin/python -c 'import casadi, numpy' 2>/dev/null || \
		$(CASADI_VENV)/bin/pip install --quiet casadi==3.8.2 numpy
	VITO_PYTHON=$(CASADI_VENV)/bin/python ./target/release/vito bench

# The nonconvex reference problems from ROBUSTNESS_STARTS seeded starts under each solve
# strategy: min/median/max objective, iterations and time per start (BENCHMARKS.md).
# ROBUSTNESS_ARGS picks a part, e.g. '--strategy shipped problems/hamr_jump.toml'.
ROBUSTNESS_STARTS ?= 10
ROBUSTNESS_ARGS ?=
robustness: build
	python3 tools/robustness.py --starts $(ROBUSTNESS_STARTS) $(ROBUSTNESS_ARGS)

# The refinement ladders: each reference problem at its file's grid and finer ones, one
# `vito solve` per grid (tools/ladders.py; BENCHMARKS.md). LADDERS_ARGS picks, e.g. 'hopper'
# or '--cold hopper'.
LADDERS_ARGS ?=
ladders: build
	python3 tools/ladders.py $(LADDERS_ARGS)

FUZZ_COUNT ?= 1000000
FUZZ_SEED ?= 1
fuzz: deps
	$(CARGO) run --release --example fuzz -- $(FUZZ_COUNT) $(FUZZ_SEED)

# Generated Python values through the package (tools/fuzz_python.py); docs/fuzz.md.
FUZZ_PYTHON_COUNT ?= 100000
fuzz-python: python
	.venv/bin/python tools/fuzz_python.py --count $(FUZZ_PYTHON_COUNT) --seed $(FUZZ_SEED)

# The two commands above on Debian 13 (trixie, Ipopt 3.14), in a debootstrapped chroot that is
# removed afterwards; needs root and Debian's archive. See tools/test-debian13.sh.
test-debian13:
	bash tools/test-debian13.sh
