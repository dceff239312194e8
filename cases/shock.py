"""The shock case of paper 004 (Sec 4.3, Fig 7): a confined nickel bar struck at one end."""
from __future__ import annotations

import math

from interfaces import (Body, BoundaryCondition, Case, CaseError, InterfacePair, LinearInterface,
                        MieGruneisen, Rectangle)
from interfaces.analytic.hugoniot import ShockHugoniot


def shock_bar(impact_speed: float = 1.84e6, split: bool = False, length: float = 50.0,
              height: float = 2.5, mpm_cell: float = 0.25, mpm_ppc: int = 2, K: float = 188e3,
              G: float = 76e3, gamma0: float = 2.0, S1: float = 1.44, rho_g_cm3: float = 8.87,
              A1: float = 0.4, A2: float = 4.0, run: float = 0.85, shape: str = "b2") -> Case:
    """Shock in a confined nickel bar (004 Sec 4.3, Fig 7), plane strain.

    A ``length`` x ``height`` mm bar of Mie-Grueneisen nickel (004 Eq 51: K = 188 GPa,
    gamma0 = 2, S1 = 1.44, rho0 = 8.87 g/cm^3; the neo-Hookean shear of Eq 18 with G, 76 GPa
    for nickel, elastic: the project has no plasticity; artificial viscosity of Eq 52 with
    004's A1 = 0.4, A2 = 4.0) between frictionless walls at its top and bottom hits a rigid
    wall at its right end at ``impact_speed`` (mm/s; 004: 1840 m/s, 40 % of the bulk wave
    speed): the whole bar starts at that speed (the wall's frame; 004 drives the wall
    into the bar at rest, the same impact seen from the bar) and a plane shock runs
    leftwards into it. ``split``: the bar is two bodies joined at mid-length by a
    perfect interface (004's multimaterial run), else one body (single-material MPM).
    MPM: 004's 0.25 mm cells with 2 x 2 particles per cell, quadratic B-spline shape
    (``shape``), no damping, dt from the current wave speeds (cfl 0.4), run until the
    front has crossed ``run`` of the bar. Measurement: the shock front (mpm/shock_front.py):
    shock speed and the shocked longitudinal stress and pressure from the particles'
    stress histories. Reference: the Hugoniot of the same material (analytic model
    shock_hugoniot with its elastic neo-Hookean shear, u_p = impact_speed).
    """
    if not isinstance(split, bool):
        raise CaseError(f"split must be true or false, got {split!r}")
    if not 0.3 <= run < 1.0:
        raise CaseError(f"run must be in [0.3, 1) (the fraction of the bar the front crosses), got {run!r}")
    rho = rho_g_cm3 * 1e-9                       # g/cm^3 -> tonne/mm^3
    C0 = math.sqrt(K / rho)
    mat = MieGruneisen(C0=C0, S1=S1, gamma0=gamma0, G=G, rho=rho, A1=A1, A2=A2)
    hugoniot = ShockHugoniot(K=K, rho=rho, S1=S1, gamma0=gamma0, G=G)
    Us = hugoniot.state(impact_speed).shock_speed     # checks impact_speed too
    duration = run * length / Us
    if split:
        bodies = [Body("left", Rectangle(0.0, 0.0, 0.5 * length, height), "nickel"),
                  Body("right", Rectangle(0.5 * length, 0.0, 0.5 * length, height), "nickel")]
        interfaces = [InterfacePair("left", "right", LinearInterface(math.inf, math.inf))]
    else:
        bodies = [Body("bar", Rectangle(0.0, 0.0, length, height), "nickel")]
        interfaces = []
    bcs = [BoundaryCondition("fixed", "*", "xmax", ("x",), (0.0,)),
           BoundaryCondition("fixed", "*", "ymin", ("y",), (0.0,)),
           BoundaryCondition("fixed", "*", "ymax", ("y",), (0.0,))]
    return Case(
        name="shock_bar", analysis="plane_strain", thickness=1.0,
        description=f"004 Fig 7: nickel bar hitting a wall at {impact_speed / 1e3:g} m/s"
                    + (", split by a perfect interface" if split else ""),
        materials={"nickel": mat}, bodies=bodies, interfaces=interfaces,
        boundary_conditions=bcs,
        measurements={"shock_front": {"sample_every": duration / 200.0, "wall": "xmax"}},
        discretization={"mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "shape": shape,
                                "damping": "none", "cfl": 0.4, "max_time": duration,
                                "grid_anchor": "origin",
                                "initial_velocity": {b.name: [impact_speed, 0.0] for b in bodies}}},
        analytic={"model": "shock_hugoniot", "K": K, "rho": rho, "S1": S1, "gamma0": gamma0,
                  "G": G, "impact_speed": impact_speed, "impact": "wall"},
        reference="analytic",
    )
