"""Where the time of a step of the Parthenon's east front goes (issue 48, item 4): run by hand.

``total``: CPU time of the front (``parthenon-east``, 103 bodies) under the first ``--seconds`` of
FEMA-FF-01 x1, no tail, least of ``--repeat`` (the damping calibration cached, not timed), with
its steps and solves. ``parts``: the parts of a step timed apart on the states the run passes
through: every ``--every`` steps the state and the step's scratch are kept, and each part of
:func:`pipeline.dynamics.compliant.semi_implicit.step` is repeated on them in a compiled loop,
its least CPU time per call quoted (the kinematics, the point pass with the joints' sums, the
system's assembly, the block solve, the active-set update, the bookings and monitor with the
positions, the statistics, the event values). Speed is measured here, never in tests.

Run by hand:  python benchmarks/bench_parthenon_step.py total parts [--seconds 10] [--repeat 3]

The numbers depend on the machine and its load: compare two trees in one session (PYTHONPATH).
``total`` runs the loop as the package compiles it (LLVM's SLP vectoriser on for it:
pipeline/dynamics/compliant/vector_lanes.py); ``parts`` compiles its own loop, as numba does by
default: set ``NUMBA_SLP_VECTORIZE=1`` to time the parts as the package's loop runs them.
"""

import argparse
import os
import platform
import time

import numpy as np


def _case(seconds):
    from pipeline.groundmotion import load
    from pipeline.groundmotion.record import GroundMotion
    from pipeline.structures.colonnade import named_colonnade

    full = load("FEMA-FF-01")
    n = int(round(seconds / full.dt)) + 1
    motion = GroundMotion.from_arrays(np.asarray(full.acc_x)[:n], np.asarray(full.acc_y)[:n], full.dt,
                                      None if full.acc_z is None else np.asarray(full.acc_z)[:n],
                                      record_id=f"FEMA-FF-01 first {seconds:g} s")
    return named_colonnade("parthenon-east"), motion


def _settings(**more):
    from pipeline.settings import ModelSettings

    return ModelSettings(model="3d-compliant", joint_friction=0.6, settle_limit=0.0, tail=0.0, **more)


def _warm(front, motion):
    from pipeline.settings import Excitation
    from pipeline.simulate import simulate

    simulate(front.column, motion, Excitation(), _settings(), histories=False)  # compiles, calibrates


def bench_total(seconds, repeat):
    from pipeline.settings import Excitation
    from pipeline.simulate import simulate

    front, motion = _case(seconds)
    _warm(front, motion)
    times, s = [], None
    for _ in range(repeat):
        cpu = time.process_time()
        s = simulate(front, motion, Excitation(), _settings(), histories=False).summary
        times.append(time.process_time() - cpu)
    best = min(times)
    print(f"total: front under FEMA-FF-01's first {seconds:g} s: {best:.3f} s of CPU (least of "
          f"{', '.join(f'{t:.3f}' for t in times)}); {s['steps']} steps of {1e3 * s['step']:.3f} ms, "
          f"{s['rhs_evaluations']} solves, {1e6 * best / s['steps']:.1f} us per step; peak "
          f"{s['peak_theta_ratio']:.6f} theta_crit", flush=True)
    return best, s


def _states(seconds, every):
    """The front's kernel parameters, and (y, t) every ``every`` steps of its run under the case."""
    from pipeline.compliant.calibration import calibrated_damping
    from pipeline.compliant.integrate import fixed_step
    from pipeline.compliant.rest import laid_state, rest_state
    from pipeline.compliant.run import turned_record
    from pipeline.compliant.tables import assemble
    from pipeline.dynamics.compliant import semi_implicit as si
    from pipeline.settings import Excitation

    front, motion = _case(seconds)
    _warm(front, motion)
    settings = _settings()
    probe = assemble(front, settings, 0.0)
    step = fixed_step(probe, probe.params(), laid_state(probe), settings)[0]
    damping = calibrated_damping(front, settings)[0]
    asm = assemble(front, settings, damping)
    params = asm.params(turned_record(motion, Excitation()), motion.dt / asm.time)
    y = rest_state(asm, params, settings.integrator)
    h = step / asm.time
    scratch = si.make_scratch(params, asm.pattern)
    n = int(seconds / step)
    kept = []
    for i in range(n):
        if i % every == 0:
            kept.append((i * h, y.copy()))
        si.step(i * h, y, h, params, scratch)
    return params, asm.pattern, h, kept


# The parts of a step, each timed as the difference of two prefixes of it (prefix k runs parts 0..k on a
# restored state): restoring the state, then each part of semi_implicit.step in its order. The states are
# taken in turn (one call of each prefix on each state, ``reps`` rounds), never one state many times over:
# a branch predictor that has seen the same state's points just before predicts them better than a run does.
PARTS = ("restore the state", "kinematics (bodies, faces)", "point pass and joint sums",
         "system assembly (1st solve)", "momentum and block solve", "active-set update", "further solves",
         "bookings, monitor, positions", "statistics and events")


def _prefixes():
    """Compiled prefixes of a step (built on first use: they compile against the tree on the path)."""
    from numba import njit

    from pipeline.dynamics.compliant import assembly as sk
    from pipeline.dynamics.compliant import linear_system as ls
    from pipeline.dynamics.compliant import semi_implicit as si
    from pipeline.dynamics.compliant import statistics as st
    from pipeline.dynamics.excitation import ground_acceleration

    @njit
    def prefix(last, reps, ts, ys, y, h, params, s, g, stats):
        bodies, joints = params[0], params[3]
        pts, mats, diag, blocks, tmp66, tmp6, pattern, vel, slip, impulse, frames, motion, pcols, contacts, \
            n_contact, kept, changed = s
        summary, body_stats, joint_stats, joint_committed = stats
        solves = 0
        for _ in range(reps):
            for i in range(ys.shape[0]):
                t = ts[i]
                y[:] = ys[i]
                if last == 0:
                    continue
                if last >= 7:
                    solves += si.step(t, y, h, params, s)
                    if last >= 8:
                        st.update_statistics(t + h, y, params, 1e9, summary, body_stats, joint_stats,
                                             joint_committed, True)
                        sk.event_values(y, bodies, joints, g)
                    continue
                ax, ay, az = ground_acceleration(t, params[4], params[5])
                sk._kinematics(y, params)
                if last == 1:
                    continue
                si._point_forces(y, h, params, pts, pcols, frames, motion, slip, mats, contacts, n_contact, kept)
                if last == 2:
                    continue
                n = 0
                while True:
                    if n > 0:
                        si._joint_loads(y, params, pts, mats, contacts, n_contact, kept, changed)
                    ls.assemble_system(y, bodies, joints, mats, h, params[6], pattern, diag, blocks, tmp66)
                    if last == 3:
                        break
                    si._momentum(y, bodies, params[6], h, ax, ay, az, vel)
                    impulse[:, :] = vel
                    ls.sparse_block_solve(pattern, diag, blocks, vel, tmp6)
                    if last == 4:
                        break
                    n += 1
                    moved = si._update_active_set(params, pts, vel, motion, contacts, n_contact, changed)
                    if last == 5 or moved == 0 or n >= si.MAX_PASSES:
                        break
        return solves

    return prefix


def bench_parts(seconds, every, repeat):
    from pipeline.dynamics.compliant import semi_implicit as si
    from pipeline.dynamics.compliant.layout import N_BODY_STATS, N_JOINT_STATS, N_SUMMARY

    params, pattern, h, kept = _states(seconds, every)
    prefix = _prefixes()
    ts = np.array([t for t, _ in kept])
    ys = np.array([y for _, y in kept])
    s = si.make_scratch(params, pattern)
    nb, nj = params[0].shape[0], params[3].shape[0]
    stats = (np.zeros(N_SUMMARY), np.zeros((nb, N_BODY_STATS)), np.zeros((nj, N_JOINT_STATS)),
             np.zeros((nj, N_JOINT_STATS)))
    y, g = ys[0].copy(), np.empty(2 * nb)
    cum = []
    for last in range(len(PARTS)):
        prefix(last, 1, ts, ys, y, h, params, s, g, stats)  # compiles
        best = np.inf
        for _ in range(3):
            cpu = time.process_time()
            prefix(last, repeat, ts, ys, y, h, params, s, g, stats)
            best = min(best, time.process_time() - cpu)
        cum.append(1e6 * best / (repeat * len(kept)))
    per = np.diff(np.concatenate([[0.0], cum]))
    print(f"parts: {len(kept)} states of the front, one every {every} steps of the first {seconds:g} s, taken in "
          f"turn {repeat} times; CPU per step [us] (least of 3 loops; a part is the difference of two prefixes)",
          flush=True)
    for name, t in zip(PARTS, per):
        print(f"  {name:28s} {t:8.1f} us  {100 * t / cum[-1]:5.1f} %", flush=True)
    print(f"  {'the whole step':28s} {cum[-1]:8.1f} us", flush=True)
    return dict(zip(PARTS, per))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("parts", nargs="+", choices=("total", "parts"))
    parser.add_argument("--seconds", type=float, default=10.0, help="of FEMA-FF-01 (default 10)")
    parser.add_argument("--repeat", type=int, default=3, help="runs (total); each part's calls per state (parts: "
                        "give about 100)")
    parser.add_argument("--every", type=int, default=500, help="steps between the states timed (parts)")
    args = parser.parse_args()
    print(f"{platform.machine()} {platform.processor() or ''}, {os.cpu_count()} cores, load average "
          f"{', '.join(f'{x:.2f}' for x in os.getloadavg())}; {__import__('pipeline').__file__}", flush=True)
    if "total" in args.parts:
        bench_total(args.seconds, args.repeat)
    if "parts" in args.parts:
        bench_parts(args.seconds, args.every, args.repeat)


if __name__ == "__main__":
    main()
