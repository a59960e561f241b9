"""Speed of the compliant-contact model (3d-compliant): one record, a fragility, the discretisation, drums.

Parts (run by hand, one or several):

* ``record``: the paper's column (R = 0.5, r = 0.4, h = 4 m) under FEMA P695 far-field record
  1, both components, 30.0 s + 5 s of free tail, scales 1 and 2: wall time of ``simulate()``
  (no histories, best of ``--repeat``), steps, rejected steps, right-hand sides, and the rigid
  3d model's time in the same run.
* ``fragility``: the 22 far-field pairs at ``--stripes`` scale levels (default 0.5, 1, 2, 3):
  the mean cost per run, and what a 22 x 11 fragility of one column (242 runs) takes on two
  cores, one run per core at a time (the sweep's layout).
* ``discretisation``: contact rings x sectors on records 1-6 at scale 1: cost, and the change of
  peak tilt against a fine reference (4 x 48). Single runs of a wobbling column are chaotic
  (docs/model.md), so the pooled mean and median of |peak change| are what to read.
* ``drums``: the paper's column cut into 1, 4 and 10 drums (joint friction 0.6) under record 1:
  CPU time of one run against the goals of issue 25 (0.15, 1.5, 5 s), with the semi-implicit
  default and, for the counts of ``--reference`` (default 1,4), the adaptive DOPRI5 reference
  side by side in the same run: steps, solves or right-hand sides, peak tilt, outcome,
  residual joint slip, energy balance. Single stack runs are chaotic: two integrators may
  differ in outcome on one record; the fragility statistics are in studies/drums_vs_rigid.

* ``colonnade``: issue 37's speed goals: under FEMA-FF-01 x1 (35 s with the tail), CPU time on one
  core of the 2-column frame (2 x (4 drums + capital) + 1 block), the 6-column row of the paper's
  column (35 bodies) and the Parthenon's east front (8 x (11 drums + capital) + 7 blocks, 103
  bodies), each as a ratio to the rigid 3d model's run of the paper's column on the same record
  in the same process (goals 100x, 300x, 1000x), the 10-drum stack beside them, and what a 22 x 6
  fragility of the Parthenon front takes on two cores.

The first call compiles the kernel (~40 s) unless the numba cache is warm; it is not timed.

Run by hand:  python benchmarks/bench_compliant.py record fragility discretisation drums colonnade
              [--reference 1,4] [--json out.json]
"""

import argparse
import json
import math
import os
import platform
import statistics
import time

PAPER = (0.5, 0.4, 4.0)


def _simulate(column, motion, scale=1.0, angle=0.0, **options):
    from pipeline.settings import Excitation, ModelSettings
    from pipeline.simulate import simulate

    settings = ModelSettings(**{"model": "3d-compliant", **options})
    t0 = time.perf_counter()
    s = simulate(column, motion, Excitation(angle=angle, scale=scale), settings, histories=False).summary
    return time.perf_counter() - t0, s


def _warm(motion):
    from pipeline.structures.column import Column

    _simulate(Column(*PAPER), motion, tail=0.0)  # compiles (or loads) the kernel, calibrates once


def bench_record(repeat):
    from pipeline.structures.column import Column
    from pipeline.groundmotion import load

    column, motion = Column(*PAPER), load("FEMA-FF-01")
    _warm(motion)
    rows = []
    for scale in (1.0, 2.0):
        best, s = min((_simulate(column, motion, scale) for _ in range(repeat)), key=lambda x: x[0])
        rigid = min(_simulate(column, motion, scale, model="3d")[0] for _ in range(repeat))
        rows.append({"scale": scale, "seconds": best, "rigid_3d_seconds": rigid, "steps": s["steps"],
                     "rejected": s["rejected_steps"], "rhs": s["rhs_evaluations"],
                     "peak_theta_ratio": s["peak_theta_ratio"], "overturned": s["overturned"],
                     "balance_over_work": s["energy_balance_error"] / s["work_ground"]})
        print(f"record FEMA-FF-01 x {scale:g}: {best:.2f} s per run (rigid 3d {rigid * 1e3:.1f} ms), "
              f"{s['steps']} steps + {s['rejected_steps']} rejected, {s['rhs_evaluations']} rhs, "
              f"{best / s['rhs_evaluations'] * 1e6:.2f} us per rhs; peak {s['peak_theta_ratio']:.2f} theta_crit, "
              f"{'overturned' if s['overturned'] else 'stands'}; energy balance "
              f"{s['energy_balance_error'] / s['work_ground']:.1e} of the work", flush=True)
    return rows


def bench_fragility(stripes):
    from pipeline.structures.column import Column
    from pipeline.groundmotion import list_records, load

    column = Column(*PAPER)
    ids = list_records("FEMA-FF")
    motions = [load(i) for i in ids]
    _warm(motions[0])
    costs, over = [], 0
    for motion in motions:
        for scale in stripes:
            seconds, s = _simulate(column, motion, scale, angle=17.0)
            costs.append(seconds)
            over += s["overturned"]
    mean = statistics.mean(costs)
    total = 242 * mean / 2.0
    print(f"fragility: {len(costs)} runs ({len(ids)} pairs x scales {', '.join(f'{x:g}' for x in stripes)}), "
          f"{over} overturned; mean {mean:.2f} s per run (median {statistics.median(costs):.2f}, max "
          f"{max(costs):.2f}); 242 runs on 2 cores: {total / 60:.1f} min "
          f"({'under' if total < 900 else 'over'} the 15 min budget of 7.4 s per run per core)", flush=True)
    return {"runs": len(costs), "mean_seconds": mean, "median_seconds": statistics.median(costs),
            "max_seconds": max(costs), "overturned": over, "minutes_242_on_2_cores": total / 60}


def bench_discretisation():
    from pipeline.structures.column import Column
    from pipeline.groundmotion import load

    column = Column(*PAPER)
    motions = [load(f"FEMA-FF-{i:02d}") for i in range(1, 7)]
    _warm(motions[0])
    variants = [(3, 48), (4, 48), (3, 16), (3, 24), (3, 32), (2, 24), (4, 24)]
    results = {}
    for rings, sectors in variants:
        runs = [_simulate(column, m, contact_rings=rings, contact_sectors=sectors) for m in motions]
        results[(rings, sectors)] = runs
    reference = results[(4, 48)]
    rows = []
    for (rings, sectors), runs in results.items():
        cost = statistics.mean(r[0] for r in runs)
        change = [abs(r[1]["peak_theta"] / ref[1]["peak_theta"] - 1) for r, ref in zip(runs, reference)]
        same = sum(r[1]["overturned"] == ref[1]["overturned"] for r, ref in zip(runs, reference))
        rows.append({"rings": rings, "sectors": sectors, "mean_seconds": cost, "mean_peak_change": statistics.mean(change),
                     "median_peak_change": statistics.median(change), "same_outcome": same})
        print(f"{rings} rings x {sectors:2d} sectors: {cost:.2f} s per run; |peak change| vs 4 x 48: mean "
              f"{statistics.mean(change):.1%}, median {statistics.median(change):.1%}; same outcome {same}/{len(runs)}",
              flush=True)
    return rows


# The speed goals of issue 25 for one run under FEMA-FF-01 x1 (35 s), CPU seconds on one core.
GOALS = {1: 0.15, 4: 1.5, 10: 5.0}


def bench_drums(reference=(1, 4), counts=(1, 4, 10), repeat=3, scale=1.0):
    """The paper's column in 1, 4 and 10 drums (joint friction 0.6) under FEMA-FF-01 x1: the
    semi-implicit default and, for the counts in ``reference``, the adaptive DOPRI5 reference,
    side by side in one run; CPU time of this process, without the damping calibration
    (cached per process, not timed). The semi-implicit runs are repeated ``repeat`` times and
    the least CPU time is quoted, all of them printed: on this shared virtual machine the
    same run's CPU time varies by up to a half from minute to minute (the DOPRI5 runs once).
    ``scale`` scales the record; the goals are for x1 (where the 10-drum stack may overturn and
    stop early, x0.5 gives a stack that stands through the whole record)."""
    from pipeline.structures.drums import DrumColumn
    from pipeline.structures.column import Column
    from pipeline.groundmotion import load

    from pipeline.settings import ModelSettings

    column, motion = Column(*PAPER), load("FEMA-FF-01")
    tail = ModelSettings().tail  # [s] of free motion after the record
    print(f"drums: the paper's column under FEMA-FF-01 x{scale:g}, joint friction 0.6", flush=True)
    rows = []
    for n in counts:
        body = column if n == 1 else DrumColumn.equal(column, n)
        for integrator in ("semi-implicit", "dopri5") if n in reference else ("semi-implicit",):
            # compiles or loads the kernel and calibrates the damping for this integrator: not timed
            _simulate(column, motion, tail=0.0, integrator=integrator)
            times = []
            for _ in range(repeat if integrator == "semi-implicit" else 1):
                cpu = time.process_time()
                seconds, s = _simulate(body, motion, scale, joint_friction=0.6, integrator=integrator)
                times.append((time.process_time() - cpu, seconds))
            cpu, seconds = min(times)
            has_goal = integrator == "semi-implicit" and n in GOALS and scale == 1.0
            slip = s["joint_slip"]
            # a run that overturns stops early: its cost per simulated second prices the whole record
            simulated = s["overturn_time"] if s["overturned"] else motion.duration + tail
            full = cpu / simulated * (motion.duration + tail)
            rows.append({"drums": n, "integrator": integrator, "seconds": seconds, "cpu_seconds": cpu,
                         "scale": scale, "goal_cpu_seconds": GOALS.get(n) if has_goal else None,
                         "step": s.get("step"), "step_limit": s.get("step_limit"),
                         "cpu_seconds_each": [c for c, _ in times], "simulated_seconds": simulated,
                         "cpu_seconds_whole_record": full,
                         "steps": s["steps"], "rejected": s["rejected_steps"], "rhs": s["rhs_evaluations"],
                         "peak_theta_ratio": s["peak_theta_ratio"], "drum_peak_theta": s["drum_peak_theta"].tolist(),
                         "overturned": s["overturned"], "joint_slip": slip.tolist(),
                         "balance_over_work": s["energy_balance_error"] / s["work_ground"]})
            step = (f"step {1e3 * s['step']:.3f} ms (limit {1e3 * s['step_limit']:.3f}), {s['steps']} steps, "
                    f"{s['rhs_evaluations']} solves" if integrator == "semi-implicit" else
                    f"{s['steps']} steps + {s['rejected_steps']} rejected, {s['rhs_evaluations']} rhs")
            goal = f" (goal {GOALS[n]:g} s)" if has_goal else ""
            each = f" (least of {', '.join(f'{c:.2f}' for c, _ in times)})" if len(times) > 1 else ""
            print(f"{n:2d} drum(s), {integrator:13s}: {cpu:7.2f} s of CPU{goal}{each}, {seconds:7.2f} s wall; {step}; peak "
                  f"{s['peak_theta_ratio']:.3f} theta_crit, {'overturned' if s['overturned'] else 'stands'}; "
                  f"largest residual joint slip {1e3 * max(slip):.2f} mm; energy balance "
                  f"{s['energy_balance_error'] / s['work_ground']:.1e} of the work", flush=True)
            if s["overturned"]:
                print(f"{'':18s} overturned at {simulated:.1f} s: {cpu / simulated:.3f} s of CPU per simulated second, "
                      f"{full:.2f} s for the whole {motion.duration + tail:g} s", flush=True)
        pair = [r for r in rows if r["drums"] == n]
        if len(pair) == 2:
            fast, slow = pair
            ratio = f"{n:2d} drum(s): DOPRI5 / semi-implicit CPU time {slow['cpu_seconds'] / fast['cpu_seconds']:.0f}x"
            if fast["simulated_seconds"] != slow["simulated_seconds"]:
                # one of them overturned and stopped early: only the cost per simulated second compares
                ratio += (f"; the runs simulated {slow['simulated_seconds']:.1f} and {fast['simulated_seconds']:.1f} s, "
                          f"per simulated second {slow['cpu_seconds_whole_record'] / fast['cpu_seconds_whole_record']:.0f}x")
            print(ratio, flush=True)
    return rows


# issue 37: CPU time of a colonnade's run as a ratio to the rigid 3d model's run of its column
COLONNADE_GOALS = {"2-column frame": 100.0, "6-column row": 300.0, "Parthenon east front": 1000.0}
# the paper's column with the capital of the examples, its proportions those of the Parthenon's
# front (interaxial 2.26 and architrave 0.71 lower diameters): 2.3 m and 0.7 m
PAPER_ROW = dict(capital=(1.1, 0.3), interaxial=2.3, epistyle=0.7)


def _cpu(run, repeat):
    """(least CPU time [s] of ``repeat`` calls of ``run``, all of them, the last result)."""
    times, out = [], None
    for _ in range(repeat):
        cpu = time.process_time()
        out = run()
        times.append(time.process_time() - cpu)
    return min(times), times, out


def bench_colonnade(repeat=3, parthenon=True):
    """Issue 37's speed goals: colonnades under FEMA-FF-01 x1 against the rigid 3d run of their column,
    CPU time of this process (the damping calibration cached, not timed), least of ``repeat``."""
    from pipeline.groundmotion import load
    from pipeline.settings import Excitation, ModelSettings
    from pipeline.simulate import simulate
    from pipeline.structures.colonnade import Colonnade, named_colonnade
    from pipeline.structures.column import Column
    from pipeline.structures.drums import Capital, DrumColumn

    motion = load("FEMA-FF-01")
    paper = Column(*PAPER)
    column = DrumColumn.equal(paper, 4, Capital(*PAPER_ROW["capital"]))
    cases = [("2-column frame", Colonnade(column, 2, PAPER_ROW["interaxial"], PAPER_ROW["epistyle"])),
             ("6-column row", Colonnade(column, 6, PAPER_ROW["interaxial"], PAPER_ROW["epistyle"])),
             ("10-drum stack", DrumColumn.equal(paper, 10))]
    if parthenon:
        cases.append(("Parthenon east front", named_colonnade("parthenon-east")))

    def rigid():
        return simulate(paper, motion, Excitation(), ModelSettings(model="3d"), histories=False).summary

    rigid()  # compiles or loads the kernels: not timed
    base, each, _ = _cpu(rigid, max(repeat, 5))
    print(f"colonnade: FEMA-FF-01 x1, {motion.duration + ModelSettings().tail:g} s with the tail; rigid 3d run of "
          f"the paper's column {base:.4f} s of CPU (least of {', '.join(f'{c:.4f}' for c in each)})", flush=True)
    rows = [{"case": "rigid 3d", "cpu_seconds": base, "cpu_seconds_each": each}]
    settings = ModelSettings(model="3d-compliant", joint_friction=0.6, settle_limit=0.0)
    for name, structure in cases:
        bodies = (structure.n_bodies if isinstance(structure, DrumColumn) else
                  structure.n_columns * structure.column.n_bodies + structure.n_blocks)
        simulate(structure.column if isinstance(structure, Colonnade) else structure, motion, Excitation(),
                 ModelSettings(model="3d-compliant", tail=0.0), histories=False)  # calibrates: not timed
        cpu, each, s = _cpu(lambda: simulate(structure, motion, Excitation(), settings, histories=False).summary,
                            repeat if bodies < 60 else 1)
        simulated = s["overturn_time"] if s["overturned"] else motion.duration + settings.tail
        full = cpu / simulated * (motion.duration + settings.tail)
        goal = COLONNADE_GOALS.get(name)
        row = {"case": name, "bodies": bodies, "cpu_seconds": cpu, "cpu_seconds_each": each,
               "ratio_to_rigid": cpu / base, "ratio_whole_record": full / base, "goal_ratio": goal,
               "steps": s["steps"], "step": s["step"], "overturned": s["overturned"], "simulated_seconds": simulated,
               "cpu_per_body_step_us": 1e6 * cpu / (s["steps"] * bodies)}
        rows.append(row)
        words = f" (goal {goal:g}x)" if goal else ""
        least = f" (least of {', '.join(f'{c:.2f}' for c in each)})" if len(each) > 1 else ""
        print(f"{name:22s} {bodies:3d} bodies: {cpu:7.2f} s of CPU{least}, {cpu / base:6.0f}x the rigid run{words}; "
              f"{s['steps']} steps of {1e3 * s['step']:.3f} ms, {row['cpu_per_body_step_us']:.2f} us per body-step; "
              f"{'overturned at %.1f s (%.0fx for the whole record)' % (simulated, full / base) if s['overturned'] else 'stands'}",
              flush=True)
        if name == "Parthenon east front":
            night = 22 * 6 * full / 2.0 / 3600.0
            print(f"{'':22s} a 22 x 6 fragility of it on two cores: about {night:.1f} h (goal: a night)", flush=True)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("parts", nargs="+", choices=("record", "fragility", "discretisation", "drums", "colonnade"))
    parser.add_argument("--repeat", type=int, default=3,
                        help="runs of each case, the least time quoted (default 3; DOPRI5 drums run once)")
    parser.add_argument("--stripes", default="0.5,1,2,3", help="scale levels of the fragility sample")
    parser.add_argument("--reference", default="1,4",
                        help="drum counts also run with the adaptive DOPRI5 reference (default 1,4; 10 drums take "
                        "8-14 min; '' for none)")
    parser.add_argument("--drums", default="1,4,10", help="drum counts of the drums part (default 1,4,10)")
    parser.add_argument("--scale", type=float, default=1.0,
                        help="scale of the record in the drums part (default 1, where the goals apply)")
    parser.add_argument("--json", help="also write the numbers to this file")
    parser.add_argument("--no-parthenon", action="store_true", help="leave the Parthenon front out of the colonnade part")
    args = parser.parse_args()
    print(f"{platform.machine()} {platform.processor() or ''}, {os.cpu_count()} cores, load average "
          f"{', '.join(f'{x:.2f}' for x in os.getloadavg())}", flush=True)
    out = {}
    if "record" in args.parts:
        out["record"] = bench_record(args.repeat)
    if "fragility" in args.parts:
        out["fragility"] = bench_fragility([float(x) for x in args.stripes.split(",")])
    if "discretisation" in args.parts:
        out["discretisation"] = bench_discretisation()
    if "drums" in args.parts:
        out["drums"] = bench_drums([int(x) for x in args.reference.split(",") if x],
                                   [int(x) for x in args.drums.split(",") if x], max(1, args.repeat), args.scale)
    if "colonnade" in args.parts:
        out["colonnade"] = bench_colonnade(max(1, args.repeat), parthenon=not args.no_parthenon)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
