# Two commands for a fresh clone (see README): `make demo` and `make test`.
# Both create .venv and install everything themselves.
PYTHON ?= python3
VENV   ?= .venv
PY      = $(VENV)/bin/python
PIP     = $(PY) -m pip

.PHONY: demo test test-fast bench lint install clean

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --quiet --upgrade pip
	$(PIP) install --quiet -e '.[test,dev,dask]'
	touch $@

# torch and onnx are optional for users; the test target installs them so the torch and
# ONNX-export tests run. Pinned: 2.13.0 is the CPU wheel on this machine, an unpinned torch
# pulls a CUDA build.
$(VENV)/.extras: $(VENV)/.installed
	$(PIP) install --quiet torch==2.13.0
	$(PIP) install --quiet -e '.[onnx]'
	touch $@

install: $(VENV)/.installed

demo: $(VENV)/.installed
	$(VENV)/bin/gaitml demo --out demo-out

# The whole suite (tests/ and experiments/tests/) in a random order, with the BLAS libraries'
# own thread count (the machine's cores); its seed is printed at the start and the end:
# GAITML_TEST_SEED=N make test repeats that order. Then the tests whose figures come out of
# BLAS and LAPACK reductions (model training and the shipped models, the domain check's
# Mahalanobis distances, the features, PDR) again with one BLAS thread: a result that
# depended on how a sum is split between threads fails one of the two runs.
THREAD_SENSITIVE = tests/models tests/domain tests/features tests/pdr
ONE_THREAD = OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MKL_NUM_THREADS=1

test: $(VENV)/.extras
	$(PY) -m pytest -q --random-order
	$(ONE_THREAD) $(PY) -m pytest -q --random-order $(THREAD_SENSITIVE)

test-fast: $(VENV)/.installed
	$(PY) -m pytest -q --random-order -m "not slow"

# benchmarks/ is in the checkout, not the installed package: gaitml bench runs it from here.
bench: $(VENV)/.installed
	$(VENV)/bin/gaitml bench --out bench-out

lint: $(VENV)/.installed
	$(VENV)/bin/ruff check gaitml tests benchmarks experiments conftest.py
	$(VENV)/bin/ruff format --check gaitml tests benchmarks experiments conftest.py

clean:
	rm -rf $(VENV) demo-out bench-out runs .pytest_cache
