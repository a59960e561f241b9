"""The time histories of a compliant run, as an xarray Dataset with the project's names.

The rigid models' histories (``theta``, ``phi``, ``psi``, the base's path, forces and friction,
energy, ground acceleration, ``phase``) of the watched body (a column's top; a colonnade's
most tilted capital for ``theta``) and of the first column's base joint (its contact point and
centre from where that base stood at rest, as the rigid models' are), and every body's
displacement, tilt, rotation, rise and tilt direction along the dimension ``drum`` (a body:
drum, capital or epistyle block, named by the coordinate ``body_label``), with each body's
shape and place at rest for drawing. The file says what the structure is
(:func:`pipeline.structures.description.attributes`).
"""

import numpy as np

from pipeline.dynamics.compliant.layout import (
    A_WORK, B_ZC, D_AREA, D_AX, D_AY, D_AZ, D_COP_X, D_COP_Y, D_ENERGY, D_MU, D_NORMAL, D_ON_RIM, D_TANGENTIAL,
    H_DX, H_DY, H_ROT, H_TILT, NB, QW, QZ, SLIDE_FRACTION, S_OVERTURN_TIME, WZ, X, Y, Z,
)
from pipeline.units import G

__all__ = ["histories"]


def _euler_zxz(q):
    """(phi, psi) of the Z-X-Z Euler angles of quaternions q (rows w, x, y, z); NaN upright."""
    w, x, y, z = q.T
    s = 2.0 / (w * w + x * x + y * y + z * z)
    r13, r23 = s * (x * z + w * y), s * (y * z - w * x)
    r31, r32 = s * (x * z - w * y), s * (y * z + w * x)
    upright = (r13 == 0.0) & (r23 == 0.0)
    phi = np.where(upright, np.nan, np.arctan2(r13, -r23))
    psi = np.where(upright, np.nan, np.arctan2(r31, r32))
    return phi, psi, r13, r23


def histories(structure, asm, settings, raw, motion, excitation, damping):
    """The run's histories (:mod:`pipeline.dataset` names, SI) of ``structure`` (a column, drums, a colonnade)."""
    from pipeline import models
    from pipeline.compliant.layouts import outline_of
    from pipeline.dataset import annotate, append_history
    from pipeline.structures.description import history_attributes

    L, T = asm.length, asm.time
    n, n_j = asm.n_bodies, asm.n_joints
    rows = raw.hist_y.shape[0]
    tau = raw.t_mon[::raw.stride][:rows]
    watched = list(asm.layout.watched)
    top = NB * watched[0]
    phi, psi, _, _ = _euler_zxz(raw.hist_y[:, top + QW:top + QZ + 1])
    _, _, e13, e23 = _euler_zxz(raw.hist_y[:, QW:QZ + 1])
    zc = asm.bodies[0, B_ZC]
    _, _, r13, r23 = _euler_zxz(raw.y0[None, QW:QZ + 1])  # the base's centre at rest, from where x_b is measured
    rest_x, rest_y = raw.y0[X] - r13[0] * zc, raw.y0[Y] - r23[0] * zc
    diag = raw.hist_diag
    # the phase flags of the rigid models (pipeline.dataset.FLAGS): in contact 0, on the rim 1,
    # overturned 2, sliding flat 3, slipping on the rim 4, in flight 5
    sliding = diag[:, D_MU] >= SLIDE_FRACTION * settings.friction
    on_rim = diag[:, D_ON_RIM] > 0.0
    phase = np.select([tau >= raw.summary[S_OVERTURN_TIME], diag[:, D_NORMAL] <= 0.0, on_rim & sliding,
                       on_rim, sliding], [2, 5, 4, 1, 3], 0).astype(np.int8)
    weight = asm.mass * G
    data = {
        "theta": np.max(raw.hist_body[:, watched, H_TILT], axis=1),
        "phi": phi,
        "psi": psi,
        "x_p": diag[:, D_COP_X] * L,
        "y_p": diag[:, D_COP_Y] * L,
        "x_b": (raw.hist_y[:, X] - e13 * zc - rest_x) * L,
        "y_b": (raw.hist_y[:, Y] - e23 * zc - rest_y) * L,
        "omega_zeta": raw.hist_y[:, top + WZ] / T,
        "energy_hat": diag[:, D_ENERGY],
        "work_ground_hat": raw.hist_y[:, NB * n + A_WORK],
        "normal_force_hat": diag[:, D_NORMAL],
        "tangential_force_hat": diag[:, D_TANGENTIAL],
        "mu_mob": diag[:, D_MU],
        "ground_acc_x": diag[:, D_AX] * G,
        "ground_acc_y": diag[:, D_AY] * G,
        "ground_acc_z": diag[:, D_AZ] * G,
        "slip": raw.hist_y[:, -n_j] * L,
        "contact_area_fraction": diag[:, D_AREA],
    }
    data["normal_force"] = data["normal_force_hat"] * weight
    data["tangential_force"] = data["tangential_force_hat"] * weight
    data["energy"] = data["energy_hat"] * weight * L
    variables = {k: ("time", np.asarray(v, dtype=np.float64)) for k, v in data.items()}
    variables["phase"] = ("time", phase)
    for name, col, scale in (("drum_dx", H_DX, L), ("drum_dy", H_DY, L), ("drum_theta", H_TILT, 1.0),
                             ("drum_rotation", H_ROT, 1.0)):
        variables[name] = (("time", "drum"), raw.hist_body[:, :, col] * scale)
    # with the direction of each drum's tilt and its rise, a drum's pose is whole (the animation draws it)
    states = raw.hist_y[:, :NB * n].reshape(rows, n, NB)
    variables["drum_dz"] = (("time", "drum"), (states[:, :, Z] - raw.y0[Z:NB * n:NB]) * L)
    variables["drum_phi"] = (("time", "drum"), np.stack(
        [_euler_zxz(states[:, b, QW:QZ + 1])[0] for b in range(n)], axis=1))
    import xarray as xr

    parts = asm.layout.parts
    coords = {"time": tau * T, "tau": ("time", tau), "drum": np.arange(n),
              "body_label": ("drum", np.array([p.label for p in parts], dtype=object)),
              # where each body's base stood at rest [m] (the joints' static penetration included)
              "drum_z": ("drum", (raw.y0[Z:NB * n:NB] - asm.bodies[:, B_ZC]) * L),
              "drum_x": ("drum", raw.y0[X:NB * n:NB] * L),
              "drum_y": ("drum", raw.y0[Y:NB * n:NB] * L)}
    for k, name in enumerate(("drum_R", "drum_r", "drum_h")):
        coords[name] = ("drum", np.array([p.shape[k] for p in parts]))
    coords["drum_kind"] = ("drum", np.array([p.kind for p in parts], dtype=np.int8))
    ds = xr.Dataset(variables, coords=coords)
    stack = outline_of(structure, whole=True)
    ds.attrs.update(history_attributes(structure, models.get(settings.model)))
    ds.attrs.update(
        model=settings.model,
        column_R_m=stack.column.R,
        column_r_m=stack.column.r,
        column_h_m=stack.column.h,
        density_kg_m3=stack.density,
        theta_crit_rad=stack.column.critical_tilt,
        normal_stiffness_Pa_m=settings.normal_stiffness,
        stiffness_ratio=settings.stiffness_ratio,
        contact_damping_Pa_s_m=damping,
        contact_points=f"{settings.contact_rings} Gauss-Lobatto rings x {settings.contact_sectors} sectors",
        friction=settings.friction,
        integrator=settings.integrator,
        **({"step_s": raw.step} if settings.integrator == "semi-implicit" else
           {"rtol": settings.rtol, "atol": settings.atol}),
        record_id=motion.record_id,
        record_sha256=motion.sha256(),
        incidence_angle_rad=excitation.angle_rad,
        scale=excitation.scale,
    )
    annotate(ds)
    append_history(ds, f"pipeline.compliant ({settings.model}, {stack.n_drums} drum(s))")
    return ds
