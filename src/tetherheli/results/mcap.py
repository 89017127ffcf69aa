"""A saved run as an MCAP file (``--format mcap``): its signals and a 3-D scene for Foxglove
or Rerun, written with the ``mcap`` package (Foxglove's reference writer) and read back by
``load_result``.

Topics, all JSON messages (``message_encoding`` "json") with JSON-Schema schemas, logged at
the sample's time t (ns from the run's start):

- ``/signals`` (schema ``tetherheli.Signals``): one message per sample holding every column
  of the run's CSV by name (``t`` [s], q1..q9, u1..u6, LN, inputs, TC, RC, Fw1..3, extras;
  SI units, listed with descriptions in the file's ``units`` and ``descriptions`` metadata);
  a non-finite value is null. ``load_result`` reads the run back from these messages.
- ``/tf`` (``foxglove.FrameTransform``): ``world`` (N, n3 up) -> ``base`` (the winch's base:
  base_n1..3, or NO; over a ship turned by the deck's roll, pitch and yaw) and ``world`` ->
  ``fuselage`` (F at the reference point O: O in N and F's attitude as a quaternion), per
  sample.
- ``/scene`` (``foxglove.SceneUpdate``): the deck and pad (frame ``base``) and the
  helicopter's body and rotor disc (frame ``fuselage``) once; per sample the tether
  (a line winch - P, or through a lumped chain's recorded nodes, coloured by tension) and the
  wind force on HO as an arrow (1 m per largest force of the run).

The schemas are written here from Foxglove's published message definitions (the fields this
file uses); the ``foxglove.*`` names make Foxglove draw the scene without configuration.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_path
from ..errors import ParameterError

__all__ = ["MCAP_TOPICS", "read_mcap_table", "tension_colour", "write_mcap"]

#: The topics of a run's MCAP file: signals, frame transforms, the 3-D scene.
MCAP_TOPICS = ("/signals", "/tf", "/scene")
_SLACK = 1e-9  # [N] a tension at or below this draws a slack (grey) tether
#: viridis at 0, 1/4, 1/2, 3/4, 1 (the figures' tension colours), linearly between
_TENSION_COLOURS = np.array(
    [
        [0.267, 0.005, 0.329],
        [0.229, 0.322, 0.546],
        [0.128, 0.567, 0.551],
        [0.369, 0.789, 0.383],
        [0.993, 0.906, 0.144],
    ]
)

_NUMBER = {"type": "number"}
_TIME = {
    "type": "object",
    "properties": {"sec": {"type": "integer", "minimum": 0}, "nsec": {"type": "integer"}},
}
_VECTOR = {"type": "object", "properties": {"x": _NUMBER, "y": _NUMBER, "z": _NUMBER}}
_QUATERNION = {
    "type": "object",
    "properties": {"x": _NUMBER, "y": _NUMBER, "z": _NUMBER, "w": _NUMBER},
}
_COLOUR = {"type": "object", "properties": {k: _NUMBER for k in "rgba"}}
_POSE = {"type": "object", "properties": {"position": _VECTOR, "orientation": _QUATERNION}}


def _primitive(**fields: Any) -> dict[str, Any]:
    return {"type": "array", "items": {"type": "object", "properties": fields}}


FRAME_TRANSFORM_SCHEMA: dict[str, Any] = {
    "title": "foxglove.FrameTransform",
    "description": "A transform between two reference frames in 3D space",
    "type": "object",
    "properties": {
        "timestamp": _TIME,
        "parent_frame_id": {"type": "string"},
        "child_frame_id": {"type": "string"},
        "translation": _VECTOR,
        "rotation": _QUATERNION,
    },
}
SCENE_UPDATE_SCHEMA: dict[str, Any] = {
    "title": "foxglove.SceneUpdate",
    "description": "An update to the entities displayed in a 3D scene",
    "type": "object",
    "properties": {
        "deletions": _primitive(timestamp=_TIME, type={"type": "integer"}, id={"type": "string"}),
        "entities": _primitive(
            timestamp=_TIME,
            frame_id={"type": "string"},
            id={"type": "string"},
            lifetime=_TIME,
            frame_locked={"type": "boolean"},
            metadata=_primitive(key={"type": "string"}, value={"type": "string"}),
            arrows=_primitive(
                pose=_POSE,
                shaft_length=_NUMBER,
                shaft_diameter=_NUMBER,
                head_length=_NUMBER,
                head_diameter=_NUMBER,
                color=_COLOUR,
            ),
            cubes=_primitive(pose=_POSE, size=_VECTOR, color=_COLOUR),
            spheres=_primitive(pose=_POSE, size=_VECTOR, color=_COLOUR),
            cylinders=_primitive(
                pose=_POSE,
                size=_VECTOR,
                bottom_scale=_NUMBER,
                top_scale=_NUMBER,
                color=_COLOUR,
            ),
            lines=_primitive(
                type={"type": "integer"},
                pose=_POSE,
                thickness=_NUMBER,
                scale_invariant={"type": "boolean"},
                points={"type": "array", "items": _VECTOR},
                color=_COLOUR,
                colors={"type": "array", "items": _COLOUR},
                indices={"type": "array", "items": {"type": "integer"}},
            ),
            triangles={"type": "array"},
            texts={"type": "array"},
            models={"type": "array"},
        ),
    },
}


def _signals_schema(units: dict[str, str], descriptions: dict[str, str]) -> dict[str, Any]:
    return {
        "title": "tetherheli.Signals",
        "description": "One sample of a tetherheli run: every recorded signal in SI units",
        "type": "object",
        "properties": {
            "timestamp": _TIME,
            **{
                name: {
                    "type": ["number", "null"],
                    "description": f"{descriptions.get(name, '')} [{units.get(name, '')}]",
                }
                for name in units
            },
        },
    }


def _stamp(t: float) -> dict[str, int]:
    ns = max(round(float(t) * 1e9), 0)
    return {"sec": ns // 1_000_000_000, "nsec": ns % 1_000_000_000}


def _number(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


def _vector(v: np.ndarray) -> dict[str, float | None]:
    return {"x": _number(v[0]), "y": _number(v[1]), "z": _number(v[2])}


def _quaternion(q: np.ndarray) -> dict[str, float | None]:
    return {"x": _number(q[0]), "y": _number(q[1]), "z": _number(q[2]), "w": _number(q[3])}


def _colour(rgb: Any, a: float = 1.0) -> dict[str, float]:
    return {"r": float(rgb[0]), "g": float(rgb[1]), "b": float(rgb[2]), "a": a}


_IDENTITY = {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}
_ORIGIN = {"x": 0.0, "y": 0.0, "z": 0.0}


def _pose(position: dict[str, Any] | None = None, orientation: dict[str, Any] | None = None):
    return {"position": position or _ORIGIN, "orientation": orientation or _IDENTITY}


def _entity(t: float, frame: str, name: str, **primitives: Any) -> dict[str, Any]:
    entity: dict[str, Any] = {
        "timestamp": _stamp(t),
        "frame_id": frame,
        "id": name,
        "lifetime": {"sec": 0, "nsec": 0},
        "frame_locked": True,
        "metadata": [],
    }
    for kind in ("arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts"):
        entity[kind] = primitives.get(kind, [])
    entity["models"] = []
    return entity


def tension_colour(tension: float, tension_max: float) -> np.ndarray:
    """The tether's colour at a tension: viridis from 0 to ``tension_max``, grey when slack.

    Parameters
    ----------
    tension : float
        The tension [N] (slack at or below 1e-9 N, or not finite: grey).
    tension_max : float
        The top of the scale [N].

    Returns
    -------
    numpy.ndarray, shape (3,)
        Red, green, blue in [0, 1].
    """
    if not math.isfinite(tension) or tension <= _SLACK:
        return np.array([0.6, 0.6, 0.6])
    x = min(max(tension / tension_max, 0.0), 1.0) * (len(_TENSION_COLOURS) - 1)
    i = min(int(x), len(_TENSION_COLOURS) - 2)
    return _TENSION_COLOURS[i] + (x - i) * (_TENSION_COLOURS[i + 1] - _TENSION_COLOURS[i])


def _x_to(direction: np.ndarray) -> np.ndarray:
    """The quaternion (x, y, z, w) turning +x onto the unit vector ``direction``."""
    dot = float(direction[0])
    if dot < -1.0 + 1e-9:
        return np.array([0.0, 0.0, 1.0, 0.0])
    q = np.array([0.0, -direction[2], direction[1], 1.0 + dot])  # (x cross d, 1 + x . d)
    return q / np.linalg.norm(q)


def _static_scene(t: float, helicopter: Any, colour: tuple[float, float, float]) -> dict:
    """The deck with its pad (frame ``base``) and the helicopter's body and rotor disc (frame
    ``fuselage``, about O), sent once."""
    deck = _entity(
        t, "base", "deck",
        cubes=[{"pose": _pose({"x": 0.0, "y": 0.0, "z": -0.05}), "size": {"x": 3.0, "y": 3.0,
                "z": 0.1}, "color": _colour((0.55, 0.59, 0.64))}],
        cylinders=[{"pose": _pose({"x": 0.0, "y": 0.0, "z": 0.005}), "size": {"x": 1.1, "y": 1.1,
                    "z": 0.01}, "bottom_scale": 1.0, "top_scale": 1.0,
                    "color": _colour((0.95, 0.76, 0.0))}],
    )  # fmt: skip
    mast = float(helicopter.d_O_MRO3)
    tail = float(helicopter.d_O_TRO1)
    body = _entity(
        t, "fuselage", "helicopter",
        cubes=[
            {"pose": _pose({"x": 0.05, "y": 0.0, "z": -0.1}),
             "size": {"x": 0.7, "y": 0.26, "z": 0.28}, "color": _colour(colour)},
            {"pose": _pose({"x": (tail - 0.3) / 2, "y": 0.0, "z": 0.0}),
             "size": {"x": abs(tail + 0.3), "y": 0.05, "z": 0.05}, "color": _colour(colour)},
        ],
        cylinders=[{"pose": _pose({"x": 0.0, "y": 0.0, "z": mast}),
                    "size": {"x": 1.8, "y": 1.8, "z": 0.01}, "bottom_scale": 1.0,
                    "top_scale": 1.0, "color": _colour(colour, 0.25)}],
    )  # fmt: skip
    return {"deletions": [], "entities": [deck, body]}


def _helicopter_params(configuration: dict[str, Any]) -> Any:
    from ..params import Params

    params = configuration.get("params")
    if isinstance(params, dict) and isinstance(params.get("helicopter"), dict):
        return Params.from_mapping({"helicopter": params["helicopter"]}).helicopter
    return Params.paper().helicopter


def _optional_mcap() -> Any:
    try:
        import mcap.writer
    except ImportError:
        raise ImportError(
            "mcap is needed for this format and is not installed: pip install mcap "
            "(or tetherheli[replay])"
        ) from None
    return mcap.writer


def write_mcap(
    path: str | Path,
    columns: dict[str, np.ndarray],
    units: dict[str, str],
    descriptions: dict[str, str],
    configuration: dict[str, Any],
    *,
    tethered: bool,
) -> Path:
    """Write a run as MCAP, atomically (the module's topics; needs the ``mcap`` package).

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write.
    columns : dict of str to numpy.ndarray
        The run's columns (``SimulationResult.columns``, ``t`` first) [SI units].
    units, descriptions : dict of str to str
        Column name -> unit, and -> description.
    configuration : dict
        The run's configuration (its name, its helicopter's parameters).
    tethered : bool
        Whether the run has a tether to draw.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    from scipy.spatial.transform import Rotation

    from ..model.kinematics import helicopter_points

    writer_module = _optional_mcap()
    n = len(columns["t"])
    t = np.asarray(columns["t"], dtype=float)
    base = np.zeros((n, 3))
    if all(f"base_n{i}" in columns for i in (1, 2, 3)):
        base = np.column_stack([columns[f"base_n{i}"] for i in (1, 2, 3)])
    deck = np.tile([0.0, 0.0, 0.0, 1.0], (n, 1))  # a level deck; over a ship its tilt
    if all(f"deck_{a}" in columns for a in ("roll", "pitch", "yaw")):
        tilt = np.column_stack([columns[f"deck_{a}"] for a in ("roll", "pitch", "yaw")])
        level = np.all(np.isfinite(tilt), axis=1)
        deck[level] = Rotation.from_euler("xyz", tilt[level]).as_quat()
    position = np.column_stack([columns[k] for k in ("q1", "q2", "q3")])
    angles = np.column_stack([columns[k] for k in ("q4", "q5", "q6")])
    helicopter = _helicopter_params(configuration)
    pts = helicopter_points(position, angles, helicopter)
    rotation = pts.N_R_F
    quaternions = np.full((n, 4), np.nan)
    ok = np.all(np.isfinite(rotation), axis=(1, 2))
    if np.any(ok):
        quaternions[ok] = Rotation.from_matrix(rotation[ok]).as_quat()
    ho = pts.N_p_HO + base
    origin = pts.N_p_O + base
    attach = pts.N_p_P + base
    nodes = 0
    while all(f"node{nodes}_n{a}" in columns for a in (1, 2, 3)):
        nodes += 1
    tension = np.asarray(columns["TC"], dtype=float)
    taut = tension[np.isfinite(tension) & (tension > _SLACK)]
    tension_max = max(float(taut.max()), 2.0 * float(np.median(taut))) if taut.size else 1.0
    wind = np.column_stack([columns[k] for k in ("Fw1", "Fw2", "Fw3")])
    wind_norm = np.linalg.norm(wind, axis=1)
    finite_wind = wind_norm[np.isfinite(wind_norm)]
    wind_max = float(finite_wind.max()) if finite_wind.size else 0.0
    colour = (0.12, 0.47, 0.71) if tethered else (0.84, 0.15, 0.16)  # the figures' colours

    def dumps(value: Any) -> bytes:
        return json.dumps(value, allow_nan=False, separators=(",", ":")).encode("utf-8")

    names = list(columns)
    values = np.column_stack([np.asarray(columns[k], dtype=float) for k in names])
    with atomic_path(Path(path)) as tmp, open(tmp, "wb") as stream:
        writer = writer_module.Writer(stream)
        writer.start(profile="", library="tetherheli")
        schema = {
            "signals": _signals_schema(units, descriptions),
            "tf": FRAME_TRANSFORM_SCHEMA,
            "scene": SCENE_UPDATE_SCHEMA,
        }
        channel = {}
        for topic, key in zip(MCAP_TOPICS, ("signals", "tf", "scene"), strict=True):
            sid = writer.register_schema(
                name=schema[key]["title"], encoding="jsonschema", data=dumps(schema[key])
            )
            channel[key] = writer.register_channel(
                topic=topic, message_encoding="json", schema_id=sid
            )
        writer.add_metadata("units", {k: units.get(k, "") for k in names})
        writer.add_metadata("descriptions", {k: descriptions.get(k, "") for k in names})
        writer.add_metadata(
            "run",
            {
                "name": str(configuration.get("name", "run")),
                "configuration": "tethered" if tethered else "free",
                "frames": "world (N, n3 up), base (the winch), fuselage (F at O)",
            },
        )
        for k in range(n):
            stamp = _stamp(t[k])
            ns = stamp["sec"] * 1_000_000_000 + stamp["nsec"]

            def log(key: str, message: dict[str, Any], ns: int = ns) -> None:
                writer.add_message(
                    channel_id=channel[key], log_time=ns, publish_time=ns, data=dumps(message)
                )

            row: dict[str, Any] = {"timestamp": stamp}
            row.update({name: _number(v) for name, v in zip(names, values[k], strict=True)})
            log("signals", row)
            for child, where, turn in (
                ("base", base[k], _quaternion(deck[k])),
                ("fuselage", origin[k], _quaternion(quaternions[k])),
            ):
                log(
                    "tf",
                    {
                        "timestamp": stamp,
                        "parent_frame_id": "world",
                        "child_frame_id": child,
                        "translation": _vector(where),
                        "rotation": turn,
                    },
                )
            scene = _static_scene(t[k], helicopter, colour) if k == 0 else None
            entities = scene["entities"] if scene else []
            if tethered:
                if nodes > 1:
                    chain = [
                        np.array([columns[f"node{i}_n{a}"][k] for a in (1, 2, 3)]) + base[k]
                        for i in range(nodes)
                    ]
                else:
                    chain = [base[k], attach[k]]
                line = {
                    "type": 0,  # LINE_STRIP
                    "pose": _pose(),
                    "thickness": 0.04,
                    "scale_invariant": False,
                    "points": [_vector(p) for p in chain],
                    "color": _colour(tension_colour(tension[k], tension_max)),
                    "colors": [],
                    "indices": [],
                }
                entities.append(_entity(t[k], "world", "tether", lines=[line]))
            arrows = []
            if wind_max > 0.0 and math.isfinite(wind_norm[k]) and wind_norm[k] > 1e-9:
                length = float(wind_norm[k] / wind_max)
                arrows.append(
                    {
                        "pose": _pose(_vector(ho[k]), _quaternion(_x_to(wind[k] / wind_norm[k]))),
                        "shaft_length": 0.8 * length,
                        "shaft_diameter": 0.04,
                        "head_length": 0.2 * length,
                        "head_diameter": 0.1,
                        "color": _colour((1.0, 0.55, 0.0)),
                    }
                )
            entities.append(_entity(t[k], "world", "wind", arrows=arrows))
            log("scene", {"deletions": [], "entities": entities})
        writer.finish()
    return Path(path)


def read_mcap_table(path: Path) -> tuple[list[str], np.ndarray]:
    """The header and values (rows x columns) of a run's MCAP file: its ``/signals``
    messages in order (null read as NaN).

    Parameters
    ----------
    path : pathlib.Path
        The run's ``<stem>.mcap``.

    Returns
    -------
    tuple of (list of str, numpy.ndarray)
        The column names and the values.

    Raises
    ------
    ParameterError
        Not a readable MCAP file of JSON ``/signals`` messages with the same fields.
    """
    _optional_mcap()
    from mcap.exceptions import McapError
    from mcap.reader import make_reader

    header: list[str] | None = None
    rows: list[list[float]] = []
    try:
        with open(path, "rb") as stream:
            for _, channel, message in make_reader(stream).iter_messages(topics=["/signals"]):
                if channel.message_encoding != "json":
                    raise ValueError(f"/signals encoded as {channel.message_encoding}")
                row = json.loads(message.data)
                row.pop("timestamp", None)
                if header is None:
                    header = list(row)
                elif list(row) != header:
                    raise ValueError(f"a message at {message.log_time} ns has other fields")
                rows.append([math.nan if v is None else float(v) for v in row.values()])
    except (OSError, McapError, ValueError, TypeError, AttributeError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ParameterError(
            "mcap", path.name, f"an MCAP file of /signals messages ({reason})", source=str(path)
        ) from None
    if header is None:
        return [], np.empty((0, 0))
    return header, np.array(rows, dtype=float).reshape(len(rows), len(header))
