"""The default ship's response amplitude operators (issue 46): the CSV shipped as
``src/tetherheli/base/data/default_ship_raos.csv``, computed with Capytaine.

Run: python benchmarks/ship_raos.py --print > src/tetherheli/base/data/default_ship_raos.csv
     python benchmarks/ship_raos.py --out FILE  (a new file, or one tetherheli wrote)

The hull: a box barge 50 m long, 8 m wide, 2.5 m draught, a patrol-vessel-like size (mass
rho L B T = 1.025e6 kg, sea water 1025 kg/m^3), its centre of gravity on the waterline
amidships (KG = 2.5 m: GM = KB + BM - KG = 1.25 + 2.133 - 2.5 = 0.883 m in closed form, 0.862 m
from Capytaine's hydrostatics of the mesh), radii of gyration
0.40 B in roll and 0.25 L in pitch and yaw. The centre of motion (the reference point of the
six degrees of freedom) is the centre of gravity, the origin of the ship's axes: x forward,
y to port, z up. Capytaine (a linear potential-flow boundary-element code, zero forward
speed, deep water) gives added mass, radiation damping and the wave excitation; a potential
flow has no viscous roll damping, so a linear roll damping of ``ROLL_DAMPING_RATIO`` of
critical is added at the roll natural frequency (B44 = 2 zeta sqrt(C44 (I44 + A44(w_n))),
the order of a hull with bilge keels, e.g. Himeno 1981); the box's free surge, sway and
yaw have no restoring and their RAOs are those of the unrestrained body. The headings
are ``tetherheli.base.ship``'s (0 head seas, 90 waves from port, 180 following), the phases
its convention (``RAO_HEADER``). A wrong argument is one line and exit 2, before anything
runs. About three minutes on two shared cores.
"""

from __future__ import annotations

import logging
import math
import sys
import warnings

import numpy as np

from tetherheli.base.ship import RAO_DOFS, RAO_HEADER, write_rao_csv
from tetherheli.cli._script import claim_file, run_script, script_parser, write_file

#: The hull's length, beam and draught [m]
LENGTH, BEAM, DRAUGHT = 50.0, 8.0, 2.5
#: Sea water's density [kg/m^3] and gravity [m/s^2]
RHO, G = 1025.0, 9.81
#: The mass [kg]: the displaced water
MASS = RHO * LENGTH * BEAM * DRAUGHT
#: The radii of gyration [m] about x, y, z through the centre of gravity
GYRATION = (0.40 * BEAM, 0.25 * LENGTH, 0.25 * LENGTH)
#: The roll damping added to the potential flow's, as a fraction of critical [-]
ROLL_DAMPING_RATIO = 0.10
#: The wave frequencies [rad/s] (40, evenly; wavelengths 1540 m to 9.1 m) and headings [deg]
FREQUENCIES = np.linspace(0.2, 2.6, 40)
HEADINGS = np.linspace(0.0, 180.0, 7)
#: The fixed-point iterations for the roll natural frequency from the added inertia
#: ``ROLL_ADDED_INERTIA`` x I44: the guess is the converged value (w_n = 0.797 rad/s, a
#: period of 7.9 s; iterated from A44 = 0 it settles at 0.30145 I44), so one iteration moves
#: w_n by less than 1e-5 and B44 by less than 1e-6 (measured when this was written)
ROLL_ITERATIONS = 1
ROLL_ADDED_INERTIA = 0.3015
#: An RAO below this is written as zero (the solver's round-off where symmetry gives none)
ZERO_RAO = 1e-9
#: The panels per metre of the mesh (panels of 0.8 m; at least six per wavelength at 2.6 rad/s)
PANELS_PER_M = 1.25


def hull():
    """The default ship's hull as a Capytaine floating body: the box's immersed part with its
    six rigid degrees of freedom about the centre of gravity (the origin), its mass, its
    inertia (``GYRATION``) and its hydrostatic stiffness.

    Returns
    -------
    capytaine.FloatingBody
    """
    import capytaine as cpt

    res = tuple(max(2, round(s * PANELS_PER_M)) for s in (LENGTH, BEAM, 2 * DRAUGHT))
    mesh = cpt.mesh_parallelepiped(size=(LENGTH, BEAM, 2 * DRAUGHT), center=(0, 0, 0),
                                   resolution=res, name="box")  # fmt: skip
    mesh = mesh.immersed_part()  # with a lid on the waterplane against irregular frequencies
    body = cpt.FloatingBody(
        mesh=mesh, lid_mesh=mesh.generate_lid(), mass=MASS, center_of_mass=(0, 0, 0),
        dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)), name="ship",
    )  # fmt: skip
    body.inertia_matrix = body.add_dofs_labels_to_matrix(
        np.diag([MASS, MASS, MASS, *(MASS * k**2 for k in GYRATION)])
    )
    body.hydrostatic_stiffness = body.compute_hydrostatic_stiffness(rho=RHO, g=G)
    return body


def ship_raos(frequencies: np.ndarray, headings: np.ndarray) -> np.ndarray:
    """The default ship's RAOs at ``frequencies`` x ``headings`` by Capytaine.

    Parameters
    ----------
    frequencies : numpy.ndarray, shape (m,)
        Wave frequencies [rad/s], > 0.
    headings : numpy.ndarray, shape (h,)
        Wave headings [deg] (``tetherheli.base.ship``: 0 head seas, 180 following).

    Returns
    -------
    numpy.ndarray, shape (m * h, 14)
        Rows of ``RAO_HEADER`` (frequency first, heading second, then amplitude and phase of
        each of ``RAO_DOFS``), frequency-major.
    """
    logging.getLogger("capytaine").setLevel(logging.ERROR)
    with warnings.catch_warnings():  # xarray's FutureWarnings on Capytaine's merges
        warnings.simplefilter("ignore", FutureWarning)
        return _solve(frequencies, headings)


def _solve(frequencies: np.ndarray, headings: np.ndarray) -> np.ndarray:
    """``ship_raos``'s work."""
    import capytaine as cpt
    import xarray as xr

    body = hull()
    # Capytaine's wave direction: where the waves travel, from x toward y; ours: where they
    # come from, from the bow toward port, so beta = heading + 180 deg
    beta = np.radians(np.asarray(headings, dtype=float) + 180.0)
    test = xr.Dataset(coords={"omega": np.asarray(frequencies, dtype=float),
                              "wave_direction": beta, "radiating_dof": list(body.dofs),
                              "water_depth": [np.inf], "rho": [RHO], "g": [G]})  # fmt: skip
    data = cpt.BEMSolver().fill_dataset(test, body, progress_bar=False)
    data["inertia_matrix"] = body.inertia_matrix
    data["hydrostatic_stiffness"] = body.hydrostatic_stiffness
    dissipation = body.add_dofs_labels_to_matrix(np.zeros((6, 6)))
    dissipation.loc["Roll", "Roll"] = roll_damping(body)
    rao = cpt.post_pro.rao(data, dissipation=dissipation)
    rao = rao.squeeze(
        [d for d in rao.dims if d not in ("omega", "wave_direction", "radiating_dof")]
    )
    rao = rao.transpose("omega", "wave_direction", "radiating_dof")
    names = dict(zip(RAO_DOFS, ("Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw"), strict=True))
    rows = []
    for i, w in enumerate(frequencies):
        for j, heading in enumerate(headings):
            row = [float(w), float(heading)]
            for dof in RAO_DOFS:
                value = complex(rao.sel(radiating_dof=names[dof]).values[i, j])
                if abs(value) < ZERO_RAO:  # e.g. sway, roll, yaw in head seas, by symmetry
                    value = 0j
                # Capytaine's time factor is exp(-i w t): x = |X| cos(w t - arg X)
                row += [abs(value), 0.0 - math.atan2(value.imag, value.real)]  # no -0
            rows.append(row)
    return np.array(rows)


def roll_damping(body) -> float:
    """The roll damping B44 [N m s/rad] of ``ROLL_DAMPING_RATIO`` of critical at the roll
    natural frequency w_n, where w_n^2 (I44 + A44(w_n)) = C44: found by the fixed-point
    iteration w <- sqrt(C44 / (I44 + A44(w))) from A44 = ``ROLL_ADDED_INERTIA`` I44,
    ``ROLL_ITERATIONS`` radiation problems of roll alone (so B44 does not depend on the
    frequencies asked for).

    Parameters
    ----------
    body : capytaine.FloatingBody
        The hull (``hull``).

    Returns
    -------
    float
        B44 = 2 zeta sqrt(C44 (I44 + A44(w_n))).
    """
    import capytaine as cpt

    i44 = float(body.inertia_matrix.sel(radiating_dof="Roll", influenced_dof="Roll"))
    c44 = float(body.hydrostatic_stiffness.sel(radiating_dof="Roll", influenced_dof="Roll"))
    solver, a44 = cpt.BEMSolver(), ROLL_ADDED_INERTIA * i44
    for _ in range(ROLL_ITERATIONS):
        problem = cpt.RadiationProblem(body=body, radiating_dof="Roll", rho=RHO, g=G,
                                       omega=math.sqrt(c44 / (i44 + a44)))  # fmt: skip
        a44 = float(solver.solve(problem).added_masses["Roll"])
    return 2 * ROLL_DAMPING_RATIO * math.sqrt(c44 * (i44 + a44))


def main(argv: list[str] | None = None) -> int:
    """Compute the RAOs and print them or write them to a file.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 done, 2 a wrong argument or a file that may not be written (one line, nothing
        run or written).
    """
    return run_script(__file__, _work, argv)


def _work(argv: list[str]) -> int:
    parser = script_parser(__file__, __doc__)
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--out", help="the CSV file to write (new, or one tetherheli wrote)")
    where.add_argument("--print", action="store_true", help="print the CSV instead")
    args = parser.parse_args(argv)
    if args.out:
        claim_file(args.out, option="--out")  # before the BEM's minute
    text = write_rao_csv(ship_raos(FREQUENCIES, HEADINGS))
    if args.print:
        sys.stdout.write(text)
    else:
        write_file(args.out, text.encode("ascii"), option="--out", writer="ship_raos.py")
        print(f"wrote {args.out} ({len(RAO_HEADER)} columns)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
