# The two commands of the README. Each creates the virtual environment it needs.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: main test setup setup-test udunits clean

# --no-compile: byte-compiling every installed module (sympy, obspy, dask, ...) took longer than
# downloading them; Python compiles the few it imports on first use.
PIP_INSTALL := $(BIN)/python -m pip install --quiet --no-compile

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(PIP_INSTALL) --upgrade pip

setup: $(BIN)/python
	$(PIP_INSTALL) -e ".[records]"

setup-test: $(BIN)/python udunits
	$(PIP_INSTALL) -e ".[records,test]"

# The CF check of the tests (cfchecks, in the test extra) loads the UDUNITS-2 C library:
# Debian's libudunits2-0, installed here when missing (as root, as in CI); otherwise the
# command to run is printed and the CF test fails naming it.
udunits:
	@ldconfig -p 2>/dev/null | grep -q libudunits2 || { \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends libudunits2-0 >/dev/null; \
	  else \
	    echo "make: the CF check needs libudunits2: sudo apt-get install libudunits2-0" >&2; \
	  fi; }

# The main job: the default study (the paper's column, FEMA far-field pairs, several
# angles and scales, both models) on a local Dask cluster of processes; writes
# out/quickstart.nc and out/quickstart.png (how long: README.md, "The two commands").
main: setup
	$(BIN)/frustum study run studies/quickstart.toml --plot out/quickstart.png

# The tests run in one worker per core (pytest-xdist), at most TEST_WORKERS_MAX: on the 2-core CI
# machine the suite took 17-18 min in one process. More workers gain little (the longest files and the
# first compile of each kernel bound the time) and each adds its own memory, and processes to the Dask
# tests. Each file stays on one worker (loadfile): many files build an expensive module fixture.
# `make test TEST_WORKERS=0` runs them in one process, as plain `pytest` does.
TEST_WORKERS ?= auto
TEST_WORKERS_MAX ?= 4
test: setup-test
	$(BIN)/python -m pytest -q -n $(TEST_WORKERS) --maxprocesses $(TEST_WORKERS_MAX) --dist loadfile

clean:
	rm -rf $(VENV) build *.egg-info
