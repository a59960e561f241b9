"""The fixed-step loop compiled with LLVM's SLP vectoriser (pipeline.dynamics.compliant.vector_lanes).

numba turned the vectoriser off by default after miscompilations; the project turns it on for the
compliant model's fixed-step loop alone, on the ground that it changes no number. This checks that
ground on the machine that runs the tests: a frame of two columns, each of 2 drums and a capital,
under a one-sine pulse (0.36 g, 0.6 s at 30 deg) that rocks it to about a fifth of its overturning
tilt (the block solve's couplings, the active-set passes and the shear returns all at work), compiled in two fresh processes (empty numba caches, so
each compiles), once as the package does it and once with ``NUMBA_SLP_VECTORIZE=0``: every summary
value and history the same to the bit, and only the first compiled with packed vector arithmetic
(so the comparison compares two different compilations).
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

_RUN = r"""
import json, sys
import numpy as np
from pipeline.groundmotion import one_sine_pulse
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.structures.colonnade import Colonnade
from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn
from pipeline.dynamics.compliant import semi_implicit as si

frame = Colonnade(DrumColumn.equal(Column(0.5, 0.4, 4.0), 2, Capital(1.1, 0.3)), 2, 2.5, 0.8)
pulse = one_sine_pulse(3.5, 0.6, dt=0.01, duration=2.0)
r = simulate(frame, pulse, Excitation(angle=30.0), ModelSettings(model="3d-compliant", output_step=0.01),
             histories=True)
arrays = {"summary|" + k: np.asarray(v) for k, v in r.summary.items() if np.asarray(v).dtype.kind in "fiub"}
arrays.update({"history|" + k: np.asarray(v.values) for k, v in r.histories.variables.items()
               if np.asarray(v.values).dtype.kind in "fiub"})
np.savez(sys.argv[1], **arrays)
asm = "".join(si.run.inspect_asm(sig) for sig in si.run.signatures)
print(json.dumps({"packed": asm.count("vmulpd") + asm.count("vsubpd"), "signatures": len(si.run.signatures),
                  "peak": float(r.summary["peak_theta_ratio"])}))
"""


def _start(tmp_path, name, slp):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_SLP_VECTORIZE"}
    env["NUMBA_CACHE_DIR"] = str(tmp_path / f"numba-{name}")  # empty: this process compiles
    if slp is not None:
        env["NUMBA_SLP_VECTORIZE"] = slp
    out = tmp_path / f"{name}.npz"
    proc = subprocess.Popen([sys.executable, "-c", _RUN, str(out)], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    return proc, out


def _finish(proc, out):
    stdout, stderr = proc.communicate(timeout=900)
    assert proc.returncode == 0, stderr[-3000:]
    return json.loads(stdout.strip().splitlines()[-1]), np.load(out)


@pytest.mark.slow
def test_the_vectorised_loop_gives_the_scalar_numbers_to_the_bit(tmp_path):
    """Compiled as the package does (SLP on, for the fixed-step loop) and with it off: the same
    summary and histories to the bit (floats compared as bit patterns), one compilation of the loop
    each, and the package's with packed multiplies or subtractions that the other has fewer of
    (the loop vectoriser alone packs a few)."""
    runs = [_start(tmp_path, "package", None), _start(tmp_path, "scalar", "0")]  # side by side: 2 cores
    (info_v, vector), (info_s, scalar) = [_finish(*r) for r in runs]
    assert info_v["signatures"] == 1 and info_s["signatures"] == 1  # the call found the SLP compilation
    assert info_v["packed"] > info_s["packed"] + 100, (info_v, info_s)
    assert sorted(vector.files) == sorted(scalar.files) and len(vector.files) > 50
    differ = [k for k in vector.files
              if vector[k].shape != scalar[k].shape or vector[k].dtype != scalar[k].dtype
              or vector[k].tobytes() != scalar[k].tobytes()]
    assert not differ, f"not the same to the bit: {differ[:8]}"
    assert info_v["peak"] > 0.1  # the frame rocked (0.18 of its overturning tilt): motion compared, not rest
