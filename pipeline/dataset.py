"""CF metadata from one variable catalog, and safe netCDF writing.

Every variable the pipeline writes is described once, here: its units,
long name and (where the CF standard-name table has one) standard name.
:func:`annotate` applies the catalog to a Dataset; :func:`write_netcdf` writes
it compressed and atomically (temporary name, then rename), so an interrupted
run never leaves a half-written file behind.
"""

import os
import tempfile
from datetime import datetime, timezone

import numpy as np

from pipeline import __version__

CONVENTIONS = "CF-1.10"
REFERENCE = (
    "Stefanou I., Psycharis I., Georgopoulos I.-O., Dynamic motion of a conical frustum "
    "over a rough horizontal plane, International Journal of Non-Linear Mechanics 46 (2011) 114-124"
)

# name: (units, long_name, standard_name or None)
VARIABLES = {
    "time": ("s", "time since the start of the simulation", "time"),
    "tau": ("1", "dimensionless time t sqrt(g/R)", None),
    "phi": ("rad", "precession angle of the column axis", None),
    "theta": ("rad", "inclination of the column axis from the vertical", None),
    "psi": ("rad", "rotation of the column about its own axis (Euler spin angle)", None),
    "x_p": ("m", "X coordinate of the contact point on the base plane", None),
    "y_p": ("m", "Y coordinate of the contact point on the base plane", None),
    "x_b": ("m", "X coordinate of the centre of the base on the base plane", None),
    "y_b": ("m", "Y coordinate of the centre of the base on the base plane", None),
    "phi_dot": ("rad s-1", "precession rate", None),
    "theta_dot": ("rad s-1", "inclination rate", None),
    "psi_dot": ("rad s-1", "spin angle rate", None),
    "omega_zeta": ("rad s-1", "spin: angular velocity component along the column axis", None),
    "energy": ("J", "mechanical energy relative to the base plane", None),
    "energy_hat": ("1", "mechanical energy relative to the base plane per m g R", None),
    "work_ground": ("J", "work done on the column by the ground motion", None),
    "work_ground_hat": ("1", "work done on the column by the ground motion per m g R", None),
    "normal_force": ("N", "normal contact force", None),
    "normal_force_hat": ("1", "normal contact force per weight m g", None),
    "tangential_force": ("N", "magnitude of the tangential contact force", None),
    "tangential_force_hat": ("1", "magnitude of the tangential contact force per weight m g", None),
    "mu_mob": ("1", "mobilized friction coefficient |F_t|/N", None),
    "ground_acc_x": ("m s-2", "ground acceleration, X component", None),
    "ground_acc_y": ("m s-2", "ground acceleration, Y component", None),
    "ground_acc_z": ("m s-2", "ground acceleration, vertical component (upwards)", None),
}

FLAGS = {
    "phase": ([0, 1, 2], "at_rest rolling_on_rim overturned", "motion phase of the column"),
}


def annotate(ds):
    """Attach units, long names and standard names from the catalog (in place).

    Returns
    -------
    xarray.Dataset
        The same dataset, for chaining.
    """
    for name in list(ds.variables):
        if name in VARIABLES:
            units, long_name, standard_name = VARIABLES[name]
            ds[name].attrs.update(units=units, long_name=long_name)
            if standard_name:
                ds[name].attrs["standard_name"] = standard_name
        elif name in FLAGS:
            values, meanings, long_name = FLAGS[name]
            ds[name].attrs.update(
                flag_values=np.array(values, dtype=ds[name].dtype),
                flag_meanings=meanings,
                long_name=long_name,
            )
    ds.attrs.setdefault("Conventions", CONVENTIONS)
    ds.attrs.setdefault("references", REFERENCE)
    ds.attrs.setdefault("source", f"frustum-pipeline {__version__}")
    return ds


def append_history(ds, line):
    """Add a time-stamped line to the global ``history`` attribute (CF)."""
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    previous = ds.attrs.get("history", "")
    ds.attrs["history"] = (previous + "\n" if previous else "") + f"{stamp} {line}"
    return ds


def write_netcdf(ds, path):
    """Write a dataset to netCDF4, compressed, atomically.

    Parameters
    ----------
    ds : xarray.Dataset
    path : str or os.PathLike
        Destination; its folder is created if needed. The file appears only
        once it is complete.
    """
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    encoding = {
        name: {"zlib": True, "complevel": 4}
        for name, var in ds.data_vars.items()
        if var.dtype.kind in "fiub"
    }
    fd, tmp = tempfile.mkstemp(prefix=".partial-", suffix=".nc", dir=folder)
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=encoding)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path
