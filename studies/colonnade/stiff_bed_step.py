"""Is the stiffest bed's extra overturning in plane a step effect? (issue 37, the bed band of ``in_plane.py --beds``)

On the 1e11 Pa/m bed the compliant frame of two, driven in plane, overturned in 10 of the 22 records at 0.8 g
against 3-6 on the softer beds and for the rigid frame. This reruns those 22 runs at a quarter of the step's
stability limit (``step_safety`` 0.25) beside the default half, and prints each run's outcome (X overturned,
. stood, ? undecided)::

    python studies/colonnade/stiff_bed_step.py        # 44 runs, about 22 min on two cores
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import in_plane  # noqa: E402

SAFETIES = (0.25, 0.5)
STRIPE = 0.8  # g


def main():
    # the former scheme (springs at the step's start), whose step this asks about, at each fraction of its limit
    variants = {f: ("3d-compliant", dict(normal_stiffness=1e11, numerics=(("springs", "explicit"), ("step_safety", f))))
                for f in SAFETIES}
    outcome, seconds = in_plane._run_variants(variants, 2, stripes=(STRIPE,))
    for f, rows in outcome.items():
        print(f"step_safety {f}: overturned {sum(r[3] for r in rows)} of {len(rows)}, "
              f"undecided {sum(r[4] for r in rows)}: " + "".join("X" if r[3] else ("?" if r[4] else ".") for r in rows))
    print(f"{len(variants) * len(in_plane.RECORDS)} runs in {seconds:.0f} s")


if __name__ == "__main__":
    main()
