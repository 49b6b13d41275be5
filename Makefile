# rollfric: one entry point for people and CI.
#   make reports   build every report of experiments/manifest.yaml (installs what is missing)
#   make test      the whole test suite (a missing tool fails it, never skips)
#   make check     fmt + clippy + tests (what CI runs: .ci/run)
#   make bench     timing figures (the twins, the reports, a sweep seed's scenes)
#   make bench-baseline  the detector's CPU on the bench twins against an earlier build
#   make fuzz      a long run of the property tests of the readers and the fit
#   make robustness  the randomised sweep of twins (detected with no options, fitted)
#   make coverage    the 95 % intervals' coverage on the sweep's twins
SHELL := /bin/bash
CARGO ?= cargo
# Debian packages the build needs: the system OpenCV and libclang for its bindings;
# ffmpeg (required) decodes video for the detector and encodes the twins (and is the
# benchmark's decode-only reference).
APT_PACKAGES := libopencv-dev clang libclang-dev pkg-config ca-certificates ffmpeg chromium chromium-driver python3-venv
BIN := $(or $(CARGO_TARGET_DIR),target)/release/rollfric
# Snakemake and its executor plugins, pinned, in a virtual environment under target/
# (for the cluster workflow's tests; python3 and its venv module come from Debian).
SNAKEMAKE_VENV := $(or $(CARGO_TARGET_DIR),target)/snakemake
SNAKEMAKE_VERSION := 8.30.0
SNAKEMAKE_PINS := snakemake==$(SNAKEMAKE_VERSION) snakemake-executor-plugin-cluster-generic==1.0.9 \
                  snakemake-executor-plugin-slurm==2.8.0

.PHONY: all deps rust-components snakemake build reports test check fmt clippy bench bench-sweep bench-baseline fuzz robustness coverage clean

all: build

# Install the missing system packages (non-interactive; only when something is missing).
deps:
	@missing=""; \
	for p in $(APT_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'ok installed' || missing="$$missing $$p"; \
	done; \
	command -v python3 >/dev/null || missing="$$missing python3"; \
	if [ -n "$$missing" ]; then \
	  echo "installing system packages:$$missing"; \
	  sudo=""; [ "$$(id -u)" -eq 0 ] || sudo=sudo; \
	  $$sudo apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $$sudo apt-get install -y -qq $$missing >/dev/null || exit 1; \
	fi

# rustfmt and clippy: part of rustup's default toolchain profile; added when missing
# (a minimal profile), which needs rustup and its server.
rust-components:
	@for c in fmt:rustfmt clippy:clippy; do \
	  $(CARGO) $${c%%:*} --version >/dev/null 2>&1 && continue; \
	  command -v rustup >/dev/null || { \
	    echo "cargo $${c%%:*} is missing: install the toolchain's $${c#*:} component" >&2; exit 1; }; \
	  echo "installing the Rust component $${c#*:}"; \
	  rustup component add $${c#*:} || exit 1; \
	done

# The pinned Snakemake, installed once (again when the pin changes).
snakemake: deps
	@if ! $(SNAKEMAKE_VENV)/bin/snakemake --version 2>/dev/null | grep -qx '$(SNAKEMAKE_VERSION)'; then \
	  echo "installing Snakemake $(SNAKEMAKE_VERSION) into $(SNAKEMAKE_VENV)"; \
	  python3 -m venv $(SNAKEMAKE_VENV) && \
	  $(SNAKEMAKE_VENV)/bin/pip install -q --disable-pip-version-check $(SNAKEMAKE_PINS) || exit 1; \
	fi

build: deps
	$(CARGO) build --release --locked

reports: build
	$(BIN) build

# The unit and integration tests (the browser test included), then a build of every
# experiment of the manifest and `rollfric check` on its summary. With
# ROLLFRIC_REQUIRE_TOOLS=1 a test whose tool (ffmpeg, python3, chromium) or real fixture
# is missing fails instead of saying SKIPPED.
test: deps snakemake
	ROLLFRIC_REQUIRE_TOOLS=1 ROLLFRIC_SNAKEMAKE=$(abspath $(SNAKEMAKE_VENV))/bin/snakemake \
	  $(CARGO) test --release --locked
	$(CARGO) build --release --locked
	$(BIN) build
	$(BIN) check

fmt: rust-components
	$(CARGO) fmt --all -- --check

clippy: deps rust-components
	$(CARGO) clippy --release --locked --all-targets -- -D warnings

check: fmt clippy test

bench: build snakemake
	ROLLFRIC_SNAKEMAKE=$(abspath $(SNAKEMAKE_VENV))/bin/snakemake $(CARGO) bench --locked --bench pipeline
	@if [ "$(BENCH_SWEEP_SCENES)" != "0" ]; then $(MAKE) --no-print-directory bench-sweep; fi

# The detector's own work on the scenes of a robustness sweep seed (BENCH_SWEEP_SCENES,
# default 64, of seed BENCH_SWEEP_SEED, 40 s each): every scene's detector CPU per frame
# besides the decoder, and on each its pace against decoding alone (BENCH_SWEEP_ROUNDS
# paired rounds of `ffmpeg -f null` and `rollfric detect`), with their percentiles.
# Part of `make bench` (about an hour on two cores); BENCH_SWEEP_SCENES=0 leaves it out.
# The lens is given as `make robustness` gives it (ROBUSTNESS_LENS), so that the
# accuracy lines are the sweep's own.
BENCH_SWEEP_SCENES ?= 64
BENCH_SWEEP_SEED ?= 1
BENCH_SWEEP_ROUNDS ?= 3
bench-sweep: build
	$(CARGO) build --release --locked --example robustness
	ROBUSTNESS_PACE=$(BENCH_SWEEP_ROUNDS) ROBUSTNESS_LENS=$(ROBUSTNESS_LENS) \
	  $(or $(CARGO_TARGET_DIR),target)/release/examples/robustness \
	  $(BENCH_SWEEP_SCENES) $(BENCH_SWEEP_SEED) 40

# The detector's CPU on the video benchmark's twins (still cameras) against the build of
# an earlier commit, BASELINE_REV (default 4fe0d54: the last before the detector followed
# a moving camera), in paired rounds (ROLLFRIC_BENCH_ROUNDS, default 3). That commit's
# sources are taken with `git archive` into target/baseline/ and built there once.
BASELINE_REV ?= 4fe0d54
BASELINE_DIR = $(abspath $(or $(CARGO_TARGET_DIR),target))/baseline/$(BASELINE_REV)
bench-baseline: build
	@if [ ! -x $(BASELINE_DIR)/target/release/rollfric ]; then \
	  rm -rf $(BASELINE_DIR)/src && mkdir -p $(BASELINE_DIR)/src && \
	  git archive $(BASELINE_REV) | tar -x -C $(BASELINE_DIR)/src && \
	  $(CARGO) build --release --locked --bin rollfric \
	    --manifest-path $(BASELINE_DIR)/src/Cargo.toml --target-dir $(BASELINE_DIR)/target; \
	fi
	ROLLFRIC_BENCH_NO_REPORTS=1 ROLLFRIC_BENCH_NO_SCALE=1 \
	  ROLLFRIC_BENCH_BASELINE=$(BASELINE_DIR)/target/release/rollfric \
	  $(CARGO) bench --locked --bench pipeline

# The property tests of tests/fuzz.rs (a short pass runs in `make test`) with many more
# inputs: FUZZ_ITERS per target, from FUZZ_SEED.
FUZZ_ITERS ?= 200000
FUZZ_SEED ?= 12
fuzz: deps
	ROLLFRIC_FUZZ_ITERS=$(FUZZ_ITERS) ROLLFRIC_FUZZ_SEED=$(FUZZ_SEED) \
	  $(CARGO) test --release --locked --test fuzz -- --nocapture --test-threads 1

# The randomised robustness sweep: ROBUSTNESS_SCENES twins drawn from ROBUSTNESS_SEED
# (styles, sizes, frame rates, codecs, camera roll and mirroring, a thin faint wire, its
# shadow, mains flicker, a held release, an off-frame fulcrum, a variable frame rate,
# materials), each ROBUSTNESS_SECONDS long, detected with no options and fitted from
# geometry only. ROBUSTNESS_ONLY=N runs scene N alone and keeps its folder (video, YAML,
# angles.csv, truth.csv). ROBUSTNESS_WORK_SIDE=PX detects at that working side
# (`video.work_side_px`; default 640). A scene with a wide lens is detected with the
# coefficient `rollfric lens` fits from a gridded sheet filmed by its camera
# (ROBUSTNESS_LENS=sheet, the default; `none`: no lens given; `known`: the true one).
ROBUSTNESS_SCENES ?= 64
ROBUSTNESS_SEED ?= 1
ROBUSTNESS_SECONDS ?= 40
ROBUSTNESS_WORK_SIDE ?= 640
ROBUSTNESS_LENS ?= sheet
robustness: deps
	ROBUSTNESS_WORK_SIDE=$(ROBUSTNESS_WORK_SIDE) ROBUSTNESS_LENS=$(ROBUSTNESS_LENS) $(CARGO) run --release --locked --example robustness -- \
	  $(ROBUSTNESS_SCENES) $(ROBUSTNESS_SEED) $(ROBUSTNESS_SECONDS) $(ROBUSTNESS_ONLY)

# The coverage of s_r's 95 % intervals: the robustness sweep with every measured scene
# kept in target/coverage (COVERAGE_SCENES of them, enough that 60 or more are fitted),
# then each scene fitted again and its intervals compared with the twin's truth. Prints
# the share held and the median half-width, calibrated and least squares.
COVERAGE_SCENES ?= 64
coverage: deps
	rm -rf target/coverage
	ROBUSTNESS_KEEP=$(abspath target/coverage) ROBUSTNESS_LENS=$(ROBUSTNESS_LENS) $(CARGO) run --release --locked --example robustness -- \
	  $(COVERAGE_SCENES) $(ROBUSTNESS_SEED) $(ROBUSTNESS_SECONDS)
	$(CARGO) run --release --locked --example coverage -- target/coverage

clean:
	$(CARGO) clean
