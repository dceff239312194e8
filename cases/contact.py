"""The contact cases of paper 004 (MPM contact detection, Sec 2.2)."""
from __future__ import annotations

import math

import numpy as np

from interfaces import (Body, BoundaryCondition, Case, CaseError, CoulombFriction, InterfacePair,
                        LinearInterface, NeoHookean, Rectangle)

from .packing import ellipse_packing

#: contact method name -> the MPM options that select it (004 Fig 2's curves)
CONTACT_METHODS = {
    "velocity": {"normal": "AG", "separation": "velocity"},              # Eq 14 alone
    "CP0.92": {"normal": "AG", "separation": "offset", "contact_offset": 0.92},   # Eq 16-17
    "CP0.80": {"normal": "AG", "separation": "offset", "contact_offset": 0.80},
    "DF": {"normal": "AG", "separation": "DF"},                          # Eq 15
    "LR": {"normal": "LR", "separation": "LR"},                          # Eq 19-25
}

#: treatments of nodes seen by three or more materials (004 Sec 3.4; mpm option three_material)
THREE_MATERIAL_METHODS = ("lump", "explicit")


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
    """Compression strain of a piston-driven specimen at ``times`` (s): piston travel over
    the initial height of the bodies below it (rigid walls beside them excluded)."""
    piston = next(bc for bc in case.boundary_conditions if bc.body == "piston")
    rigid = set(case.discretization.get("mpm", {}).get("rigid_bodies", ()))
    bounds = [b.shape.bounds() for b in case.bodies if b.name not in rigid]
    height = max(hi[1] for _, hi in bounds) - min(lo[1] for lo, _ in bounds)
    return -piston.value[1] * np.asarray(times, float) / height


def compression_20(contact: str = "LR", strain: float = 0.2, width: float = 40.0, height: float = 50.0,
                   mpm_cell: float = 5.0, mpm_ppc: int = 2, mu: float = 0.2, push: float = 5e-4,
                   rho: float = 1.0e-9, K: float = 2450.0, G: float = 940.0) -> Case:
    """Two identical neo-Hookean blocks in contact compressed to ``strain`` (004 Fig 5).

    The blocks of :func:`gap_contact` touching (contact plane on a grid line), pushed by
    the bonded rigid piston at ``push`` x the wave speed until the stack is shortened by
    ``strain``; ``contact`` one of ``CONTACT_METHODS`` or ``single``: one block of the
    stack's height (single-material MPM, 004's SMM, the reference). Measurement: the mean
    axial stress of the stack (the volume average over its particles,
    :mod:`mpm.contact_gauge`), sampled 2000 times (quantity ``axial_stress``,
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


def three_material_node(contact: str = "LR", three_material: str = "lump", plane: str = "grid",
                        strain: float = 0.05, width: float = 40.0, height: float = 50.0,
                        mpm_cell: float = 5.0, mpm_ppc: int = 2, mu: float = 0.2, push: float = 5e-4,
                        rho: float = 1.0e-9, K: float = 2450.0, G: float = 940.0) -> Case:
    """Three identical neo-Hookean blocks meeting at one node, compressed (004 Fig 4).

    004 Sec 3.4, Fig 4A-B. A lower block ``width`` x ``height``/2 fixed at its bottom
    carries two upper blocks side by side (``width``/2 each); the three meet at one point
    (a "3+" node: three materials), on a grid node (``plane = grid``) or half a cell off it
    in both directions (``mid``).
    The top is pushed down by the bonded rigid piston of :func:`gap_contact` at ``push`` x
    the wave speed until the stack is shortened by ``strain`` (004: 5 %, half a cell with
    these sizes). All pairs touch with Coulomb friction ``mu``; ``contact`` selects the
    detection (``CONTACT_METHODS``) and ``three_material`` how nodes seen by 3+ materials
    are corrected: ``lump`` (each material against the lump of the others, 004 Eq 50) or
    ``explicit`` (the pairs in contact found per pair and, for one or two pairs, their
    contact laws solved simultaneously, 004 Eq 49; lumping for three or more pairs).
    ``contact = single``: the same region as one block (single-material MPM), the reference:
    identical materials compressed along the stack must not open or slide at their
    interfaces, so any difference from it is an error of the contact method (004 Fig 4B:
    lumping tilts the normals at the 3+ nodes, the interface rotates and opens there).
    Measurement: the mean axial stress of the blocks, sampled 400 times (quantity
    ``axial_stress``).
    """
    if contact not in CONTACT_METHODS and contact != "single":
        raise CaseError(f"contact must be one of {', '.join(CONTACT_METHODS)}, single, got {contact!r}")
    if three_material not in THREE_MATERIAL_METHODS:
        raise CaseError(f"three_material must be one of {', '.join(THREE_MATERIAL_METHODS)}, "
                        f"got {three_material!r}")
    if plane not in ("grid", "mid"):
        raise CaseError(f"plane must be 'grid' or 'mid', got {plane!r}")
    strain = float(strain)
    if not 0.0 < strain < 0.5:
        raise CaseError(f"strain must be in (0, 0.5), got {strain!r}")
    mat = NeoHookean(K=K, G=G, rho=rho)
    c, speed = _push(mat, push)
    duration = strain * height / speed
    shift = 0.5 * mpm_cell if plane == "mid" else 0.0
    x_mid, y_mid = 0.5 * width + shift, 0.5 * height + shift
    if contact == "single":
        blocks = [Body("block", Rectangle(0.0, 0.0, width, height), "rubber")]
    else:
        blocks = [Body("lower", Rectangle(0.0, 0.0, width, y_mid), "rubber"),
                  Body("left", Rectangle(0.0, y_mid, x_mid, height - y_mid), "rubber"),
                  Body("right", Rectangle(x_mid, y_mid, width - x_mid, height - y_mid), "rubber")]
    names = [b.name for b in blocks]
    bodies = blocks + [Body("piston", Rectangle(0.0, height, width, mpm_cell), "rubber")]
    bcs = [BoundaryCondition("fixed", names[0], "ymin", ("x", "y"), (0.0, 0.0)),
           BoundaryCondition("velocity", "piston", "ymax", ("x", "y"), (0.0, -speed))]
    bonded = LinearInterface(math.inf, math.inf)
    interfaces = [InterfacePair(n, "piston", bonded) for n in names if n != "lower"] \
        if contact != "single" else [InterfacePair("block", "piston", bonded)]
    options = {}
    if contact != "single":
        interfaces += [InterfacePair(a, b, CoulombFriction(mu))
                       for a, b in (("lower", "left"), ("lower", "right"), ("left", "right"))]
        options = {**CONTACT_METHODS[contact], "three_material": three_material}
    return Case(
        name="three_material_node", analysis="plane_strain", thickness=1.0,
        description=f"004 Fig 4: three blocks meeting at a node ({plane}), compressed "
                    f"{100 * strain:g} %, contact {contact}, 3+ nodes {three_material}",
        materials={"rubber": mat}, bodies=bodies, interfaces=interfaces, boundary_conditions=bcs,
        measurements={"axial_stress": {"bodies": names, "component": "yy",
                                       "sample_every": duration / 400.0}},
        discretization={"mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "damping": "none",
                                "max_time": duration, "grid_anchor": "origin",
                                **_PISTON_OPTIONS, **options}},
    )


def ellipse_compaction(contact: str = "LR", three_material: str = "lump", n: int = 20,
                       seed: int = 2004, fill: float = 0.55, width: float = 1.0, height: float = 2.0,
                       strain: float = 0.75, speed: float = 1.0e5, mpm_cell: float = 0.0143,
                       mpm_ppc: int = 2, mu: float = 0.0, K: float = 78090.0, G: float = 27600.0,
                       rho: float = 2.78e-9) -> Case:
    """Compaction of a box of ellipses, each its own material (004 Sec 4.2, Fig 6).

    ``n`` disjoint ellipses (:func:`cases.packing.ellipse_packing`, ``seed``, covering
    ``fill`` of the box; 004 drew theirs by hand in a bitmap) in a ``width`` x ``height`` box
    (004: 1 x 2 mm) of rigid walls (left, right, floor; one cell thick), compressed by
    ``strain`` (004: 75 %, to 1 x 0.5 mm) by a rigid piston (one cell thick, spanning the
    walls) moving down at ``speed`` (004: 100 m/s, about 2 % of the
    wave speed). The ellipses are neo-Hookean aluminium without plasticity (004 Eq 18,
    K = 78090, G = 27600 MPa, rho = 2.78 g/cm^3); every pair of bodies (ellipses, walls,
    piston) is in Coulomb contact ``mu`` (004 does not give it; default frictionless).
    ``contact`` selects the detection (``CONTACT_METHODS``), ``three_material`` the
    treatment of nodes seen by 3+ materials (004 used lumping). MPM: ``mpm_cell`` (004:
    0.0143 mm, 2 x 2 particles per cell), no damping; 004 used CPDI shape functions and
    XPIC(5). Measurements: the mean axial stress of the ellipses (volume average, as 004's
    NairnMPM reports it), sampled 300 times
    (quantity ``axial_stress``; 004: LR reached 105 GPa, DF 84 GPa, CP = 0.8 80 GPa), and the
    particles of one ellipse inside another at the end (``interpenetration``; 004: many
    with DF, none visible with LR).
    """
    if contact not in CONTACT_METHODS:
        raise CaseError(f"contact must be one of {', '.join(CONTACT_METHODS)}, got {contact!r}")
    if three_material not in THREE_MATERIAL_METHODS:
        raise CaseError(f"three_material must be one of {', '.join(THREE_MATERIAL_METHODS)}, "
                        f"got {three_material!r}")
    strain = float(strain)
    if not 0.0 < strain < 0.9:
        raise CaseError(f"strain must be in (0, 0.9), got {strain!r}")
    ellipses = ellipse_packing(int(n), width, height, fill, gap=0.5 * mpm_cell / mpm_ppc, seed=int(seed))
    names = [f"ellipse_{k + 1}" for k in range(len(ellipses))]
    bodies = [Body(name, e, "aluminium") for name, e in zip(names, ellipses)]
    # the piston spans the walls too and slides over them (rigid bodies do not meet): a
    # piston only as wide as the box has its end faces on the walls' faces, where its
    # volume gradient points into the wall, and ellipse fields crept up the corner
    # nodes into the piston (LR lost a particle at 64 % compression)
    t = mpm_cell
    walls = {"left_wall": Rectangle(-t, -t, t, height + t),
             "right_wall": Rectangle(width, -t, t, height + t),
             "floor": Rectangle(0.0, -t, width, t),
             "piston": Rectangle(-t, height, width + 2 * t, t)}
    bodies += [Body(name, shape, "aluminium") for name, shape in walls.items()]
    bcs = [BoundaryCondition("fixed", name, "ymin", ("x", "y"), (0.0, 0.0))
           for name in ("left_wall", "right_wall", "floor")]
    bcs.append(BoundaryCondition("velocity", "piston", "ymax", ("x", "y"), (0.0, -float(speed))))
    duration = strain * height / float(speed)
    return Case(
        name="ellipse_compaction", analysis="plane_strain", thickness=1.0,
        description=f"004 Fig 6: {len(ellipses)} ellipses compacted {100 * strain:g} % at "
                    f"{speed / 1e3:g} m/s, contact {contact}, 3+ nodes {three_material}",
        materials={"aluminium": NeoHookean(K=K, G=G, rho=rho)}, bodies=bodies,
        interfaces=[InterfacePair(a, b, CoulombFriction(mu))
                    for i, a in enumerate(names) for b in names[i + 1:] + list(walls)],
        boundary_conditions=bcs,
        measurements={"axial_stress": {"bodies": names, "component": "yy",
                                       "sample_every": duration / 300.0},
                      "interpenetration": {"bodies": names, "container": {
                          "left": "left_wall", "right": "right_wall", "bottom": "floor",
                          "top": "piston"}}},
        discretization={"mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "damping": "none",
                                "max_time": duration, "grid_anchor": "origin",
                                "rigid_bodies": list(walls), "default_law": "none",
                                **CONTACT_METHODS[contact], "three_material": three_material}},
    )
