# overseec: one-command setup, demo and tests on Debian 12.
#   make demo   install what is missing, then run the pipeline on the bundled sample scene
#   make test   install what is missing, then the lint gate (make lint) and the whole test suite
#   make docs   the API reference from the docstrings (pdoc) into build/docs/
# Every target is idempotent: a second run installs nothing and only re-checks.

SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
VENV ?= .venv
PY := $(VENV)/bin/python
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
DEBIAN_PACKAGES := qgis python3-qgis qgis-providers python3-rasterio python3-fiona python3-pyproj \
	python3-venv python3-dev build-essential xvfb xauth
DEMO_OUT ?= runs/demo
export QT_QPA_PLATFORM ?= offscreen

.PHONY: setup system venv demo test test-fast lint bench plugin docs clean

setup: system venv

## Debian packages: installed only when one is missing.
system:
	@missing=$$(for p in $(DEBIAN_PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q 'install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "overseec setup: installing Debian packages: $$missing"; \
	  $(SUDO) apt-get update -q; \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -q --no-install-recommends $$missing; \
	fi

## The venv sees Debian's GDAL/QGIS bindings; pip adds the rest under constraints.txt.
$(VENV)/bin/python:
	/usr/bin/python3 -m venv --system-site-packages $(VENV)

$(VENV)/.installed: $(VENV)/bin/python requirements.txt constraints.txt pyproject.toml setup.py
	$(PY) -m pip install -q -c constraints.txt -r requirements.txt
	$(PY) -m pip install -q -c constraints.txt --no-build-isolation --no-deps -e .
	touch $@

venv: system $(VENV)/.installed
	@# Debian's pyproj looks for PROJ data under sys.prefix; in a venv that is the venv.
	@mkdir -p $(VENV)/share && ln -sfn /usr/share/proj $(VENV)/share/proj
	@OVERSEEC_REQUIRE_KERNEL=1 $(PY) setup.py -q build_ext --inplace >/dev/null

demo: setup
	$(VENV)/bin/overseec demo --out $(DEMO_OUT)

## The lint and type gate: ruff (lint + format check) and mypy, configured in pyproject.toml.
lint: setup
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/mypy

test: setup lint
	$(PY) -m pytest -q -p no:cacheprovider

test-fast: setup
	$(PY) -m pytest -q -p no:cacheprovider -m "not slow"

bench: setup
	$(PY) -m pip install -q -c constraints.txt -r requirements-bench.txt
	for b in bench/bench_*.py; do echo "== $$b"; $(PY) $$b; done

## The API reference from the docstrings: pdoc (pinned in requirements-docs.txt, installed once, so
## later runs need no network) into build/docs/index.html. torch is never imported: the script
## blocks it and fails on any module that cannot be documented without it.
$(VENV)/.docs-installed: $(VENV)/.installed requirements-docs.txt constraints.txt
	$(PY) -m pip install -q -c constraints.txt -r requirements-docs.txt
	touch $@

docs: setup $(VENV)/.docs-installed
	$(PY) docs/build_reference.py --out build/docs

## QGIS plugin zip (Plugins > Manage and Install Plugins > Install from ZIP): pure Python, the same
## zip for every platform, built with the standard library alone. The plugin plans and segments in
## the overseec environment (`make setup` here, `pip install overseec[models]` elsewhere).
plugin:
	python3 scripts/build_plugin.py

clean:
	rm -rf build dist *.egg-info runs .pytest_cache
