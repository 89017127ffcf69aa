"""Model parameters: the paper's Tables II and III, the rotor-drag arm, and the tension PI gains.

All parameter sets are frozen dataclasses; derived quantities (dO-HO,3, the K constants of
eqs 19-26) are properties, computed, never stored. ``Params.paper()`` returns the paper's set;
``Params.from_toml(path)`` or ``Params.paper().replace(...)`` override any field, strictly
validated.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Self

import numpy as np

from ._io import read_toml
from ._validation import Key, check_number, trusted
from .errors import InfeasibleError, ParameterError

__all__ = [
    "MAX_TETHER_STRAIN",
    "OFFSET_RANGE",
    "TETHER_LENGTH_RANGE",
    "HelicopterParams",
    "Params",
    "TensionControlParams",
    "TetherParams",
    "check_tether_length",
    "check_tether_strain",
]

#: Tether lengths [m] with a physical meaning for the model (q9, L0N): at least 0.5 m, so the
#: attachment point stays clear of the ground at hover; at most 1 km, beyond which a straight,
#: massless, linearly elastic tether (eq 28) is no longer a model of a real one.
TETHER_LENGTH_RANGE = (0.5, 1000.0)
#: Offsets of points of the helicopter from O [m] (eq 2, the rotor-drag arm): within 10 m,
#: the size of a small helicopter with a generous margin (Table II's are below 1.1 m).
OFFSET_RANGE = (-10.0, 10.0)
#: The tether's largest elastic elongation at hover as a fraction of its natural length LN:
#: q9 - LN <= MAX_TETHER_STRAIN LN. Eq 28's linear spring is a model of a real tether only
#: below it (tether fibres break at a few % to 30 % strain; even elastic cords stay near-linear
#: only up to about 100 %); beyond it LN shrinks to nothing and then goes negative.
MAX_TETHER_STRAIN = 1.0


def check_tether_length(value: Any, field: str = "q9", source: str | None = None) -> float:
    """A tether length checked against ``TETHER_LENGTH_RANGE``.

    Parameters
    ----------
    value : object
        The value to check (m).
    field : str, optional
        The name put in the error message (default ``"q9"``).
    source : str, optional
        Where the value came from (a file name), put in front of the message.

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        A value that is not a number in ``TETHER_LENGTH_RANGE``.
    """
    lo, hi = TETHER_LENGTH_RANGE
    allowed = f"a tether length in [{lo:g}, {hi:g}] m"
    return check_number(field, value, low=lo, high=hi, allowed=allowed, source=source)


def check_tether_strain(
    tension: float, EA: float, field: str, value: Any, source: str | None = None
) -> None:
    """Refuse a tether that ``tension`` [N] stretches by more than ``MAX_TETHER_STRAIN`` of
    its natural length at axial stiffness ``EA`` [N]: strain = tension / EA. This is the one
    rule of a physical tether in every model: the massless one (EA = K_C LN, eq 28,
    ``TetherParams.check_tension``), the lumped chain and the drum winch's.

    Parameters
    ----------
    tension : float
        The largest hover tension along the tether [N].
    EA : float
        Axial stiffness [N].
    field : str
        The user's field put in the error message.
    value : object
        Its value, as the user wrote it.
    source : str, optional
        Where the value came from (a file name), put in front of the message.

    Raises
    ------
    InfeasibleError
        Naming ``field``, with the smallest stiffness that holds ``tension``.
    """
    if not tension <= MAX_TETHER_STRAIN * EA:
        raise InfeasibleError(
            field,
            value,
            f"an axial stiffness EA >= {tension / MAX_TETHER_STRAIN:.6g} N: the hover "
            f"tension {tension:.6g} N would stretch the tether by {100 * tension / EA:.4g}% "
            f"of its natural length (at most {100 * MAX_TETHER_STRAIN:g}% for a physical "
            "tether)",
            source=source,
        )


def _meta(
    doc: str,
    *,
    positive: bool = False,
    nonzero: bool = False,
    nonnegative: bool = False,
    bounds: tuple[float, float] | None = None,
    default: float | None = None,
):
    """A parameter field: its documentation (unit in brackets) and its ``Key``, the one
    description the validation (``_Validated``) and the scenario reference use; ``default``
    gives the field a default value (None: none)."""
    low, high = bounds or (None, None)
    low_open = False
    if (positive or nonnegative) and (low is None or low <= 0.0):
        low, low_open = 0.0, positive
    unit = re.search(r"\[([^\]]+)\]", doc)
    key = Key(
        doc, unit.group(1) if unit else "", low=low, high=high, low_open=low_open,
        nonzero=nonzero,
    )  # fmt: skip
    if default is not None:
        return field(default=default, metadata={"doc": doc, "key": key})
    return field(metadata={"doc": doc, "key": key})


class _Validated:
    """Mixin: validate every float field of a frozen dataclass after construction, from the
    field's ``Key`` (``_meta``), with the package's one validation style."""

    def __post_init__(self) -> None:
        for f in fields(self):  # type: ignore[arg-type]
            object.__setattr__(self, f.name, self._check(f, getattr(self, f.name)))

    def _check(self, f: dataclasses.Field, value: Any) -> Any:
        """``value`` of field ``f`` checked against its ``Key``."""
        return f.metadata["key"].check(f"{self._section}.{f.name}", value)  # type: ignore[attr-defined]

    def _replaced(self, values: dict[str, Any]) -> Self:
        """A copy with ``values`` (field -> value) replaced: only they are checked (the
        others were, when this one was built); no values: this one."""
        if not values:
            return self
        new = {f.name: getattr(self, f.name) for f in fields(self)}  # type: ignore[arg-type]
        for f in fields(self):  # type: ignore[arg-type]
            if f.name in values:  # in field order: the first bad one named, as on construction
                new[f.name] = self._check(f, values[f.name])
        return trusted(type(self), **new)


@dataclass(frozen=True)
class HelicopterParams(_Validated):
    """Mechanical parameters of the helicopter (paper Table II, eqs 1-2, Sec. II-D).

    Parameters
    ----------
    g, m_F, m_MR, I_F11, I_F22, I_F33, I_MR11, omega_MR, d_O_FO3, d_O_MRO3, d_O_TRO1, d_O_P3
        Table II's values (``Params.paper()``).
        Each field's documentation and allowed range is its ``Key`` (``_meta``), printed
        in the scenario TOML reference (``docs/scenario_reference.md``).
    rotor_drag_arm, t_TR2
        The rotor drag torque per unit lift and the tail rotor's torque, implied by
        Tables IV-V and Sec. II-D (see docs/paper.md).
    """

    _section = "helicopter"

    g: float = _meta("gravity acceleration g [m/s^2] (Table II)", nonnegative=True)
    m_F: float = _meta("fuselage mass mF [kg] (Table II)", positive=True)
    m_MR: float = _meta("main-rotor mass mMR [kg] (Table II)", positive=True)
    I_F11: float = _meta("fuselage principal inertia IF11 [kg m^2] (Table II)", positive=True)
    I_F22: float = _meta("fuselage principal inertia IF22 [kg m^2] (Table II)", positive=True)
    I_F33: float = _meta("fuselage principal inertia IF33 [kg m^2] (Table II)", positive=True)
    I_MR11: float = _meta(
        "main-rotor inertia IMR11 [kg m^2]; the thin disc has 2 IMR11 about mr3 (eq 1)",
        positive=True,
    )
    omega_MR: float = _meta(
        "main-rotor angular speed relative to the fuselage, about f3, omegaMR [rad/s] (Table II)"
    )
    d_O_FO3: float = _meta(
        "f3 offset of the fuselage centre of mass FO from O [m] (eq 2)", bounds=OFFSET_RANGE
    )
    d_O_MRO3: float = _meta(
        "f3 offset of the rotor centre MRO from O [m] (eq 2)", bounds=OFFSET_RANGE
    )
    d_O_TRO1: float = _meta(
        "f1 offset of the tail rotor TRO from O [m] (eq 2)", nonzero=True, bounds=OFFSET_RANGE
    )
    d_O_P3: float = _meta(
        "f3 offset of the tether attachment P from O [m] (eq 2)", bounds=OFFSET_RANGE
    )
    rotor_drag_arm: float = _meta(
        "main-rotor drag torque per unit lift, tMR,3 = rotor_drag_arm * fMR,3 [m] "
        "(implied by Tables IV-V, see docs/paper.md)",
        positive=True,
        bounds=OFFSET_RANGE,
    )
    t_TR2: float = _meta("tail-rotor torque on the fuselage about f2, tTR,2 [N m] (Sec. II-D)")

    # --- derived quantities (never stored) -------------------------------------------------
    @property
    def m(self) -> float:
        """Total mass mF + mMR [kg]."""
        return self.m_F + self.m_MR

    @property
    def d_O_HO3(self) -> float:
        """f3 offset of the whole helicopter's centre of mass HO from O [m] (eq 3)."""
        return (self.m_F * self.d_O_FO3 + self.m_MR * self.d_O_MRO3) / self.m

    @property
    def mu(self) -> float:
        """Reduced mass mF mMR / (mF + mMR) [kg] (eqs 19-23)."""
        return self.m_F * self.m_MR / self.m

    @property
    def _mu_d2(self) -> float:
        return self.mu * (self.d_O_FO3 - self.d_O_MRO3) ** 2

    @property
    def K4p4(self) -> float:
        """Eq 19 [kg m^2]."""
        return self._mu_d2 + self.I_F11 + self.I_MR11

    @property
    def K456(self) -> float:
        """Eq 20 [kg m^2]."""
        return self._mu_d2 + self.I_F22 - self.I_F33 - self.I_MR11

    @property
    def K45(self) -> float:
        """Eq 21 [kg m^2/s]."""
        return -2.0 * self.I_MR11 * self.omega_MR

    @property
    def K5p5(self) -> float:
        """Eq 22 [kg m^2]."""
        return self._mu_d2 + self.I_F22 + self.I_MR11

    @property
    def K546(self) -> float:
        """Eq 23 [kg m^2]."""
        return -self._mu_d2 + self.I_F33 - self.I_F11 + self.I_MR11

    @property
    def K54(self) -> float:
        """Eq 24 [kg m^2/s]."""
        return 2.0 * self.I_MR11 * self.omega_MR

    @property
    def K6p6(self) -> float:
        """Eq 25 [kg m^2]."""
        return self.I_F33 + 2.0 * self.I_MR11

    @property
    def K645(self) -> float:
        """Eq 26 [kg m^2]."""
        return self.I_F11 - self.I_F22

    @property
    def tether_arm(self) -> float:
        """dO-P,3 - dO-HO,3 [m]: the f3 lever of the tether force about HO (eqs 33-34, 40)."""
        return self.d_O_P3 - self.d_O_HO3

    def as_array(self) -> np.ndarray:
        """The parameters in the fixed order of the generated code.

        Returns
        -------
        numpy.ndarray, shape (len(PARAM_ORDER),)
        """
        return np.array([getattr(self, n) for n in PARAM_ORDER], dtype=np.float64)


#: Order of the helicopter parameters in the array handed to the generated numeric code.
PARAM_ORDER: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(HelicopterParams))


@dataclass(frozen=True)
class TetherParams(_Validated):
    """Elastic tether and ground winch (paper Table III, eqs 28, 36-37) and its law.

    Two laws give the massless tether's tension TC from its length q9 and natural length LN
    (the one source of both; the engine's compiled twin is ``model.kernels.tether_tension``):

    - the paper's (eq 28), ``EA = 0``: TC = KC (q9 - LN), KC independent of the length;
    - the rope (issue 46), ``EA > 0``: TC = EA (q9 - LN) / LN, a stiffness EA / LN that grows
      as the tether is reeled in (the paper's hover: EA = KC L0N = 40 N/m x 9.375 m = 375 N).

    Both are slack (TC = 0) for q9 <= LN.

    Parameters
    ----------
    L_N0, K_C, EA
        Table III's values and the rope's axial stiffness (0: the paper's law). A scenario
        sets EA from ``[tether] law`` and ``EA`` (``scenario.tables.TetherSettings``).
        Each field's documentation and allowed range is its ``Key`` (``_meta``), printed
        in the scenario TOML reference (``docs/scenario_reference.md``).
    """

    _section = "tether"

    L_N0: float = _meta(
        "initial tether natural length L0N [m] (Table III)",
        positive=True,
        bounds=TETHER_LENGTH_RANGE,
    )
    K_C: float = _meta(
        "tether elasticity constant KC [N/m] (Table III; printed 'Nm', see docs/paper.md)",
        positive=True,
    )
    EA: float = _meta(
        "the rope law's axial stiffness EA [N] (TC = EA (q9 - LN) / LN); 0: the paper's law "
        "(eq 28, KC); set by a scenario's [tether] law and EA",
        nonnegative=True,
        default=0.0,
    )

    @property
    def law(self) -> str:
        """The tension law: "paper" (eq 28, EA = 0) or "rope" (EA > 0)."""
        return "rope" if self.EA > 0.0 else "paper"

    def tension(self, q9: float, natural_length: float) -> float:
        """The tension TC [N] at length q9 and natural length LN: KC (q9 - LN) (eq 28) or
        EA (q9 - LN) / LN (the rope) when taut, 0 when slack.

        Parameters
        ----------
        q9 : float
            Tether length [m].
        natural_length : float
            Natural length LN [m], > 0 for the rope.

        Returns
        -------
        float
            TC [N], >= 0.
        """
        stretch = q9 - natural_length
        if stretch <= 0.0:
            return 0.0
        # the compiled twin's arithmetic, bit for bit (the stiffness times the stretch)
        stiffness = self.EA / natural_length if self.EA > 0.0 else self.K_C
        return stiffness * stretch

    def natural_length(self, q9: float, tension: float) -> float:
        """The natural length LN [m] giving tension TC at length q9 (the trim's): eq 28's
        LN = q9 - TC / KC, or the rope's LN = q9 EA / (EA + TC).

        Parameters
        ----------
        q9 : float
            Tether length (m).
        tension : float
            Tension TC (N).

        Returns
        -------
        float
            The natural length LN (m) giving that tension at that length.
        """
        if self.EA > 0.0:
            return q9 * self.EA / (self.EA + tension)
        return q9 - tension / self.K_C

    def stiffness(self, q9: float, natural_length: float) -> tuple[float, float]:
        """The tension's partial derivatives at a taut state, for the linearizations: eq 28's
        (KC, -KC), the rope's (EA / LN, -EA q9 / LN^2).

        Parameters
        ----------
        q9 : float
            Tether length [m].
        natural_length : float
            Natural length LN [m], below q9 (taut).

        Returns
        -------
        dT_dq9 : float
            dTC/dq9 [N/m].
        dT_dLN : float
            dTC/dLN [N/m].
        """
        if self.EA > 0.0:
            return self.EA / natural_length, -self.EA * q9 / natural_length**2
        return self.K_C, -self.K_C

    def max_tension(self, q9: float) -> float:
        """The largest tension the tether gives at a length within ``MAX_TETHER_STRAIN``.

        Parameters
        ----------
        q9 : float
            Tether length (m).

        Returns
        -------
        float
            The tension (N) with LN = q9 / (1 + MAX_TETHER_STRAIN): KC (q9 - LN), or the
            rope's EA MAX_TETHER_STRAIN.
        """
        if self.EA > 0.0:
            return self.EA * MAX_TETHER_STRAIN
        return self.K_C * q9 * MAX_TETHER_STRAIN / (1.0 + MAX_TETHER_STRAIN)

    @property
    def _LN_text(self) -> str:
        """The law's trim natural length as a formula, for messages."""
        return "q9 EA/(EA + TC)" if self.EA > 0.0 else "q9 - TC/K_C"

    @property
    def _law_text(self) -> str:
        """The law in words, for messages."""
        if self.EA > 0.0:
            return f"a rope, EA = {self.EA:g} N"
        return f"K_C = {self.K_C:g} N/m"

    def check_tension(
        self, tension: float, q9: float, field: str, source: str | None = None
    ) -> None:
        """Refuse a hover tension the tether cannot give at length q9 (``max_tension``).

        Parameters
        ----------
        tension : float
            The hover tension (N).
        q9 : float
            Tether length (m).
        field : str
            The name put in the error message.
        source : str, optional
            Where the value came from (a file name), put in front of the message.

        Raises
        ------
        InfeasibleError
            Naming ``field``, with the largest allowed value.
        """
        limit = self.max_tension(q9)
        if tension > limit:
            raise InfeasibleError(
                field,
                tension,
                f"a tension <= {limit:.6g} N, the most this tether ({self._law_text}) "
                f"gives at q9 = {q9:g} m: above it the natural length LN = {self._LN_text} "
                f"= {self.natural_length(q9, tension):.4g} m would be below "
                f"q9/{1.0 + MAX_TETHER_STRAIN:g} (strain > {100 * MAX_TETHER_STRAIN:g}%)",
                source=source,
            )


@dataclass(frozen=True)
class TensionControlParams(_Validated):
    """Ground-winch tension PI controller (eq 56) and its reference (eq 40, Sec. VI).

    Parameters
    ----------
    T_ref, K_P, K_I
        The reference tension and the PI gains.
        Each field's documentation and allowed range is its ``Key`` (``_meta``), printed
        in the scenario TOML reference (``docs/scenario_reference.md``).
    """

    _section = "tension_control"

    T_ref: float = _meta("reference tether tension TrefC [N] (Sec. VI: 25 N)", nonnegative=True)
    K_P: float = _meta("proportional gain KP of eq 56 [m/(s N)]", nonnegative=True)
    K_I: float = _meta("integral gain KI of eq 56 [m/(s^2 N)]", nonnegative=True)


_PAPER_HELICOPTER = dict(
    g=9.81,
    m_F=12.0,
    m_MR=0.67,
    I_F11=0.6,
    I_F22=1.0,
    I_F33=1.0,
    I_MR11=0.1159,
    omega_MR=-141.37,
    d_O_FO3=-0.11,
    d_O_MRO3=0.166,
    d_O_TRO1=-1.08,
    d_O_P3=-0.3,
    rotor_drag_arm=0.1,
    t_TR2=0.0,
)
_PAPER_TETHER = dict(L_N0=9.375, K_C=40.0)
_PAPER_TENSION_CONTROL = dict(T_ref=25.0, K_P=1.0, K_I=0.1)


@dataclass(frozen=True)
class Params:
    """The full parameter set: helicopter (Table II), tether (Table III), tension control.

    Parameters
    ----------
    helicopter : HelicopterParams
        Mechanical parameters (Table II).
    tether : TetherParams
        Tether and winch (Table III).
    tension_control : TensionControlParams
        The winch's PI controller and reference tension (eq 56).
    """

    helicopter: HelicopterParams
    tether: TetherParams
    tension_control: TensionControlParams

    @classmethod
    def paper(cls) -> Self:
        """The paper's values (Tables II-III, KP = 1, KI = 0.1, TrefC = 25 N).

        Returns
        -------
        Params
        """
        return cls(  # the code's own constants: trusted (tests/test_validate_once.py checks them)
            helicopter=trusted(HelicopterParams, **_PAPER_HELICOPTER),
            tether=trusted(TetherParams, **_PAPER_TETHER),
            tension_control=trusted(TensionControlParams, **_PAPER_TENSION_CONTROL),
        )

    def replace(self, overrides: dict[str, Any] | None = None, **sections: dict[str, Any]) -> Self:
        """A copy with overridden fields, e.g. ``replace(tether={"K_C": 60.0})`` or
        ``replace({"tether.K_C": 60.0})``.

        Parameters
        ----------
        overrides : dict, optional
            ``"section.field"`` -> value.
        **sections : dict
            Section name -> ``{field: value}``.

        Returns
        -------
        Params

        Raises
        ------
        ParameterError
            An unknown section or key, or an invalid value.
        """
        merged: dict[str, dict[str, Any]] = {}
        for dotted, value in (overrides or {}).items():
            section, _, key = dotted.partition(".")
            if not key:
                raise ParameterError(dotted, value, "a key of the form section.field")
            merged.setdefault(section, {})[key] = value
        for section, values in sections.items():
            if not isinstance(values, dict):
                raise ParameterError(section, values, "a table of field = value")
            merged.setdefault(section, {}).update(values)
        return self._with(merged, source=None)

    def _with(self, merged: dict[str, dict[str, Any]], source: str | None) -> Self:
        kwargs = {}
        for f in fields(self):
            current = getattr(self, f.name)
            values = merged.pop(f.name, {})
            allowed = {g.name for g in fields(current)}
            for key in values:
                if key not in allowed:
                    raise ParameterError(
                        f"{f.name}.{key}", values[key], f"one of {sorted(allowed)}", source=source
                    )
            try:
                kwargs[f.name] = current._replaced(values)
            except ParameterError as exc:
                raise ParameterError(exc.field, exc.value, exc.allowed, source=source) from None
        if merged:
            name = next(iter(merged))
            raise ParameterError(
                name, merged[name], f"one of {[f.name for f in fields(self)]}", source=source
            )
        return type(self)(**kwargs)

    @classmethod
    def from_toml(cls, path: str | Path, *, base: Params | None = None) -> Self:
        """Load overrides of the paper's values from a TOML file.

        Parameters
        ----------
        path : str or pathlib.Path
            A TOML file with tables ``[helicopter]``, ``[tether]``, ``[tension_control]``.
        base : Params, optional
            The values to override (default ``Params.paper()``).

        Returns
        -------
        Params
        """
        return cls.from_mapping(read_toml(path), base=base, source=str(path))

    @classmethod
    def from_mapping(
        cls, data: dict[str, Any], *, base: Params | None = None, source: str | None = None
    ) -> Self:
        """Overrides from a nested mapping (the parsed form of the TOML file).

        Parameters
        ----------
        data : dict
            Section name -> ``{field: value}``.
        base : Params, optional
            The values to override (default ``Params.paper()``).
        source : str, optional
            Where the data came from (a file name), put in front of error messages.

        Returns
        -------
        Params
        """
        base = base if base is not None else cls.paper()
        merged: dict[str, dict[str, Any]] = {}
        for section, values in data.items():
            if not isinstance(values, dict):
                raise ParameterError(section, values, "a table of field = value", source=source)
            merged[section] = dict(values)
        return base._with(merged, source=source)  # type: ignore[return-value]

    def to_dict(self) -> dict[str, dict[str, float]]:
        """Plain nested dict (for recording a run's configuration).

        Returns
        -------
        dict of str to dict of str to float
        """
        return dataclasses.asdict(self)

    @staticmethod
    def field_docs() -> dict[str, str]:
        """The documentation of every parameter.

        Returns
        -------
        dict of str to str
            ``section.field`` -> the field's documentation (units and source).
        """
        out = {}
        for section_cls, section in (
            (HelicopterParams, "helicopter"),
            (TetherParams, "tether"),
            (TensionControlParams, "tension_control"),
        ):
            for f in fields(section_cls):
                out[f"{section}.{f.name}"] = f.metadata["doc"]
        return out
