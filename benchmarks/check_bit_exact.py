"""Are a tree's compliant runs the same to the bit as another tree's? Run by hand (issue 48, speed).

``save OUT.npz`` runs the cases below with the tree on the path (``PYTHONPATH``) and keeps every
summary value and every history variable of each; ``compare A.npz B.npz`` says, case by case, how
many arrays the two files hold and how many are equal to the bit (floats compared as their bit
patterns, so -0.0 differs from 0.0 and NaNs must match), and names the first that differ.

The cases (FEMA-FF-01, joint friction 0.6, histories every 0.01 s): the paper's column in 4 drums
with its capital, a row of 3 and the frame of 2 of that column (the capital 1.1 x 0.3 m, interaxial
2.3 m, epistyle 0.7 m), at x1 and at x1.5 and 30 deg (the latter slide and rock harder); the
Parthenon's east front at x1 along the row and at x2 and 30 deg (which may overturn: the end of a
run); and 3 drums with the adaptive DOPRI5 reference over the first 4 s (the right-hand side shares
the tables and helpers of the fixed-step kernel).

Give each tree an empty numba cache (``NUMBA_CACHE_DIR``): numba does not recompile a cached kernel
when only a kernel it calls, in another file, has changed.

Run by hand:
    PYTHONPATH=/path/to/tree-a python benchmarks/check_bit_exact.py save /tmp/a.npz
    PYTHONPATH=/path/to/tree-b python benchmarks/check_bit_exact.py save /tmp/b.npz
    python benchmarks/check_bit_exact.py compare /tmp/a.npz /tmp/b.npz
"""

import argparse
import time

import numpy as np

PAPER = (0.5, 0.4, 4.0)
ROW = dict(capital=(1.1, 0.3), interaxial=2.3, epistyle=0.7)


def _cases():
    from pipeline.groundmotion import load
    from pipeline.groundmotion.record import GroundMotion
    from pipeline.structures.colonnade import Colonnade, named_colonnade
    from pipeline.structures.column import Column
    from pipeline.structures.drums import Capital, DrumColumn

    motion = load("FEMA-FF-01")
    n = int(round(4.0 / motion.dt)) + 1
    first = GroundMotion.from_arrays(np.asarray(motion.acc_x)[:n], np.asarray(motion.acc_y)[:n], motion.dt,
                                     None if motion.acc_z is None else np.asarray(motion.acc_z)[:n],
                                     record_id="FEMA-FF-01 first 4 s")
    paper = Column(*PAPER)
    column = DrumColumn.equal(paper, 4, Capital(*ROW["capital"]))
    frame = Colonnade(column, 2, ROW["interaxial"], ROW["epistyle"])
    row = Colonnade(column, 3, ROW["interaxial"], ROW["epistyle"])
    front = named_colonnade("parthenon-east")
    cases = []
    for name, structure in (("4 drums + capital", column), ("row of 3", row), ("frame of 2", frame)):
        cases.append((f"{name}, x1", structure, motion, 1.0, 0.0, {}))
        cases.append((f"{name}, x1.5 at 30 deg", structure, motion, 1.5, 30.0, {}))
    cases.append(("Parthenon front, x1", front, motion, 1.0, 0.0, {}))
    cases.append(("Parthenon front, x2 at 30 deg", front, motion, 2.0, 30.0, {}))
    cases.append(("3 drums, DOPRI5, first 4 s", DrumColumn.equal(paper, 3), first, 1.0, 0.0,
                  {"integrator": "dopri5", "tail": 0.0}))
    return cases


def save(out):
    from pipeline.settings import Excitation, ModelSettings
    from pipeline.simulate import simulate

    arrays = {}
    for name, structure, motion, scale, angle, more in _cases():
        settings = ModelSettings(**{"model": "3d-compliant", "joint_friction": 0.6, "output_step": 0.01, **more})
        t0 = time.process_time()
        r = simulate(structure, motion, Excitation(angle=angle, scale=scale), settings, histories=True)
        kept = 0
        for key, value in r.summary.items():
            value = np.asarray(value)
            if value.dtype.kind in "fiub":
                arrays[f"{name}|summary|{key}"] = value
                kept += 1
        for key, var in r.histories.variables.items():
            value = np.asarray(var.values)
            if value.dtype.kind in "fiubM":
                arrays[f"{name}|history|{key}"] = value
                kept += 1
        s = r.summary
        end = f"overturned at {s['overturn_time']:.4f} s" if s["overturned"] else "stands"
        print(f"{name}: {kept} arrays, {s['steps']} steps, {time.process_time() - t0:.1f} s of CPU; peak "
              f"{s['peak_theta_ratio']:.9f} theta_crit, {end}", flush=True)
    np.savez_compressed(out, **arrays)


def _bits(a):
    a = np.ascontiguousarray(a)
    if a.dtype.kind == "f":
        return a.view(np.uint64 if a.dtype.itemsize == 8 else np.uint32)
    if a.dtype.kind == "M":
        return a.view(np.int64)
    return a


def compare(a_path, b_path):
    a, b = np.load(a_path), np.load(b_path)
    cases = sorted({k.split("|")[0] for k in set(a.files) | set(b.files)})
    same_all = True
    for case in cases:
        keys = sorted(k for k in set(a.files) | set(b.files) if k.startswith(case + "|"))
        differ = []
        for k in keys:
            if k not in a.files or k not in b.files:
                differ.append(f"{k.split('|', 1)[1]} (only in {'B' if k not in a.files else 'A'})")
                continue
            x, y = a[k], b[k]
            if x.shape != y.shape or x.dtype != y.dtype or not np.array_equal(_bits(x), _bits(y)):
                differ.append(k.split("|", 1)[1])
        same_all &= not differ
        print(f"{case}: {len(keys) - len(differ)} of {len(keys)} arrays equal to the bit"
              + (f"; differ: {', '.join(differ[:6])}{' ...' if len(differ) > 6 else ''}" if differ else ""))
    print("all equal to the bit" if same_all else "NOT all equal")
    return same_all


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="what", required=True)
    s = sub.add_parser("save", help="run the cases with the tree on the path, keep their arrays")
    s.add_argument("out")
    c = sub.add_parser("compare", help="compare two saved files, to the bit")
    c.add_argument("a")
    c.add_argument("b")
    args = parser.parse_args()
    if args.what == "save":
        save(args.out)
    else:
        raise SystemExit(0 if compare(args.a, args.b) else 1)


if __name__ == "__main__":
    main()
