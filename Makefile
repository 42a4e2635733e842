# slipstep: build, test and demo entry points.
#
#   make demo    set up everything, build the extension, run the embedded default case
#   make test    set up everything, build, then cargo tests + pytest
#   make bench   set up everything, build, then bench/run.py
#   make wheel   set up everything, build, then the wheel dist/slipstep-*.whl (README "pip")
#
# Set-up is idempotent and stamp-driven, so a second run with nothing changed does no apt, no pip
# and no maturin:
#   build/stamps/apt   Debian packages present (ci/setup-apt.sh; apt only if something is missing)
#   build/stamps/apt-bench  the bench's Debian packages (ci/apt-bench.txt: GetFEM, also in apt-packages)
#   .venv/.stamp-venv  venv made by /usr/bin/python3 --system-site-packages + pip packages, verified
#   .venv/.stamp-ext   `maturin develop --release` done; redone only when rust/, bindings/, Cargo
#                      files or pyproject.toml change (or the built _engine*.so has disappeared)

SHELL := bash
.SHELLFLAGS := -eu -o pipefail -c
.DELETE_ON_ERROR:
.DEFAULT_GOAL := help

ROOT        := $(CURDIR)
VENV        := $(ROOT)/.venv
PY          := $(VENV)/bin/python
STAMPS      := $(ROOT)/build/stamps
APT_STAMP   := $(STAMPS)/apt
BENCH_APT_STAMP := $(STAMPS)/apt-bench
VENV_STAMP  := $(VENV)/.stamp-venv
EXT_STAMP   := $(VENV)/.stamp-ext

# Environment for every recipe: the venv and rustup's cargo first on PATH; every pip install,
# including the one maturin runs for the project's dependencies, is constrained (numpy==1.24.2).
export VIRTUAL_ENV              := $(VENV)
export PATH                     := $(VENV)/bin:$(HOME)/.cargo/bin:$(PATH)
export PIP_CONSTRAINT           := $(ROOT)/ci/constraints.txt
export PIP_DISABLE_PIP_VERSION_CHECK := 1

# Everything that can change the compiled extension.
EXT_INPUTS := $(shell find rust bindings -type f -not -path '*/target/*' 2>/dev/null) \
              $(wildcard Cargo.toml Cargo.lock .cargo/config.toml rust-toolchain.toml) \
              pyproject.toml
# Rebuild if the installed extension module is gone (e.g. py/slipstep was wiped).
EXT_SO     := $(wildcard py/slipstep/_engine*.so)

.PHONY: help setup build wheel demo test test-rust test-py bench fmt clean distclean FORCE

help:
	@echo "make demo | test | bench   (each does all set-up first; see README.md)"
	@echo "make setup | build | wheel | test-rust | test-py | fmt | clean | distclean"

# ---------------------------------------------------------------- set-up
$(APT_STAMP): ci/setup-apt.sh ci/apt-packages.txt
	ci/setup-apt.sh
	@mkdir -p $(@D) && touch $@

$(BENCH_APT_STAMP): ci/setup-apt.sh ci/apt-bench.txt
	ci/setup-apt.sh ci/apt-bench.txt
	@mkdir -p $(@D) && touch $@

$(VENV_STAMP): ci/setup-venv.sh ci/debian-h5py.sh ci/check-env.py ci/requirements.txt ci/constraints.txt | $(APT_STAMP)
	ci/setup-venv.sh
	touch $@

setup: $(VENV_STAMP)

# ---------------------------------------------------------------- build
# --release everywhere: the Rust tests below reuse every artifact this build leaves in
# target/release (see test-rust).
$(EXT_STAMP): $(EXT_INPUTS) $(VENV_STAMP) $(if $(EXT_SO),,FORCE)
	maturin develop --release
	$(PY) ci/check-env.py --built
	touch $@

build: $(EXT_STAMP)

# The wheel of README "pip": same release profile and target/ as `maturin develop --release`,
# so after `make build` this only packs (about 1.5 s measured); the cases ship as package data.
wheel: $(EXT_STAMP)
	maturin build --release --out dist

# ---------------------------------------------------------------- run
demo: $(EXT_STAMP)
	MPLBACKEND=Agg $(VENV)/bin/slipstep run --out results/demo

# Rust tests: `cargo test --release --workspace` through ci/cargo-test.sh, which mirrors maturin's
# PYO3_* environment, so it shares every artifact in target/release with `maturin develop
# --release`. Measured on 2 cores, clean clone: maturin 3.8 min (placeholder crates) to 6.1 min
# (current engine, with a concurrent pytest); then this compiles only the test harnesses of
# slipstep-core and slipstep-py (0.5 s placeholder, 29 s engine), no dependency.
# Rejected, measured: plain `cargo test` (dev/test profile, target/debug) compiles every
# dependency again: +3.8 min, +790 MB. `cargo test --release -p slipstep-core` resolves features
# without bindings/ (num-traits/num-complex lose "default") and so recompiles faer, nalgebra &
# co.: +2.0 min, and slipstep-core twice after every change. Plain cargo without maturin's PYO3_*
# variables re-runs pyo3's build script, and pyo3 is rebuilt back and forth (~10 s each way).
test-rust: $(EXT_STAMP)
	ci/cargo-test.sh

# Exit code 5 (no tests collected) is a failure on purpose: it is not masked.  A skip for want of
# something `make test` installs fails (tests/conftest.py, ENFORCED); SLIPSTEP_ALLOW_MISSING, a
# developer's list of what their machine lacks, is unset here so that no such skip passes.
test-py: $(EXT_STAMP)
	env -u SLIPSTEP_ALLOW_MISSING MPLBACKEND=Agg $(PY) -m pytest -q tests

test: $(EXT_STAMP)
	ci/check-format.sh
	ci/cargo-test.sh
	env -u SLIPSTEP_ALLOW_MISSING MPLBACKEND=Agg $(PY) -m pytest -q tests

# bench/getfem_hertz.py: GetFEM 5.4 on the elastoplastic Hertz scene, slipstep's meshes, N = 5..40
# load steps, 3 processes each (bench/getfem_results.json; first, so the charts can use it);
# bench/getfem_hertz_3d.py: GetFEM on the 3D Hertz sphere, slipstep's meshes up to 92.6k DOFs
# (~40 min: its 92.6k-DOF run alone takes ~20 min on a quiet machine);
# bench/paired_3d.py: the 3D speed target, slipstep's command line and GetFEM alternated (~20 min);
# bench/run.py: the Hertz series (~30-40 min on 2 cores) and the 3D series (bench/series_3d.py);
# bench/dolfinx_side_by_side.py: the thick cylinder against dolfinx on identical meshes (~4 min),
# --scene sphere: the thick sphere in 3D likewise (~10 min; into bench/error_vs_time_3d.png too);
# bench/large_3d.py: the Hertz sphere at 100k, 300k, 600k DOFs, whole process (~10 min, 11 GiB).
# All write into bench/.
bench: $(EXT_STAMP) $(BENCH_APT_STAMP)
	$(PY) bench/getfem_hertz.py series
	$(PY) bench/getfem_hertz_3d.py series
	$(PY) bench/paired_3d.py
	MPLBACKEND=Agg $(PY) bench/run.py
	MPLBACKEND=Agg $(PY) bench/dolfinx_side_by_side.py
	MPLBACKEND=Agg $(PY) bench/dolfinx_side_by_side.py --scene sphere
	$(PY) bench/large_3d.py --size 100k 300k 600k

# Formats Rust (rustfmt.toml) and Python (pyproject.toml [tool.ruff]); `make test` checks both.
fmt: $(VENV_STAMP)
	cargo fmt --all
	ruff format --quiet .

# clean: build products (keeps .venv, results/). distclean: also the venv.
clean:
	cargo clean
	rm -rf build py/slipstep/_engine*.so $(EXT_STAMP)

distclean: clean
	rm -rf $(VENV)

FORCE:

# Fuzzing (tests/case/test_fuzz.py): `make test` runs a bounded, derandomized set of examples per
# target (a few seconds each); `make fuzz` runs SLIPSTEP_FUZZ_EXAMPLES random ones per target
# (default 2000: about 4 minutes on 2 cores, most of it gmsh on damaged binary files).
.PHONY: fuzz
fuzz: $(EXT_STAMP)
	SLIPSTEP_FUZZ_EXAMPLES=$${SLIPSTEP_FUZZ_EXAMPLES:-2000} MPLBACKEND=Agg \
		$(PY) -m pytest -q -p no:cacheprovider tests/case/test_fuzz.py

# The 3D engine fuzzer (tests/engine/test_fuzz_3d.py): `make test` runs 100 derandomized scenes;
# `make fuzz-3d` runs SLIPSTEP_FUZZ_EXAMPLES random ones per family (default 200: six families,
# about 5-10 minutes on 2 cores; 40 per family took 51-114 s).
.PHONY: fuzz-3d
fuzz-3d: $(EXT_STAMP)
	SLIPSTEP_FUZZ_EXAMPLES=$${SLIPSTEP_FUZZ_EXAMPLES:-200} MPLBACKEND=Agg \
		$(PY) -m pytest -q -p no:cacheprovider tests/engine/test_fuzz_3d.py
