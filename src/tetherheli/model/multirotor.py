"""The multirotor vehicle: parameters, RotorPy's state dictionary, hover trim, linearization.

``Multirotor`` is RotorPy 3.0.0's ``Multirotor`` (S. Folk et al., "RotorPy: a Python-based
multirotor simulator with aerodynamics for education and research", 2023) with a tether's
pull at a point P of the body. Frames (docs/multirotor.md): N inertial with n3 up and gravity
-g n3 (the paper's N and RotorPy's world frame); B the body, b3 along the rotor axes (thrust
+b3), RotorPy's body frame. The equations are Kane's (``multirotor_derive``), evaluated by the
compiled ``multirotor_kernels.multirotor_derivative``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, NamedTuple

import numpy as np

from .. import layout as L
from .._validation import check_bool, check_number, check_vector
from ..errors import InfeasibleError, ParameterError
from .multirotor_presets import MULTIROTOR_PRESETS

__all__ = ["MULTIROTOR_PRESETS", "Multirotor", "MultirotorTrim"]

_STATE_KEYS = ("x", "v", "q", "w", "rotor_speeds")


def _array(field_name: str, value: Any, shape: tuple[int, ...], allowed: str) -> np.ndarray:
    """``value`` as a finite float64 array of ``shape`` (-1: any length >= 1), read-only;
    else ParameterError naming ``field_name``."""
    try:
        a = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(field_name, value, allowed) from None
    ok = a.ndim == len(shape) and all(
        (n == -1 and m >= 1) or n == m for n, m in zip(shape, a.shape, strict=True)
    )
    if not ok or not np.all(np.isfinite(a)):
        raise ParameterError(field_name, value, allowed)
    a.setflags(write=False)
    return a


class MultirotorTrim(NamedTuple):
    """A hover equilibrium of the multirotor (``Multirotor.hover_trim``).

    Parameters
    ----------
    state : dict
        RotorPy's state dictionary at the equilibrium: x [m], v = 0 [m/s], q (x, y, z, w),
        w = 0 [rad/s], rotor_speeds [rad/s].
    rotor_speeds : numpy.ndarray, shape (n,)
        The rotor speeds, also the commanded speeds [rad/s].
    tether_force : numpy.ndarray, shape (3,)
        The tether's pull at P in N components [N].
    thrust : float
        The total thrust along b3 [N].
    """

    state: dict[str, np.ndarray]
    rotor_speeds: np.ndarray
    tether_force: np.ndarray
    thrust: float


@dataclass(frozen=True, eq=False)
class Multirotor:
    """A multirotor with n rotors along b3 (RotorPy 3.0.0's model), tethered at P.

    Parameters
    ----------
    mass : float
        m [kg], > 0.
    inertia : array_like, shape (3, 3)
        J about the centre of mass in body axes [kg m^2], symmetric positive definite.
    rotor_positions : array_like, shape (n, 3)
        Rotor hubs from the centre of mass in body axes [m], n >= 1.
    rotor_directions : array_like, shape (n,)
        +1 or -1 each: the sign of a rotor's yaw moment about b3 (RotorPy's
        ``rotor_directions``).
    k_eta : float
        Thrust coefficient: a rotor's thrust k_eta w^2 [N/(rad/s)^2], > 0.
    k_m : float
        Yaw-moment coefficient: a rotor's moment k_m w^2 [N m/(rad/s)^2], >= 0.
    tau_m : float
        The motors' first-order time constant [s], > 0.
    rotor_speed_min, rotor_speed_max : float
        Rotor speed limits [rad/s], 0 <= min < max: a command is clipped to them.
    drag : array_like, shape (3,), optional
        Parasitic drag c_Dx, c_Dy, c_Dz [N/(m/s)^2], >= 0: -|va| diag(c_D) va at the centre
        of mass, va the air's velocity relative to the body in B.
    k_d, k_z : float, optional
        Rotor drag in the rotor plane and induced inflow along b3 [N/(rad m/s^2)], >= 0.
    k_h : float, optional
        Translational lift [N/(m/s)^2], >= 0.
    k_flap : float, optional
        Flapping moment [N m/(rad m/s^2)], >= 0.
    aero : bool, optional
        True (RotorPy's default): the drag terms act; False: thrust and yaw moment only.
    tether_point : array_like, shape (3,), optional
        P, the tether's attachment, from the centre of mass in body axes [m]. Default the
        centre of mass, as in Tognon and Franchi (T-RO 2017) and Nicotra et al. (Automatica
        2017), where the cable pulls the robot's centre of mass.
    g : float, optional
        Gravity [m/s^2] (RotorPy's 9.81), > 0.
    """

    mass: float
    inertia: Any
    rotor_positions: Any
    rotor_directions: Any
    k_eta: float
    k_m: float
    tau_m: float
    rotor_speed_min: float
    rotor_speed_max: float
    drag: Any = (0.0, 0.0, 0.0)
    k_d: float = 0.0
    k_z: float = 0.0
    k_h: float = 0.0
    k_flap: float = 0.0
    aero: bool = True
    tether_point: Any = field(default=(0.0, 0.0, 0.0))
    g: float = 9.81

    def __post_init__(self) -> None:
        def put(name: str, value: Any) -> None:
            object.__setattr__(self, name, value)

        put("mass", check_number("mass", self.mass, low=0.0, low_open=True, unit="kg"))
        inertia = _array(
            "inertia", self.inertia, (3, 3), "a symmetric positive definite (3, 3) array [kg m^2]"
        )
        if not np.allclose(inertia, inertia.T, rtol=1e-12, atol=0.0) or np.any(
            np.linalg.eigvalsh(inertia) <= 0.0
        ):
            raise ParameterError(
                "inertia", self.inertia, "a symmetric positive definite (3, 3) array [kg m^2]"
            )
        put("inertia", inertia)
        positions = _array(
            "rotor_positions", self.rotor_positions, (-1, 3), "an (n, 3) array, n >= 1 [m]"
        )
        put("rotor_positions", positions)
        n = positions.shape[0]
        allowed = f"{n} entries of +1 or -1 (one per rotor of rotor_positions)"
        directions = _array("rotor_directions", self.rotor_directions, (n,), allowed)
        if not np.all(np.abs(directions) == 1.0):
            raise ParameterError("rotor_directions", self.rotor_directions, allowed)
        put("rotor_directions", directions)
        put("k_eta", check_number("k_eta", self.k_eta, low=0.0, low_open=True, unit="N/(rad/s)^2"))
        put("k_m", check_number("k_m", self.k_m, low=0.0, unit="N m/(rad/s)^2"))
        put("tau_m", check_number("tau_m", self.tau_m, low=0.0, low_open=True, unit="s"))
        put(
            "rotor_speed_min",
            check_number("rotor_speed_min", self.rotor_speed_min, low=0.0, unit="rad/s"),
        )
        put(
            "rotor_speed_max",
            check_number(
                "rotor_speed_max",
                self.rotor_speed_max,
                low=self.rotor_speed_min,
                low_open=True,
                unit="rad/s",
            ),
        )
        put("drag", check_vector("drag", self.drag, 3, low=0.0, unit="N/(m/s)^2"))
        for name, unit in (
            ("k_d", "N/(rad m/s^2)"),
            ("k_z", "N/(rad m/s^2)"),
            ("k_h", "N/(m/s)^2"),
            ("k_flap", "N m/(rad m/s^2)"),
        ):
            put(name, check_number(name, getattr(self, name), low=0.0, unit=unit))
        put("aero", check_bool("aero", self.aero))
        put("tether_point", check_vector("tether_point", self.tether_point, 3, unit="m"))
        put("g", check_number("g", self.g, low=0.0, low_open=True, unit="m/s^2"))

    # --- construction -----------------------------------------------------------------------
    @classmethod
    def from_rotorpy(
        cls,
        quad_params: Mapping[str, Any],
        *,
        aero: bool = True,
        tether_point: Sequence[float] = (0.0, 0.0, 0.0),
    ) -> Multirotor:
        """The vehicle of a RotorPy parameter dictionary, taken as is.

        Parameters
        ----------
        quad_params : mapping
            RotorPy's ``quad_params`` (``rotorpy/vehicles/*_params.py``): mass, Ixx ... Iyz,
            num_rotors, rotor_pos (a dict of (3,) positions [m]), rotor_directions, k_eta,
            k_m, tau_m, rotor_speed_min, rotor_speed_max and, optional (default 0), c_Dx,
            c_Dy, c_Dz, k_d, k_z, k_h, k_flap. Other keys (RotorPy's low-level gains, motor
            noise, IMU position) are ignored.
        aero : bool, optional
            RotorPy's ``Multirotor(..., aero=)``: the drag terms act (default True).
        tether_point : sequence of float, optional
            P from the centre of mass in body axes [m] (default the centre of mass).

        Returns
        -------
        Multirotor
            The vehicle.
        """

        def key(name: str) -> Any:
            if name not in quad_params:
                raise ParameterError(f"quad_params['{name}']", None, "a value (RotorPy's key)")
            return quad_params[name]

        I = [key(k) for k in ("Ixx", "Iyy", "Izz", "Ixy", "Iyz", "Ixz")]  # noqa: E741
        positions = key("rotor_pos")
        if isinstance(positions, Mapping):
            positions = [positions[k] for k in positions]
        n = key("num_rotors")
        try:
            n_given = len(positions)
        except TypeError:
            n_given = -1
        if n_given != n:
            raise ParameterError(
                "quad_params['num_rotors']", n, f"the number of rotor_pos entries ({n_given})"
            )
        return cls(
            mass=key("mass"),
            inertia=[[I[0], I[3], I[5]], [I[3], I[1], I[4]], [I[5], I[4], I[2]]],
            rotor_positions=positions,
            rotor_directions=key("rotor_directions"),
            k_eta=key("k_eta"),
            k_m=key("k_m"),
            tau_m=key("tau_m"),
            rotor_speed_min=key("rotor_speed_min"),
            rotor_speed_max=key("rotor_speed_max"),
            drag=tuple(quad_params.get(k, 0.0) for k in ("c_Dx", "c_Dy", "c_Dz")),
            k_d=quad_params.get("k_d", 0.0),
            k_z=quad_params.get("k_z", 0.0),
            k_h=quad_params.get("k_h", 0.0),
            k_flap=quad_params.get("k_flap", 0.0),
            aero=aero,
            tether_point=tether_point,
        )

    @classmethod
    def preset(cls, name: str, **options: Any) -> Multirotor:
        """A vehicle of ``MULTIROTOR_PRESETS`` (RotorPy 3.0.0's published parameter sets).

        Parameters
        ----------
        name : str
            "crazyflie", "hummingbird" or "px4_quadx".
        **options
            ``aero``, ``tether_point``: as for ``from_rotorpy``.

        Returns
        -------
        Multirotor
            The vehicle.
        """
        if name not in MULTIROTOR_PRESETS:
            raise ParameterError("preset", name, "one of " + ", ".join(MULTIROTOR_PRESETS))
        return cls.from_rotorpy(MULTIROTOR_PRESETS[name], **options)

    def replace(self, **changes: Any) -> Multirotor:
        """A copy with some fields changed (checked again).

        Parameters
        ----------
        **changes
            Field names and their new values.

        Returns
        -------
        Multirotor
            The new vehicle.
        """
        return dataclasses.replace(self, **changes)

    # --- derived values ---------------------------------------------------------------------
    @property
    def n_rotors(self) -> int:
        """The number of rotors n.

        Returns
        -------
        int
            n.
        """
        return int(self.rotor_positions.shape[0])

    @cached_property
    def allocation(self) -> np.ndarray:
        """The mixer's (4, n) matrix: rotor thrusts [N] -> [thrust N, moments about b1, b2,
        b3 N m] (RotorPy's ``f_to_TM``: rows 1, (r_i x b3)_1,2, dir_i k_m / k_eta).

        Returns
        -------
        numpy.ndarray, shape (4, n)
            The matrix (read-only).
        """
        r = self.rotor_positions
        a = np.vstack(
            (
                np.ones(self.n_rotors),
                r[:, 1],
                -r[:, 0],
                (self.k_m / self.k_eta) * self.rotor_directions,
            )
        )
        a.setflags(write=False)
        return a

    @cached_property
    def mixer(self) -> np.ndarray:
        """The (n, 4) map [thrust N, moment N m (3,)] -> rotor thrusts [N]: the inverse of
        ``allocation`` (RotorPy's ``TM_to_f``) for n = 4, its pseudo-inverse otherwise.

        Returns
        -------
        numpy.ndarray, shape (n, 4)
            The matrix (read-only).
        """
        a = self.allocation
        m = np.linalg.inv(a) if a.shape[1] == 4 else np.linalg.pinv(a)
        m.setflags(write=False)
        return m

    @cached_property
    def packed(self) -> np.ndarray:
        """The parameters packed for ``multirotor_derivative`` (slots ``layout.MR_*``).

        Returns
        -------
        numpy.ndarray, shape (MR_HEADER + 4 n,)
            The packed array (read-only).
        """
        n = self.n_rotors
        p = np.zeros(L.MR_HEADER + L.MR_ROTOR_COLUMNS * n)
        p[L.MR_MASS] = self.mass
        p[L.MR_G] = self.g
        p[L.MR_INERTIA : L.MR_INERTIA + 9] = self.inertia.ravel()
        p[L.MR_INERTIA_INV : L.MR_INERTIA_INV + 9] = np.linalg.inv(self.inertia).ravel()
        p[L.MR_TETHER_POINT : L.MR_TETHER_POINT + 3] = self.tether_point
        p[L.MR_DRAG : L.MR_DRAG + 3] = self.drag
        p[L.MR_K_ETA] = self.k_eta
        p[L.MR_K_M] = self.k_m
        p[L.MR_K_D] = self.k_d
        p[L.MR_K_Z] = self.k_z
        p[L.MR_K_H] = self.k_h
        p[L.MR_K_FLAP] = self.k_flap
        p[L.MR_TAU_M] = self.tau_m
        p[L.MR_SPEED_MIN] = self.rotor_speed_min
        p[L.MR_SPEED_MAX] = self.rotor_speed_max
        p[L.MR_AERO] = 1.0 if self.aero else 0.0
        p[L.MR_ROTORS] = n
        rows = p[L.MR_HEADER :].reshape(n, L.MR_ROTOR_COLUMNS)
        rows[:, L.MR_ROTOR_POSITION : L.MR_ROTOR_POSITION + 3] = self.rotor_positions
        rows[:, L.MR_ROTOR_DIRECTION] = self.rotor_directions
        p.setflags(write=False)
        return p

    # --- RotorPy's state dictionary ---------------------------------------------------------
    def pack_state(self, state: Mapping[str, Any]) -> np.ndarray:
        """RotorPy's state dictionary as the kernel's state vector (``layout.MRS_*``).

        Parameters
        ----------
        state : mapping
            x (3,) [m], v (3,) [m/s] in N, q (4,) (x, y, z, w) of B in N, w (3,) body rates
            [rad/s], rotor_speeds (n,) [rad/s]; other keys (RotorPy's wind) are ignored.

        Returns
        -------
        numpy.ndarray, shape (13 + n,)
            The state vector.
        """
        sizes = (3, 3, 4, 3, self.n_rotors)
        parts = []
        for k, size in zip(_STATE_KEYS, sizes, strict=True):
            if k not in state:
                raise ParameterError(f"state['{k}']", None, f"{size} finite numbers")
            parts.append(_array(f"state['{k}']", state[k], (size,), f"{size} finite numbers"))
        s = np.concatenate(parts)
        if not np.any(s[L.MRS_Q : L.MRS_Q + 4]):
            raise ParameterError("state['q']", state["q"], "a nonzero quaternion (x, y, z, w)")
        return s

    def unpack_state(self, s: np.ndarray) -> dict[str, np.ndarray]:
        """The kernel's state vector (or its derivative) as RotorPy's dictionary.

        Parameters
        ----------
        s : numpy.ndarray, shape (13 + n,)
            The vector (``layout.MRS_*``).

        Returns
        -------
        dict
            x, v, q, w, rotor_speeds (copies).
        """
        return {
            "x": s[L.MRS_X : L.MRS_X + 3].copy(),
            "v": s[L.MRS_V : L.MRS_V + 3].copy(),
            "q": s[L.MRS_Q : L.MRS_Q + 4].copy(),
            "w": s[L.MRS_W : L.MRS_W + 3].copy(),
            "rotor_speeds": s[L.MRS_ROTORS : L.MRS_ROTORS + self.n_rotors].copy(),
        }

    def derivative(
        self,
        s: np.ndarray,
        command: np.ndarray,
        wind: np.ndarray | None = None,
        tether_force: np.ndarray | None = None,
    ) -> np.ndarray:
        """ds/dt of the state vector (the compiled ``multirotor_derivative``, unchecked).

        Parameters
        ----------
        s : numpy.ndarray, shape (13 + n,)
            The state (``layout.MRS_*``).
        command : numpy.ndarray, shape (n,)
            Commanded rotor speeds [rad/s].
        wind : numpy.ndarray, shape (3,), optional
            The wind velocity in N [m/s] (default still air).
        tether_force : numpy.ndarray, shape (3,), optional
            The tether's pull at P in N [N] (default none).

        Returns
        -------
        numpy.ndarray, shape (13 + n,)
            ds/dt.
        """
        from .multirotor_kernels import multirotor_derivative

        # one compiled signature: p read-only, every other array a writable C-order copy
        state = np.array(s, dtype=np.float64)
        out = np.empty_like(state)
        multirotor_derivative(
            self.packed,
            state,
            np.array(command, dtype=np.float64),
            np.zeros(3) if wind is None else np.array(wind, dtype=np.float64),
            np.zeros(3) if tether_force is None else np.array(tether_force, dtype=np.float64),
            out,
        )
        return out

    def state_derivative(
        self,
        state: Mapping[str, Any],
        rotor_speed_command: Any,
        wind: Any = None,
        tether_force: Any = (0.0, 0.0, 0.0),
    ) -> dict[str, np.ndarray]:
        """The time derivative of RotorPy's state dictionary (``Multirotor._s_dot_fn``).

        Parameters
        ----------
        state : mapping
            RotorPy's state: x (3,) [m], v (3,) [m/s], q (4,) (x, y, z, w), w (3,) [rad/s],
            rotor_speeds (n,) [rad/s], optional wind (3,) [m/s] in N.
        rotor_speed_command : array_like, shape (n,)
            Commanded rotor speeds [rad/s], clipped to the rotors' limits.
        wind : array_like, shape (3,), optional
            The wind velocity in N [m/s]; default ``state['wind']`` if given, else still air.
        tether_force : array_like, shape (3,), optional
            The tether's pull at P in N components [N] (default none).

        Returns
        -------
        dict
            d/dt of x, v, q, w, rotor_speeds, and wind (zero, as RotorPy's).
        """
        s = self.pack_state(state)
        n = self.n_rotors
        cmd = _array("rotor_speed_command", rotor_speed_command, (n,), f"{n} finite numbers")
        if wind is None:
            wind = state.get("wind", (0.0, 0.0, 0.0))
        air = _array("wind", wind, (3,), "3 finite numbers [m/s]")
        pull = _array("tether_force", tether_force, (3,), "3 finite numbers [N]")
        d = self.unpack_state(self.derivative(s, cmd, air, pull))
        d["wind"] = np.zeros(3)
        return d

    # --- equilibrium and linearization ------------------------------------------------------
    def hover_trim(
        self,
        *,
        tension: float = 0.0,
        elevation: float = math.pi / 2,
        azimuth: float = 0.0,
        yaw: float = 0.0,
        position: Sequence[float] = (0.0, 0.0, 0.0),
    ) -> MultirotorTrim:
        """Hover in still air, free or on a taut tether (Tognon and Franchi, T-RO 2017, Sec. III;
        Nicotra et al., Automatica 2017).

        The tether from the winch reaches P at ``elevation`` above the horizontal, towards
        ``azimuth``, and pulls P back along itself with ``tension``: f_p = -T (cos e cos a,
        cos e sin a, sin e). At rest the thrust vector balances weight and pull,
        thrust b3 = m g n3 - f_p, so the vehicle tilts towards the winch's far side; its yaw
        about b3 is free (b1 from ``yaw`` as in Lee et al. 2010's desired attitude); the rotor
        thrusts balance that thrust and the pull's moment r_P x R^T f_p about the centre of
        mass (``mixer``).

        Parameters
        ----------
        tension : float, optional
            T >= 0 [N] (default 0: free hover).
        elevation : float, optional
            The tether's elevation e at P [rad] in [-pi/2, pi/2] (default pi/2: straight down).
        azimuth : float, optional
            The direction a from the winch to the vehicle, about n3 [rad] (default 0).
        yaw : float, optional
            The vehicle's heading [rad] (default 0).
        position : sequence of float, optional
            x [m] (default the origin).

        Returns
        -------
        MultirotorTrim
            State, rotor speeds, tether force and thrust.
        """
        from scipy.spatial.transform import Rotation

        T = check_number("tension", tension, low=0.0, unit="N")
        e = check_number("elevation", elevation, low=-math.pi / 2, high=math.pi / 2, unit="rad")
        a = check_number("azimuth", azimuth, unit="rad")
        psi = check_number("yaw", yaw, unit="rad")
        x = check_vector("position", position, 3, unit="m")
        f_p = -T * np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
        f = np.array([0.0, 0.0, self.mass * self.g]) - f_p
        thrust = float(np.linalg.norm(f))
        if thrust == 0.0:
            raise InfeasibleError("tension", tension, "a pull that leaves a thrust to give")
        b3 = f / thrust
        b2 = np.cross(b3, [math.cos(psi), math.sin(psi), 0.0])
        b2 /= np.linalg.norm(b2)
        R = np.column_stack((np.cross(b2, b3), b2, b3))
        moment = np.cross(np.asarray(self.tether_point), R.T @ f_p)
        rotor_thrust = self.mixer @ np.concatenate(([thrust], -moment))
        residual = self.allocation @ rotor_thrust - np.concatenate(([thrust], -moment))
        top = self.k_eta * self.rotor_speed_max**2
        bottom = self.k_eta * self.rotor_speed_min**2
        if (
            not np.allclose(residual, 0.0, atol=1e-12 * thrust)
            or np.any(rotor_thrust < bottom)
            or np.any(rotor_thrust > top)
        ):
            raise InfeasibleError(
                "tension",
                tension,
                f"a hover the rotors can hold (thrusts {np.round(rotor_thrust, 6).tolist()} N "
                f"outside [{bottom:g}, {top:g}] N or not allocatable)",
            )
        speeds = np.sqrt(rotor_thrust / self.k_eta)
        state = {
            "x": np.array(x),
            "v": np.zeros(3),
            "q": Rotation.from_matrix(R).as_quat(),
            "w": np.zeros(3),
            "rotor_speeds": speeds.copy(),
        }
        return MultirotorTrim(state, speeds, f_p, thrust)

    def linearize(
        self, trim: MultirotorTrim, *, step: float = 1e-6
    ) -> tuple[np.ndarray, np.ndarray]:
        """A, B of ds/dt ~ A ds + B dcmd about a trim, by central differences of the kernel,
        the tether force and the wind held.

        Parameters
        ----------
        trim : MultirotorTrim
            The equilibrium (``hover_trim``).
        step : float, optional
            The relative difference step (default 1e-6); each variable steps by
            step * max(1, |value|).

        Returns
        -------
        A : numpy.ndarray, shape (13 + n, 13 + n)
            d(ds/dt)/ds over ``layout.MRS_*`` (the quaternion's four components).
        B : numpy.ndarray, shape (13 + n, n)
            d(ds/dt)/dcmd [1/s].
        """
        h = check_number("step", step, low=0.0, low_open=True, high=1e-2)
        s0 = self.pack_state(trim.state)
        u0 = np.array(trim.rotor_speeds, dtype=np.float64)

        def jac(x0: np.ndarray, f: Any) -> np.ndarray:
            cols = []
            for i in range(x0.size):
                d = h * max(1.0, abs(x0[i]))
                up = x0.copy()
                dn = x0.copy()
                up[i] += d
                dn[i] -= d
                cols.append((f(up) - f(dn)) / (2 * d))
            return np.column_stack(cols)

        f_p = trim.tether_force
        A = jac(s0, lambda s: self.derivative(s, u0, None, f_p))
        B = jac(u0, lambda u: self.derivative(s0, u, None, f_p))
        return A, B
