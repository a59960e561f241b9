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
    # compliant-contact model (pipeline.compliant): the base's joint, and per drum
    "slip": ("m", "slip path of the base: area-weighted mean plastic slip of its contact points", None),
    "contact_area_fraction": ("1", "fraction of the base's contact area that carries load", None),
    "drum": ("1", "drum index, 0 at the bottom (a capital is the last)", None),
    "drum_dx": ("m", "X displacement of the drum's centre of mass relative to the ground", None),
    "drum_dy": ("m", "Y displacement of the drum's centre of mass relative to the ground", None),
    "drum_theta": ("rad", "inclination of the drum's axis from the vertical", None),
    "drum_rotation": ("rad", "rotation of the drum about the vertical (phi + psi), unwrapped", None),
    # study results (pipeline.sweep): one value per column, record, angle, scale, model
    "peak_theta": ("rad", "peak inclination of the column axis from the vertical", None),
    "peak_theta_ratio": ("1", "peak inclination over the critical (static overturning) inclination", None),
    "peak_time": ("s", "time of the peak inclination", None),
    "overturn_time": ("s", "time of overturning (NaN if the column stands)", None),
    "uplift_time": ("s", "time of the first uplift (NaN if the base never leaves the ground)", None),
    "n_impacts": ("1", "number of landings (impacts of the base on the ground)", None),
    "peak_mu_mob": ("1", "peak mobilized friction coefficient |F_t|/N", None),
    "residual_rotation": ("rad", "residual rotation of the column about the vertical at the end", None),
    "residual_displacement": ("m", "residual horizontal displacement of the centre of the base", None),
    "energy_balance_error": ("m", "error of the energy balance per unit weight, E/(m g)", None),
    # study coordinates
    "angle": ("degree", "incidence angle: counter-clockwise turn of the horizontal record pair", None),
    "scale": ("1", "factor on the record (all components)", None),
    "scale_factor": ("1", "factor applied to the record (all components)", None),
    "column_R": ("m", "radius of the base of the column", None),
    "column_r": ("m", "radius of the top of the column", None),
    "column_h": ("m", "height of the column", None),
    "slenderness": ("1", "slenderness h/R of the column", None),
    "beta": ("1", "conicity r/R of the column", None),
    "theta_crit": ("rad", "critical (static overturning) inclination atan(R/z_cm)", None),
    "latitude": ("degree_north", "latitude of the column", "latitude"),
    "longitude": ("degree_east", "longitude of the column", "longitude"),
    "column_label": ("1", "label of the column", None),
    "record_label": ("1", "identifier of the ground-motion record", None),
    "model_label": ("1", "model: 3d rolling frustum, 2d planar rocking or 3d-compliant drums on joints", None),
    "earthquake": ("1", "earthquake (event) of the record", None),
    "station": ("1", "recording station", None),
    "year": ("1", "year of the earthquake (-1: unknown)", None),
    "magnitude": ("1", "moment magnitude of the earthquake (NaN: unknown)", None),
    "record_sha256": ("1", "SHA-256 digest of the record samples and time step (GroundMotion.sha256)", None),
    "pga": ("m s-2", "peak ground acceleration of the scaled record: peak of the horizontal vector", None),
    "pgv": ("m s-1", "peak ground velocity of the scaled record: peak of the horizontal vector", None),
    "sa": ("m s-2", "5%-damped spectral acceleration RotD50 of the scaled record at the study period", None),
}

# Names whose meaning in a study Dataset differs from the time-history one:
# study energies are per unit weight (summary of pipeline.simulate) [m].
STUDY_VARIABLES = dict(VARIABLES)
STUDY_VARIABLES.update({
    "work_ground": ("m", "work done on the column by the ground motion per unit weight, W/(m g)", None),
})

FLAGS = {
    "phase": ([0, 1, 2], "at_rest rolling_on_rim overturned",
              "motion phase of the column (compliant model: base in contact / rocking on its rim or in "
              "flight / overturned)"),
    "overturned": ([0, 1], "stands overturned", "the column overturned"),
    "uplifted": ([0, 1], "never_uplifted uplifted", "the base left full contact with the ground"),
    "sliding_onset": ([0, 1], "no_sliding sliding_onset",
                      "the peak mobilized friction exceeded the study's friction coefficient "
                      "(before any final fall past theta_crit)"),
    "lift_off": ([0, 1], "no_lift_off lift_off",
                 "the normal contact force fell below zero, free flight (before any final fall past theta_crit)"),
    "status": ([0, 1], "ok failed", "status of the simulation (failed: values are NaN or 0)"),
}


def annotate(ds, catalog=None):
    """Attach units, long names and standard names from the catalog (in place).

    Parameters
    ----------
    ds : xarray.Dataset
    catalog : dict, optional
        Variable catalog to use instead of :data:`VARIABLES` (e.g.
        :data:`STUDY_VARIABLES` for study results).

    Returns
    -------
    xarray.Dataset
        The same dataset, for chaining.
    """
    catalog = VARIABLES if catalog is None else catalog
    for name in list(ds.variables):
        if name in catalog:
            units, long_name, standard_name = catalog[name]
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


def write_netcdf(ds, path, encoding=None):
    """Write a dataset to netCDF4, compressed, atomically.

    Parameters
    ----------
    ds : xarray.Dataset
    path : str or os.PathLike
        Destination; its folder is created if needed. The file appears only
        once it is complete.
    encoding : dict, optional
        Extra per-variable encodings, merged over the default compression.
    """
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    extra_encoding = encoding or {}
    encoding = {
        name: {"zlib": True, "complevel": 4}
        for name, var in ds.data_vars.items()
        if var.dtype.kind in "fiub"
    }
    for name, extra in extra_encoding.items():
        encoding[name] = {**encoding.get(name, {}), **extra}
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


# Study results keep string labels on the dimensions column, record and model in
# memory; CF wants coordinate variables numeric and monotonic, so in the file the
# labels are auxiliary character coordinates and the dimensions have none.
RESULT_LABELS = {"column": "column_label", "record": "record_label", "model": "model_label"}


def write_results(ds, path):
    """Write a study results Dataset as CF netCDF (compressed, atomic).

    The string labels of the dimensions ``column``, ``record`` and ``model``
    are written as auxiliary coordinates ``column_label``, ``record_label``
    and ``model_label`` (character arrays); every string variable is stored as
    characters (CF 2.2). :func:`open_results` restores the in-memory layout.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`pipeline.sweep.run_study`.
    path : str or os.PathLike
    """
    out = ds.copy()
    for dim, label in RESULT_LABELS.items():
        if dim in out.coords:
            values = np.asarray(out[dim].values).astype(str)
            attrs = dict(out[dim].attrs)
            out = out.drop_vars(dim).assign_coords({label: (dim, values, attrs)})
    # attributes set by the caller (e.g. a target-level ``scale``) win over the catalog
    annotate(out, {k: v for k, v in STUDY_VARIABLES.items() if k not in out.variables or "long_name" not in out[k].attrs})
    encoding = {name: {"dtype": "S1"} for name, var in out.variables.items() if var.dtype.kind in "UO"}
    return write_netcdf(out, path, encoding=encoding)


def open_results(path):
    """Open a study results file written by :func:`write_results`.

    Returns
    -------
    xarray.Dataset
        Loaded into memory (the file is closed), with string coordinates
        ``column``, ``record`` and ``model`` on their dimensions again.
    """
    import xarray as xr

    with xr.open_dataset(path, engine="netcdf4") as f:
        ds = f.load()
    for dim, label in RESULT_LABELS.items():
        if label in ds.variables:
            attrs = dict(ds[label].attrs)
            values = np.asarray(ds[label].values).astype(str)
            ds = ds.drop_vars(label).assign_coords({dim: (dim, values, attrs)})
    return ds


def catalog_markdown():
    """The output-variable reference (``docs/variables.md``) as Markdown, from the catalogs."""
    lines = [
        "# Output variables",
        "",
        "Every variable the pipeline writes, with the units and long name its netCDF files",
        "carry (generated from `pipeline/dataset.py` by `python -m pipeline.dataset`; a test",
        "keeps this page equal to the catalog). Study results: `docs/studies.md`; fragility",
        "datasets: `docs/fragility.md`.",
        "",
        "| name | units | long name | CF standard name |",
        "|---|---|---|---|",
    ]
    for name, (units, long_name, standard) in STUDY_VARIABLES.items():
        lines.append(f"| `{name}` | {units} | {long_name} | {standard or ''} |")
    lines += ["", "Flags (integer, with `flag_values` and `flag_meanings`):", "",
              "| name | values | meanings | long name |", "|---|---|---|---|"]
    for name, (values, meanings, long_name) in FLAGS.items():
        lines.append(f"| `{name}` | {', '.join(map(str, values))} | {meanings} | {long_name} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(catalog_markdown(), end="")
