# optri: two commands on a fresh machine.
#   make demo   set up .venv, solve the bundled octagon, print it and its table,
#               plot it, and reproduce the paper's tables into demo-output/
#   make test   set up .venv, lint (ruff, mypy), run the whole test suite, build the docs
#   make docs   build the documentation site into docs/_build/html (warnings are errors)
# make demo installs the package alone (numpy, matplotlib, click, rich) and builds its
# compiled core; make test and make docs add the dev extra (tests, linters, docs toolchain,
# every optional feature). The checkout is used from src/ (a path file in .venv, the core
# built in place as src/optri/_core*.so), so PYTHONPATH=src always means this checkout.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
BASE   := $(VENV)/.installed-base
STAMP  := $(VENV)/.installed
OUT    := demo-output

.PHONY: demo test lint bench clean browser docs core

CORE   := src/optri/.core-built
CORE_SOURCES := CMakeLists.txt $(shell find src/core -name '*.cpp' -o -name '*.hpp' 2>/dev/null)

# pip install -e . brings the dependencies and proves the package builds; its import hook
# is then replaced by a plain path file to src/ (the hook would shadow PYTHONPATH)
USE_SRC = $(BIN)/python -c "import pathlib, shutil, site; \
  sp = pathlib.Path(site.getsitepackages()[0]); \
  [p.unlink() for p in sp.glob('_editable_skbc_optri.*')]; \
  shutil.rmtree(sp / 'optri', ignore_errors=True); \
  (sp / 'optri-src.pth').write_text('$(CURDIR)/src\n')"

$(BASE): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e .
	$(BIN)/python -m pip install --quiet "nanobind>=2.4" "cmake>=3.18" ninja
	$(USE_SRC)
	touch $(BASE)

# the compiled core, rebuilt in place when a C++ source changes
$(CORE): $(BASE) $(CORE_SOURCES)
	$(BIN)/cmake -S . -B build/dev -G Ninja -DCMAKE_MAKE_PROGRAM=$(CURDIR)/$(BIN)/ninja \
	  -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=$(CURDIR)/$(BIN)/python >/dev/null
	$(BIN)/cmake --build build/dev
	cp build/dev/_core*.so src/optri/
	touch $(CORE)

$(STAMP): $(BASE)
	$(BIN)/python -m pip install --quiet -e ".[dev]"
	$(USE_SRC)
	touch $(STAMP)

demo: $(CORE)
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

test: $(STAMP) $(CORE) browser
	$(BIN)/ruff check src tests benchmarks examples docs
	$(BIN)/mypy src/optri
	$(MAKE) --no-print-directory docs
	NUMBA_CACHE_DIR=$(CURDIR)/.numba-cache $(BIN)/python -m pytest -n 2 tests src/optri README.md docs

# the site: topic pages (docs/*.md), the API reference from the docstrings, the gallery
# (examples/plot_*.py run now); shares make test's kernel cache, so it compiles nothing twice
docs: $(STAMP) $(CORE)
	NUMBA_CACHE_DIR=$(CURDIR)/.numba-cache MPLBACKEND=Agg \
	  $(BIN)/python -m sphinx -W --keep-going -q -b html docs docs/_build/html
	@echo "documentation: docs/_build/html/index.html"

bench: $(STAMP) $(CORE)
	NUMBA_CACHE_DIR=$(CURDIR)/.numba-cache $(BIN)/python benchmarks/bench_fast.py

lint: $(STAMP) $(CORE)
	$(BIN)/ruff check src tests benchmarks examples docs
	$(BIN)/mypy src/optri

core: $(CORE)

clean:
	rm -rf $(VENV) $(OUT) build src/optri/_core*.so $(CORE) .numba-cache .pytest_cache docs/_build docs/api docs/auto_gallery \
	  docs/sg_execution_times.rst
