"""Generate the numeric model code from the Kane derivation (``tetherheli derive``).

The generated module ``_generated.py`` holds plain-Python scalar functions (``math`` only, a
fixed argument order, array parameters, results written into caller-owned arrays) that Numba
compiles in ``dynamics.py``. SymPy never runs inside a simulation.

Argument order of every generated function: ``(x, inp, wind, tension, c, out...)`` with
x (12,) the model state (q, u), inp (4,) = [fMR3, tMR1, tMR2, fTR2] [N, N m], wind (3,) the
wind force on HO in N [N], tension TC [N], c the model's constants: every parameter-only
subexpression, computed once by ``<model>_constants(p, c)`` from the helicopter parameters
p (14,) in ``params.PARAM_ORDER``.
"""

from __future__ import annotations

import re
from pathlib import Path

import sympy as sp
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.pycode import PythonCodePrinter

from .._io import atomic_write_text
from .derive import Derivation, Kinematics, derive, kinematics

__all__ = ["GENERATED_PATH", "generate_source", "write_generated"]

GENERATED_PATH = Path(__file__).with_name("_generated.py")


class _ProductPowers:
    """Print integer powers as products (fast, exact in Numba)."""

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.as_base_exp()
        if exp.is_Integer and 1 < abs(int(exp)) <= 4:
            prod = "*".join([f"({self._print(base)})"] * abs(int(exp)))
            return prod if exp > 0 else f"1.0/({prod})"
        return super()._print_Pow(expr, rational=rational)


class _Printer(_ProductPowers, PythonCodePrinter):
    """Print ``math.sin`` etc. and integer powers as products."""


class _ArrayPrinter(_ProductPowers, NumPyPrinter):
    """Print ``numpy.sin`` etc. and integer powers as products: the function runs on floats
    in Numba and on arrays in NumPy (each q[i] a row of samples)."""


class _ConstantPool:
    """Hoists every parameter-only subexpression into a constant c[k], computed once per
    parameter set by ``<model>_constants(p, c)`` instead of at every evaluation."""

    def __init__(self, params: tuple[sp.Symbol, ...]) -> None:
        self.params = frozenset(params)
        self.index: dict[sp.Expr, sp.Symbol] = {}

    def _is_constant(self, e: sp.Expr) -> bool:
        return e.free_symbols <= self.params

    def _const(self, e: sp.Expr) -> sp.Expr:
        if e.is_Number:
            return e
        if e not in self.index:
            self.index[e] = sp.Symbol(f"c[{len(self.index)}]")
        return self.index[e]

    def _split(self, term: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
        """term = coefficient * rest, the coefficient parameter-only."""
        if self._is_constant(term):
            return term, sp.S.One
        if term.is_Mul:
            const = [a for a in term.args if self._is_constant(a)]
            rest = [a for a in term.args if not self._is_constant(a)]
            return sp.Mul(*const), sp.Mul(*rest)
        return sp.S.One, term

    def hoist(self, e: sp.Expr) -> sp.Expr:
        if self._is_constant(e):
            return self._const(e)
        if e.is_Add:
            # collect: c_a x + c_b x -> (c_a + c_b) x, one hoisted constant per distinct x
            groups: dict[sp.Expr, list[sp.Expr]] = {}
            for term in e.args:
                coeff, rest = self._split(term)
                groups.setdefault(rest, []).append(coeff)
            return sp.Add(
                *(self._const(sp.Add(*cs)) * self.hoist(rest) for rest, cs in groups.items())
            )
        if e.is_Mul:
            const = [a for a in e.args if self._is_constant(a)]
            rest = [self.hoist(a) for a in e.args if not self._is_constant(a)]
            if const:
                rest.insert(0, self._const(e.func(*const)))
            return e.func(*rest)
        if e.args:
            return e.func(*[self.hoist(a) for a in e.args])
        return e

    def definitions(self) -> list[tuple[sp.Symbol, sp.Expr]]:
        return [(sym, expr) for expr, sym in self.index.items()]


_ELEMENT = re.compile(r"\b(x|sc|inp|wind|c)\[(\d+)\]|\btension\b")


def _lane_element(match: re.Match) -> str:
    """``x[3]`` -> ``x[3 * LANES + j]``, ``tension`` -> ``tension[j]``: the lane form's
    indexing of flat (variable, lane) arrays."""
    if match.group(1) is None:
        return "tension[j]"
    return f"{match.group(1)}[{match.group(2)} * LANES + j]"


def _emit(
    name: str,
    args: str,
    doc: str,
    outputs: list[tuple[str, sp.Matrix]],
    printer: _Printer,
    *,
    lanes: bool = False,
) -> str:
    """One generated function: CSE over all outputs, then element assignments.

    With ``lanes`` the same statements run for every lane j of flat arrays laid out
    (variable, lane), element (i, j) at i * LANES + j (``tension`` becomes an array), in one
    loop over the lanes with no branch and no call. LANES (``layout.LANES``) is a constant of
    the compiled code, so every offset is known to the compiler: it proves the arrays' rows
    apart and vectorises the loop with a handful of run-time alias checks.
    """
    flat = [e for _, mat in outputs for e in mat]
    replacements, reduced = sp.cse(flat, symbols=sp.numbered_symbols("t"), optimizations="basic")
    body = [f"{sym} = {printer.doprint(expr)}" for sym, expr in replacements]
    k = 0
    for out_name, mat in outputs:
        if out_name == "return":  # a scalar result
            body.append(f"return {printer.doprint(reduced[k])}")
            k += 1
            continue
        rows, cols = mat.shape
        for i in range(rows):
            for j in range(cols):
                index = f"{i}" if cols == 1 else f"{i}, {j}"
                if lanes:
                    index = f"{index} * LANES + j"
                body.append(f"{out_name}[{index}] = {printer.doprint(reduced[k])}")
                k += 1
    lines = [f"def {name}({args}):", f'    """{doc}"""']
    if lanes:
        lines.append("    for j in range(LANES):")
        lines.extend("        " + _ELEMENT.sub(_lane_element, line) for line in body)
    else:
        lines.extend("    " + line for line in body)
    return "\n".join(lines) + "\n"


def _substitutions(d: Derivation) -> tuple[dict, dict]:
    """(time functions and inputs -> array-element symbols, parameters -> p[i] symbols)."""
    subs = {}
    for i, s in enumerate((*d.q, *d.u)):
        subs[s] = sp.Symbol(f"x[{i}]")
    for i, s in enumerate(d.inputs):
        subs[s] = sp.Symbol(f"inp[{i}]")
    for i, s in enumerate(d.wind):
        subs[s] = sp.Symbol(f"wind[{i}]")
    subs[d.tension] = sp.Symbol("tension")
    params = {s: sp.Symbol(f"p[{i}]") for i, s in enumerate(d.params)}
    return subs, params


def _model_functions(d: Derivation, printer: _Printer) -> list[str]:
    subs, params = _substitutions(d)
    pool = _ConstantPool(d.params)
    rhs = sp.Matrix([*d.qdot, *d.udot])
    states = sp.Matrix([*d.q, *d.u])

    def prepared(mat: sp.Matrix) -> sp.Matrix:
        return mat.xreplace(subs).applyfunc(pool.hoist)

    args = "x, inp, wind, tension, c"
    k = d.kind
    specs = [
        (
            f"{k}_rhs",
            f"{args}, out",
            f"{k} model: out (12,) = d(q, u)/dt (eqs {'9-18' if k == 'free' else '10-12, 29-35'}).",
            [("out", rhs)],
        ),
        (
            f"{k}_jacobian",
            f"{args}, A, B, E_wind, E_tension",
            f"{k} model: Jacobians of {k}_rhs w.r.t. x (12, 12), inp (12, 4), wind (12, 3), "
            "tension (12,).",
            [
                ("A", rhs.jacobian(states)),
                ("B", rhs.jacobian(sp.Matrix(d.inputs))),
                ("E_wind", rhs.jacobian(sp.Matrix(d.wind))),
                ("E_tension", rhs.diff(d.tension)),
            ],
        ),
        (
            f"{k}_outputs",
            "x, c, out",
            f"{k} model: out (4,) = [q1, q2, q3, q6], HO in N and yaw (eqs 4, 43-45).",
            [("out", d.outputs)],
        ),
        (
            f"{k}_output_jacobian",
            "x, c, C",
            f"{k} model: C (4, 12) = d[q1, q2, q3, q6]/dx.",
            [("C", d.outputs.jacobian(states))],
        ),
    ]
    if k == "tethered":
        specs.append(
            (
                "tethered_tether_torque",
                "x, tension, c, out",
                "out (2,) = tether torque about HO on f1, f2 [N m] (the C1, C2 of eqs 33-34, 55).",
                [("out", d.tether_torque)],
            )
        )
    funcs = [
        _emit(name, fargs, doc, [(o, prepared(m)) for o, m in outs], printer)
        for name, fargs, doc, outs in specs
    ]
    if k == "tethered":
        # the same functions with sin/cos of the angles q4..q8 given in sc (10,) =
        # [sin x0..x4, cos x0..x4]: the engine gets them cheaply at the RK4 stages
        trig = {}
        for i in range(5):
            xi = sp.Symbol(f"x[{i}]")
            trig[sp.sin(xi)] = sp.Symbol(f"sc[{i}]")
            trig[sp.cos(xi)] = sp.Symbol(f"sc[{i + 5}]")
        for name, fargs, _, outs in specs:
            if name not in ("tethered_rhs", "tethered_outputs", "tethered_tether_torque"):
                continue
            funcs.append(
                _emit(
                    f"{name}_sc",
                    fargs.replace("x, ", "x, sc, ", 1),
                    f"{name} with sc (10,) = [sin x[0..4], cos x[0..4]] given.",
                    [(o, prepared(m).xreplace(trig)) for o, m in outs],
                    printer,
                )
            )
        # the right-hand side, the outputs and the tether's torque once more in the lane form
        # (``_emit(lanes=True)``): arrays laid out (variable, lane), sc given; the lane engine
        # advances a block of runs with the first and runs its control sample with the others
        lane_docs = {
            "tethered_rhs": "x (13 LANES,), sc (10 LANES,), inp (4 LANES,), wind (3 LANES,), "
            "tension (LANES,), c (n_c LANES,), out (13 LANES,) (rows 0-11 written).",
            "tethered_outputs": "x (13 LANES,), sc (10 LANES,), c (n_c LANES,), out (4 LANES,).",
            "tethered_tether_torque": "x (13 LANES,), sc (10 LANES,), tension (LANES,), "
            "c (n_c LANES,), out (2 LANES,).",
        }
        for name, fargs, _, outs in specs:
            if name not in lane_docs:
                continue
            funcs.append(
                _emit(
                    f"{name}_lanes",
                    fargs.replace("x, ", "x, sc, ", 1),
                    f"{name}_sc for every lane j of flat (variable, lane) arrays, element "
                    f"(i, j) at i * LANES + j: {lane_docs[name]}",
                    [(o, prepared(m).xreplace(trig)) for o, m in outs],
                    printer,
                    lanes=True,
                )
            )
    defs = pool.definitions()
    constants = _emit(
        f"{k}_constants",
        "p, c",
        f"{k} model: c ({len(defs)},) = the parameter-only subexpressions of the {k} "
        "functions, from the helicopter parameters p in PARAM_ORDER.",
        [("c", sp.Matrix([expr.xreplace(params) for _, expr in defs]))],
        printer,
    )
    # the pool numbered c[i] in order of appearance: assignments c[i] = ... match
    header = f"N_{k.upper()}_CONSTANTS = {len(defs)}\n"
    return [header, constants, *funcs]


def _kinematics_functions(kin: Kinematics, printer: _ArrayPrinter) -> list[str]:
    """The geometry of ``derive.kinematics`` as functions that take floats (Numba) or arrays
    (NumPy, samples along the last axis). Argument order ``(q, [p | altitude, arm], out)``."""
    q = kin.q
    euler = {q[3 + i]: sp.Symbol(f"q[{i}]") for i in range(3)}  # q = [q4, q5, q6]
    free = {q[i]: sp.Symbol(f"q[{i}]") for i in range(6)}  # q = [q1, ..., q6]
    tethered = {q[3 + i]: sp.Symbol(f"q[{i}]") for i in range(6)}  # q = [q4, ..., q9]
    params = {s: sp.Symbol(f"p[{i}]") for i, s in enumerate(kin.params)}
    specs = [
        (
            "kinematics_dcm",
            "q, R",
            "R (3, 3) = N.dcm(F) at q = [q4, q5, q6]: column j holds f_j in N (Table I).",
            [("R", kin.dcm.xreplace(euler))],
        ),
        (
            "kinematics_points",
            "q, p, out",
            "out (5, 3) = HO, O, MRO, TRO, P from NO in N [m] at q = [q1, ..., q6] (eqs 2-4); "
            "p the helicopter parameters in PARAM_ORDER.",
            [("out", kin.points.xreplace({**free, **params}))],
        ),
        (
            "kinematics_tethered_HO",
            "q, arm, out",
            "out (3,) = HO in N [m] at the tethered coordinates q = [q4, ..., q9] (eqs 27, "
            "43-45); arm = dO-P,3 - dO-HO,3 [m].",
            [("out", kin.tethered_HO.xreplace(tethered))],
        ),
        (
            "kinematics_tether_length",
            "q, altitude, arm",
            "q9 [m] from eq 45 given the altitude q3 of HO [m], q = [q4, ..., q9] (q9 unused); "
            "arm = dO-P,3 - dO-HO,3 [m] (Sec. IV-F).",
            [("return", sp.Matrix([kin.tether_length.xreplace(tethered)]))],
        ),
    ]
    # the tethered state x = [q4..q9, u1..u6, ...] with sin, cos of x[0..4] given in sc (10,),
    # as the engine's stages have them (``kernels.angle_trig``)
    state = {**tethered, **{u: sp.Symbol(f"x[{6 + i}]") for i, u in enumerate(kin.u)}}
    state = {s: sp.Symbol(str(v).replace("q[", "x[")) for s, v in state.items()}
    trig = {}
    for i in range(5):
        xi = sp.Symbol(f"x[{i}]")
        trig[sp.sin(xi)] = sp.Symbol(f"sc[{i}]")
        trig[sp.cos(xi)] = sp.Symbol(f"sc[{i + 5}]")
    point = {s: sp.Symbol(f"P[{i}]") for i, s in enumerate(kin.tether_point)}
    specs += [
        (
            "kinematics_tether_direction",
            "q, out",
            "out (3,) = c3, the unit tether direction in N, at q = [q4, ..., q9] (only q7, q8 "
            "used; eq 27).",
            [("out", kin.tether_direction.xreplace(tethered))],
        ),
        (
            "kinematics_tether_angles",
            "P, out",
            "out (3,) = (q7 [rad], q8 [rad], q9 [m]) of P (3,) from the winch in N [m]: the "
            "inverse of P = q9 c3 (eqs 27, 43-45), |q7|, |q8| < pi/2.",
            [("out", kin.tether_angles.xreplace(point))],
        ),
        (
            "kinematics_P_motion_sc",
            "x, sc, arm, out",
            "out (6,) = P = q9 c3 from the winch [m] and its velocity v_HO + w x (arm f3) in N "
            "[m/s] (eqs 7-8, 27, 43-45) at the tethered state x = [q4..q9, u1..u6, ...] with "
            "sc (10,) = [sin x[0..4], cos x[0..4]] given; arm = dO-P,3 - dO-HO,3 [m].",
            [("out", kin.P_motion.xreplace(state).xreplace(trig))],
        ),
    ]
    subs_symbols = {kin.arm: sp.Symbol("arm"), kin.altitude: sp.Symbol("altitude")}
    return [
        _emit(name, args, doc, [(o, m.xreplace(subs_symbols)) for o, m in outs], printer)
        for name, args, doc, outs in specs
    ]


def generate_source() -> str:
    """Derive both models and return the source text of ``_generated.py``.

    Returns
    -------
    str
        The module's source: the free and tethered model functions and the kinematics.
    """
    printer = _Printer({"fully_qualified_modules": True, "standard": "python3"})
    parts = [
        '"""Numeric model code generated by ``tetherheli derive`` from model/derive.py.\n\n'
        "Do not edit by hand: a test fails if this file and a fresh derivation disagree.\n"
        f"Generated with SymPy {sp.__version__}.\n"
        '"""\n\n'
        "# ruff: noqa\n"
        "import math\n\n"
        "import numpy\n\n"
        "from tetherheli.layout import LANES\n\n"
        f"SYMPY_VERSION = {sp.__version__!r}\n"
    ]
    for kind in ("free", "tethered"):
        for func in _model_functions(derive(kind), printer):
            parts.append("\n\n" + func)
    array_printer = _ArrayPrinter({"fully_qualified_modules": True})
    for func in _kinematics_functions(kinematics(), array_printer):
        parts.append("\n\n" + func)
    return "".join(parts)


def write_generated(path: Path = GENERATED_PATH) -> Path:
    """Regenerate the committed numeric code, atomically (the compiled code that uses it is
    recompiled on the next import: ``tetherheli._compile``).

    Parameters
    ----------
    path : pathlib.Path, optional
        The file to write (default ``GENERATED_PATH``, the package's ``_generated.py``).

    Returns
    -------
    pathlib.Path
        ``path``, written.
    """
    atomic_write_text(path, generate_source())
    return path
