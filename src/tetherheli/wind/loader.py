"""The strict loader: TOML-style tables -> disturbances, dispatching on the ``type`` key
and on the field annotations."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import MISSING, fields
from typing import Any

from .._validation import check_integer, check_number, check_vector
from ..errors import ParameterError
from .calibration import CalibratedGaussMarkovTurbulence
from .drag import DragModel
from .gusts import DrydenGust, GaussMarkovTurbulence
from .profiles import ConstantForce, Disturbance, NoWind, Pulse, Sine, Step, WindSum
from .turbulence import SteadyWind, Turbulence

__all__ = ["disturbance_from_dict"]


class _Missing:
    def __repr__(self) -> str:
        return "<missing>"


_MISSING_VALUE = _Missing()

_DISTURBANCES: dict[str, type] = {
    cls.type_name: cls
    for cls in (Pulse, Step, Sine, ConstantForce, NoWind, WindSum, Turbulence, SteadyWind)
}
_GUST_MODELS: dict[str, type] = {cls.type_name: cls for cls in (DrydenGust, GaussMarkovTurbulence)}


def _convert(kind: str, value: Any, where: str, source: str | None) -> Any:
    # types and finiteness here; each class checks its ranges in __post_init__
    if kind == "float":
        return check_number(where, value, source=source)
    if kind == "str":
        if not isinstance(value, str):
            raise ParameterError(where, value, "a string", source=source)
        return value
    if kind == "float | None":
        return check_number(where, value, source=source)
    if kind == "Vec3":
        return check_vector(where, value, 3, source=source)
    if kind == "int":
        return check_integer(where, value, source=source)
    if kind == "tuple[int, ...]":
        if not isinstance(value, (list, tuple)):
            raise ParameterError(where, value, "an array of integers", source=source)
        return tuple(
            check_integer(where, v, allowed="an array of integers", source=source) for v in value
        )
    if kind == "GustModel":
        return _build_typed(value, _GUST_MODELS, where, source)
    if kind == "DragModel":
        return _build(DragModel, value, where, source)
    if kind == "tuple[Disturbance, ...]":
        if not isinstance(value, (list, tuple)):
            raise ParameterError(where, value, "an array of disturbance tables", source=source)
        return tuple(
            _build_typed(v, _DISTURBANCES, f"{where}[{i}]", source) for i, v in enumerate(value)
        )
    raise AssertionError(f"no loader for field type {kind!r}")  # pragma: no cover


def _build(cls: type, spec: Any, where: str, source: str | None, *, typed: bool = False) -> Any:
    if not isinstance(spec, Mapping):
        raise ParameterError(where, spec, "a table (key = value)", source=source)
    init = {f.name: f for f in fields(cls) if f.init}
    allowed = set(init) | ({"type"} if typed else set())
    for key in spec:
        if key not in allowed:
            raise ParameterError(
                f"{where}.{key}", spec[key], f"a key among {sorted(allowed)}", source=source
            )
    kwargs = {}
    for name, f in init.items():
        if name not in spec:
            if f.default is MISSING and f.default_factory is MISSING:
                raise ParameterError(
                    f"{where}.{name}", _MISSING_VALUE, "a required key", source=source
                )
            continue
        kwargs[name] = _convert(str(f.type), spec[name], f"{where}.{name}", source)
    try:
        return cls(**kwargs)
    except ParameterError as exc:
        prefix = cls.__name__ + "."
        rest = exc.field[len(prefix) :] if exc.field.startswith(prefix) else exc.field
        raise ParameterError(f"{where}.{rest}", exc.value, exc.allowed, source=source) from None


def _build_typed(spec: Any, registry: dict[str, type], where: str, source: str | None) -> Any:
    if not isinstance(spec, Mapping):
        raise ParameterError(where, spec, "a table with a 'type' key", source=source)
    kind = spec.get("type", _MISSING_VALUE)
    if kind not in registry:
        raise ParameterError(f"{where}.type", kind, f"one of {sorted(registry)}", source=source)
    cls = registry[kind]
    if cls is GaussMarkovTurbulence and "calibration" in spec:
        cls = CalibratedGaussMarkovTurbulence
    return _build(cls, spec, where, source, typed=True)


def disturbance_from_dict(
    spec: Mapping[str, Any] | Sequence[Mapping[str, Any]],
    *,
    source: str | None = None,
    name: str = "wind",
) -> Disturbance:
    """Build a disturbance from a TOML-style table, strictly.

    Parameters
    ----------
    spec : mapping or sequence of mappings
        A table with a ``type`` key (``"pulse"``, ``"step"``, ``"sine"``, ``"constant"``,
        ``"none"``, ``"sum"``, ``"turbulence"``) and the class's fields, e.g.
        ``{"type": "pulse", "start": 10.0, "duration": 1.0, "magnitude": 20.0,
        "direction": [1, 0, 0]}``; a list of tables gives their ``WindSum``. A turbulence
        table holds a ``model`` table (``type`` ``"dryden"`` or ``"gauss_markov"``, the latter
        with ``gain`` and ``pole_rad_s`` or with a ``calibration`` and its inputs) and a
        ``drag`` table.
        ``Disturbance.to_dict()`` gives tables of this form.
    source : str, optional
        Where the table came from (a file name), passed to the errors.
    name : str, optional
        Prefix of field names in error messages (default ``"wind"``: ``wind[0].duration``).

    Returns
    -------
    Disturbance

    Raises
    ------
    ParameterError
        Unknown ``type``, unknown or missing keys, values of the wrong type or out of range;
        the error names the key.
    """
    if isinstance(spec, Mapping):
        return _build_typed(spec, _DISTURBANCES, name, source)
    if isinstance(spec, (list, tuple)):
        return WindSum(
            tuple(
                _build_typed(item, _DISTURBANCES, f"{name}[{i}]", source)
                for i, item in enumerate(spec)
            )
        )
    raise ParameterError(name, spec, "a table or an array of tables", source=source)
