"""CF metadata from one variable catalog, and the one netCDF convention of every results file.

Every variable the pipeline writes is described once, here: its units, long
name, (where the CF standard-name table has one) standard name and whether
people read it in degrees. :func:`annotate` applies the catalog to a Dataset;
:func:`write_netcdf` writes any results Dataset (one simulation, a study, a
fragility fit) in the one convention below, compressed and atomically
(temporary name, then rename), so an interrupted run never leaves a
half-written file behind.

The convention
--------------
* Label dimensions (``column``, ``record``, ``model``, ``state``, any
  dimension whose coordinate holds strings) keep their labels as the
  dimension's own coordinate, so plain xarray selects by name::

      xr.open_dataset(f).sel(column="paper", model="3d", record="FEMA-FF-01")

  In the file the labels are character arrays (CF 2.2) named like their
  dimension and declared in every data variable's ``coordinates`` attribute:
  CF coordinate variables must be numeric, so for CF they are string-valued
  auxiliary coordinates (CF 6.1), which xarray reads back as the index.
* Every string variable is a character array; numbers are compressed.
* A catalog entry with ``degrees=True`` is also written in degrees as
  ``NAME_deg`` (units ``degree``).

A new output variable is one entry of :data:`VARIABLES`.
"""

import os
import shutil
from datetime import datetime, timezone
from typing import NamedTuple

import numpy as np

from pipeline import __version__
from pipeline.atomic import atomic_path
from pipeline.citation import REFERENCE
from pipeline.errors import OutputError

CONVENTIONS = "CF-1.10"


class Var(NamedTuple):
    """One catalog entry.

    Attributes
    ----------
    units : str
        UDUNITS string (CF ``units``).
    long_name : str
    standard_name : str or None
        A name of the CF standard-name table, where one fits.
    degrees : bool
        An angle [rad] people read: also written in degrees as ``NAME_deg``.
    """

    units: str
    long_name: str
    standard_name: str | None = None
    degrees: bool = False


VARIABLES = {
    # elapsed time, not a date: no standard_name "time" (CF 4.4 would want "s since <date>")
    "time": Var("s", "time since the start of the simulation (start of the record)"),
    "tau": Var("1", "dimensionless time t sqrt(g/R)"),
    "phi": Var("rad", "precession angle of the column axis"),
    "theta": Var("rad", "inclination of the column axis from the vertical", degrees=True),
    "psi": Var("rad", "rotation of the column about its own axis (Euler spin angle)"),
    # positions on the ground are from where the base's centre stood at rest (a colonnade's first column's)
    "x_p": Var("m", "X coordinate of the contact point on the base plane, from where the base's centre stood at rest"),
    "y_p": Var("m", "Y coordinate of the contact point on the base plane, from where the base's centre stood at rest"),
    "x_b": Var("m", "X coordinate of the centre of the base on the base plane, from where it stood at rest"),
    "y_b": Var("m", "Y coordinate of the centre of the base on the base plane, from where it stood at rest"),
    "phi_dot": Var("rad s-1", "precession rate"),
    "theta_dot": Var("rad s-1", "inclination rate"),
    "psi_dot": Var("rad s-1", "spin angle rate"),
    "omega_zeta": Var("rad s-1", "spin: angular velocity component along the column axis"),
    "energy": Var("J", "mechanical energy relative to the base plane"),
    "energy_hat": Var("1", "mechanical energy relative to the base plane per m g R"),
    "work_ground": Var("J", "work done on the column by the ground motion"),
    "work_ground_hat": Var("1", "work done on the column by the ground motion per m g R"),
    "normal_force": Var("N", "normal contact force"),
    "normal_force_hat": Var("1", "normal contact force per weight m g"),
    "tangential_force": Var("N", "magnitude of the tangential contact force"),
    "tangential_force_hat": Var("1", "magnitude of the tangential contact force per weight m g"),
    "mu_mob": Var("1", "mobilized friction coefficient |F_t|/N (3d-compliant: N is the joint's elastic normal "
                       "force, the one its friction cap mu N uses, so mu_mob never exceeds mu; the dashpot's share "
                       "of N is left out)"),
    "slip_velocity": Var("m s-1", "speed of the sliding base or rim point relative to the ground"),
    "ground_acc_x": Var("m s-2", "ground acceleration, X component"),
    "ground_acc_y": Var("m s-2", "ground acceleration, Y component"),
    "ground_acc_z": Var("m s-2", "ground acceleration, vertical component (upwards)"),
    # compliant-contact model (pipeline.compliant): the base's joint, and per drum
    "slip": Var("m", "slip path of the base: area-weighted mean plastic slip of its contact points"),
    "contact_area_fraction": Var("1", "fraction of the base's contact area that carries load"),
    "drum": Var("1", "body index in the structure's order (body_label names each): a column's drums bottom up "
                "and its capital; a colonnade's columns in turn, then its epistyle blocks"),
    "body_label": Var("1", "what the body is: drum 2, capital, column 2 drum 3, epistyle block 1"),
    "drum_dx": Var("m", "X displacement of the drum's centre of mass relative to the ground"),
    "drum_dy": Var("m", "Y displacement of the drum's centre of mass relative to the ground"),
    "drum_theta": Var("rad", "inclination of the drum's axis from the vertical", degrees=True),
    "drum_rotation": Var("rad", "rotation of the drum about the vertical (phi + psi), unwrapped"),
    "drum_dz": Var("m", "vertical displacement of the drum's centre of mass from its place at rest"),
    "drum_phi": Var("rad", "precession angle of the drum's axis: direction of its tilt (NaN upright)"),
    "drum_R": Var("m", "radius of the base of the drum (a capital: half its side)"),
    "drum_r": Var("m", "radius of the top of the drum (a capital: half its side)"),
    "drum_h": Var("m", "height of the drum"),
    "drum_z": Var("m", "height of the drum's base above the ground at rest"),
    # a code, not a flag: CF checks an auxiliary coordinate's flags as misused and asks for its units
    "drum_kind": Var("1", "kind of body: 0 a drum (frustum), 1 a capital (square block), 2 an epistyle block"),
    "drum_x": Var("m", "X coordinate of the body's centre of mass at rest (a colonnade's row along X, centred on 0)"),
    "drum_y": Var("m", "Y coordinate of the body's centre of mass at rest"),
    # the rigid planar frame of a colonnade (pipeline.frame, 2d-frame): its epistyle translates with the capitals
    "epistyle_dx": Var("m", "horizontal displacement of the epistyle along the row (2d-frame: it translates with "
                       "the capitals' top edges)"),
    "epistyle_dz": Var("m", "vertical displacement of the epistyle from its place at rest (2d-frame)"),
    # study results (pipeline.study): one value per column, record, angle, scale, model
    "peak_theta": Var("rad", "peak inclination of the column axis from the vertical", degrees=True),
    "peak_theta_ratio": Var("1", "peak inclination over the critical (static overturning) inclination"),
    "peak_time": Var("s", "time of the peak inclination"),
    "overturn_time": Var("s", "time of overturning (NaN if the column stands)"),
    "uplift_time": Var("s", "time of the first uplift (NaN if the base never leaves the ground)"),
    "n_impacts": Var("1", "number of landings (impacts of the base on the ground)"),
    "peak_mu_mob": Var("1", "peak mobilized friction coefficient |F_t|/N while in contact (3d-compliant: N "
                            "elastic, as for mu_mob; never above the friction coefficient)"),
    "min_normal_force_hat": Var("1", "lowest normal contact force per weight m g while in contact"),
    "sliding_time": Var("s", "time the base or the rim first slides (NaN if it never does)"),
    "lift_off_time": Var("s", "time the column first lifts off into flight (NaN if it never does)"),
    "energy_friction": Var("m", "energy removed by sliding friction per unit weight, E/(m g)"),
    "residual_rotation": Var("rad", "residual rotation of the column about the vertical at the end", degrees=True),
    "residual_displacement": Var("m", "residual horizontal displacement of the centre of the base"),
    "energy_balance_error": Var("m", "error of the energy balance per unit weight, E/(m g)"),
    # study results of the compliant model (pipeline.compliant): the residual dislocation per joint
    "joint": Var("1", "joint index in the structure's order (joint_label names each): a column's base on the "
                 "ground, its bed joints bottom up and its capital's; a colonnade's columns in turn, then the "
                 "epistyle blocks' bearings on the capitals and the head joints between blocks"),
    "joint_label": Var("1", "what the joint is: base of the column, bed joint under drum 2, capital 2 / epistyle "
                       "block 1, head joint blocks 1-2"),
    "joint_slip": Var("m", "residual slip of the joint: offset of the upper body's bearing face from the centre "
                      "of the face below (a base: from where its column stood)"),
    "joint_twist": Var("rad", "residual twist of the joint: rotation of the upper body relative to the lower one "
                       "about the lower axis", degrees=True),
    "joint_tilt": Var("rad", "residual relative tilt of the joint: angle between the axes of the upper and the "
                      "lower body (a base: the tilt of the body on it)", degrees=True),
    "joint_opening": Var("m", "residual opening of the joint: widest gap between a contact point and the face below"),
    "joint_diameter": Var("m", "diameter of the joint's bearing face"),
    "dislocation_ratio": Var("1", "largest residual slip of a bed joint over its diameter (0: no bed joint)"),
    "overturn_drum": Var("1", "index of the body that lay down or fell first, in the structure's order (-1: none "
                         "fell; a model that runs the structure as one body: 0)"),
    "overturn_body": Var("1", "label of the body that lay down or fell first (empty: none fell; the column or the "
                         "colonnade: a model that runs it as one body)"),
    "epistyle_slip": Var("m", "largest residual slip of an epistyle block on a capital (a colonnade; NaN for a column)"),
    "epistyle_opening": Var("m", "widest head joint between epistyle blocks at the end (a colonnade; NaN for a "
                            "column)"),
    "n_drums": Var("1", "number of drums of the column (1: a monolith)"),
    "structure_source": Var("1", "where the structure's dimensions come from: a named column's or colonnade's source "
                            "(empty: given in the study file)"),
    # a colonnade's numbers (pipeline.structures.description.DIMENSIONS; a column alone: 1 column, 0 blocks)
    "n_columns": Var("1", "number of columns in the row (1: the column stands alone)"),
    "interaxial": Var("m", "spacing of the column axes of the colonnade (NaN: the column stands alone)"),
    "epistyle_height": Var("m", "height of the epistyle blocks (NaN: the column stands alone)"),
    "epistyle_width": Var("m", "width of the epistyle blocks across the row (NaN: the column stands alone)"),
    "course_height": Var("m", "course above the epistyle carried as mass, as a height of its width (NaN: the "
                         "column stands alone)"),
    "n_blocks": Var("1", "number of epistyle blocks (0: the column stands alone)"),
    # imperfect drums (pipeline.structures.imperfections): what was drawn, the joints' per joint
    "seed": Var("1", "seed of the imperfections' draw (a study's [imperfections] seeds)"),
    "imperfection_tolerance": Var("m", "tolerance of the imperfect drums: each bed offset within a disc of this "
                                  "radius and out of level by up to it across its diameter (NaN: perfect drums)"),
    "imperfection_seed": Var("1", "seed of the imperfections' draw (-1: perfect drums)"),
    "imperfection_friction_min": Var("1", "lower end of the range the columns' joints drew their friction from "
                                     "(NaN: no range, the friction given)"),
    "imperfection_friction_max": Var("1", "upper end of the range the columns' joints drew their friction from "
                                     "(NaN: no range, the friction given)"),
    "bed_offset_x": Var("m", "drawn X offset of the axis of the joint's upper body from the lower body's (0 at a "
                        "base on the ground; NaN: a joint that draws no imperfection, an epistyle's)"),
    "bed_offset_y": Var("m", "drawn Y offset of the axis of the joint's upper body from the lower body's (0 at a "
                        "base on the ground; NaN: a joint that draws no imperfection, an epistyle's)"),
    "bed_tilt": Var("rad", "drawn lean of the joint's bed from level: tan(tilt) is how far it is out of level "
                    "over its diameter (NaN: a joint that draws no imperfection)", degrees=True),
    "bed_tilt_azimuth": Var("rad", "drawn direction in which the joint's bed descends, counter-clockwise from X "
                            "(NaN: a joint that draws no imperfection)"),
    "bed_friction": Var("1", "drawn friction coefficient of the joint (NaN: no friction range, or a joint that "
                        "draws none)"),
    "structure": Var("1", "what stands, in words: the colonnade the column stands in (its number of columns, "
                     "interaxial spacing, epistyle), its drums and capital, or the column alone"),
    # the summary of one compliant run (pipeline.compliant) in a simulate file, beside the names above
    "drum_peak_theta": Var("rad", "peak inclination of the drum's axis from the vertical", degrees=True),
    "restitution": Var("1", "coefficient of restitution of planar rocking that the joints' normal damping "
                       "reaches (NaN: damping given, not calibrated, or a rigid model)"),
    "contact_damping": Var("Pa s m-1", "normal damping of the joints per unit area, c_n (NaN: a rigid model)"),
    # study coordinates
    "angle": Var("degree", "incidence angle: counter-clockwise turn of the horizontal record pair"),
    "scale": Var("1", "factor on the record (all components)"),
    "scale_factor": Var("1", "factor applied to the record (all components)"),
    "column_R": Var("m", "radius of the base of the column"),
    "column_r": Var("m", "radius of the top of the column"),
    "column_h": Var("m", "height of the column"),
    "slenderness": Var("1", "slenderness h/R of the column"),
    "beta": Var("1", "conicity r/R of the column"),
    "theta_crit": Var("rad", "critical (static overturning) inclination atan(R/z_cm)", degrees=True),
    "theta_crit_model": Var("rad", "critical inclination of the structure as the model runs it, which "
                            "peak_theta_ratio divides by (2d-frame: the rigid frame's, atan(b_e/z_e); the other "
                            "models: the column's theta_crit)", degrees=True),
    "latitude": Var("degree_north", "latitude of the column", "latitude"),
    "longitude": Var("degree_east", "longitude of the column", "longitude"),
    # label dimensions: strings on the dimension itself (module docstring)
    "column": Var("1", "label of the column"),
    "record": Var("1", "identifier of the ground-motion record"),
    "model": Var("1", "model: 3d rolling frustum, 2d planar rocking, 3d-compliant drums on joints or 2d-frame "
                 "rigid frame of a colonnade"),
    "earthquake": Var("1", "earthquake (event) of the record"),
    "station": Var("1", "recording station"),
    "year": Var("1", "year of the earthquake (-1: unknown)"),
    "magnitude": Var("1", "moment magnitude of the earthquake (NaN: unknown)"),
    "record_sha256": Var("1", "SHA-256 digest of the record samples and time step (GroundMotion.sha256)"),
    "pga": Var("m s-2", "peak ground acceleration of the scaled record: peak of the horizontal vector"),
    "pgv": Var("m s-1", "peak ground velocity of the scaled record: peak of the horizontal vector"),
    "sa": Var("m s-2", "5%-damped spectral acceleration RotD50 of the scaled record at the study period"),
    # site risk (pipeline.risk, frustum risk): a fragility integrated against a site's hazard curve. Intensities
    # are in the fragility's units (m s-2 for PGA and Sa, m s-1 for PGV), the units written in the file win.
    "site": Var("1", "label of the site of the hazard curve (the file's custom_site_id, else site-<row>)"),
    "site_longitude": Var("degree_east", "longitude of the site as the hazard curve gives it", "longitude"),
    "site_latitude": Var("degree_north", "latitude of the site as the hazard curve gives it", "latitude"),
    "site_depth": Var("km", "depth of the site as the hazard curve gives it (OpenQuake: km)"),
    "years": Var("year", "period T of probability_in_period"),
    "intensity": Var("m s-2", "intensity at which the integrand, the fragility and the interpolated hazard are given"),
    "intensity_g": Var("1", "intensity over standard gravity g = 9.80665 m s-2"),
    "hazard_level": Var("m s-2", "intensity level of the hazard curve (converted to SI from the file's unit)"),
    "hazard_level_g": Var("1", "intensity level of the hazard curve over standard gravity g = 9.80665 m s-2"),
    "hazard_rate": Var("year-1", "annual rate of exceedance of the hazard curve at its levels, -ln(1 - PoE)/T "
                       "from a probability of exceedance PoE in T years (inf: PoE 1)"),
    "hazard_poe": Var("1", "probability of exceedance of the level in the hazard curve's investigation time, as "
                      "the file gives it"),
    "hazard_rate_interpolated": Var("year-1", "annual rate of exceedance, log-log interpolated between the curve's "
                                    "levels and extended beyond them by its first and last segments' power laws"),
    "hazard_curve_end": Var("m s-2", "last level of the hazard curve with a positive rate"),
    "fragility_median": Var("m s-2", "median of the lognormal fragility curve (from the fragility file)"),
    "fragility_beta": Var("1", "lognormal dispersion of the fragility curve (from the fragility file)"),
    "fragility_probability": Var("1", "probability of reaching the damage state at the intensity (the fragility's "
                                 "lognormal curve)"),
    "risk_integrand": Var("year-1", "risk integrand P(DS | a) |dH/d ln a|: annual rate of reaching the damage state "
                          "per unit of ln intensity (its area over ln a is annual_frequency)"),
    "annual_frequency": Var("year-1", "mean annual frequency of reaching the damage state, integral of "
                            "P(DS | a) |dH/da| da (hazard curve extended beyond its ends by its end segments)"),
    "annual_frequency_lower": Var("year-1", "lower bound of the mean annual frequency: shaking beyond the hazard "
                                  "curve's last level counted at that level's probability, none below its first"),
    "annual_frequency_upper": Var("year-1", "upper bound of the mean annual frequency: every shaking beyond the "
                                  "hazard curve's last level reaches the damage state"),
    "annual_frequency_band_lower": Var("year-1", "lower bound of the mean annual frequency, bootstrap interval "
                                       "over the fragility's replicates"),
    "annual_frequency_band_upper": Var("year-1", "upper bound of the mean annual frequency, bootstrap interval "
                                       "over the fragility's replicates"),
    "probability_in_period": Var("1", "probability of reaching the damage state at least once in `years`, "
                                 "1 - exp(-annual_frequency years)"),
    "probability_in_period_lower": Var("1", "probability in `years` from annual_frequency_lower"),
    "probability_in_period_upper": Var("1", "probability in `years` from annual_frequency_upper"),
    "probability_in_period_band_lower": Var("1", "probability in `years` from annual_frequency_band_lower"),
    "probability_in_period_band_upper": Var("1", "probability in `years` from annual_frequency_band_upper"),
    "return_period": Var("year", "mean return period of the damage state, 1 / annual_frequency"),
    "share_below_first_level": Var("1", "share of annual_frequency from shaking below the hazard curve's first "
                                   "level (first segment extended)"),
    "share_beyond_last_level": Var("1", "share of annual_frequency from shaking beyond the hazard curve's last "
                                   "level (last segment extended)"),
    "intensity_risk_05": Var("m s-2", "intensity below which 5 % of annual_frequency accrues"),
    "intensity_risk_50": Var("m s-2", "intensity below which half of annual_frequency accrues"),
    "intensity_risk_95": Var("m s-2", "intensity below which 95 % of annual_frequency accrues"),
}

# Names whose meaning in a study Dataset differs from the time-history one:
# study energies are per unit weight (summary of pipeline.simulate) [m].
STUDY_VARIABLES = dict(VARIABLES)
STUDY_VARIABLES.update({
    "work_ground": Var("m", "work done on the column by the ground motion per unit weight, W/(m g)"),
})

FLAGS = {
    "phase": ([0, 1, 2, 3, 4, 5], "at_rest rolling_on_rim overturned sliding_flat slipping_on_rim flight",
              "motion phase of the column"),
    "overturned": ([0, 1], "stands overturned", "the column overturned"),
    "undecided": ([0, 1], "decided undecided",
                  "the column could still overturn when the run reached its settle limit after the tail "
                  "(neither standing nor overturned; fragility and reports count it as a stated choice, standing by "
                  "default, and say what counting it as overturned moves)"),
    "uplifted": ([0, 1], "never_uplifted uplifted", "the base left full contact with the ground"),
    "sliding_onset": ([0, 1], "no_sliding sliding_onset",
                      "the base or the rim slid on the ground (friction reached mu N)"),
    "lift_off": ([0, 1], "no_lift_off lift_off",
                 "the normal contact force reached zero and the column flew"),
    "status": ([0, 1], "ok failed", "status of the simulation (failed: values are NaN or 0)"),
    "seeded": ([0, 1], "perfect seeded", "the model's runs draw imperfect drums from each seed (perfect: it runs "
               "perfect drums once, repeated along seed)"),
    "risk_flag": ([0, 1, 2, 3, 4, 5], "ok median_beyond_hazard_curve no_median_no_exceedance_observed "
                  "no_median_every_run_exceeds no_fit integral_overflows",
                  "how far the site risk rests on the data: the fragility's median beyond the hazard curve's last "
                  "level (mostly extrapolated), no median to integrate, or an integral beyond the largest float "
                  "(a hazard curve too steep where it is extended)"),
}


def annotate(ds, catalog=None):
    """Attach units, long names and standard names from the catalog, add the degree twins (in place).

    Parameters
    ----------
    ds : xarray.Dataset
    catalog : dict, optional
        Variable catalog to use instead of :data:`VARIABLES` (e.g.
        :data:`STUDY_VARIABLES` for study results).

    Returns
    -------
    xarray.Dataset
        The same dataset, for chaining: every catalogued variable carries
        ``units`` and ``long_name``; every one marked ``degrees`` has a twin
        ``NAME_deg`` [degree] (a coordinate if it is one).
    """
    catalog = VARIABLES if catalog is None else catalog
    for name in list(ds.variables):
        if name in catalog:
            entry = catalog[name]
            ds[name].attrs.update(units=entry.units, long_name=entry.long_name)
            if entry.standard_name:
                ds[name].attrs["standard_name"] = entry.standard_name
            if entry.degrees:
                _add_degrees(ds, name, entry)
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


def _add_degrees(ds, name, entry):
    twin = f"{name}_deg"
    values = ds[name].copy(data=np.degrees(ds[name].values))
    values.attrs = {"units": "degree", "long_name": f"{entry.long_name}, in degrees"}
    if name in ds.coords:
        ds.coords[twin] = values
    else:
        ds[twin] = values


def label_dims(ds):
    """Dimensions of ``ds`` whose coordinate holds string labels (``column``, ``record``, ``model``, ...)."""
    return [d for d in ds.dims if d in ds.coords and ds[d].dtype.kind in "UOS"]


def append_history(ds, line):
    """Add a time-stamped line to the global ``history`` attribute (CF)."""
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    previous = ds.attrs.get("history", "")
    ds.attrs["history"] = (previous + "\n" if previous else "") + f"{stamp} {line}"
    return ds


def _encoding(ds, extra=None):
    """Per-variable netCDF encoding of the convention (module docstring)."""
    encoding = {}
    for name, var in ds.variables.items():
        if var.dtype.kind in "UOS":
            encoding[name] = {"dtype": "S1"}  # character array (CF 2.2)
        elif var.dtype.kind in "fiub" and name in ds.data_vars:
            encoding[name] = {"zlib": True, "complevel": 4}
    for name, more in (extra or {}).items():
        encoding[name] = {**encoding.get(name, {}), **more}
    return encoding


def _declare_coordinates(ds):
    """Set each data variable's ``coordinates``: its auxiliary coordinates and the labels of its dimensions.

    With the labels declared, CF sees them as string-valued auxiliary
    coordinates rather than misdeclared coordinate variables (in place).
    """
    labels = label_dims(ds)
    for name, var in ds.data_vars.items():
        aux = [c for c in ds.coords if c not in ds.dims and set(ds[c].dims) <= set(var.dims)]
        declared = [d for d in var.dims if d in labels] + aux
        var.attrs.pop("coordinates", None)
        if declared:
            var.encoding["coordinates"] = " ".join(declared)
        else:
            var.encoding.pop("coordinates", None)


def write_netcdf(ds, path, encoding=None):
    """Write a results Dataset in the project's convention, compressed, atomically.

    Parameters
    ----------
    ds : xarray.Dataset
        Any results Dataset (histories, study results, fragility). String
        labels on dimensions stay the dimensions' coordinates (module
        docstring).
    path : str or os.PathLike
        Destination; its folder is created if needed. The file appears only
        once it is complete.
    encoding : dict, optional
        Extra per-variable encodings, merged over the convention's.

    Returns
    -------
    str
        ``path``.
    """
    out = ds.copy()
    for name in label_dims(out):  # numpy unicode or object -> plain str labels
        out.coords[name] = out[name].copy(data=np.asarray(out[name].values).astype(str).astype(object))
    _declare_coordinates(out)
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    try:
        with atomic_path(path) as tmp:  # permissions from the umask, not mkstemp's 0600
            out.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=_encoding(out, encoding))
    except OSError as exc:  # read-only, no permission, disk full: one clear line
        raise OutputError(f"{path}: cannot write ({exc.strerror or exc})") from None
    except RuntimeError as exc:  # the HDF5 library reports a full disk as "NetCDF: HDF error"
        if "NetCDF" not in str(exc):
            raise
        free = shutil.disk_usage(folder).free
        raise OutputError(f"{path}: the netCDF library could not write ({exc}); {free / 2**20:.0f} MiB free "
                          "on that disk") from None
    return path


def write_results(ds, path):
    """Write a study results Dataset as CF netCDF (:func:`write_netcdf`), catalog attributes filled in.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`pipeline.study.run_study`.
    path : str or os.PathLike
    """
    out = ds.copy()
    # attributes set by the caller (e.g. a target-level ``scale``) win over the catalog
    annotate(out, {k: v for k, v in STUDY_VARIABLES.items() if k not in out.variables or "long_name" not in out[k].attrs})
    return write_netcdf(out, path)


def open_results(path):
    """Open a results file (any kind) into memory; the file is closed afterwards.

    Plain ``xarray.open_dataset`` reads the same layout; this only loads the
    values and gives the labels as ``str``.

    Returns
    -------
    xarray.Dataset
    """
    import xarray as xr

    with xr.open_dataset(path, engine="netcdf4") as f:
        ds = f.load()
    for name in label_dims(ds):
        ds.coords[name] = ds[name].copy(data=np.asarray(ds[name].values).astype(str))
    return ds


def open_results_file(path, made_by):
    """:func:`open_results` of a user's path, with errors that name the file and the fix.

    Parameters
    ----------
    path : str or os.PathLike
    made_by : str
        The command that writes such a file (e.g. ``"frustum study run"``), named in the errors.

    Raises
    ------
    InputError
        The file is missing or cannot be read as netCDF.
    """
    from pipeline.errors import InputError

    path = os.fspath(path)
    if not os.path.exists(path):
        raise InputError(f"{path}: no such file; give the netCDF written by '{made_by}'")
    try:
        return open_results(path)
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: cannot be read as netCDF ({exc}); give the file '{made_by}' wrote") from None


#: The summary of one simulation (:class:`pipeline.simulate.Response`) a simulate file carries, one
#: value per (column, record, model), by catalog name (:data:`VARIABLES`, :data:`FLAGS`): the study
#: results' names, and a compliant run's restitution reached and joint damping. Per joint (dimension
#: ``joint``) and per body (dimension ``drum``) below.
SUMMARY_VARIABLES = (
    "peak_theta", "peak_theta_ratio", "peak_time", "overturned", "undecided", "overturn_time", "uplifted",
    "uplift_time", "n_impacts", "peak_mu_mob", "min_normal_force_hat", "sliding_onset", "sliding_time", "lift_off",
    "lift_off_time", "residual_rotation", "residual_displacement", "energy_friction", "energy_balance_error",
    "restitution", "contact_damping", "dislocation_ratio", "overturn_drum", "imperfection_tolerance",
    "imperfection_seed", "imperfection_friction_min", "imperfection_friction_max",
)
SUMMARY_JOINT_VARIABLES = ("joint_slip", "joint_twist", "joint_tilt", "joint_opening", "bed_offset_x", "bed_offset_y",
                           "bed_tilt", "bed_tilt_azimuth", "bed_friction")
SUMMARY_DRUM_VARIABLES = ("drum_peak_theta",)
# the integer ones (the rest are float64); a flag or count a run does not report is 0, except
# overturn_drum: a rigid column is one body, which fell if anything did (as in study results)
_SUMMARY_INTEGERS = {"n_impacts": np.int32, "overturn_drum": np.int32, "imperfection_seed": np.int64,
                     **{name: np.int8 for name in ("overturned", "undecided", "uplifted", "sliding_onset", "lift_off")}}


def _summary_value(summary, name):
    if name in summary:
        return summary[name]
    if name == "overturn_drum" and "overturned" in summary:
        return 0 if summary["overturned"] else -1
    if name == "imperfection_seed":
        return -1  # perfect drums
    return 0 if name in _SUMMARY_INTEGERS else np.nan


def add_summaries(ds, summaries):
    """Add the runs' summaries to a histories file (:func:`histories_file`), as catalogued variables.

    Parameters
    ----------
    ds : xarray.Dataset
        Dims ``column``, ``record`` (one each) and ``model``.
    summaries : list of dict
        :attr:`pipeline.simulate.Response.summary` of each model, in the order of ``ds.model``
        (SI units: angles rad, times s, lengths m).

    Returns
    -------
    xarray.Dataset
        ``ds`` with every name of :data:`SUMMARY_VARIABLES` some run reports, on (column, record,
        model): floats NaN and flags and counts 0 for a run that does not report it. With a
        compliant run also the residual dislocation per joint (dims ..., ``joint``; coordinates
        ``joint_diameter`` [m] and ``joint_label``), the peak tilt of every body (..., ``drum``) and
        ``n_drums``; ``overturn_body``, the label of the body that fell first ("" none), of every run
        that reports it.
    """
    if len(summaries) != ds.sizes["model"]:
        raise ValueError(f"{len(summaries)} summaries for {ds.sizes['model']} models")
    dims = ("column", "record", "model")
    for name in SUMMARY_VARIABLES:
        if not any(name in s for s in summaries):
            continue
        values = np.array([_summary_value(s, name) for s in summaries],
                          dtype=_SUMMARY_INTEGERS.get(name, np.float64))
        ds[name] = (dims, values[None, None, :])
    n_joints = max((len(s["joint_slip"]) for s in summaries if "joint_slip" in s), default=0)
    if n_joints:
        for name in SUMMARY_JOINT_VARIABLES:
            if not any(name in s for s in summaries):
                continue  # the drawn imperfections of perfect drums
            values = np.full((len(summaries), n_joints), np.nan)
            for m, s in enumerate(summaries):
                if name in s:
                    values[m, :len(s[name])] = s[name]
            ds[name] = (dims + ("joint",), values[None, None])
        diameters = next(s["joint_diameter"] for s in summaries if "joint_diameter" in s)
        ds.coords["joint"] = ("joint", np.arange(n_joints, dtype=np.int32))
        ds.coords["joint_diameter"] = (("column", "joint"), np.asarray(diameters, dtype=np.float64)[None])
        ds.coords["n_drums"] = ("column", np.array([next(s["n_drums"] for s in summaries if "n_drums" in s)],
                                                   dtype=np.int32))
        labels = next((s["joint_label"] for s in summaries if "joint_label" in s), ())
        if labels:
            # one structure per file: on the joint alone (CF: a label coordinate has one dimension and its length)
            ds.coords["joint_label"] = ("joint", np.array(list(labels), dtype=object))
    if any("overturn_body" in s for s in summaries):
        ds["overturn_body"] = (dims, np.array([str(s.get("overturn_body", "")) for s in summaries],
                                              dtype=object)[None, None, :])
    for name in SUMMARY_DRUM_VARIABLES:
        if "drum" in ds.dims and any(name in s for s in summaries):
            values = np.full((len(summaries), ds.sizes["drum"]), np.nan)
            for m, s in enumerate(summaries):
                if name in s:
                    values[m, :len(s[name])] = s[name]
            ds[name] = (dims + ("drum",), values[None, None])
    return annotate(ds)


def histories_file(runs, column, record, summaries=None):
    """The histories of one column under one record, one or more models, as one Dataset of the convention.

    Parameters
    ----------
    runs : list of xarray.Dataset
        Histories from :func:`pipeline.simulate.simulate` or
        :func:`pipeline.simulate.simulate_free`, one per model, on one time grid: a run that ended
        sooner (it came to rest before another's settle limit) holds the first rows of the longest
        run's, and NaN after its end.
    column : str
        Label of the column (or of the colonnade).
    record : str
        Identifier of the record (``free-motion`` for a free motion).
    summaries : list of dict, optional
        The summary of each run (:attr:`pipeline.simulate.Response.summary`), written beside
        the histories by :func:`add_summaries`, so the file says what happened.

    Returns
    -------
    xarray.Dataset
        Dims ``column``, ``record``, ``model`` (string labels) and ``time``;
        the geometry as coordinates on ``column`` (``column_R``, ``column_r``,
        ``column_h``, the column's ``theta_crit`` and ``theta_crit_deg``), each model's critical
        tilt on (column, model) (``theta_crit_model``: a rigid frame's differs); incidence angle
        [degree] and scale factor as scalar coordinates; the structure each model ran in the
        title and attributes (:mod:`pipeline.structures.description`); with ``summaries``, the
        summary variables on (column, record, model).
    """
    import xarray as xr

    from pipeline.structures.column import Column

    first = runs[0].attrs
    runs = _on_one_grid(runs)
    names = list(dict.fromkeys(n for run in runs for n in run.data_vars))
    shapes = {n: run[n] for run in reversed(runs) for n in run.data_vars}  # a run that has each variable
    # a run that ended sooner (it came to rest, or fell, while another still moved) is NaN after its end,
    # in the phase it ended in: the runs share the time grid of the longest, of which theirs is the start
    stacked = []
    for run in runs:
        run = run.copy()
        for name in names:  # 2D has no spin or base-centre path, the rigid models no drums: NaN there
            if name not in run:
                like = shapes[name]
                run[name] = (like.dims, np.full((run.sizes["time"],) + like.shape[1:], np.nan))
                # the coordinates of its other dimensions too (the drums' geometry)
                run = run.assign_coords({c: like[c] for c in like.coords
                                         if like[c].dims and "time" not in like[c].dims})
        stacked.append(run.expand_dims(model=[str(run.attrs["model"])]))
    ds = xr.concat(stacked, dim="model", join="exact", combine_attrs="drop_conflicts")
    for name in ("model", "column_R_m", "column_r_m", "column_h_m", "theta_crit_rad", "incidence_angle_rad", "scale"):
        ds.attrs.pop(name, None)
    ds.attrs.update(_what_ran(runs))
    ds = ds.expand_dims(column=[column], record=[record]).transpose("column", "record", "model", "time", ...)
    ds = ds.assign_coords(
        column_R=("column", [first["column_R_m"]]),
        column_r=("column", [first["column_r_m"]]),
        column_h=("column", [first["column_h_m"]]),
        # the column's own; a model that runs another structure (a rigid frame) has its own below
        theta_crit=("column", [Column(first["column_R_m"], first["column_r_m"], first["column_h_m"]).critical_tilt]),
        theta_crit_model=(("column", "model"), [[run.attrs["theta_crit_rad"] for run in runs]]),
        angle=float(np.degrees(first.get("incidence_angle_rad", 0.0))),
        scale=float(first.get("scale", 1.0)),
    )
    if "phase" in ds:
        ds["phase"] = ds["phase"].fillna(0).astype(np.int8)
    if summaries is not None:
        ds = add_summaries(ds, summaries)
    return annotate(ds)


def _on_one_grid(runs):
    """The runs on the longest one's time grid: every other's rows are its first ones (the models of one file
    share one output grid, to the bit), NaN after a run's end (a run that came to rest, or fell, while another
    still moved), its phase the one it ended in; anything else is a caller's bug."""
    longest = max(runs, key=lambda run: run.sizes["time"])
    time = longest["time"].values
    out = []
    for run in runs:
        n = run.sizes["time"]
        if not np.array_equal(run["time"].values, time[:n]):
            raise ValueError(f"the runs of one file have different output instants ({run.attrs.get('model')} "
                             f"against {longest.attrs.get('model')})")
        if n < time.size:  # in the phase it ended in, tau = t sqrt(g/R) of its own R on the whole grid
            last = run["phase"].isel(time=-1) if "phase" in run else None
            per_second = float(run["tau"][-1] / run["time"][-1]) if "tau" in run.coords else None
            run = run.reindex(time=time)
            if last is not None:
                run["phase"] = run["phase"].fillna(last)
            if per_second is not None:
                run = run.assign_coords(tau=("time", time * per_second))
        out.append(run)
    return out


def _what_ran(runs):
    """The file's title and ``structure`` attribute from each run's (its model and the structure it ran); one
    run's own stand (a free motion's title)."""
    from pipeline import models
    from pipeline.structures.description import what_ran

    if len(runs) == 1:
        return {}
    groups = {}
    for run in runs:
        if "structure" not in run.attrs:
            return {}  # a free motion, or histories made by hand: their own words stand
        name = str(run.attrs["model"])
        groups.setdefault(str(run.attrs["structure"]), []).append((models.title(name), name))
    return {"title": "Response to ground motion of " + what_ran(list(groups.items())),
            "structure": "; ".join(groups)}


def one_run(ds, column=None, record=None, model=None):
    """One simulation of a histories file (:func:`histories_file`): histories over ``time`` alone.

    Parameters
    ----------
    ds : xarray.Dataset
    column, record, model : str, optional
        Labels; default the first of each.

    Returns
    -------
    xarray.Dataset
        With the attributes the plotting code reads (``model``,
        ``column_R_m``, ``column_r_m``, ``column_h_m``, ``theta_crit_rad``: the model's own critical
        tilt where the file has it, ``theta_crit_model``).
    """
    pick = {d: (str(ds[d].values[0]) if v is None else v)
            for d, v in (("column", column), ("record", record), ("model", model))}
    run = ds.sel(pick)
    crit = run["theta_crit_model"] if "theta_crit_model" in run.coords else run["theta_crit"]
    run.attrs = dict(ds.attrs, model=pick["model"], record_id=pick["record"],
                     column_R_m=float(run["column_R"]), column_r_m=float(run["column_r"]),
                     column_h_m=float(run["column_h"]), theta_crit_rad=float(crit))
    return run


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
        "Every file has its labels on its dimensions (`column`, `record`, `model`; `state` in a",
        "fragility file), so `xr.open_dataset(f).sel(column=..., model=...)` works. The histories of",
        "`frustum simulate` have dims (column, record, model, time), both models in one file when",
        "both were run (`--model 3d,2d`), the geometry as coordinates on `column` and the incidence",
        "angle [degree] and scale as scalar coordinates; `time` is seconds since the start of the",
        "record (elapsed time, hence no CF `standard_name` time). Beside the histories a simulate file",
        "carries the run's summary on (column, record, model) under the study results' names",
        "(`peak_theta`, `overturned`, `overturn_time`, `n_impacts`, `sliding_onset`, `lift_off`, ...;",
        "`pipeline.dataset.SUMMARY_VARIABLES`) and, for the compliant model, `restitution`,",
        "`contact_damping`, the residual dislocation per `joint`, `drum_peak_theta` per `drum` and",
        "`overturn_drum`.",
        "",
        "Positions are relative to where each body stood at rest: `x_p`, `y_p` (the contact point)",
        "and `x_b`, `y_b` (the base's centre) from where the base's centre stood (a colonnade's: its",
        "first column's; 2d-frame: every column's), `drum_dx`, `drum_dy`, `drum_dz` every body's",
        "centre of mass from its place at rest (`drum_x`, `drum_y`, `drum_z`: where it stood), so",
        "a plot of a colonnade's contact path starts at 0, at its base.",
        "",
        "Every file says what stood: its title names the structure and the models that ran it",
        "(\"a colonnade of 8 columns of 11 drums and a capital carrying 7 epistyle blocks",
        "(parthenon-east: ...) run by the 3D compliant drums on joints (3d-compliant)\") and its",
        "attributes hold it (`structure`, `structure_kind`, `n_drums`, `capital`; a colonnade's",
        "`n_columns`, `interaxial_m`, `epistyle_height_m`, `epistyle_width_m`, `course_height_m`,",
        "`n_blocks`; a named colonnade's `colonnade`, `colonnade_title`, `colonnade_source`, a named",
        "column's `named_column`, `column_title`, `column_source`); a study's, fragility's and",
        "risk's attribute `structures` names every column's, and their coordinates on `column` the",
        "colonnades' numbers (`n_columns`, `interaxial`, ...). Bodies and joints carry their labels",
        "(`body_label` on `drum`, `joint_label` on `joint`; in study results a string variable on",
        "(column, joint), as CF takes a label coordinate of one dimension only) and `overturn_body`",
        "names the body that fell first. A simulate file holds each model's critical tilt as",
        "`theta_crit_model` (a rigid frame's is the frame's), `theta_crit` the column's own.",
        "A compliant run of imperfect drums (`--imperfections TOL_M --seed N [--friction-range LO,HI]`,",
        "`pipeline/structures/imperfections.py`) also carries what it drew: `imperfection_tolerance`,",
        "`imperfection_seed`, `imperfection_friction_min` and `_max` on (column, record, model), and per",
        "`joint` the drawn `bed_offset_x`, `bed_offset_y`, `bed_tilt`, `bed_tilt_azimuth` and `bed_friction`",
        "(NaN for the joints that draw none, an epistyle's); its dislocations are measured from the rest",
        "state, where its drums stand off. A study with `[imperfections]` has the dimension `seed` (integer",
        "seeds, after `model`), the flag `seeded` on `model` (a model of perfect drums runs once and is",
        "repeated along `seed`), the drawn values as coordinates on (column, seed, joint) and the tolerance",
        "and friction range as the attributes `imperfection_tolerance_m` and `imperfection_friction_range`.",
        "",
        "The rigid frame of a colonnade (`2d-frame`) writes the same names for the whole frame:",
        "`theta` is the common tilt of its columns, `x_b` and `x_p` every column's base centre and pivot",
        "from where it stood, `epistyle_dx` and `epistyle_dz` the epistyle's translation; its forces are",
        "the sum over the column bases and, with `energy_hat`, per the frame's weight m g (m the frame's",
        "mass, R the column's base radius); `peak_theta_ratio` divides by the frame's critical tilt.",
        "",
        "| name | units | long name | CF standard name |",
        "|---|---|---|---|",
    ]
    for name, entry in STUDY_VARIABLES.items():
        lines.append(f"| `{name}` | {entry.units} | {entry.long_name} | {entry.standard_name or ''} |")
        if entry.degrees:
            lines.append(f"| `{name}_deg` | degree | {entry.long_name}, in degrees | |")
    lines += ["", "Flags (integer, with `flag_values` and `flag_meanings`):", "",
              "| name | values | meanings | long name |", "|---|---|---|---|"]
    for name, (values, meanings, long_name) in FLAGS.items():
        lines.append(f"| `{name}` | {', '.join(map(str, values))} | {meanings} | {long_name} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(catalog_markdown(), end="")
