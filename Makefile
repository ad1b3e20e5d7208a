# optri: two commands on a fresh machine.
#   make demo   set up .venv, solve the bundled octagon, print it and its table,
#               plot it, and reproduce the paper's tables into demo-output/
#   make test   set up .venv, lint (ruff, mypy), run the whole test suite, build the docs
#   make docs   build the documentation site into docs/_build/html (warnings are errors)
# make demo installs the package alone (numpy, numba, matplotlib, click, rich); make test
# and make docs add the dev extra (tests, linters, docs toolchain, every optional feature).
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
BASE   := $(VENV)/.installed-base
STAMP  := $(VENV)/.installed
OUT    := demo-output

.PHONY: demo test lint bench clean browser docs core

$(BASE): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e .
	touch $(BASE)

$(STAMP): $(BASE)
	$(BIN)/python -m pip install --quiet -e ".[dev]"
	touch $(STAMP)

demo: $(BASE)
	mkdir -p $(OUT)
	$(BIN)/optri solve examples/octagon.csv --method memo --table --plot $(OUT)/octagon.png
	$(BIN)/optri chain 30 35 15 5 10 20 25
	$(BIN)/optri paper -o $(OUT)/paper

# the explorer page's tests drive Chromium from the system packages (playwright never
# downloads a browser); installed here when missing and we are root, else they skip
browser:
	@command -v chromium >/dev/null 2>&1 || [ "$$(id -u)" != 0 ] || \
	  { apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium; } || \
	  echo "chromium could not be installed: the browser tests will skip"

test: $(STAMP) browser
	$(BIN)/ruff check src tests benchmarks examples docs
	$(BIN)/mypy src/optri
	$(MAKE) --no-print-directory docs
	NUMBA_CACHE_DIR=$(CURDIR)/.numba-cache $(BIN)/python -m pytest -n 2 tests src/optri README.md docs

# the site: topic pages (docs/*.md), the API reference from the docstrings, the gallery
# (examples/plot_*.py run now); shares make test's kernel cache, so it compiles nothing twice
docs: $(STAMP)
	NUMBA_CACHE_DIR=$(CURDIR)/.numba-cache MPLBACKEND=Agg \
	  $(BIN)/python -m sphinx -W --keep-going -q -b html docs docs/_build/html
	@echo "documentation: docs/_build/html/index.html"

bench: $(STAMP)
	NUMBA_CACHE_DIR=$(CURDIR)/.numba-cache $(BIN)/python benchmarks/bench_fast.py

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks examples docs
	$(BIN)/mypy src/optri

# the compiled core built in place (src/optri/_core*.so), for working on the C++ with
# PYTHONPATH=src and no reinstall; `pip install -e .` builds it into the virtualenv instead
core: $(STAMP)
	cmake -S . -B build/dev -G Ninja -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=$(CURDIR)/$(BIN)/python
	cmake --build build/dev
	cp build/dev/_core*.so src/optri/

clean:
	rm -rf $(VENV) $(OUT) .numba-cache .pytest_cache docs/_build docs/api docs/auto_gallery \
	  docs/sg_execution_times.rst
