"""Compiled Dormand–Prince 8(5,3) integrator with dense output and terminal events.

A numba kernel of Hairer's DOP853 with the coefficients, error norm, step controller and
initial-step rule of :class:`scipy.integrate.DOP853` (so that at equal ``rtol``/``atol`` the
accuracy and the step counts match scipy's), the 7th-order continuous extension
(3 extra stages, as scipy's ``Dop853DenseOutput``) to fill a caller-given output grid without
restricting the steps, and location of terminal events on that interpolant (Brent's method).

Everything is floats and arrays: the right-hand side, the event functions and their
parameters are supplied by the caller.

Calling convention
------------------
``rhs(t, y, params, dydt_out)``
    numba-jitted; writes dy/dt into ``dydt_out`` (length n) and returns nothing. It must not
    allocate if speed matters: it is called 12 times per step (15 when the step is
    interpolated).
``events(t, y, params, g_out)``
    numba-jitted; writes the values of the event functions g_k into ``g_out`` (length
    ``len(event_direction)``). Use :func:`no_events` when there are none.
``params``
    anything numba can type and both functions accept: a float64 array, a tuple of arrays
    (e.g. column constants and a sampled ground-acceleration record), ...

How to call it (compilation and caching)
----------------------------------------
:func:`dop853` is specialised by numba for each (rhs, events, params-type). Findings with
numba 0.68 (``benchmarks/bench_integrator.py`` measures the compile times):

* A function passed as an *argument* to an ``@njit(cache=True)`` function is typed by its
  identity (``type(CPUDispatcher(<function f at 0x...>))``), so the on-disk cache never hits
  in a new process, and every process appends one more entry to ``__pycache__``
  (numba issues #6251, #9237, #6972). A factory that closes over the functions fails the
  same way (the closure variables pickle with the dispatcher's UUID, numba #6264), and a
  cached caller that passes a global jitted function as a value is refused outright
  ("uses dynamic globals").
* What works: :func:`dop853` is declared ``inline="always"``, so numba splices its IR into
  the caller, where ``rhs`` and ``events`` become direct calls to globals. The caller writes
  one small ``@njit(cache=True)`` wrapper in its own module per problem; that wrapper caches
  (its key is its own argument types only) and its calls to ``rhs`` can be inlined by LLVM::

      @njit(cache=True)
      def integrate_rocking(params, t0, y0, t_end, t_out, y_out, out_start, t_samples, h0):
          return dop853(rocking_rhs, rocking_events, params, t0, y0, t_end,
                        t_out, y_out, out_start, ROCKING_EVENT_DIRECTION, t_samples,
                        1e-9, 1e-12, np.inf, h0, 1_000_000)

  Trade-offs: the integrator is compiled once per wrapper (cold: ~5-9 s; a fresh process
  that loads it from the cache starts in ~0.8 s, imports included);
  :func:`dop853` itself carries no ``cache=True`` because called directly from Python it
  could never hit the cache and would only grow ``__pycache__``. As with every numba cache,
  the wrapper's cache is keyed on *its own* file: editing this module or the rhs module
  does not invalidate it (clear ``__pycache__``, or point ``NUMBA_CACHE_DIR`` at a directory
  named after a digest of the sources). The alternative, first-class function types
  (``cfunc`` rhs with a fixed signature), caches the integrator itself but makes every rhs
  call an indirect, non-inlinable call and fixes the type of ``params`` in the signature.

Sampled forcing: pass the sample times as ``t_breaks``
-----------------------------------------------------
A record interpolated linearly has a kink at every sample; the error estimate assumes a
smooth rhs, so steps across kinks are accepted with errors ~1e3 rtol after cascades of
rejections. With the sample times as break points no step crosses one: on the benchmark's
30 s pendulum at rtol 1e-9 that is 14x fewer rhs calls and a 1e4x smaller error. Without
break points the steps are exactly scipy's.

Restarting (hybrid simulations)
-------------------------------
One call integrates one smooth phase. It fills ``y_out[i]`` for the grid times
``t_out[i] <= t`` reached, starting at ``out_start``, and returns ``out_next``, the first
index not filled. At a terminal event it stops at the event time with the interpolated
state; the caller applies its impact map and calls again from ``(t_event, y_new)`` with
``out_start=out_next``, so the grid is filled continuously with no point written twice.
The start state usually *is* the previous event's state (g ~ 0, its sign rounding noise),
so the event functions' signs are first taken at the end of a restart window,
``t0 + 1e-7 h`` on the interpolant, with h the first step the controller wanted: the
restart is not reported again, and a return to zero after the window still is. Roots
closer than that to ``t0`` are therefore not reported. When a break point cuts the first
step short (a record sample 1e-9 after ``t0``, say), the window still has the wanted
step's length: steps inside it report nothing, and the first step that leaves it reads
the signs at its end. (Scaling the window by the cut step instead put the reading within
rounding of ``t0``, where a noisy sign could report the restart again and again.)

Limitations
-----------
Forward integration only (``t_end >= t0``). Every event is terminal; if several events
change sign in one step the earliest root wins. As in scipy, only sign changes between the
ends of accepted steps are seen: an event function that goes out and back within one step
is missed (bound ``max_step`` if that matters).

References
----------
.. [1] E. Hairer, S. P. Nørsett, G. Wanner, "Solving Ordinary Differential Equations I:
       Nonstiff Problems", 2nd ed., Springer, 1993, Sec. II.5 and II.6.
.. [2] scipy.integrate.DOP853 and scipy/integrate/_ivp/dop853_coefficients.py (BSD licence),
       whose coefficient table is reproduced below.
.. [3] R. P. Brent, "Algorithms for Minimization without Derivatives", 1973, ch. 4
       (the root finder, in the form of scipy's ``brentq``).
"""

from collections import namedtuple

import numpy as np
from numba import njit

__all__ = [
    "dop853",
    "dop853_monitored",
    "no_events",
    "no_monitor",
    "Dop853Result",
    "STATUS_END",
    "STATUS_EVENT",
    "STATUS_STEP_TOO_SMALL",
    "STATUS_MAX_STEPS",
    "STATUS_BAD_INPUT",
]

STATUS_END = 0  #: reached t_end
STATUS_EVENT = 1  #: stopped at a terminal event
STATUS_STEP_TOO_SMALL = -1  #: step size underflow (stiffness, singularity or NaN in rhs)
STATUS_MAX_STEPS = -2  #: max_steps accepted steps taken before t_end
STATUS_BAD_INPUT = -3  #: inconsistent arguments (t_end < t0, shapes, out_start, tolerances)

Dop853Result = namedtuple(
    "Dop853Result",
    [
        "status",  # int: one of the STATUS_* codes
        "t",  # float [s]: time reached (t_end, the event time, or where it failed)
        "y",  # float64[n]: state at t (a new array)
        "event_index",  # int: index of the event that stopped the run, -1 if none
        "nfev",  # int: rhs evaluations in this call
        "n_accepted",  # int: accepted steps
        "n_rejected",  # int: rejected steps
        "out_next",  # int: first index of t_out not filled; pass as out_start to continue
        "n_out",  # int: output samples filled by this call (out_next - out_start)
        "h_next",  # float [s]: the step size the controller proposes next (first_step to resume)
    ],
)

# Step size controller of scipy's RungeKutta solvers (scipy/integrate/_ivp/rk.py).
_SAFETY = 0.9  # multiply steps predicted from the asymptotic error by this
_MIN_FACTOR = 0.2  # largest decrease of the step size after a rejection
_MAX_FACTOR = 10.0  # largest increase after an acceptance
_ERROR_EXPONENT = -1.0 / 8.0  # -1/(error estimator order + 1); the estimator is of order 7

# Root finder tolerance on the event time, as scipy's solve_ivp (xtol = rtol = 4 eps): the
# interpolant is cheap to evaluate, so the root is taken to the precision of t itself.
_EPS = np.finfo(np.float64).eps
_ROOT_XTOL = 4.0 * _EPS
_ROOT_RTOL = 4.0 * _EPS
_ROOT_MAXITER = 100
# Event roots within this fraction of the first step of a call are the restart itself
# (the caller starts on the previous event) and are not reported.
_START_WINDOW = 1e-7

# --- Coefficients of DOP853 (Hairer's dop853.f via scipy's dop853_coefficients.py) ---------
_N_STAGES = 12
_N_STAGES_EXTENDED = 16
_INTERPOLATOR_POWER = 7

_C = np.array([0.0,
              0.526001519587677318785587544488e-01,
              0.789002279381515978178381316732e-01,
              0.118350341907227396726757197510,
              0.281649658092772603273242802490,
              0.333333333333333333333333333333,
              0.25,
              0.307692307692307692307692307692,
              0.651282051282051282051282051282,
              0.6,
              0.857142857142857142857142857142,
              1.0,
              1.0,
              0.1,
              0.2,
              0.777777777777777777777777777778])

_A = np.zeros((_N_STAGES_EXTENDED, _N_STAGES_EXTENDED))
_A[1, 0] = 5.26001519587677318785587544488e-2

_A[2, 0] = 1.97250569845378994544595329183e-2
_A[2, 1] = 5.91751709536136983633785987549e-2

_A[3, 0] = 2.95875854768068491816892993775e-2
_A[3, 2] = 8.87627564304205475450678981324e-2

_A[4, 0] = 2.41365134159266685502369798665e-1
_A[4, 2] = -8.84549479328286085344864962717e-1
_A[4, 3] = 9.24834003261792003115737966543e-1

_A[5, 0] = 3.7037037037037037037037037037e-2
_A[5, 3] = 1.70828608729473871279604482173e-1
_A[5, 4] = 1.25467687566822425016691814123e-1

_A[6, 0] = 3.7109375e-2
_A[6, 3] = 1.70252211019544039314978060272e-1
_A[6, 4] = 6.02165389804559606850219397283e-2
_A[6, 5] = -1.7578125e-2

_A[7, 0] = 3.70920001185047927108779319836e-2
_A[7, 3] = 1.70383925712239993810214054705e-1
_A[7, 4] = 1.07262030446373284651809199168e-1
_A[7, 5] = -1.53194377486244017527936158236e-2
_A[7, 6] = 8.27378916381402288758473766002e-3

_A[8, 0] = 6.24110958716075717114429577812e-1
_A[8, 3] = -3.36089262944694129406857109825
_A[8, 4] = -8.68219346841726006818189891453e-1
_A[8, 5] = 2.75920996994467083049415600797e1
_A[8, 6] = 2.01540675504778934086186788979e1
_A[8, 7] = -4.34898841810699588477366255144e1

_A[9, 0] = 4.77662536438264365890433908527e-1
_A[9, 3] = -2.48811461997166764192642586468
_A[9, 4] = -5.90290826836842996371446475743e-1
_A[9, 5] = 2.12300514481811942347288949897e1
_A[9, 6] = 1.52792336328824235832596922938e1
_A[9, 7] = -3.32882109689848629194453265587e1
_A[9, 8] = -2.03312017085086261358222928593e-2

_A[10, 0] = -9.3714243008598732571704021658e-1
_A[10, 3] = 5.18637242884406370830023853209
_A[10, 4] = 1.09143734899672957818500254654
_A[10, 5] = -8.14978701074692612513997267357
_A[10, 6] = -1.85200656599969598641566180701e1
_A[10, 7] = 2.27394870993505042818970056734e1
_A[10, 8] = 2.49360555267965238987089396762
_A[10, 9] = -3.0467644718982195003823669022

_A[11, 0] = 2.27331014751653820792359768449
_A[11, 3] = -1.05344954667372501984066689879e1
_A[11, 4] = -2.00087205822486249909675718444
_A[11, 5] = -1.79589318631187989172765950534e1
_A[11, 6] = 2.79488845294199600508499808837e1
_A[11, 7] = -2.85899827713502369474065508674
_A[11, 8] = -8.87285693353062954433549289258
_A[11, 9] = 1.23605671757943030647266201528e1
_A[11, 10] = 6.43392746015763530355970484046e-1

_A[12, 0] = 5.42937341165687622380535766363e-2
_A[12, 5] = 4.45031289275240888144113950566
_A[12, 6] = 1.89151789931450038304281599044
_A[12, 7] = -5.8012039600105847814672114227
_A[12, 8] = 3.1116436695781989440891606237e-1
_A[12, 9] = -1.52160949662516078556178806805e-1
_A[12, 10] = 2.01365400804030348374776537501e-1
_A[12, 11] = 4.47106157277725905176885569043e-2

_A[13, 0] = 5.61675022830479523392909219681e-2
_A[13, 6] = 2.53500210216624811088794765333e-1
_A[13, 7] = -2.46239037470802489917441475441e-1
_A[13, 8] = -1.24191423263816360469010140626e-1
_A[13, 9] = 1.5329179827876569731206322685e-1
_A[13, 10] = 8.20105229563468988491666602057e-3
_A[13, 11] = 7.56789766054569976138603589584e-3
_A[13, 12] = -8.298e-3

_A[14, 0] = 3.18346481635021405060768473261e-2
_A[14, 5] = 2.83009096723667755288322961402e-2
_A[14, 6] = 5.35419883074385676223797384372e-2
_A[14, 7] = -5.49237485713909884646569340306e-2
_A[14, 10] = -1.08347328697249322858509316994e-4
_A[14, 11] = 3.82571090835658412954920192323e-4
_A[14, 12] = -3.40465008687404560802977114492e-4
_A[14, 13] = 1.41312443674632500278074618366e-1

_A[15, 0] = -4.28896301583791923408573538692e-1
_A[15, 5] = -4.69762141536116384314449447206
_A[15, 6] = 7.68342119606259904184240953878
_A[15, 7] = 4.06898981839711007970213554331
_A[15, 8] = 3.56727187455281109270669543021e-1
_A[15, 12] = -1.39902416515901462129418009734e-3
_A[15, 13] = 2.9475147891527723389556272149
_A[15, 14] = -9.15095847217987001081870187138


_B = _A[_N_STAGES, :_N_STAGES].copy()

_E3 = np.zeros(_N_STAGES + 1)
_E3[:-1] = _B.copy()
_E3[0] -= 0.244094488188976377952755905512
_E3[8] -= 0.733846688281611857341361741547
_E3[11] -= 0.220588235294117647058823529412e-1

_E5 = np.zeros(_N_STAGES + 1)
_E5[0] = 0.1312004499419488073250102996e-1
_E5[5] = -0.1225156446376204440720569753e+1
_E5[6] = -0.4957589496572501915214079952
_E5[7] = 0.1664377182454986536961530415e+1
_E5[8] = -0.3503288487499736816886487290
_E5[9] = 0.3341791187130174790297318841
_E5[10] = 0.8192320648511571246570742613e-1
_E5[11] = -0.2235530786388629525884427845e-1

# First 3 coefficients are computed separately.
_D = np.zeros((_INTERPOLATOR_POWER - 3, _N_STAGES_EXTENDED))
_D[0, 0] = -0.84289382761090128651353491142e+1
_D[0, 5] = 0.56671495351937776962531783590
_D[0, 6] = -0.30689499459498916912797304727e+1
_D[0, 7] = 0.23846676565120698287728149680e+1
_D[0, 8] = 0.21170345824450282767155149946e+1
_D[0, 9] = -0.87139158377797299206789907490
_D[0, 10] = 0.22404374302607882758541771650e+1
_D[0, 11] = 0.63157877876946881815570249290
_D[0, 12] = -0.88990336451333310820698117400e-1
_D[0, 13] = 0.18148505520854727256656404962e+2
_D[0, 14] = -0.91946323924783554000451984436e+1
_D[0, 15] = -0.44360363875948939664310572000e+1

_D[1, 0] = 0.10427508642579134603413151009e+2
_D[1, 5] = 0.24228349177525818288430175319e+3
_D[1, 6] = 0.16520045171727028198505394887e+3
_D[1, 7] = -0.37454675472269020279518312152e+3
_D[1, 8] = -0.22113666853125306036270938578e+2
_D[1, 9] = 0.77334326684722638389603898808e+1
_D[1, 10] = -0.30674084731089398182061213626e+2
_D[1, 11] = -0.93321305264302278729567221706e+1
_D[1, 12] = 0.15697238121770843886131091075e+2
_D[1, 13] = -0.31139403219565177677282850411e+2
_D[1, 14] = -0.93529243588444783865713862664e+1
_D[1, 15] = 0.35816841486394083752465898540e+2

_D[2, 0] = 0.19985053242002433820987653617e+2
_D[2, 5] = -0.38703730874935176555105901742e+3
_D[2, 6] = -0.18917813819516756882830838328e+3
_D[2, 7] = 0.52780815920542364900561016686e+3
_D[2, 8] = -0.11573902539959630126141871134e+2
_D[2, 9] = 0.68812326946963000169666922661e+1
_D[2, 10] = -0.10006050966910838403183860980e+1
_D[2, 11] = 0.77771377980534432092869265740
_D[2, 12] = -0.27782057523535084065932004339e+1
_D[2, 13] = -0.60196695231264120758267380846e+2
_D[2, 14] = 0.84320405506677161018159903784e+2
_D[2, 15] = 0.11992291136182789328035130030e+2

_D[3, 0] = -0.25693933462703749003312586129e+2
_D[3, 5] = -0.15418974869023643374053993627e+3
_D[3, 6] = -0.23152937917604549567536039109e+3
_D[3, 7] = 0.35763911791061412378285349910e+3
_D[3, 8] = 0.93405324183624310003907691704e+2
_D[3, 9] = -0.37458323136451633156875139351e+2
_D[3, 10] = 0.10409964950896230045147246184e+3
_D[3, 11] = 0.29840293426660503123344363579e+2
_D[3, 12] = -0.43533456590011143754432175058e+2
_D[3, 13] = 0.96324553959188282948394950600e+2
_D[3, 14] = -0.39177261675615439165231486172e+2
_D[3, 15] = -0.14972683625798562581422125276e+3


# --- Building blocks --------------------------------------------------------------------------


@njit(cache=True)
def no_events(t, y, params, g_out):
    """Event function for problems without events (writes nothing).

    Parameters
    ----------
    t : float
        Time [s] (unused).
    y, params, g_out
        Unused; ``g_out`` has length 0 when ``event_direction`` is empty.
    """


@njit(cache=True)
def no_monitor(t, y, params, g):
    """Step monitor for problems that watch nothing (does nothing)."""


@njit(inline="always")
def _select_initial_step(rhs, params, t0, y0, f0, t_end, max_step, rtol, atol, y1, f1, error_order=7):
    """First step size by Hairer's rule, as scipy's ``select_initial_step``.

    ``error_order``: the order of the method's error estimate (7 for DOP853, 4 for
    DOPRI5, :mod:`pipeline.dynamics.integrators.dopri5`). Returns the step size [s]; costs one
    rhs evaluation (``y1``, ``f1`` are work arrays).
    """
    n = y0.shape[0]
    interval = t_end - t0
    if interval == 0.0:
        return 0.0
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        scale = atol[i] + abs(y0[i]) * rtol
        d0 += (y0[i] / scale) ** 2
        d1 += (f0[i] / scale) ** 2
    d0 = np.sqrt(d0 / n)
    d1 = np.sqrt(d1 / n)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, interval)
    for i in range(n):
        y1[i] = y0[i] + h0 * f0[i]
    rhs(t0 + h0, y1, params, f1)
    d2 = 0.0
    for i in range(n):
        scale = atol[i] + abs(y0[i]) * rtol
        d2 += ((f1[i] - f0[i]) / scale) ** 2
    d2 = np.sqrt(d2 / n) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (error_order + 1))
    return min(100.0 * h0, h1, interval, max_step)


@njit(inline="always")
def _rk_step(rhs, params, t, y, h, K, y_stage, y_new):
    """One DOP853 step: stages 1..11 into ``K``, ``y_new``, and f(t+h, y_new) into ``K[12]``.

    ``K[0]`` must hold f(t, y). Costs 12 rhs evaluations.
    """
    n = y.shape[0]
    for s in range(1, _N_STAGES):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += _A[s, j] * K[j, i]
            y_stage[i] = y[i] + h * acc
        rhs(t + _C[s] * h, y_stage, params, K[s])
    for i in range(n):
        acc = 0.0
        for j in range(_N_STAGES):
            acc += _B[j] * K[j, i]
        y_new[i] = y[i] + h * acc
    rhs(t + h, y_new, params, K[_N_STAGES])


@njit(cache=True)
def _error_norm(K, h, y, y_new, rtol, atol):
    """Scaled error of a step, DOP853's blend of the 5th- and 3rd-order estimates.

    Identical to scipy's ``DOP853._estimate_error_norm``: a step is accepted when < 1.
    """
    n = y.shape[0]
    err5 = 0.0
    err3 = 0.0
    for i in range(n):
        scale = atol[i] + max(abs(y[i]), abs(y_new[i])) * rtol
        e5 = 0.0
        e3 = 0.0
        for j in range(_N_STAGES + 1):
            e5 += _E5[j] * K[j, i]
            e3 += _E3[j] * K[j, i]
        e5 /= scale
        e3 /= scale
        err5 += e5 * e5
        err3 += e3 * e3
    if err5 == 0.0 and err3 == 0.0:
        return 0.0
    denom = err5 + 0.01 * err3
    return abs(h) * err5 / np.sqrt(denom * n)


@njit(inline="always")
def _dense_coefficients(rhs, params, t_old, h, y_old, y_new, K, F, y_stage):
    """Coefficients ``F`` (7 x n) of the 7th-order interpolant on [t_old, t_old + h].

    Evaluates the 3 extra stages into ``K[13:16]`` (3 rhs evaluations), as scipy's
    ``DOP853._dense_output_impl``; ``K[0]`` = f(t_old), ``K[12]`` = f(t_old + h).
    """
    n = y_old.shape[0]
    for s in range(_N_STAGES + 1, _N_STAGES_EXTENDED):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += _A[s, j] * K[j, i]
            y_stage[i] = y_old[i] + h * acc
        rhs(t_old + _C[s] * h, y_stage, params, K[s])
    for i in range(n):
        dy = y_new[i] - y_old[i]
        F[0, i] = dy
        F[1, i] = h * K[0, i] - dy
        F[2, i] = 2.0 * dy - h * (K[_N_STAGES, i] + K[0, i])
        for r in range(_INTERPOLATOR_POWER - 3):
            acc = 0.0
            for j in range(_N_STAGES_EXTENDED):
                acc += _D[r, j] * K[j, i]
            F[3 + r, i] = h * acc


@njit(cache=True)
def _dense_eval(F, y_old, x, out):
    """Interpolated state at ``x = (t - t_old) / h`` in [0, 1] (scipy's nested form)."""
    n = y_old.shape[0]
    for i in range(n):
        v = 0.0
        for r in range(_INTERPOLATOR_POWER - 1, -1, -1):
            v += F[r, i]
            # alternating factors x, 1-x, x, ... from the highest coefficient down
            if (_INTERPOLATOR_POWER - 1 - r) % 2 == 0:
                v *= x
            else:
                v *= 1.0 - x
        out[i] = y_old[i] + v


@njit(inline="always")
def _event_value(events, params, k, t, t_old, h, F, y_old, y_buf, g_buf):
    """g_k at time t on the interpolant of the current step."""
    _dense_eval(F, y_old, (t - t_old) / h, y_buf)
    events(t, y_buf, params, g_buf)
    return g_buf[k]


@njit(inline="always")
def _locate_root(events, params, k, t_a, t_b, g_a, g_b, t_old, h, F, y_old, y_buf, g_buf):
    """Root of g_k on [t_a, t_b] (g_a, g_b of opposite signs or zero) by Brent's method.

    A transcription of scipy's ``brentq`` (scipy/optimize/Zeros/brentq.c) working on the
    dense output, with xtol = rtol = 4 eps.
    """
    x_pre = t_a
    x_cur = t_b
    f_pre = g_a
    f_cur = g_b
    if f_pre == 0.0:
        return x_pre
    if f_cur == 0.0:
        return x_cur
    x_blk = 0.0
    f_blk = 0.0
    s_pre = 0.0
    s_cur = 0.0
    for _ in range(_ROOT_MAXITER):
        if f_pre != 0.0 and f_cur != 0.0 and (f_pre < 0.0) != (f_cur < 0.0):
            x_blk = x_pre
            f_blk = f_pre
            s_pre = x_cur - x_pre
            s_cur = s_pre
        if abs(f_blk) < abs(f_cur):
            x_pre = x_cur
            x_cur = x_blk
            x_blk = x_pre
            f_pre = f_cur
            f_cur = f_blk
            f_blk = f_pre
        delta = 0.5 * (_ROOT_XTOL + _ROOT_RTOL * abs(x_cur))
        s_bis = 0.5 * (x_blk - x_cur)
        if f_cur == 0.0 or abs(s_bis) < delta:
            return x_cur
        if abs(s_pre) > delta and abs(f_cur) < abs(f_pre):
            if x_pre == x_blk:
                s_try = -f_cur * (x_cur - x_pre) / (f_cur - f_pre)  # secant
            else:
                d_pre = (f_pre - f_cur) / (x_pre - x_cur)
                d_blk = (f_blk - f_cur) / (x_blk - x_cur)
                s_try = -f_cur * (f_blk * d_blk - f_pre * d_pre) / (
                    d_blk * d_pre * (f_blk - f_pre)
                )  # inverse quadratic interpolation
            if 2.0 * abs(s_try) < min(abs(s_pre), 3.0 * abs(s_bis) - delta):
                s_pre = s_cur
                s_cur = s_try
            else:
                s_pre = s_bis
                s_cur = s_bis
        else:
            s_pre = s_bis
            s_cur = s_bis
        x_pre = x_cur
        f_pre = f_cur
        if abs(s_cur) > delta:
            x_cur += s_cur
        elif s_bis > 0.0:
            x_cur += delta
        else:
            x_cur -= delta
        f_cur = _event_value(events, params, k, x_cur, t_old, h, F, y_old, y_buf, g_buf)
    return x_cur


@njit(cache=True)
def _event_triggered(g_old, g_new, direction):
    """scipy's ``find_active_events`` rule for one event: a sign change allowed by direction."""
    up = g_old <= 0.0 and g_new >= 0.0
    down = g_old >= 0.0 and g_new <= 0.0
    if direction > 0:
        return up
    if direction < 0:
        return down
    return up or down


# --- The integrator ---------------------------------------------------------------------------


@njit(inline="always")
def dop853(
    rhs,
    events,
    params,
    t0,
    y0,
    t_end,
    t_out,
    y_out,
    out_start,
    event_direction,
    t_breaks,
    rtol,
    atol,
    max_step,
    first_step,
    max_steps,
):
    """Integrate dy/dt = rhs(t, y) from t0 to t_end with DOP853, dense output and events.

    :func:`dop853_monitored` without a step monitor; see it for the parameters.
    """
    return dop853_monitored(rhs, events, no_monitor, params, t0, y0, t_end, t_out, y_out, out_start,
                            event_direction, t_breaks, rtol, atol, max_step, first_step, max_steps)


@njit(inline="always")
def _read_event_signs(events, params, event_direction, n_ev, t_old, t_new, h, y, y_new, F, y_stage, g_old, g_new,
                      in_window, read_in_step, frac):
    """Event functions at the end of an accepted step, and where the step's signs start.

    Inside a call's restart window (see the loop) the signs are read at its end,
    ``t_old + frac h`` on the interpolant ``F`` (built by the caller when
    ``read_in_step``); a step wholly inside it reports nothing. Returns ``(t_a,
    any_event)``: where the signs were read and whether an event changed sign.
    Shared by :func:`dop853_monitored` and :func:`pipeline.dynamics.integrators.dopri5.dopri5_monitored`.
    """
    t_a = t_old
    any_event = False
    if n_ev > 0:
        events(t_new, y_new, params, g_new)
        if read_in_step:
            t_a = t_old + frac * h
            _dense_eval(F, y, frac, y_stage)
            events(t_a, y_stage, params, g_old)
        elif in_window:
            g_old[:] = g_new  # the whole step is inside the restart window
        for k in range(n_ev):
            if _event_triggered(g_old[k], g_new[k], event_direction[k]):
                any_event = True
    return t_a, any_event


@njit(inline="always")
def _earliest_event(events, params, event_direction, n_ev, t_a, t_new, t_old, h, F, y, y_stage, g_old, g_new,
                    g_buf):
    """Roots of the triggered events on the interpolant; the earliest wins: ``(index or -1, time)``."""
    event_index = -1
    t_ev = np.inf
    for k in range(n_ev):
        if not _event_triggered(g_old[k], g_new[k], event_direction[k]):
            continue
        t_root = _locate_root(
            events, params, k, t_a, t_new, g_old[k], g_new[k],
            t_old, h, F, y, y_stage, g_buf,
        )
        if t_root < t_ev:
            t_ev = t_root
            event_index = k
    return event_index, t_ev


@njit(inline="always")
def _outputs_until(F, y, t_old, h, t_stop, y_stop, t_out, y_out, out_i, m):
    """Output rows of the step up to ``t_stop`` (inclusive) on the interpolant; a row exactly
    at ``t_stop`` is ``y_stop`` itself. Returns the next output index."""
    while out_i < m and t_out[out_i] <= t_stop:
        if t_out[out_i] == t_stop:
            y_out[out_i, :] = y_stop
        else:
            _dense_eval(F, y, (t_out[out_i] - t_old) / h, y_out[out_i])
        out_i += 1
    return out_i


@njit(inline="always")
def dop853_monitored(
    rhs,
    events,
    monitor,
    params,
    t0,
    y0,
    t_end,
    t_out,
    y_out,
    out_start,
    event_direction,
    t_breaks,
    rtol,
    atol,
    max_step,
    first_step,
    max_steps,
):
    """Integrate dy/dt = rhs(t, y) from t0 to t_end with DOP853, dense output and events.

    Call it from an ``@njit(cache=True)`` wrapper in the caller's module (see the module
    docstring); all arguments are positional.

    Parameters
    ----------
    rhs : numba-jitted function
        ``rhs(t, y, params, dydt_out)``; writes dy/dt into ``dydt_out``.
    events : numba-jitted function
        ``events(t, y, params, g_out)``; writes the event functions into ``g_out``.
        :func:`no_events` when ``event_direction`` is empty.
    monitor : numba-jitted function
        ``monitor(t, y, params, g)``, called once per accepted step with the state at its
        end (at the event, for the step that ends on one) and the event functions' values
        there, and never at trial or interpolated points. It may update accumulators held
        in ``params`` (peaks of derived quantities, say, which the event functions often
        already hold): the steps do not depend on ``t_out``, so what it sees is the same
        for every output grid. :func:`no_monitor` for none.
    params : any numba-typable value
        Passed unchanged to ``rhs`` and ``events``.
    t0 : float
        Start time [s].
    y0 : float64[n]
        State at ``t0``.
    t_end : float
        End time [s], ``>= t0``.
    t_out : float64[m]
        Output times [s], increasing. Need not be aligned with anything.
    y_out : float64[m, n]
        Filled in place: ``y_out[i]`` is the state at ``t_out[i]`` for every
        ``i >= out_start`` with ``t_out[i] <= t`` reached (points at or before ``t0`` get
        ``y0``). Rows are interpolated with the 7th-order continuous extension.
    out_start : int
        First index of ``t_out`` to fill (``out_next`` of the previous phase, or 0).
    event_direction : float64[k]
        Per event: +1 triggers on g rising through 0, -1 on falling, 0 on both. Every event
        is terminal. Empty (length 0) for none.
    t_breaks : float64[b]
        Increasing times [s] that no step may cross, e.g. the sample times of a record that
        ``rhs`` interpolates linearly: there the rhs has a kink, which the error estimate
        (built for a smooth rhs) handles by many rejected, inaccurate steps. Empty for none;
        with none the steps are exactly scipy's.
    rtol : float
        Relative tolerance [1].
    atol : float or float64[n]
        Absolute tolerance, in the units of each state component.
    max_step : float
        Largest step [s]; ``np.inf`` for no bound.
    first_step : float
        First step [s]; ``<= 0`` to select it as scipy does (1 extra rhs evaluation).
    max_steps : int
        Give up (status -2) after this many accepted steps.

    Returns
    -------
    Dop853Result
        ``(status, t, y, event_index, nfev, n_accepted, n_rejected, out_next, n_out,
        h_next)``; see :data:`Dop853Result` and the ``STATUS_*`` codes.
    """
    n = y0.shape[0]
    n_ev = event_direction.shape[0]
    m = t_out.shape[0]

    # All work arrays of the call, allocated once here.
    y = np.empty(n)
    y[:] = y0
    y_new = np.empty(n)
    y_stage = np.empty(n)
    K = np.empty((_N_STAGES_EXTENDED, n))
    F = np.empty((_INTERPOLATOR_POWER, n))
    atol_v = np.empty(n)
    atol_v[:] = atol  # a scalar broadcasts; an array is copied
    g_old = np.full(n_ev, np.nan)  # NaN triggers nothing: no sign is ever read before it is set
    g_new = np.empty(n_ev)
    g_buf = np.empty(n_ev)

    t = t0
    out_i = out_start
    bad = (
        not (t_end >= t0)
        or y_out.shape[0] != m
        or y_out.shape[1] != n
        or out_start < 0
        or out_start > m
        or not (rtol > 0.0)
        or not (max_step > 0.0)
    )
    for i in range(n):
        if not (atol_v[i] >= 0.0):
            bad = True
    if bad:
        return Dop853Result(STATUS_BAD_INPUT, t, y, -1, 0, 0, 0, out_i, 0, 0.0)

    while out_i < m and t_out[out_i] <= t0:
        y_out[out_i, :] = y
        out_i += 1
    if t_end == t0:
        return Dop853Result(STATUS_END, t, y, -1, 0, 0, 0, out_i, out_i - out_start, 0.0)

    rhs(t, y, params, K[0])
    nfev = 1
    if first_step > 0.0:
        h_abs = first_step
    else:
        h_abs = _select_initial_step(
            rhs, params, t, y, K[0], t_end, max_step, rtol, atol_v, y_stage, K[1]
        )
        nfev += 1

    n_acc = 0
    n_rej = 0
    restart_end = t0  # end of the restart window, set by the first step (events only)
    status = STATUS_END
    event_index = -1
    n_breaks = t_breaks.shape[0]
    i_break = 0
    while t < t_end:
        if n_acc >= max_steps:
            status = STATUS_MAX_STEPS
            break
        # no step crosses a break point: the rhs may have a kink there
        while i_break < n_breaks and t_breaks[i_break] <= t:
            i_break += 1
        t_stop = t_end
        if i_break < n_breaks and t_breaks[i_break] < t_end:
            t_stop = t_breaks[i_break]
        # --- one accepted step, as scipy's RungeKutta._step_impl -------------------------
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        if h_abs > max_step:
            h_abs = max_step
        elif h_abs < min_step:
            h_abs = min_step
        rejected = False
        accepted = False
        t_new = t
        h = 0.0
        h_wanted = h_abs
        while not accepted:
            if not (h_abs >= min_step):  # also a NaN step (NaN in rhs or tolerances)
                break
            h_wanted = h_abs
            t_new = t + h_abs
            if t_new > t_stop:
                t_new = t_stop
            h = t_new - t
            h_abs = abs(h)
            _rk_step(rhs, params, t, y, h, K, y_stage, y_new)
            nfev += 12
            err = _error_norm(K, h, y, y_new, rtol, atol_v)
            if err < 1.0:
                if err == 0.0:
                    factor = _MAX_FACTOR
                else:
                    factor = min(_MAX_FACTOR, _SAFETY * err**_ERROR_EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                accepted = True
            else:
                factor = _SAFETY * err**_ERROR_EXPONENT
                if not (factor > _MIN_FACTOR):  # also when err is NaN: shrink, never NaN h
                    factor = _MIN_FACTOR
                h_abs *= factor
                rejected = True
                n_rej += 1
        if not accepted:
            status = STATUS_STEP_TOO_SMALL
            break
        if t_stop < t_end and t_new == t_stop and not rejected and h_abs < h_wanted:
            # A step shortened to end on a break says little about the step size the
            # solution allows; keep the step that was wanted (scipy has no breaks).
            h_abs = h_wanted
        n_acc += 1
        t_old = t

        # The interpolant costs 3 rhs evaluations: build it only for a step that holds an
        # output point before its end or a sign change of an event function.
        need_dense = out_i < m and t_out[out_i] < t_new
        # A call starts on the previous phase's event (the restart state, g ~ 0, its sign
        # rounding noise). The signs are first taken at the end of the restart window,
        # 1e-7 of the step the controller wanted (not of a first step cut short by a
        # break, which may be ~1e-9 long): the restart is not reported again while a
        # return to zero after the window still is. Steps inside the window report nothing.
        first_step_of_call = n_acc == 1
        if n_ev > 0 and first_step_of_call:
            # at a late time a tiny first step's window can round away (t + 1e-16 == t):
            # it still ends at least one float after the start, so the first step reads signs
            restart_end = max(t_old + _START_WINDOW * max(h, h_wanted), np.nextafter(t_old, np.inf))
        in_window = n_ev > 0 and t_old < restart_end
        read_in_step = in_window and t_new > restart_end
        if need_dense or read_in_step:
            _dense_coefficients(rhs, params, t_old, h, y, y_new, K, F, y_stage)
            nfev += 3
        # an uncut first step reads at exactly t_old + 1e-7 h
        frac = 0.0
        if read_in_step:
            frac = _START_WINDOW if (first_step_of_call and h_wanted <= h) else (restart_end - t_old) / h
        t_a, any_event = _read_event_signs(events, params, event_direction, n_ev, t_old, t_new, h, y, y_new, F,
                                           y_stage, g_old, g_new, in_window, read_in_step, frac)
        if any_event and not (need_dense or read_in_step):
            _dense_coefficients(rhs, params, t_old, h, y, y_new, K, F, y_stage)
            nfev += 3

        if any_event:
            event_index, t_ev = _earliest_event(events, params, event_direction, n_ev, t_a, t_new, t_old, h, F, y,
                                                y_stage, g_old, g_new, g_buf)
            if event_index >= 0:
                _dense_eval(F, y, (t_ev - t_old) / h, y_new)
                out_i = _outputs_until(F, y, t_old, h, t_ev, y_new, t_out, y_out, out_i, m)
                t = t_ev
                y[:] = y_new
                events(t, y, params, g_buf)
                monitor(t, y, params, g_buf)
                status = STATUS_EVENT
                break
        if n_ev > 0:
            g_old[:] = g_new

        # output grid points inside the step (the end point is y_new itself)
        out_i = _outputs_until(F, y, t_old, h, t_new, y_new, t_out, y_out, out_i, m)

        t = t_new
        y[:] = y_new
        monitor(t, y, params, g_new)
        K[0, :] = K[_N_STAGES]  # FSAL: f at the new point starts the next step

    return Dop853Result(
        status, t, y, event_index, nfev, n_acc, n_rej, out_i, out_i - out_start, h_abs
    )
