"""Speed of the compiled DOP853 kernel against scipy's solve_ivp(method="DOP853").

Problem: a damped pendulum under a 30 s horizontal base acceleration sampled every 0.01 s
and linearly interpolated by the rhs (the shape of the column problem: a few states, a
sampled record in ``params``), rtol 1e-9, atol 1e-12, output on the 0.01 s grid.

Rows, all measured in this one run:

* ``numba kernel``: :func:`pipeline.dynamics.integrators.dop853.dop853` through a cached wrapper;
* ``numba kernel, breaks``: the same with ``t_breaks`` at the sample times, so that no step
  straddles a kink of the interpolated record (the setting the physics should use);
* ``dopri5 kernel, breaks``: :func:`pipeline.dynamics.integrators.dopri5.dopri5`, the same
  problem and break points (the same driver, a 5(4) method);
* ``scipy + Python rhs``: solve_ivp with a plain Python rhs;
* ``scipy + numba rhs``: solve_ivp calling the numba-compiled rhs from Python.

It also measures the compile cost in fresh processes with an empty ``NUMBA_CACHE_DIR``:
the first process compiles the wrapper (and the kernel inlined in it), the second loads it
from the cache.

Run by hand: ``.venv/bin/python benchmarks/bench_integrator.py``.
"""

import math
import os
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np
from numba import njit

from pipeline.dynamics.integrators.dop853 import dop853, no_events
from pipeline.dynamics.integrators.dopri5 import dopri5

# the problem's right-hand side is the tests' (tests/dynamics/integrators/integrator_problems.py)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "dynamics",
                                "integrators"))
from integrator_problems import forced_pendulum  # noqa: E402

RTOL, ATOL = 1e-9, 1e-12
DT = 0.01  # record sampling [s]
DURATION = 30.0  # [s]
EMPTY = np.zeros(0)


@njit(cache=True)
def integrate_pendulum(p, y0, t_end, t_out, y_out, t_breaks):
    return dop853(forced_pendulum, no_events, p, 0.0, y0, t_end, t_out, y_out, 0, EMPTY,
                  t_breaks, RTOL, ATOL, np.inf, 0.0, 10_000_000)


@njit(cache=True)
def integrate_pendulum5(p, y0, t_end, t_out, y_out, t_breaks):
    return dopri5(forced_pendulum, no_events, p, 0.0, y0, t_end, t_out, y_out, 0, EMPTY,
                  t_breaks, RTOL, ATOL, np.inf, 0.0, 10_000_000)


@njit(cache=True)
def integrate_pendulum_tight(p, y0, t_end, t_out, y_out, t_breaks):
    return dop853(forced_pendulum, no_events, p, 0.0, y0, t_end, t_out, y_out, 0, EMPTY,
                  t_breaks, 1e-13, 1e-16, np.inf, 0.0, 10_000_000)


def make_case():
    """Consts, a 30 s synthetic record (band-limited noise under an envelope), y0, grid."""
    rng = np.random.default_rng(1)
    t = np.arange(0.0, DURATION + DT / 2, DT)
    freqs = np.linspace(0.3, 8.0, 40)
    acc = np.zeros_like(t)
    for f, ph in zip(freqs, rng.uniform(0, 2 * np.pi, freqs.size)):
        acc += np.sin(2 * np.pi * f * t + ph) / np.sqrt(f)
    envelope = np.minimum(t / 3.0, 1.0) * np.exp(-np.maximum(t - 15.0, 0.0) / 5.0)
    acc *= 2.0 / np.abs(acc).max() * envelope  # peak ~2 m/s^2
    omega0 = 2 * np.pi * 0.8
    consts = np.array([omega0**2, 2 * 0.02 * omega0, 1.0 / 0.5, DT])
    return consts, acc, np.array([0.05, 0.0]), t


def best_time(fn, repeat, number=1):
    """Best wall time [s] per call over ``repeat`` rounds of ``number`` calls."""
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            out = fn()
        best = min(best, (time.perf_counter() - t0) / number)
    return best, out


def compile_times():
    """Seconds for a fresh process to import + first call: cold cache, then warm cache."""
    code = (
        "import time; t0 = time.perf_counter()\n"
        "import numpy as np\n"
        "import bench_integrator as b\n"
        "c, a, y0, t = b.make_case()\n"
        "b.integrate_pendulum((c, a), y0, 1.0, t, np.empty((t.size, 2)), b.EMPTY)\n"
        "print(time.perf_counter() - t0)\n"
    )
    here = os.path.dirname(os.path.abspath(__file__))
    times = []
    with tempfile.TemporaryDirectory() as cache:
        # keep the caller's PYTHONPATH (an older checkout to compare, say) behind this folder
        path = os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH")) if p)
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=path)
        for _ in range(2):
            out = subprocess.run([sys.executable, "-c", code], env=env, cwd=here,
                                 capture_output=True, text=True, check=True)
            times.append(float(out.stdout.strip().splitlines()[-1]))
    return times


def main():
    consts, acc, y0, t_out = make_case()
    params = (consts, acc)
    t_samples = DT * np.arange(acc.size)
    y_out = np.empty((t_out.size, 2))

    def numba_kernel():
        return integrate_pendulum(params, y0, DURATION, t_out, y_out, EMPTY)

    def numba_kernel_breaks():
        return integrate_pendulum(params, y0, DURATION, t_out, y_out, t_samples)

    c0, c1, c2, dt = consts

    def rhs_python(t, y):
        s = t / dt
        i = int(s)
        if i >= acc.size - 1:
            a = acc[-1]
        else:
            w = s - i
            a = (1.0 - w) * acc[i] + w * acc[i + 1]
        return np.array([y[1], -c0 * math.sin(y[0]) - c1 * y[1] - c2 * a * math.cos(y[0])])

    rhs_numba = forced_pendulum

    def rhs_numba_from_python(t, y):
        dydt = np.empty(2)
        rhs_numba(t, y, params, dydt)
        return dydt

    def scipy_with(fun):
        from scipy.integrate import solve_ivp

        return lambda: solve_ivp(fun, (0.0, DURATION), y0, method="DOP853", rtol=RTOL,
                                 atol=ATOL, t_eval=t_out)

    def dopri5_kernel_breaks():
        return integrate_pendulum5(params, y0, DURATION, t_out, y_out, t_samples)

    numba_kernel()  # compile (or load from cache) outside the timing
    dopri5_kernel_breaks()
    rhs_numba_from_python(0.0, y0)
    # reference for the error column: rtol 1e-13 with steps ending on every quarter sample
    # (a step sequence of its own, independent of the rows' steps)
    y_ref = np.empty_like(y_out)
    t_quarters = 0.25 * DT * np.arange(4 * (acc.size - 1) + 1)
    r_ref = integrate_pendulum_tight(params, y0, DURATION, t_out, y_ref, t_quarters)
    assert r_ref.status == 0

    rows = []
    t_k, r_k = best_time(numba_kernel, repeat=5, number=3)
    err_k = np.abs(y_out - y_ref).max()
    rows.append(("numba kernel", t_k, r_k.nfev, r_k.n_accepted, r_k.n_rejected, err_k))
    t_b, r_b = best_time(numba_kernel_breaks, repeat=5, number=3)
    err_b = np.abs(y_out - y_ref).max()
    rows.append(("numba kernel, breaks", t_b, r_b.nfev, r_b.n_accepted, r_b.n_rejected,
                 err_b))
    t_5, r_5 = best_time(dopri5_kernel_breaks, repeat=5, number=3)
    err_5 = np.abs(y_out - y_ref).max()
    rows.append(("dopri5 kernel, breaks", t_5, r_5.nfev, r_5.n_accepted, r_5.n_rejected, err_5))
    for name, fun in (("scipy + Python rhs", rhs_python),
                      ("scipy + numba rhs", rhs_numba_from_python)):
        t_s, sol = best_time(scipy_with(fun), repeat=2)
        err_s = np.abs(sol.y.T - y_ref).max()
        rows.append((name, t_s, sol.nfev, None, None, err_s))

    cold, warm = compile_times()

    print(f"machine: {platform.platform()}, {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} CPUs; Python {platform.python_version()}")
    import numba
    import scipy

    print(f"numba {numba.__version__}, numpy {np.__version__}, scipy {scipy.__version__}")
    print(f"problem: forced pendulum, {DURATION:.0f} s record sampled at {DT} s "
          f"(linear interpolation), rtol {RTOL:g}, atol {ATOL:g}, "
          f"{t_out.size} output points")
    print()
    head = (f"{'integrator':<22} {'time/run [ms]':>14} {'rhs calls':>10} {'steps ok/rej':>13} "
            f"{'max err':>9} {'time ratio':>11}")
    print(head)
    print("-" * len(head))
    for name, t, nfev, acc_, rej, err in rows:
        steps = f"{acc_}/{rej}" if acc_ is not None else "-"
        print(f"{name:<22} {1e3 * t:>14.2f} {nfev:>10d} {steps:>13} {err:>9.1e} "
              f"{t / t_k:>10.3g}x")
    print()
    print("max err: largest |y - y_ref| on the output grid [rad, rad/s]; y_ref from the kernel "
          "at rtol 1e-13 with steps ending every dt/4.")
    print("time ratio: wall time per run / that of the numba kernel without breaks.")
    print(f"compile, fresh process (import + first call): cold cache {cold:.2f} s, "
          f"warm cache {warm:.2f} s")


if __name__ == "__main__":
    main()
