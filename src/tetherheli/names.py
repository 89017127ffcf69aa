"""Names and units of the model's variables: the one source that the model, results, plots,
reports and the command line use (notation: ``docs/notation.md``)."""

from __future__ import annotations

__all__ = [
    "BASE_ACCELERATION",
    "BASE_ACCELERATION_UNITS",
    "DEFAULT_METRIC",
    "FREE_STATE",
    "FREE_STATE_UNITS",
    "INPUT",
    "INPUT_UNITS",
    "METRIC_NAMES",
    "METRIC_UNITS",
    "MONTECARLO_METRICS",
    "OUTPUT",
    "OUTPUT_UNITS",
    "POSITION",
    "REEL_RATE",
    "REEL_RATE_UNITS",
    "TETHERED_STATE",
    "TETHERED_STATE_UNITS",
    "TETHER_STUDY_CABLES",
    "TETHER_STUDY_ELEVATIONS_DEG",
    "TETHER_STUDY_LENGTHS_M",
    "TETHER_STUDY_MODELS",
    "TETHER_STUDY_THRUST_TO_WEIGHT",
    "TETHER_STUDY_WINCH_GAINS",
    "TETHER_STUDY_WINDS_M_S",
    "UNITS",
    "WIND",
    "WIND_UNITS",
]

#: Tethered state (13,): q4..q6 body-123 Euler angles [rad], q7, q8 tether angles at the ground
#: [rad], q9 tether length [m], u1..u3 velocity of HO in N [m/s], u4..u6 angular velocity of F
#: in F [rad/s], LN the tether's natural length [m] (eqs 27-37).
TETHERED_STATE = ("q4", "q5", "q6", "q7", "q8", "q9", "u1", "u2", "u3", "u4", "u5", "u6", "LN")
TETHERED_STATE_UNITS = ("rad",) * 5 + ("m",) + ("m/s",) * 3 + ("rad/s",) * 3 + ("m",)
#: Free state (12,): q1..q3 position of HO in N [m], then q4..q6, u1..u6 as above (eqs 1-18).
FREE_STATE = ("q1", "q2", "q3", "q4", "q5", "q6", "u1", "u2", "u3", "u4", "u5", "u6")
FREE_STATE_UNITS = ("m",) * 3 + ("rad",) * 3 + ("m/s",) * 3 + ("rad/s",) * 3
#: Inputs (4,): main-rotor thrust, roll and pitch torques, tail-rotor thrust (Table I).
INPUT = ("fMR3", "tMR1", "tMR2", "fTR2")
INPUT_UNITS = ("N", "N m", "N m", "N")
#: Controlled outputs (4,): position of HO in N and the yaw angle (eqs 43-45).
OUTPUT = ("q1", "q2", "q3", "q6")
OUTPUT_UNITS = ("m", "m", "m", "rad")
#: The position outputs, whose deviations the metrics report.
POSITION = OUTPUT[:3]
#: The winch input of the tethered model: the reel rate RC = dLN/dt [m/s] (eq 37).
REEL_RATE = "RC"
REEL_RATE_UNITS = "m/s"
#: The disturbance inputs: the wind force on HO, N components [N] (Sec. VI).
WIND = ("Fw1", "Fw2", "Fw3")
WIND_UNITS = ("N",) * 3
#: a moving winch's acceleration b'' in N (the linearization's ``E_base`` columns)
BASE_ACCELERATION = ("ab1", "ab2", "ab3")
BASE_ACCELERATION_UNITS = ("m/s^2",) * 3
#: Unit of every name above (name -> unit).
UNITS: dict[str, str] = {
    **dict(zip(TETHERED_STATE, TETHERED_STATE_UNITS, strict=True)),
    **dict(zip(FREE_STATE, FREE_STATE_UNITS, strict=True)),
    **dict(zip(INPUT, INPUT_UNITS, strict=True)),
    REEL_RATE: REEL_RATE_UNITS,
    **dict(zip(WIND, WIND_UNITS, strict=True)),
    **dict(zip(BASE_ACCELERATION, BASE_ACCELERATION_UNITS, strict=True)),
}

#: Names of the metrics derived from a summary (``runs.batch.summary_metrics``), in table order.
METRIC_NAMES = (
    "peak_q1",
    "peak_q2",
    "peak_q3",
    "peak_q4_deg",
    "peak_q5_deg",
    "rms_q1",
    "rms_q2",
    "rms_q3",
    "tension_min",
    "tension_max",
    "n_samples",
)
#: Unit of every metric of ``METRIC_NAMES`` (deviations from the trim in m or deg, tensions).
METRIC_UNITS: dict[str, str] = {
    m: "N" if m.startswith("tension") else "deg" if m.endswith("_deg") else
    "1" if m == "n_samples" else "m"
    for m in METRIC_NAMES
}  # fmt: skip
#: The Monte Carlo table's metrics (``studies.montecarlo.runner.METRICS``): all but the count
MONTECARLO_METRICS = tuple(m for m in METRIC_NAMES if m != "n_samples")
#: The metric of every command that takes ``--metric`` when none is given (``sweep``, its
#: ``--find-min``, ``montecarlo``): the peak deviation along n1, the paper's first claim.
DEFAULT_METRIC = "peak_q1"

# The tether study's (``studies.tether_study``) choices and default grids, named here so that
# the command line's help builds without the study (which imports the lumped chain's compiled
# code); the study takes its defaults from these.
#: The keys of ``studies.tether_study.STUDY_CABLES``, in order (``--cables``).
TETHER_STUDY_CABLES: tuple[str, ...] = ("paper", "power", "data")
#: The tether models the dynamic half can fly (``--model``).
TETHER_STUDY_MODELS: tuple[str, ...] = ("lumped", "massless")
#: The winch gains the dynamic half can fly (``--winch-gain``).
TETHER_STUDY_WINCH_GAINS: tuple[str, ...] = ("paper", "scaled")
#: Default tether lengths q9 [m] (10-100 m), steady winds [m/s] and elevations of P seen from
#: the winch [deg] of the sensing half.
TETHER_STUDY_LENGTHS_M: tuple[float, ...] = (10.0, 20.0, 30.0, 50.0, 70.0, 100.0)
TETHER_STUDY_WINDS_M_S: tuple[float, ...] = (0.0, 2.5, 5.0, 7.5, 10.0)
TETHER_STUDY_ELEVATIONS_DEG: tuple[float, ...] = (60.0, 90.0)
#: The maximum main-rotor thrust as a multiple of the free hover thrust when none is given.
TETHER_STUDY_THRUST_TO_WEIGHT = 1.5
