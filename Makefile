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

test: $(VENV)/.extras
	$(PY) -m pytest -q

test-fast: $(VENV)/.installed
	$(PY) -m pytest -q -m "not slow"

# benchmarks/ is in the checkout, not the installed package: gaitml bench runs it from here.
bench: $(VENV)/.installed
	$(VENV)/bin/gaitml bench --out bench-out

lint: $(VENV)/.installed
	$(VENV)/bin/ruff check gaitml tests benchmarks experiments
	$(VENV)/bin/ruff format --check gaitml tests benchmarks experiments

clean:
	rm -rf $(VENV) demo-out bench-out runs .pytest_cache
