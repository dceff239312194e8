"""The contact cases of paper 004 (MPM contact detection, Sec 2.2)."""
from __future__ import annotations

import math

from interfaces import (Body, BoundaryCondition, Case, CaseError, CoulombFriction, InterfacePair,
                        LinearInterface, NeoHookean, Rectangle)

#: contact method name -> the MPM options that select it (004 Fig 2's curves)
CONTACT_METHODS = {
    "velocity": {"normal": "AG", "separation": "velocity"},              # Eq 14 alone
    "CP0.92": {"normal": "AG", "separation": "offset", "contact_offset": 0.92},   # Eq 16-17
    "CP0.80": {"normal": "AG", "separation": "offset", "contact_offset": 0.80},
    "DF": {"normal": "AG", "separation": "DF"},                          # Eq 15
    "LR": {"normal": "LR", "separation": "LR"},                          # Eq 19-25
}


def gap_contact(contact: str = "DF", plane: str = "grid", gap: float = 7.5, width: float = 40.0,
                height: float = 50.0, mpm_cell: float = 5.0, mpm_ppc: int = 2, mu: float = 0.2,
                push: float = 5e-4, rho: float = 1.0e-9, K: float = 2450.0, G: float = 940.0) -> Case:
    """Two neo-Hookean blocks closing a gap (004 Sec 2.2, Fig 2), plane strain.

    Lower block ``width`` x ``height`` mm, fixed at its bottom; upper block of the same size
    ``gap`` above it, its top pushed down at ``push`` x the dilatational wave speed
    (0.05 %, quasi-static) by a rigid piston one cell thick bonded to it (a velocity
    condition on grid nodes stays where it is while the top moves away from it: after a
    cell of travel it no longer pushes); Coulomb friction ``mu`` (004: 0.2); K = 2450, G = 940 MPa
    (004 Eq 18). 004 gives "material dimensions 40 x 100 mm": read here as the two blocks
    together (each 40 x 50); the contact time does not depend on it beyond the push's
    transit (0.3 %), and 004 gives no density (``rho``; the time scales with 1 / c).
    ``plane``: the lower block's top (the contact plane) on a grid line (``grid``) or in the
    middle of a cell (``mid``). ``contact``: the detection of 004 Fig 2, one of
    ``CONTACT_METHODS`` (velocity alone, CP = 0.92, CP = 0.80, DF, LR), with AG normals
    for the grid-based ones. MPM: 5 mm cells, 2 x 2 uGIMP particles per cell (004's four
    per cell), no damping, run to 1.1 x the contact time; measurement: the contact time,
    the first departure of the lower block's mean axial stress from zero (sampled every
    1/2000 of the expected time). Reference: the gap over the push speed plus one transit
    of the push through the upper block (analytic model gap_closure).
    """
    if contact not in CONTACT_METHODS:
        raise CaseError(f"contact must be one of {', '.join(CONTACT_METHODS)}, got {contact!r}")
    if plane not in ("grid", "mid"):
        raise CaseError(f"plane must be 'grid' or 'mid', got {plane!r}")
    mat = NeoHookean(K=K, G=G, rho=rho)
    c = math.sqrt((mat.K + 4.0 * mat.G / 3.0) / mat.rho)     # plane-strain dilatational speed
    speed = push * c
    top = height + (0.5 * mpm_cell if plane == "mid" else 0.0)
    t_contact = gap / speed + height / c
    bodies = [Body("lower", Rectangle(0.0, 0.0, width, top), "rubber"),
              Body("upper", Rectangle(0.0, top + gap, width, height), "rubber"),
              Body("piston", Rectangle(0.0, top + gap + height, width, mpm_cell), "rubber")]
    bcs = [BoundaryCondition("fixed", "lower", "ymin", ("x", "y"), (0.0, 0.0)),
           BoundaryCondition("velocity", "piston", "ymax", ("x", "y"), (0.0, -speed))]
    return Case(
        name="gap_contact", analysis="plane_strain", thickness=1.0,
        description=f"004 Fig 2: two blocks closing a {gap:g} mm gap, contact {contact}, plane on "
                    f"{'a grid line' if plane == 'grid' else 'mid-cell'}",
        materials={"rubber": mat}, bodies=bodies,
        interfaces=[InterfacePair("lower", "upper", CoulombFriction(mu)),
                    InterfacePair("upper", "piston", LinearInterface(math.inf, math.inf))],
        boundary_conditions=bcs,
        measurements={"contact_time": {"body": "lower", "component": "yy",
                                       "sample_every": t_contact / 2000.0}},
        discretization={"mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "damping": "none",
                                "max_time": 1.1 * t_contact, "grid_anchor": "origin",
                                "rigid_bodies": ["piston"], "default_law": "none",
                                # the rigid piston's work is not in the run's external work,
                                # so the energy-growth divergence test would fire at contact
                                "blowup": 1e6,
                                **CONTACT_METHODS[contact]}},
        analytic={"model": "gap_closure", "gap": gap, "speed": speed, "height": height, "wave_speed": c},
        reference="analytic",
    )
