"""The contact cases of paper 004 (MPM contact detection, Sec 2.2)."""
from __future__ import annotations

import math

import numpy as np

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
    c, speed = _push(mat, push)
    top = height + (0.5 * mpm_cell if plane == "mid" else 0.0)
    t_contact = gap / speed + height / c
    bodies, bcs = _pushed_stack([("lower", 0.0, top), ("upper", top + gap, height)], width, mpm_cell, speed)
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
                                **_PISTON_OPTIONS, **CONTACT_METHODS[contact]}},
        analytic={"model": "gap_closure", "gap": gap, "speed": speed, "height": height, "wave_speed": c},
        reference="analytic",
    )


#: MPM options of a stack pushed by a rigid piston (mpm skips its energy-growth test and
#: energy balance for driven rigid bodies, whose work it does not track)
_PISTON_OPTIONS = {"rigid_bodies": ["piston"], "default_law": "none"}


def _push(mat: NeoHookean, push: float) -> tuple[float, float]:
    """Plane-strain dilatational wave speed of ``mat`` and the push speed push * c."""
    c = math.sqrt((mat.K + 4.0 * mat.G / 3.0) / mat.rho)
    return c, push * c


def _pushed_stack(blocks, width: float, cell: float, speed: float):
    """Bodies (name, bottom y, height) of material "rubber", the lowest fixed at its
    bottom, and a rigid piston one cell thick on the highest, moving down at ``speed``
    (a velocity condition on grid nodes stays where it is while the top moves away from
    it: after a cell of travel it no longer pushes)."""
    bodies = [Body(name, Rectangle(0.0, y0, width, h), "rubber") for name, y0, h in blocks]
    name, y0, h = blocks[-1]
    bodies.append(Body("piston", Rectangle(0.0, y0 + h, width, cell), "rubber"))
    bcs = [BoundaryCondition("fixed", blocks[0][0], "ymin", ("x", "y"), (0.0, 0.0)),
           BoundaryCondition("velocity", "piston", "ymax", ("x", "y"), (0.0, -speed))]
    return bodies, bcs


def compression_strain(case: Case, times) -> np.ndarray:
    """Compression strain of a piston-driven stack at ``times`` (s): piston travel over the
    stack's initial height."""
    piston = next(bc for bc in case.boundary_conditions if bc.body == "piston")
    height = sum(b.shape.height for b in case.bodies if b.name != "piston")
    return -piston.value[1] * np.asarray(times, float) / height


def compression_20(contact: str = "LR", strain: float = 0.2, width: float = 40.0, height: float = 50.0,
                   mpm_cell: float = 5.0, mpm_ppc: int = 2, mu: float = 0.2, push: float = 5e-4,
                   rho: float = 1.0e-9, K: float = 2450.0, G: float = 940.0) -> Case:
    """Two identical neo-Hookean blocks in contact compressed to ``strain`` (004 Fig 5).

    The blocks of :func:`gap_contact` touching (contact plane on a grid line), pushed by
    the bonded rigid piston at ``push`` x the wave speed until the stack is shortened by
    ``strain``; ``contact`` one of ``CONTACT_METHODS`` or ``single``: one block of the
    stack's height (single-material MPM, 004's SMM, the reference). Measurement: the mean
    axial stress of the stack's particles, sampled 2000 times (quantity ``axial_stress``,
    at the end; the history in ``diagnostics["gauges"]``). 004 reports (MM - SMM) / SMM
    of that stress against strain.
    """
    if contact not in CONTACT_METHODS and contact != "single":
        raise CaseError(f"contact must be one of {', '.join(CONTACT_METHODS)}, single, got {contact!r}")
    strain = float(strain)
    if not 0.0 < strain < 0.5:
        raise CaseError(f"strain must be in (0, 0.5), got {strain!r}")
    mat = NeoHookean(K=K, G=G, rho=rho)
    c, speed = _push(mat, push)
    duration = strain * 2.0 * height / speed
    blocks = [("stack", 0.0, 2.0 * height)] if contact == "single" else \
        [("lower", 0.0, height), ("upper", height, height)]
    bodies, bcs = _pushed_stack(blocks, width, mpm_cell, speed)
    stack = [b[0] for b in blocks]
    interfaces = [InterfacePair(stack[-1], "piston", LinearInterface(math.inf, math.inf))]
    if contact != "single":
        interfaces.insert(0, InterfacePair("lower", "upper", CoulombFriction(mu)))
    options = {} if contact == "single" else CONTACT_METHODS[contact]
    return Case(
        name="compression_20", analysis="plane_strain", thickness=1.0,
        description=f"004 Fig 5: two blocks in contact compressed to {100 * strain:g} %, contact {contact}",
        materials={"rubber": mat}, bodies=bodies, interfaces=interfaces, boundary_conditions=bcs,
        measurements={"axial_stress": {"bodies": stack, "component": "yy",
                                       "sample_every": duration / 2000.0}},
        discretization={"mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "damping": "none",
                                "max_time": duration, "grid_anchor": "origin",
                                **_PISTON_OPTIONS, **options}},
    )
