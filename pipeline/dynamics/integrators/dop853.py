"""Compiled Dormand–Prince 8(5,3) integrator with dense output and terminal events.

A numba kernel of Hairer's DOP853 with the coefficients, error norm, step controller and
initial-step rule of :class:`scipy.integrate.DOP853` (so that at equal ``rtol``/``atol`` the
accuracy and the step counts match scipy's), and the 7th-order continuous extension
(3 extra stages, as scipy's ``Dop853DenseOutput``) to fill a caller-given output grid without
restricting the steps and to locate terminal events (Brent's method on the interpolant).

This module holds the method: its coefficient table (12 stages, the last one the next step's
first), the error estimate and the continuous extension. The steps, the step loop, break
points, restart window, output grid and events are the driver's, shared with DOPRI5
(:mod:`pipeline.dynamics.integrators.driver`, :mod:`pipeline.dynamics.integrators.events`);
its docstring gives the calling convention and how to call :func:`dop853` from a cached
wrapper. Everything is floats and arrays: the right-hand side, the event functions and
their parameters are supplied by the caller.

References
----------
.. [1] E. Hairer, S. P. Nørsett, G. Wanner, "Solving Ordinary Differential Equations I:
       Nonstiff Problems", 2nd ed., Springer, 1993, Sec. II.5 and II.6.
.. [2] scipy.integrate.DOP853 and scipy/integrate/_ivp/dop853_coefficients.py (BSD licence),
       whose coefficient table is reproduced below.
"""

import numpy as np
from numba import njit

from pipeline.dynamics.integrators.driver import (
    STATUS_BAD_INPUT,
    STATUS_END,
    STATUS_EVENT,
    STATUS_MAX_STEPS,
    STATUS_STEP_TOO_SMALL,
    Dop853Result,
    integrate,
    rk_stages,
)
from pipeline.dynamics.integrators.events import N_DENSE, no_events, no_monitor

__all__ = ["dop853", "dop853_monitored", "no_events", "no_monitor", "Dop853Result", "STATUS_END", "STATUS_EVENT",
           "STATUS_STEP_TOO_SMALL", "STATUS_MAX_STEPS", "STATUS_BAD_INPUT"]

_ERROR_ORDER = 7  # the blended error estimate is of order 7
_ERROR_EXPONENT = -1.0 / 8.0  # -1/(error estimator order + 1), the step controller's

# --- Coefficients of DOP853 (Hairer's dop853.f via scipy's dop853_coefficients.py) ---------
_N_STAGES = 12
_N_STAGES_EXTENDED = 16
_INTERPOLATOR_POWER = N_DENSE  # rows of the 7th-order extension, read by events.dense_eval

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


# --- The method's error estimate and continuous extension -------------------------------------


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
    rk_stages(_A, _C, _N_STAGES + 1, _N_STAGES_EXTENDED, rhs, params, t_old, y_old, h, K, y_stage)
    n = y_old.shape[0]
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


# --- The integrator ---------------------------------------------------------------------------


@njit(inline="always")
def dop853(rhs, events, params, t0, y0, t_end, t_out, y_out, out_start, event_direction, t_breaks,
           rtol, atol, max_step, first_step, max_steps):
    """Integrate dy/dt = rhs(t, y) from t0 to t_end with DOP853, dense output and events.

    :func:`dop853_monitored` without a step monitor; see it for the parameters.
    """
    return dop853_monitored(rhs, events, no_monitor, params, t0, y0, t_end, t_out, y_out, out_start,
                            event_direction, t_breaks, rtol, atol, max_step, first_step, max_steps)


@njit(inline="always")
def dop853_monitored(rhs, events, monitor, params, t0, y0, t_end, t_out, y_out, out_start, event_direction,
                     t_breaks, rtol, atol, max_step, first_step, max_steps):
    """Integrate dy/dt = rhs(t, y) from t0 to t_end with DOP853, dense output and events.

    Call it from an ``@njit(cache=True)`` wrapper in the caller's module (see
    :mod:`pipeline.dynamics.integrators.driver`); all arguments are positional.

    Parameters
    ----------
    rhs : numba-jitted function
        ``rhs(t, y, params, dydt_out)``; writes dy/dt into ``dydt_out``. Called 12 times
        per attempted step, 3 more when the step is interpolated.
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
        Passed unchanged to ``rhs``, ``events`` and ``monitor``.
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
        h_next)``; see :data:`~pipeline.dynamics.integrators.driver.Dop853Result` and the
        ``STATUS_*`` codes.
    """
    return integrate(_A, _B, _C, _N_STAGES, _N_STAGES_EXTENDED, _error_norm, _dense_coefficients,
                     _N_STAGES_EXTENDED - _N_STAGES - 1, _ERROR_ORDER, _ERROR_EXPONENT,
                     rhs, events, monitor, params, t0, y0, t_end, t_out, y_out, out_start, event_direction,
                     t_breaks, rtol, atol, max_step, first_step, max_steps)
