# optri: two commands on a fresh machine.
#   make demo   set up .venv, solve the bundled octagon, print it and its table,
#               plot it, and reproduce the paper's tables into demo-output/
#   make test   set up .venv, lint (ruff, mypy) and run the whole test suite
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
OUT    := demo-output

.PHONY: demo test lint bench clean browser

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test,shapely,mesh,gpu,dask,geo,compare]"
	touch $(STAMP)

demo: $(STAMP)
	mkdir -p $(OUT)
	$(BIN)/optri solve examples/octagon.csv --method memo --table --plot $(OUT)/octagon.png
	$(BIN)/optri chain 30 35 15 5 10 20 25
	$(BIN)/optri paper --out $(OUT)/paper

# the explorer page's tests drive Chromium from the system packages (playwright never
# downloads a browser); installed here when missing and we are root, else they skip
browser:
	@command -v chromium >/dev/null 2>&1 || [ "$$(id -u)" != 0 ] || \
	  { apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium; } || \
	  echo "chromium could not be installed: the browser tests will skip"

test: $(STAMP) browser
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/mypy src/optri
	NUMBA_CACHE_DIR=$(CURDIR)/.numba-cache $(BIN)/python -m pytest -n 2 tests src/optri README.md docs

bench: $(STAMP)
	NUMBA_CACHE_DIR=$(CURDIR)/.numba-cache $(BIN)/python benchmarks/bench_fast.py

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/mypy src/optri

clean:
	rm -rf $(VENV) $(OUT) .numba-cache .pytest_cache
