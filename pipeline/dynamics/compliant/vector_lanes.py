"""LLVM's SLP vectoriser for the fixed-step loop of the compliant model, and for it alone.

numba compiles with LLVM's superword-level-parallelism (SLP) vectoriser off by default since its
0.57 (numba pull request #8852, after the miscompilations of its issues #8705 and #8681). The block
solve's updates are six independent multiply-subtracts a term
(:func:`pipeline.dynamics.compliant.linear_system.sparse_block_solve`), which the SLP vectoriser puts
side by side in vector lanes; without it they stay scalar, and the Parthenon's front runs about 6 %
slower (issue 48, speed: docs/model.md, "Then the block solve in vector lanes"). Without fast-math flags the vectoriser neither reassociates nor contracts,
so every number is the one the scalar code computes; that is checked, not assumed:
``benchmarks/check_bit_exact.py`` (every case the same to the bit with it and without) and
``tests/dynamics/compliant/test_vector_lanes.py`` (a frame's run compiled each way in a fresh
process, equal to the bit, and only one of them in vector lanes).

Only :func:`pipeline.dynamics.compliant.semi_implicit.run` is compiled with it, and with it
everything it calls (numba links the callees' code into its module and optimises that module
whole); the rigid kernels and the adaptive reference keep numba's default. A user's
``NUMBA_SLP_VECTORIZE``, either way, stands. A compilation numba finds in its cache is loaded as it
was compiled.
"""

import os

import numba
from numba.core import config
from numba.core.compiler_lock import global_compiler_lock

__all__ = ["compile_with_slp"]


def compile_with_slp(dispatcher, args):
    """Compile (or load from numba's cache) ``dispatcher`` for the types of ``args``, with LLVM's
    SLP vectoriser on unless the environment sets ``NUMBA_SLP_VECTORIZE``.

    Parameters
    ----------
    dispatcher : numba.core.registry.CPUDispatcher
        An ``@njit`` function.
    args : tuple
        Arguments of the types it will be called with (only their types are used).
    """
    if "NUMBA_SLP_VECTORIZE" in os.environ:
        return
    signature = tuple(numba.typeof(a) for a in args)
    # numba's own lock: no other thread compiles while the setting is changed (numba reads it as it
    # builds each module's optimisation passes)
    with global_compiler_lock:
        before = config.SLP_VECTORIZE
        config.SLP_VECTORIZE = 1
        try:
            dispatcher.compile(signature)
        finally:
            config.SLP_VECTORIZE = before
