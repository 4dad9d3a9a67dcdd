# Every target bootstraps its own virtual environment from nothing.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: all venv test test-portable test-explore lint format docs demo bench reproduce clean

all: test

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# Re-install only when the project's metadata changes.
$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[dev]"
	@touch $(STAMP)

venv: $(STAMP)

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks examples
	$(BIN)/ruff format --check src tests benchmarks examples

format: $(STAMP)
	$(BIN)/ruff check --fix src tests benchmarks examples
	$(BIN)/ruff format src tests benchmarks examples

# `make test` is deterministic: hypothesis replays the same derandomized examples
# on every run (tests/conftest.py), so the result depends only on the code.
# `make test-explore` runs the property tests with fresh random examples to hunt
# for new counterexamples (kept in .hypothesis/); turn each one found into an
# explicit @example or known-answer test.
test: lint test-portable
	$(BIN)/python -m pytest -q

# A machine unlike this one, simulated on every run (issue 25): the identity
# tests (bit-identical fits from stored inputs) and a smoke of the kernels,
# the decoder and the estimator, with numpy's AVX-512 paths disabled, then its
# AVX2/FMA paths too, and numba compiling for a generic x86-64 CPU.
PORTABLE_TESTS := tests/learner/test_learner_identity.py tests/dp/test_dp_simplify.py \
	tests/hmm/test_hmm_decode.py tests/learner/test_learner_estimator.py \
	tests/learner/test_learner_persist.py
test-portable: $(STAMP)
	@for level in avx512 avx2; do \
	  off="$$($(BIN)/python tests/cpu_dispatch.py $$level)"; \
	  echo "portable: NPY_DISABLE_CPU_FEATURES='$$off' NUMBA_CPU_NAME=generic"; \
	  NPY_DISABLE_CPU_FEATURES="$$off" NUMBA_CPU_NAME=generic \
	    $(BIN)/python -m pytest -q -p no:cacheprovider $(PORTABLE_TESTS) || exit 1; \
	done

test-explore: $(STAMP)
	NDLFD_HYPOTHESIS=explore $(BIN)/python -m pytest -q

# The documentation site, offline, warnings as errors: Sphinx + numpydoc, one
# page per public name (docs/generated/, rewritten each time so a removed name
# leaves no stale page), the gallery of examples/plot_*.py run and drawn
# (docs/auto_examples/), into docs/_build/html.
docs: $(STAMP)
	rm -rf docs/generated
	$(BIN)/python -m sphinx -b html -W --keep-going -q docs docs/_build/html
	@echo "docs: open docs/_build/html/index.html"

# A first run compiles ndlfd's kernels (numba, cached after) before its timed
# runs: the fit's here, the generation's in a second process meanwhile; on a
# terminal it says which while it does (benchmarks/bench_firstrun.py).
demo: $(STAMP)
	@echo "make demo: ndlfd demo --out demo-output (a first run compiles the kernels first, about 5 s on 2 idle cores; cached after)"
	$(BIN)/ndlfd demo --out demo-output

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_simplify.py
	$(BIN)/python benchmarks/bench_hmm.py

reproduce: $(STAMP)
	$(BIN)/ndlfd reproduce --out docs/reproduction

clean:
	rm -rf $(VENV) build dist *.egg-info src/*.egg-info .pytest_cache .ruff_cache demo-output \
	  docs/_build docs/generated docs/auto_examples docs/sg_execution_times.rst
