"""The generated model's constants vector, computed without Numba.

``model_constants`` evaluates the generated parameter-only subexpressions (``_generated``'s
``free_constants``, ``tethered_constants``) as plain Python, once per parameter set, so that
the trim (``model.trim``) and the model classes get their constants without importing the
compiled stack. The compiled kernels (``kernels``) take the vector as an argument; the values
are those the compiled evaluation gives (``kernels`` compiles with the ``nnan``/``ninf``
flags only, which allow no reassociation: finite results equal strict IEEE evaluation).
"""

from __future__ import annotations

import numpy as np

from ..params import HelicopterParams
from . import _generated as gen

__all__ = ["model_constants"]


def model_constants(kind: str, helicopter: HelicopterParams) -> np.ndarray:
    """The constants vector c of the "free" or "tethered" generated functions (read-only).

    Parameters
    ----------
    kind : {"free", "tethered"}
        Which model's functions the vector is for.
    helicopter : HelicopterParams
        The helicopter's parameters (Tables II, III).

    Returns
    -------
    numpy.ndarray
        The constants, shape (``N_FREE_CONSTANTS``,) or (``N_TETHERED_CONSTANTS``,), not
        writeable.

    Raises
    ------
    ValueError
        A ``kind`` other than "free" or "tethered".
    """
    if kind == "tethered":
        c = np.empty(gen.N_TETHERED_CONSTANTS)
        gen.tethered_constants(helicopter.as_array(), c)
    elif kind == "free":
        c = np.empty(gen.N_FREE_CONSTANTS)
        gen.free_constants(helicopter.as_array(), c)
    else:
        raise ValueError(f"kind = {kind!r} is invalid; allowed: 'free' or 'tethered'")
    c.setflags(write=False)
    return c
