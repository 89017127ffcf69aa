"""RotorPy 3.0.0's published multirotor parameter sets, in RotorPy's dictionary form.

Copied from the ``rotorpy`` wheel 3.0.0 (``rotorpy/vehicles/*_params.py``, MIT licence) so
that the presets need no RotorPy install; ``tests/test_multirotor.py`` compares them with the
installed package's dictionaries when it is present. Each set's sources, as RotorPy gives
them:

- ``crazyflie``: Bitcraze Crazyflie 2.0 (Forster, "System identification of the Crazyflie 2.0
  nano quadrocopter", ETH 2015; Eschmann et al. 2024, arXiv:2404.07837 for tau_m; k_eta from
  14.5 g of thrust at 2500 rad/s).
- ``hummingbird``: AscTec Hummingbird (RotorPy's default vehicle; k_d and k_z scaled down by
  ten by RotorPy's authors).
- ``px4_quadx``: PX4's SIH simulated quad-x (``10040_sihsim_quadx``: SIH_MASS, SIH_IXX, ...,
  k_eta = SIH_T_MAX / w_max^2, k_m = SIH_Q_MAX / w_max^2, tau_m = SIH_T_TAU).

Units: kg, kg m^2, m, N/(rad/s)^2, N m/(rad/s)^2, s, rad/s; drag as in ``layout.MR_*``.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Any

__all__ = ["MULTIROTOR_PRESETS"]

_S_ROTORPY = 0.70710678118  # RotorPy writes sqrt(1/2) so


def _x_rotors(d: float) -> dict[str, tuple[float, float, float]]:
    """RotorPy's quad-x rotor positions r1..r4 at arm length d [m]."""
    s = _S_ROTORPY
    return {
        "r1": (d * s, d * s, 0.0),
        "r2": (d * s, -d * s, 0.0),
        "r3": (-d * s, -d * s, 0.0),
        "r4": (-d * s, d * s, 0.0),
    }


_CRAZYFLIE: dict[str, Any] = {
    "mass": 0.03,
    "Ixx": 1.43e-5,
    "Iyy": 1.43e-5,
    "Izz": 2.89e-5,
    "Ixy": 0.0,
    "Iyz": 0.0,
    "Ixz": 0.0,
    "num_rotors": 4,
    "rotor_pos": _x_rotors(0.043),
    "rotor_directions": (1, -1, 1, -1),
    "c_Dx": 0.0,
    "c_Dy": 0.0,
    "c_Dz": 0.0,
    "k_eta": 2.3e-08,
    "k_m": 7.8e-10,
    "k_d": 10.2506e-07,
    "k_z": 7.553e-07,
    "k_h": 0.0,
    "k_flap": 0.0,
    "tau_m": 0.072,
    "rotor_speed_min": 0,
    "rotor_speed_max": 2500,
    "kp_att": 310,
    "kd_att": 57.0,
}

_HUMMINGBIRD: dict[str, Any] = {
    "mass": 0.500,
    "Ixx": 3.65e-3,
    "Iyy": 3.68e-3,
    "Izz": 7.03e-3,
    "Ixy": 0.0,
    "Iyz": 0.0,
    "Ixz": 0.0,
    "num_rotors": 4,
    "rotor_pos": _x_rotors(0.17),
    "rotor_directions": (1, -1, 1, -1),
    "c_Dx": 0.5e-2,
    "c_Dy": 0.5e-2,
    "c_Dz": 1e-2,
    "k_eta": 5.57e-06,
    "k_m": 1.36e-07,
    "k_d": 1.19e-04,
    "k_z": 2.32e-04,
    "k_h": 3.39e-3,
    "k_flap": 0.0,
    "tau_m": 0.005,
    "rotor_speed_min": 0,
    "rotor_speed_max": 1500,
    "kp_att": 544,
    "kd_att": 46.64,
}

_PX4_ARM = 0.17
_PX4_QUADX: dict[str, Any] = {
    "mass": 1.0,
    "Ixx": 0.025,
    "Iyy": 0.025,
    "Izz": 0.030,
    "Ixy": 0.0,
    "Ixz": 0.0,
    "Iyz": 0.0,
    "num_rotors": 4,
    "rotor_pos": {
        "r1": (_PX4_ARM, -_PX4_ARM, 0.0),
        "r2": (-_PX4_ARM, _PX4_ARM, 0.0),
        "r3": (_PX4_ARM, _PX4_ARM, 0.0),
        "r4": (-_PX4_ARM, -_PX4_ARM, 0.0),
    },
    "rotor_directions": (-1, -1, 1, 1),
    "c_Dx": 1e-2,
    "c_Dy": 1e-2,
    "c_Dz": 1e-2,
    "k_eta": 5e-6,
    "k_m": 1e-7,
    "k_d": 0.0,
    "k_z": 0.0,
    "k_h": 0.0,
    "k_flap": 0.0,
    "tau_m": 0.05,
    "rotor_speed_min": 0.0,
    "rotor_speed_max": 1000.0,
}

#: RotorPy 3.0.0's parameter dictionaries by preset name (read-only; ``Multirotor.preset``,
#: ``SE3Controller.preset``). px4_quadx has no attitude gains: RotorPy's SE3Control then
#: uses kp_att 310, kd_att 57.
MULTIROTOR_PRESETS = MappingProxyType(
    {
        "crazyflie": MappingProxyType(_CRAZYFLIE),
        "hummingbird": MappingProxyType(_HUMMINGBIRD),
        "px4_quadx": MappingProxyType(_PX4_QUADX),
    }
)
