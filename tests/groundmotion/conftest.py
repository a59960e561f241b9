"""Shared fixtures: ObsPy's own test files and the FEMA P695 sets."""

from pathlib import Path

import obspy
import pytest

OBSPY_IO = Path(obspy.__file__).parent / "io"
KNET_FILE = OBSPY_IO / "nied" / "tests" / "data" / "test.knet"
EVT_FILE = OBSPY_IO / "kinemetrics" / "tests" / "data" / "BI008_MEMA-04823.evt"


@pytest.fixture(scope="session")
def knet_file():
    assert KNET_FILE.is_file(), "ObsPy's K-NET test file is missing from the installed obspy"
    return KNET_FILE


@pytest.fixture(scope="session")
def evt_file():
    assert EVT_FILE.is_file(), "ObsPy's Kinemetrics EVT test file is missing from the installed obspy"
    return EVT_FILE


@pytest.fixture(scope="session")
def fema_ff01():
    from pipeline.groundmotion import load

    return load("FEMA-FF-01")
