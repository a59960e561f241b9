# The two commands of the README. Each creates the virtual environment it needs.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: main test setup setup-test clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

setup: $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[records]"

setup-test: $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[records,test]"

# The main job: the default study on a local Dask cluster (until the
# earthquake pipeline lands, the paper reproduction).
main: setup
	$(BIN)/python studies/paper/reproduce.py --out studies/paper

test: setup-test
	$(BIN)/python -m pytest -q

clean:
	rm -rf $(VENV) build *.egg-info
