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

# The main job: the default study (the paper's column, FEMA far-field pairs, several
# angles and scales, both models) on a local Dask cluster of processes; writes
# out/quickstart.nc and out/quickstart.png (under half a minute on two cores).
main: setup
	$(BIN)/frustum study run studies/quickstart.toml --plot out/quickstart.png

test: setup-test
	$(BIN)/python -m pytest -q

clean:
	rm -rf $(VENV) build *.egg-info
