"""Named cases on curved geometry (FEM meshes them with gmsh into curved 6-node triangles).

* ``composite_spheres``: a glass sphere in a concentric polymer shell (000 Sec 3), the
  axisymmetric r-z section, uniform radial displacement on the outer sphere; bulk modulus
  against the composite-spheres model with an imperfect interface;
* ``composite_cylinders``: a glass fibre in a polymer cylinder, plane strain, uniform
  radial displacement; transverse bulk modulus against the composite-cylinders model;
* ``inclusion``: a circular or elliptical glass inclusion with an imperfect interface in a
  polymer plate under uniaxial tension (stiffness and energies; no closed form).

Units: mm, N, MPa, MPa/mm.
"""
from __future__ import annotations

import math

from interfaces import Case
from interfaces.case import Body, BoundaryCondition, InterfacePair
from interfaces.errors import CaseError, check_number
from interfaces.geometry import CURVE_SIDE, Circle, Ellipse, Rectangle
from interfaces.laws import LinearInterface
from interfaces.materials import IsotropicElastic
from interfaces.units import G_PER_CM3


def glass_polymer() -> dict:
    """The particle and matrix constants of 000 Sec 3: glass E = 70 GPa, nu = 0.25; polymer
    E = 2400 MPa, nu = 0.33."""
    return {"glass": IsotropicElastic(E=70000.0, nu=0.25, rho=2.5 * G_PER_CM3),
            "polymer": IsotropicElastic(E=2400.0, nu=0.33, rho=1.2 * G_PER_CM3)}


def _concentric(radius: float, outer: float, clip: Rectangle, core_name: str) -> list[Body]:
    core, shell = Circle(0.0, 0.0, radius), Circle(0.0, 0.0, outer)
    return [Body(core_name, core, "glass", within=clip),
            Body("matrix", shell, "polymer", holes=[core], within=clip)]


def _dilatation_bcs(strain: float) -> list[BoundaryCondition]:
    """Symmetry planes x = 0 and y = 0 (axis and equator for the sphere), u = strain * x outside."""
    return [BoundaryCondition("fixed", "*", "xmin", ("x",), (0.0,)),
            BoundaryCondition("fixed", "*", "ymin", ("y",), (0.0,)),
            BoundaryCondition("deformation_gradient", "matrix", CURVE_SIDE, ("x", "y"),
                              (strain, 0.0, 0.0, strain))]


def _checked_fraction(volume_fraction: float) -> float:
    return check_number("volume_fraction", volume_fraction, low=0.0, high=1.0, low_open=True, high_open=True)


def composite_spheres(D: float = math.inf, radius: float = 0.7, volume_fraction: float = 0.1796,
                      strain: float = 0.005, section: str = "quarter", fem_h: float | None = None) -> Case:
    """Composite sphere of 000 Sec 3 (glass in polymer, Dn = Dt = D), axisymmetric.

    A sphere of ``radius`` (mm) in a concentric shell of outer radius b = radius /
    volume_fraction^(1/3), meshed in the r-z plane: ``section = "quarter"`` (default) is the
    upper half (r, z >= 0, the equator z = 0 a symmetry plane, which also holds a debonded
    particle in place), ``"half"`` the whole meridian half disc (r >= 0; needs D > 0, a
    debonded particle is free along the axis there). The outer sphere moves radially,
    u = strain * x. Bulk modulus K = 2 U / (9 V eps0^2) (000 Eq 35) with U the whole-ring
    energy and V the meshed volume; reference: the composite-spheres model with an
    imperfect interface (exact for this geometry).
    """
    a = check_number("radius", radius, low=0.0, low_open=True)
    phi = _checked_fraction(volume_fraction)
    if section not in ("quarter", "half"):
        raise CaseError(f"section must be 'quarter' or 'half', got {section!r}")
    if section == "half" and D == 0.0:
        raise CaseError("section 'half' needs D > 0: a debonded particle is free to move along the axis "
                        "(use section 'quarter', whose equator holds it)")
    b = a / phi ** (1.0 / 3.0)
    mats = glass_polymer()
    g, p = mats["glass"], mats["polymer"]
    half = section == "half"
    clip = Rectangle(0.0, -b if half else 0.0, b, 2.0 * b if half else b)
    bcs = _dilatation_bcs(strain)
    if half:    # no equator plane: the outer dilatation holds the axial position
        bcs = [bc for bc in bcs if bc.side != "ymin"]
    return Case(
        name="composite_spheres", analysis="axisymmetric", thickness=1.0,
        description=f"Composite sphere, a = {a:g} mm, phi = {phi:.4g}, D = {D:g} MPa/mm",
        materials=mats, bodies=_concentric(a, b, clip, "particle"),
        interfaces=[InterfacePair("particle", "matrix", LinearInterface(Dn=D, Dt=D))],
        boundary_conditions=bcs,
        measurements={"bulk_modulus": {"strain": strain, "volume": (4.0 if half else 2.0) * math.pi * b ** 3 / 3.0}},
        discretization={"fem": {"h": fem_h if fem_h is not None else min(a, b - a) / 6.0}},
        analytic={"model": "composite_spheres", "K_p": g.K, "G_p": g.G, "K_m": p.K, "G_m": p.G,
                  "phi": phi, "a": a, "Dn": D, "Dt": D},
        reference="analytic", lines={})


def composite_cylinders(D: float = math.inf, radius: float = 0.7, volume_fraction: float = 0.3,
                        strain: float = 0.005, fem_h: float | None = None) -> Case:
    """Composite cylinder: a glass fibre in a polymer cylinder (Dn = Dt = D), plane strain.

    The quarter cross-section (x, y >= 0, symmetry planes) of a fibre of ``radius`` in a
    matrix of outer radius b = radius / sqrt(volume_fraction), u = strain * x on the outer
    circle. Transverse bulk modulus k = U / (2 V eps0^2) (V: quarter area x unit length);
    reference: the composite-cylinders model with an imperfect interface.
    """
    a = check_number("radius", radius, low=0.0, low_open=True)
    phi = _checked_fraction(volume_fraction)
    b = a / math.sqrt(phi)
    mats = glass_polymer()
    g, p = mats["glass"], mats["polymer"]
    bodies = _concentric(a, b, Rectangle(0.0, 0.0, b, b), "fibre")
    return Case(
        name="composite_cylinders", analysis="plane_strain", thickness=1.0,
        description=f"Composite cylinder, a = {a:g} mm, phi = {phi:.4g}, D = {D:g} MPa/mm",
        materials=mats, bodies=bodies,
        interfaces=[InterfacePair("fibre", "matrix", LinearInterface(Dn=D, Dt=D))],
        boundary_conditions=_dilatation_bcs(strain),
        measurements={"bulk_modulus": {"strain": strain, "volume": math.pi * b * b / 4.0}},
        discretization={"fem": {"h": fem_h if fem_h is not None else min(a, b - a) / 6.0}},
        analytic={"model": "composite_cylinders", "K_p": g.K, "G_p": g.G, "K_m": p.K, "G_m": p.G,
                  "phi": phi, "a": a, "Dn": D, "Dt": D},
        reference="analytic", lines={})


def inclusion(D: float = 100.0, shape: str = "circle", a: float = 1.0, b: float = 0.5, angle: float = 0.0,
              width: float = 10.0, stress: float = 10.0, fem_h: float | None = None) -> Case:
    """Circular or elliptical glass inclusion, imperfect interface, in a polymer plate under tension.

    A circle of radius ``a``, or an ellipse with semi-axes a, b rotated by ``angle`` degrees,
    with Dn = Dt = D at the centre of a square plate of side ``width``, plane strain,
    uniaxial tension ``stress`` (MPa) on x = +width/2, x = -width/2 held in x. Stiffness
    P/<u> (002 Eq 43, 45) and energies (no closed form: FEM convergence is the check).
    """
    if shape not in ("circle", "ellipse"):
        raise CaseError(f"shape must be 'circle' or 'ellipse', got {shape!r}")
    a = check_number("a", a, low=0.0, low_open=True)
    b = check_number("b", b, low=0.0, low_open=True)
    w = check_number("width", width, low=2.0 * max(a, b), low_open=True)
    core = Circle(0.0, 0.0, a) if shape == "circle" else Ellipse(0.0, 0.0, a, b, angle)
    plate = Rectangle(-w / 2, -w / 2, w, w)
    return Case(
        name="inclusion", analysis="plane_strain", thickness=1.0,
        description=f"{shape.capitalize()} inclusion in a plate, D = {D:g} MPa/mm",
        materials=glass_polymer(),
        bodies=[Body("inclusion", core, "glass"), Body("plate", plate, "polymer", holes=[core])],
        interfaces=[InterfacePair("inclusion", "plate", LinearInterface(Dn=D, Dt=D))],
        boundary_conditions=[BoundaryCondition("fixed", "plate", "xmin", ("x",), (0.0,)),
                             BoundaryCondition("traction", "plate", "xmax", ("x", "y"), (stress, 0.0))],
        measurements={"stiffness": {"load": [["plate", "xmax"]], "support": [["plate", "xmin"]],
                                    "direction": "x"}},
        discretization={"fem": {"h": fem_h if fem_h is not None else min(a, b) / 4.0}},
        reference="fem", lines={"axis": [[-w / 2, 0.0], [w / 2, 0.0]]})


__all__ = ["composite_spheres", "composite_cylinders", "inclusion", "glass_polymer"]
