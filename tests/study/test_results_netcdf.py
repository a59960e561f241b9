"""The results file: opens in xarray and netCDF4, CF attributes on every variable (cfchecks: tests/test_netcdf_convention.py)."""

from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

from pipeline.dataset import FLAGS, open_results
from pipeline.study import load_study, run_study
from pipeline.study.results import RESULT_VARIABLES

GLOBAL = ("title", "summary", "history", "source", "references", "Conventions", "study_file", "study_sha256")

NAMED = """\
title = "named columns, with positions"
output = "named.nc"
[[columns]]
named = "pompeys-pillar"
[[columns]]
named = "paper"
[records]
synthetic = [{generator = "one_sine_pulse", id = "pulse", ap = 6.0, tp = 0.6, dt = 0.01}]
[excitation]
angles = [0.0]
scales = [1.0, 2.0]
sa_period = 0.5
"""


@pytest.fixture(scope="module")
def results_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("named")
    (folder / "study.toml").write_text(NAMED, encoding="utf-8")
    report = run_study(load_study(folder / "study.toml"), serial=True, progress=False)
    return Path(report.path)


def test_opens_in_xarray_with_the_schema(results_file):
    ds = open_results(results_file)
    assert ds.peak_theta.dims == ("column", "record", "angle", "scale", "model")
    assert list(ds.column.values) == ["pompeys-pillar", "paper"] and list(ds.model.values) == ["3d"]
    assert ds.angle.attrs["units"] == "degree"
    for name in ("column_R", "column_r", "column_h", "slenderness", "beta", "theta_crit", "latitude", "longitude"):
        assert ds[name].dims == ("column",), name
    for name in ("earthquake", "station", "year", "magnitude", "record_sha256"):
        assert ds[name].dims == ("record",), name
    for name in ("pga", "pgv", "sa", "scale_factor"):
        assert ds[name].dims == ("record", "scale"), name
    assert np.isnan(ds.latitude.sel(column="paper")) and ds.latitude.sel(column="pompeys-pillar") > 31
    assert ds.overturned.dtype == np.int8 and ds.n_impacts.dtype == np.int32
    # plain xarray works too: the labels are the dimensions' coordinates
    with xr.open_dataset(results_file) as raw:
        assert list(raw.column.values) == ["pompeys-pillar", "paper"]
        assert float(raw.peak_theta.sel(column="paper", record="pulse", model="3d", angle=0.0, scale=2.0)) > 0


def test_every_variable_has_units_and_long_name(results_file):
    with netCDF4.Dataset(results_file) as nc:
        for name, var in nc.variables.items():
            assert "long_name" in var.ncattrs(), name
            if name in FLAGS:
                values = np.asarray(var.getncattr("flag_values"))
                assert values.dtype == var.dtype and len(var.getncattr("flag_meanings").split()) == values.size
            else:
                assert "units" in var.ncattrs(), name
        for name in RESULT_VARIABLES:
            assert name in nc.variables
            assert nc.variables[name].filters()["zlib"], name  # compressed
        for attr in GLOBAL:
            assert nc.getncattr(attr), attr
        assert nc.Conventions == "CF-1.10"
        assert "frustum-pipeline" in nc.source and "Vardoulakis" in nc.references
        assert nc.variables["latitude"].standard_name == "latitude"
        assert len(nc.study_sha256) == 64


def test_provenance(results_file):
    from pipeline.groundmotion.synthesis import one_sine_pulse

    ds = open_results(results_file)
    digest = one_sine_pulse(6.0, 0.6, dt=0.01, record_id="pulse").sha256()
    assert ds.record_sha256.values[0] == digest
    assert "study run" in ds.attrs["history"] and ds.attrs["study_file"] == "study.toml"


def test_write_is_atomic(results_file, tmp_path, monkeypatch):
    """A write that fails leaves neither a partial file nor a temporary one."""
    from pipeline import dataset

    ds = open_results(results_file)
    target = tmp_path / "out.nc"

    def boom(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", boom)
    with pytest.raises(RuntimeError):
        dataset.write_results(ds, target)
    assert list(tmp_path.iterdir()) == []
