"""The named cases of the papers, as functions returning a :class:`interfaces.Case`.

Every builder takes keyword overrides (``Dt=5``, sizes, resolutions ...) and keeps the
analytic reference (``case.analytic``) consistent with them. Units: mm, N, MPa, s,
tonne/mm^3, Dn and Dt in MPa/mm.
"""
from __future__ import annotations

import math

import numpy as np

from interfaces import (Body, BoundaryCondition, Box, Case, CaseError, InterfacePair, IsotropicElastic,
                        LinearInterface, Polygon, Rectangle, Sphere, TransverselyIsotropicElastic)
from interfaces.analytic.dcb import dcb_compliance
from interfaces.analytic.waves import dilatational_wave_speed
from interfaces.errors import check_number
from interfaces.laws import BilinearNormalInterface
from interfaces.units import G_PER_CM3, MS

WOOD_DENSITY = 0.5 * G_PER_CM3
"""Wood strand density (not given in 000/002; irrelevant for their static answers)."""


def wood_strand(fiber=(0.0, 1.0)) -> TransverselyIsotropicElastic:
    """Wood strand of 002 Sec 3.1 / 000 Sec 3: E_A = 10 GPa, E_T = 1 GPa, G_A = 0.5 GPa, nu_A = 0.2, nu_T = 0.3."""
    return TransverselyIsotropicElastic(E_A=10000.0, E_T=1000.0, G_A=500.0, nu_A=0.2, nu_T=0.3,
                                        fiber=tuple(fiber), rho=WOOD_DENSITY)


def _interface_law(Dn: float, Dt: float, Dn_compression: float | None):
    if Dn_compression is None:
        return LinearInterface(Dn=Dn, Dt=Dt)
    return BilinearNormalInterface(Dn_tension=Dn, Dt=Dt, Dn_compression=Dn_compression)


def _rotate(points, angle_deg: float) -> np.ndarray:
    a = math.radians(angle_deg)
    R = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    return np.asarray(points, dtype=float) @ R.T


def dls(Dt: float = math.inf, Dn: float = math.inf, variant: str = "002", t: float | None = None,
        l: float = 25.0, L: float = 5.0, W: float | None = None, load: float | None = None,
        Dn_compression: float | None = None, zone_y: float | None = None, zone_Dn: float | None = None,
        angle: float = 0.0, shift_x: float = 0.0, shift_y: float = 0.0, support: str | None = None,
        fem_h: float = 0.1, mpm_cell: float = 0.1, mpm_ppc: int = 2) -> Case:
    """Double lap shear specimen (002 Sec 3.1 Fig 4; 000 Fig 4B).

    Three wood strands of thickness t (grain along the specimen axis y): the central
    strip x in [t, 2t], y in [0, L + l], the outer strips x in [0, t] and [2t, 3t],
    y in [L, 2L + l]; bond lines of length l at x = t and x = 2t; width W is the
    plane-stress thickness. The bottom of the central strip is gripped (fixed), the
    tops of the outer strips carry a traction ``load`` (MPa) along the axis.
    Stiffness k = P / (<u_top> - <u_bottom>) (002 Eq 43), P = 2 load t W.

    variant ``"002"``: t = 0.6, W = 10 (002 Sec 3.1); ``"000"``: t = 1, W = 1, tops
    loaded to 1 MPa (000 Sec 3). ``support``: ``"grip"`` (default for 002) fixes the
    bottom of the central strip; ``"traction"`` (default for 000, as there) loads it
    with the balancing traction 2 ``load`` instead, a free, self-equilibrated specimen
    (FEM removes the rigid motions; the stiffness uses displacement differences). A
    grip on a rotated specimen clamps the grid nodes beyond a side that cuts cells (a
    staircase), which is softer than a straight grip in MPM: the traction support is
    the one that makes a rotated specimen comparable with the unrotated one (000
    Fig 9). ``Dn_compression`` makes the
    normal law bilinear (002 Fig 6 "inf/1": Dn in tension, Dn_compression in
    compression); ``zone_y``/``zone_Dn``: Dn = zone_Dn below y = zone_y (002 Fig 6).
    ``angle`` rotates the specimen about the origin (000 Fig 9), ``shift_x``/``shift_y``
    translate it (interface on a grid line or at mid-cell for MPM, 000 Fig 8/11).
    Reference: shear lag, 002 Appendix A with the strips' own shear counted
    (``layer_shear``): equal to Eq 40-42 to 1e-6 for the perfect 002 specimen (0.05 .. 0.22 %
    below it for Dt = 1 .. 100), and still
    within 0.03 % of FEM for short bonds (l = 5 mm, beta l = 4.6) where the printed
    A.9 form is 3 % stiff and tends to zero compliance as l -> 0 (Dn = inf assumed).
    """
    if variant not in ("002", "000"):
        raise CaseError(f"variant must be '002' or '000', got {variant!r}")
    t = check_number("t", t if t is not None else (0.6 if variant == "002" else 1.0), low=0, low_open=True)
    W = check_number("W", W if W is not None else (10.0 if variant == "002" else 1.0), low=0, low_open=True)
    load = check_number("load", load if load is not None else 1.0, low=0, low_open=True)
    l = check_number("l", l, low=0, low_open=True)
    L = check_number("L", L, low=0, low_open=True)
    angle = check_number("angle", angle)
    if support is None:
        support = "grip" if variant == "002" else "traction"
    if support not in ("grip", "traction"):
        raise CaseError(f"support must be 'grip' or 'traction', got {support!r}")
    law = _interface_law(Dn, Dt, Dn_compression)
    zones = []
    if zone_y is not None:
        if zone_Dn is None:
            raise CaseError("zone_Dn must be given with zone_y")
        zones = [(Rectangle(-1.0, -1.0, 3 * t + 2.0, zone_y + 1.0), LinearInterface(zone_Dn, Dt))]
    wood = wood_strand(fiber=tuple(_rotate([[0.0, 1.0]], angle)[0]))
    shift = np.array([shift_x, shift_y])

    def rect(x0, y0, w, h):
        o = _rotate([[x0, y0]], angle)[0] + shift
        return Rectangle(float(o[0]), float(o[1]), w, h, angle=angle)

    bodies = [Body("outer_left", rect(0.0, L, t, l + L), "wood"),
              Body("center", rect(t, 0.0, t, L + l), "wood"),
              Body("outer_right", rect(2 * t, L, t, l + L), "wood")]
    axis = _rotate([[0.0, 1.0]], angle)[0]
    traction = tuple(float(v) for v in load * axis)
    ramp = 0.5 * MS if variant == "002" else 0.04 * MS
    if support == "grip":
        bottom = BoundaryCondition("fixed", "center", "ymin", ("x", "y"), (0.0, 0.0))
    else:
        bottom = BoundaryCondition("traction", "center", "ymin", ("x", "y"),
                                   tuple(-2.0 * v for v in traction), ramp_time=ramp)
    bcs = [bottom,
           BoundaryCondition("traction", "outer_left", "ymax", ("x", "y"), traction, ramp_time=ramp),
           BoundaryCondition("traction", "outer_right", "ymax", ("x", "y"), traction, ramp_time=ramp)]
    P = 2 * load * t * W
    y_line = [_rotate([[1.5 * t, 0.0]], angle)[0] + shift, _rotate([[1.5 * t, L + l]], angle)[0] + shift]
    return Case(
        name="dls", analysis="plane_stress", thickness=W,
        description=f"Double lap shear ({variant} specimen), Dt = {Dt} MPa/mm, Dn = {Dn} MPa/mm, P = {P:g} N",
        materials={"wood": wood}, bodies=bodies,
        interfaces=[InterfacePair("outer_left", "center", law, zones), InterfacePair("center", "outer_right", law, zones)],
        boundary_conditions=bcs,
        measurements={"stiffness": {"load": [["outer_left", "ymax"], ["outer_right", "ymax"]],
                                    "support": [["center", "ymin"]],
                                    "direction": "y" if angle == 0 else [float(v) for v in axis]},
                      "interface_energy": {}},
        discretization={"fem": {"element_size": fem_h, "order": 2},
                        "mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "ramp_time": ramp, "normal": "SN",
                                "normal_vector": [float(v) for v in _rotate([[1.0, 0.0]], angle)[0]],
                                "grid_anchor": "origin"}},
        analytic={"model": "dls_shear_lag", "t1": t, "t2": t, "E1": 10000.0, "E2": 10000.0, "G1": 500.0,
                  "G2": 500.0, "l": l, "L": L, "W": W, "Dt": Dt, "P": P, "layer_shear": True,
                  "origin": [float(v) for v in _rotate([[t, L]], angle)[0] + shift], "axis": [float(v) for v in axis]},
        reference="analytic",
        lines={"axis": [list(map(float, y_line[0])), list(map(float, y_line[1]))]},
    )


def two_layer(Dt: float = 5.0, Dn: float = math.inf, width: float = 4.0, height: float = 20.0,
              depth: float = 4.0, stress: float = 0.5, E: float = 2400.0, nu: float = 0.33,
              shift_x: float = 0.0, fem_h: float = 0.25, mpm_cell: float = 0.25, mpm_ppc: int = 2,
              cpd_h: float = 0.1) -> Case:
    """Two identical layers joined by an imperfect interface (000 Fig 4A, Sec 3).

    Layers ``width`` x ``height`` (mm) side by side (interface at x = width), depth
    ``depth`` out of plane; E = 2400 MPa, nu = 0.33. The whole bottom is fixed and the
    left layer carries ``stress`` (0.5 MPa) on its top, ramped over 0.02 ms for MPM.
    Dn = inf, Dt varied (000 Fig 5: interfacial energy per unit volume vs Dt).
    ``shift_x`` moves the specimen against the MPM grid, whose node lines pass through
    the origin (interface on a grid line for shift_x = 0, mid-cell for cell/2: 000 Fig 8).
    CPD: grid spacing ``cpd_h``, delta = 3.01 h, the compliant overlap on the interface
    row (overlap delta/4) with lattice-calibrated constants (docs/cpd_interface.md).
    Reference: FEM (no closed form).
    """
    for n, v in (("width", width), ("height", height), ("depth", depth), ("stress", stress)):
        check_number(n, v, low=0, low_open=True)
    mat = IsotropicElastic(E=E, nu=nu, rho=1.2 * G_PER_CM3)
    bodies = [Body("left", Rectangle(shift_x, 0.0, width, height), "polymer"),
              Body("right", Rectangle(shift_x + width, 0.0, width, height), "polymer")]
    ramp = 0.02 * MS
    bcs = [BoundaryCondition("fixed", "left", "ymin", ("x", "y"), (0.0, 0.0)),
           BoundaryCondition("fixed", "right", "ymin", ("x", "y"), (0.0, 0.0)),
           BoundaryCondition("traction", "left", "ymax", ("x", "y"), (0.0, stress), ramp_time=ramp)]
    return Case(
        name="two_layer", analysis="plane_stress", thickness=depth,
        description=f"Two-layer shear (000 Fig 4A), Dt = {Dt} MPa/mm, Dn = {Dn} MPa/mm",
        materials={"polymer": mat}, bodies=bodies,
        interfaces=[InterfacePair("left", "right", LinearInterface(Dn=Dn, Dt=Dt))],
        boundary_conditions=bcs,
        measurements={"interface_energy": {"per_volume": 2 * width * height * depth}},
        discretization={"fem": {"element_size": fem_h, "order": 2},
                        "mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "ramp_time": ramp, "normal": "SN",
                                "normal_vector": [1.0, 0.0], "grid_anchor": "origin"},
                        "cpd": {"h": cpd_h, "overlap": 0.25, "calibration": "lattice"}},
        reference="fem",
        lines={"across": [[shift_x, 0.75 * height], [shift_x + 2 * width, 0.75 * height]]},
    )


def core_sleeve(Dt: float = 10.0, Dn: float = math.inf, radius: float = 1.0, outer: float = 3.0,
                length: float = 10.0, stress: float = 1.0, support: str = "base",
                fem_h: float = 0.125, mpm_cell: float = 0.125, mpm_ppc: int = 2) -> Case:
    """Fibre pull-out from a sleeve: a glass core in a polymer tube, axisymmetric (000 Sec 2.3).

    x = r, y = z (mm), per radian. A glass core (E = 70 GPa, nu = 0.25; 000 Sec 3) of
    ``radius`` fills r < a and is bonded by an imperfect interface (Dn, Dt; Dn = inf:
    no normal opening) to a polymer sleeve (E = 2400 MPa, nu = 0.33) a < r < ``outer``,
    both of ``length`` along z. ``support = "base"``: the sleeve's base z = 0 is held
    (u_r = u_z = 0); ``"outer"``: its outer surface r = b is held instead. The core's
    base is free and its top face carries the axial ``stress`` (MPa), ramped over 0.02 ms
    for MPM: the load reaches the sleeve only through the interface's shear, so Dt sets
    the compliance. Stiffness k = P / (<u_z core top> - <u_z held side>), whole ring,
    P = stress pi a^2. Reference: axisymmetric FEM (no closed form). With a perfect bond
    (Dt = inf) and the base support the stiffness does not converge under mesh refinement
    (the clamped sleeve base meets the free core base at the interface); the outer
    support has no such corner on the interface.
    """
    if support not in ("base", "outer"):
        raise CaseError(f"support must be 'base' or 'outer', got {support!r}")
    held = "ymin" if support == "base" else "xmax"
    for n, v in (("radius", radius), ("length", length), ("stress", stress)):
        check_number(n, v, low=0, low_open=True)
    check_number("outer", outer, low=radius, low_open=True)
    from .curved import glass_polymer   # the constants of 000 Sec 3
    bodies = [Body("core", Rectangle(0.0, 0.0, radius, length), "glass"),
              Body("sleeve", Rectangle(radius, 0.0, outer - radius, length), "polymer")]
    ramp = 0.02 * MS
    bcs = [BoundaryCondition("fixed", "sleeve", held, ("x", "y"), (0.0, 0.0)),
           BoundaryCondition("fixed", "core", "xmin", ("x",), (0.0,)),   # the axis r = 0
           BoundaryCondition("traction", "core", "ymax", ("y",), (stress,), ramp_time=ramp)]
    return Case(
        name="core_sleeve", analysis="axisymmetric", thickness=1.0,
        description=f"Core-and-sleeve pull-out (axisymmetric), Dt = {Dt} MPa/mm, Dn = {Dn} MPa/mm",
        materials=glass_polymer(), bodies=bodies,
        interfaces=[InterfacePair("core", "sleeve", LinearInterface(Dn=Dn, Dt=Dt))],
        boundary_conditions=bcs,
        measurements={"stiffness": {"load": [["core", "ymax"]], "support": [["sleeve", held]],
                                    "direction": "y"},
                      "interface_energy": {}},
        discretization={"fem": {"element_size": fem_h, "order": 2},
                        "mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "ramp_time": ramp, "normal": "SN",
                                "normal_vector": [1.0, 0.0], "grid_anchor": "origin"}},
        reference="fem",
        lines={"core": [[0.5 * radius, 0.0], [0.5 * radius, length]]},
    )


def dcb(Dn: float = math.inf, a: float = 25.0, length: float = 50.0, h: float = 0.6, W: float = 10.0,
        P: float = 0.01, kb: float = 7808.0, clamp_end: bool = False, fem_h: float = 0.1, mpm_cell: float = 0.1, mpm_ppc: int = 2) -> Case:
    """Double cantilever beam (002 Sec 3.2 Fig 8) with wood arms (grain along x).

    Arms of depth h (0.6 mm) over ``length`` (50 mm), crack of length a (25 mm) from
    x = 0 (debonded: Dn = Dt = 0 there), bonded for x > a with normal parameter Dn
    (Dt = Dn: the symmetric opening produces no tangential jump). The left ends of
    the arms carry opposite shear tractions giving forces +/- P: a self-equilibrated
    load, the right end is free (static solvers remove the rigid-body modes);
    ``clamp_end`` clamps it instead. Load-point stiffness k = P / opening. Reference: beam on elastic
    foundation, 002 Eq 46-47, with kb (002 found 7808 MPa by FEA; recompute it with
    ``interfaces.analytic`` from a perfect-interface run).

    P (0.01 N) keeps the arms in the small-displacement regime of FEM and the theory:
    they open P C = 0.059 mm, a tenth of their depth. MPM follows the geometry: at 1 N
    the arms open 5.9 mm and turn 13 deg at the load point, which neither reference
    models.
    """
    for n, v in (("a", a), ("length", length), ("h", h), ("W", W), ("P", P)):
        check_number(n, v, low=0, low_open=True)
    if not a < length:
        raise CaseError(f"a must be < length = {length:g}, got {a:g}")
    wood = wood_strand(fiber=(1.0, 0.0))
    bodies = [Body("lower", Rectangle(0.0, 0.0, length, h), "wood"),
              Body("upper", Rectangle(0.0, h, length, h), "wood")]
    crack = (Rectangle(-1.0, 0.0, a + 1.0, 2 * h), LinearInterface(0.0, 0.0))
    tr = P / (h * W)
    ramp = 1.0 * MS
    bcs = [BoundaryCondition("traction", "upper", "xmin", ("x", "y"), (0.0, tr), ramp_time=ramp),
           BoundaryCondition("traction", "lower", "xmin", ("x", "y"), (0.0, -tr), ramp_time=ramp)]
    if clamp_end:
        bcs += [BoundaryCondition("fixed", "upper", "xmax", ("x", "y"), (0.0, 0.0)),
                BoundaryCondition("fixed", "lower", "xmax", ("x", "y"), (0.0, 0.0))]
    # the arms open by P C (002 Eq 46-47; 0.059 mm at the defaults), each by half of it and
    # up to ~1.4x that while the load ramps up: the MPM grid reaches P C beyond the arms,
    # or particles leave it (with the default 3 cells of padding they did at 0.7 ms)
    opening = P * dcb_compliance(a, h, W, wood.E_A, Dn, kb)
    padding = min(100, 3 + math.ceil(opening / mpm_cell)) if math.isfinite(opening) else 100
    return Case(
        name="dcb", analysis="plane_stress", thickness=W,
        description=f"Double cantilever beam (002 Sec 3.2), Dn = {Dn} MPa/mm, a = {a} mm",
        materials={"wood": wood}, bodies=bodies,
        interfaces=[InterfacePair("lower", "upper", LinearInterface(Dn=Dn, Dt=Dn), [crack])],
        boundary_conditions=bcs,
        measurements={"stiffness": {"load": [["upper", "xmin"]], "support": [["lower", "xmin"]], "direction": "y"}},
        discretization={"fem": {"element_size": fem_h, "order": 2},
                        "mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "ramp_time": ramp, "normal": "SN",
                                "normal_vector": [0.0, 1.0], "padding": padding}},
        analytic={"model": "dcb_beam_foundation", "a": a, "h": h, "W": W, "E_xx": wood.E_A, "Dn": Dn, "kb": kb,
                  "P": P, "origin": [a, h], "axis": [1.0, 0.0], "x_max": length - a},
        reference="analytic",
        lines={"upper_arm": [[0.0, 1.5 * h], [length, 1.5 * h]]},
    )


def wave(Dn: float = 1.0e5, f: float = 100.0e3, amplitude: float = -1.0e-4, length: float = 350.0,
         height: float = 5.0, x_interface: float = 150.0, gauge_offset: float = 25.0,
         E: float = 410.0e3, nu: float = 0.28, rho_g_cm3: float = 15.0, nonlinear: bool = False,
         mpm_cell: float = 1.0, mpm_ppc: int = 2, fem_h: float = 0.5) -> Case:
    """Plane wave through an imperfect interface (002 Sec 3.3, Eq 48-49, Fig 10-11).

    Model: uniaxial strain. A plane-strain strip with roller sides (v = 0 on y = 0 and
    y = height) carries an exact 1D longitudinal wave at the dilatational speed
    c = sqrt(E (1 - nu) / ((1 + nu)(1 - 2 nu) rho)) (5911 m/s for the tungsten of 002,
    E = 410 GPa, nu = 0.28, rho = 15 g/cm^3), so the reference impedance is Z = rho c
    (not the bar value rho sqrt(E / rho) that 002 Eq 48 prints), and the height does
    not matter (002's block was 150 x 100 mm). The left edge gets the displacement of
    002 Eq 49, x(t) = x0/2 (1 - cos 2 pi f t) for t <= 1/(2f), a single half-sine
    stress pulse (``amplitude`` = x0 < 0: tensile). ``nonlinear``: the bilinear law of
    002 Fig 10 "NL", Dn in tension and perfect in compression.

    Gauges at ``gauge_offset`` before and after the interface. The length is chosen so
    that no wave other than the incident pulse (incident gauge) and the first
    transmitted pulse with its whole exponential tail (transmitted gauge) passes a
    gauge before the measurement ends: the reflection from the interface reaches the
    incident gauge after the incident pulse has passed, and the first echo at the
    transmitted gauge (from the far end, or re-reflected at the clamped left end)
    arrives 2 min(x_interface, length - x_t) / c after the transmitted pulse, 300 mm
    (51 us, 4.3 tail time constants Z / (2 Dn) at Dn = 3800 MPa/mm, where T = 0.05) by default.
    Quantities: ``transmitted_energy`` as 002 measured it (the squared ratio of
    transmitted to incident peak stress, the reference's ``measure = "pulse_peak"``),
    ``pulse_transmitted_energy`` (energy-flux ratio int s_t^2 / int s_i^2 of the
    gauges) and ``incident_pulse_energy`` (N mm through the cross-section). Methods:
    the exact pulse solution, MPM, and transient FEM (Q1 elements one strip high;
    Newmark for the linear law, central differences for the bilinear one).
    """
    check_number("f", f, low=0, low_open=True)
    check_number("x_interface", x_interface, low=0, high=length, low_open=True, high_open=True)
    mat = IsotropicElastic(E=E, nu=nu, rho=rho_g_cm3 * G_PER_CM3)
    c = dilatational_wave_speed(E, nu, mat.rho, "plane_strain")
    pulse_length = c / (2.0 * f)
    x_inc, x_tr = x_interface - gauge_offset, x_interface + gauge_offset
    if not 0.5 * pulse_length < gauge_offset < min(x_interface, length - x_interface):
        raise CaseError(f"gauge_offset must lie between half the pulse length ({0.5 * pulse_length:.4g} mm, "
                        f"so the reflection passes the incident gauge after the pulse) and the distance "
                        f"from the interface to the ends, got {gauge_offset:g}")
    window = 2.0 * min(x_interface, length - x_tr)
    if window <= pulse_length:
        raise CaseError(f"length must leave the transmitted pulse {pulse_length:.4g} mm before the first "
                        f"echo reaches its gauge; got an echo after {window:.4g} mm: lengthen the strip")
    law = BilinearNormalInterface(Dn_tension=Dn, Dt=math.inf) if nonlinear else LinearInterface(Dn=Dn, Dt=math.inf)
    bodies = [Body("incident", Rectangle(0.0, 0.0, x_interface, height), "tungsten"),
              Body("transmitted", Rectangle(x_interface, 0.0, length - x_interface, height), "tungsten")]
    rollers = [BoundaryCondition("fixed", b.name, side, ("y",), (0.0,))
               for b in bodies for side in ("ymin", "ymax")]
    bcs = [BoundaryCondition("displacement", "incident", "xmin", ("x",), (amplitude,),
                             ramp_time=1 / (2 * f), ramp="cosine")] + rollers
    duration = (x_tr + window) / c  # the first echo reaches the transmitted gauge
    discretization = {"mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "damping": "none", "max_time": duration}}
    # transient FEM: Newmark; the bilinear law closes interpenetrating pairs on the explicit step
    discretization["fem"] = {"element_size": [fem_h, height], "order": 1,
                             "dynamics": "central" if nonlinear else "newmark"}
    return Case(
        name="wave", analysis="plane_strain", thickness=1.0,
        description=f"Wave transmission (002 Sec 3.3), uniaxial strain, Dn = {Dn} MPa/mm, f = {f:g} Hz",
        materials={"tungsten": mat}, bodies=bodies,
        interfaces=[InterfacePair("incident", "transmitted", law)],
        boundary_conditions=bcs,
        measurements={"transmitted_energy": {"x_incident": x_inc, "x_interface": x_interface,
                                             "x_transmitted": x_tr, "duration": duration}},
        discretization=discretization,
        analytic={"model": "wave_transmission", "Dn": Dn, "f": f, "rho": mat.rho, "v": c,
                  "nonlinear": nonlinear, "pulse": "tensile" if amplitude < 0 else "compressive",
                  "measure": "pulse_peak"},
        reference="analytic",
        lines={"axis": [[0.0, 0.5 * height], [length, 0.5 * height]]},
    )


def particulate(D: float = math.inf, radius: float = 0.7, side: float = 1.0, strain: float = 0.005,
                mpm_cell: float = 0.05, mpm_ppc: int = 2) -> Case:
    """1/8 of a spherical glass particle in a polymer cube (000 Sec 3, Fig 4C; Eq 34-36).

    Particle radius 0.7 mm (700 um) centred at the origin in a cube of side 1 mm,
    glass E = 70 GPa, nu = 0.25; matrix E = 2400 MPa, nu = 0.33; interface Dn = Dt = D.
    Symmetry planes x, y, z = 0 have zero normal displacement; the outer faces move
    outward by ``strain`` x side. Bulk modulus K = 2 (U_strain + U_interface) / (9 l^3 eps0^2)
    (000 Eq 35), or K = P / (3 eps0) from the average pressure (Eq 36). Reference:
    composite spheres with an imperfect interface (approximate for a cubic array).
    The nanoparticle composite of 000 Fig 13: radius = 7e-4, side = 1e-3 (same D).
    """
    check_number("radius", radius, low=0, high=side, low_open=True, high_open=True)
    glass = IsotropicElastic(E=70000.0, nu=0.25, rho=2.5 * G_PER_CM3)
    polymer = IsotropicElastic(E=2400.0, nu=0.33, rho=1.2 * G_PER_CM3)
    cube = Box(0.0, 0.0, 0.0, side, side, side)
    sphere = Sphere(0.0, 0.0, 0.0, radius)
    bodies = [Body("particle", sphere, "glass", within=cube), Body("matrix", cube, "polymer", holes=[sphere])]
    u = strain * side
    # the faces move at ~0.02 % of the polymer wave speed (000: "about 0.1 %"), then hold:
    # a ramp of 0.02 ms per mm of cube side (the same number of wave transits at any size)
    ramp = 0.02 * MS * side
    bcs = [BoundaryCondition("fixed", "*", "xmin", ("x",), (0.0,)),
           BoundaryCondition("fixed", "*", "ymin", ("y",), (0.0,)),
           BoundaryCondition("fixed", "*", "zmin", ("z",), (0.0,)),
           BoundaryCondition("displacement", "*", "xmax", ("x",), (u,), ramp_time=ramp),
           BoundaryCondition("displacement", "*", "ymax", ("y",), (u,), ramp_time=ramp),
           BoundaryCondition("displacement", "*", "zmax", ("z",), (u,), ramp_time=ramp)]
    phi = (math.pi / 6) * radius**3 / side**3
    return Case(
        name="particulate", analysis="3d", thickness=1.0,
        description=f"Particulate composite unit cell (000 Fig 4C), Dn = Dt = {D} MPa/mm",
        materials={"glass": glass, "polymer": polymer}, bodies=bodies,
        interfaces=[InterfacePair("particle", "matrix", LinearInterface(Dn=D, Dt=D))],
        boundary_conditions=bcs,
        measurements={"bulk_modulus": {"strain": strain, "volume": side**3}},
        discretization={"mpm": {"cell": mpm_cell, "ppc": mpm_ppc, "normal": "SN", "normal_center": [0.0, 0.0, 0.0]}},
        analytic={"model": "composite_spheres", "K_p": glass.K, "G_p": glass.G, "K_m": polymer.K, "G_m": polymer.G,
                  "phi": phi, "a": radius, "Dn": D},
        reference="analytic",
        lines={},
    )


# ---- CPD bimaterial square (003 Sec 4) -----------------------------------------
TABLE2 = {  # set: (C1B/C1A, nu_A (2D), C2A delta^3/C1A, nu_B (2D), C2B delta^3/C1B)
    1: (100.0, 0.1, -7 / 64, 0.1, -7 / 64),
    2: (1.0, 1 / 3, 0.0, 0.7, 33 / 64),
    3: (1 / 20, 0.4, 3 / 64, 0.2, -9 / 128),
    4: (1.0, 0.6, 9 / 32, 0.6, 9 / 32),
}
LOAD_CASES = {  # H = F - I applied to the left and right boundary regions (003 Fig 4)
    1: (0.001, 0.0, 0.0, 0.0),     # I: uniaxial stretch in x
    2: (0.001, 0.0, 0.0, 0.001),   # II: biaxial stretch
    3: (0.0, 0.001, 0.001, 0.0),   # III: shear in x and y
}


def cpd_plane_material(C1: float, C2_ratio: float, delta: float) -> IsotropicElastic:
    """Plane-strain isotropic material equivalent to 2D CPD constants (ERRATA 12).

    mu = pi C1 delta^3 / 24, lambda = mu + 8 pi C2 delta^6 / 27 with C2 = C2_ratio C1 / delta^3;
    plane strain uses the same Lame constants, so nu_3D = nu_2D / (1 + nu_2D).
    """
    mu = math.pi * C1 * delta**3 / 24
    lam = mu + 8 * math.pi * C2_ratio * C1 * delta**3 / 27
    return IsotropicElastic(E=mu * (3 * lam + 2 * mu) / (lam + mu), nu=lam / (2 * (lam + mu)), rho=1.0 * G_PER_CM3)


def bimaterial_square(parameter_set: int = 1, load_case: int = 1, interface: str = "vertical",
                      hole: bool = False, strain_scale: float = 1.0, h: float = 0.01, delta_factor: float = 3.01,
                      overlap: float | None = None, fem_h: float = 0.01, Dn: float = math.inf, Dt: float = math.inf,
                      mpm_cell: float = 0.05) -> Case:
    """Bimaterial unit square of 003 Sec 4.1 (Fig 4-7, 9-12), plane strain, interface Dn, Dt.

    Square [-0.5, 0.5]^2 split in halves by a ``vertical`` (x = 0), ``horizontal``
    (y = 0) or ``diagonal`` (45 degrees, y = x) interface; material A left/bottom, B
    right/top. Materials from Table 2 ``parameter_set`` (1-4): C1^A = 1 at the paper's
    delta = 3.01 x 0.01, converted to plane-strain (E, nu) by ERRATA 12 so that every
    method (and every horizon) sees the same continuum. Load cases (003 Fig 4): the
    left and right sides get u = H X with H of ``LOAD_CASES`` (0.1 % stretch, biaxial
    stretch, shear), scaled by ``strain_scale`` (1000 gives the 100 % stretch of Sec 4.4).
    ``hole``: a centred square hole of side 0.4 (003 Fig 9 bottom). CPD options: grid
    spacing h, delta = delta_factor h, overlap width = ``overlap`` x delta.
    ``Dn``, ``Dt`` (MPa/mm): the interface law (inf = the perfect interface of 003; finite
    values use the compliant CPD overlap, ``docs/cpd_interface.md``, with its choices: the
    narrowest band, overlap = 0.25 unless given, and the lattice calibration; the perfect
    interface keeps 003's overlap = 1 and the ERRATA 12 conversion).
    MPM: cells of ``mpm_cell``, SN normals from A to B, the 000 Eq 20 contact area on
    the reference nodal volumes (option interface_area; the square's materials are so
    soft, E_A ~ 1e-5 MPa, that a compliant interface opens by a few % of a cell).
    Reference: plane-strain FEM.
    """
    if parameter_set not in TABLE2:
        raise CaseError(f"parameter_set must be 1, 2, 3 or 4, got {parameter_set!r}")
    if load_case not in LOAD_CASES:
        raise CaseError(f"load_case must be 1 (I), 2 (II) or 3 (III), got {load_case!r}")
    if interface not in ("vertical", "horizontal", "diagonal"):
        raise CaseError(f"interface must be vertical, horizontal or diagonal, got {interface!r}")
    ratio, _, rA, _, rB = TABLE2[parameter_set]
    delta0 = 3.01 * 0.01
    mats = {"A": cpd_plane_material(1.0, rA, delta0), "B": cpd_plane_material(ratio, rB, delta0)}
    if interface == "vertical":
        shapes = (Rectangle(-0.5, -0.5, 0.5, 1.0), Rectangle(0.0, -0.5, 0.5, 1.0))
    elif interface == "horizontal":
        shapes = (Rectangle(-0.5, -0.5, 1.0, 0.5), Rectangle(-0.5, 0.0, 1.0, 0.5))
    else:
        shapes = (Polygon([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5]]), Polygon([[-0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]]))
    perfect = math.isinf(Dn) and math.isinf(Dt)
    cpd = {"h": h, "delta_factor": delta_factor, "overlap": overlap if overlap is not None else 1.0 if perfect else 0.25}
    if not perfect:
        cpd["calibration"] = "lattice"
    normal = {"vertical": [1.0, 0.0], "horizontal": [0.0, 1.0], "diagonal": [-math.sqrt(0.5), math.sqrt(0.5)]}
    holes = [Rectangle(-0.2, -0.2, 0.4, 0.4)] if hole else []
    bodies = [Body("A", shapes[0], "A", holes=list(holes)), Body("B", shapes[1], "B", holes=list(holes))]
    H = tuple(float(v) * strain_scale for v in LOAD_CASES[load_case])
    bcs = [BoundaryCondition("deformation_gradient", "*", "xmin", ("x", "y"), H),
           BoundaryCondition("deformation_gradient", "*", "xmax", ("x", "y"), H)]
    y_line = 0.35 if hole else 0.1
    return Case(
        name="bimaterial_square", analysis="plane_strain", thickness=1.0,
        description=(f"CPD bimaterial square (003 Sec 4.1): set {parameter_set}, load case "
                     f"{'I' * load_case if load_case < 3 else 'III'}, {interface} interface{', hole' if hole else ''}"),
        materials=mats, bodies=bodies,
        interfaces=[InterfacePair("A", "B", LinearInterface(Dn, Dt))],
        boundary_conditions=bcs,
        measurements={"strain_energy": {}},
        discretization={"fem": {"element_size": fem_h, "order": 2},
                        "mpm": {"cell": mpm_cell, "normal": "SN", "normal_vector": normal[interface],
                                "interface_area": "reference"},
                        "cpd": cpd},
        reference="fem",
        lines={"vertical": [[0.1, -0.5], [0.1, 0.5]], "horizontal": [[-0.5, y_line], [0.5, y_line]]},
    )


def cuboid(interface: str = "vertical", load_case: int = 1, size=(1.0, 1.0, 1.0), h: float = 0.035,
           delta_factor: float = 3.01, Dn: float = math.inf, Dt: float = math.inf,
           nu_A: float = 0.1) -> Case:
    """Bimaterial cuboid of 003 Sec 4.5 (Fig 13), 3D, interface Dn, Dt (inf: perfect, as in 003).

    Material A (``nu_A`` = 0.1 in 003: C3^A < 0; 0.25 gives C3^A = 0) and B (nu = 0.4,
    C1^B = 20 C1^A) with C1^A = 1 at
    delta = 3.01 x 0.035, converted by ERRATA 12 (mu = pi C1 delta^4 / 30). Interface
    ``vertical`` (x = 0) or ``horizontal`` (z = 0); u = H X on the x-sides with H of
    load case I-III extended to 3D (0.1 %).
    """
    if interface not in ("vertical", "horizontal"):
        raise CaseError(f"interface must be vertical or horizontal, got {interface!r}")
    if load_case not in LOAD_CASES:
        raise CaseError(f"load_case must be 1, 2 or 3, got {load_case!r}")
    sx, sy, sz = (check_number(f"size[{i}]", v, low=0, low_open=True) for i, v in enumerate(size))
    delta0 = 3.01 * 0.035

    def mat(C1, nu):
        mu = math.pi * C1 * delta0**4 / 30
        return IsotropicElastic(E=2 * mu * (1 + nu), nu=nu, rho=1.0 * G_PER_CM3)

    nu_A = check_number("nu_A", nu_A, low=-1.0, high=0.5, low_open=True, high_open=True)
    mats = {"A": mat(1.0, nu_A), "B": mat(20.0, 0.4)}
    if interface == "vertical":
        shapes = (Box(-sx / 2, -sy / 2, -sz / 2, sx / 2, sy, sz), Box(0.0, -sy / 2, -sz / 2, sx / 2, sy, sz))
    else:
        shapes = (Box(-sx / 2, -sy / 2, -sz / 2, sx, sy, sz / 2), Box(-sx / 2, -sy / 2, 0.0, sx, sy, sz / 2))
    Hxx, Hxy, Hyx, Hyy = LOAD_CASES[load_case]
    H = (Hxx, Hxy, 0.0, Hyx, Hyy, 0.0, 0.0, 0.0, 0.0)
    bcs = [BoundaryCondition("deformation_gradient", "*", "xmin", ("x", "y", "z"), H),
           BoundaryCondition("deformation_gradient", "*", "xmax", ("x", "y", "z"), H)]
    return Case(
        name="cuboid", analysis="3d", thickness=1.0,
        description=f"CPD bimaterial cuboid (003 Sec 4.5), {interface} interface, load case {load_case}",
        materials=mats, bodies=[Body("A", shapes[0], "A"), Body("B", shapes[1], "B")],
        interfaces=[InterfacePair("A", "B", LinearInterface(Dn, Dt))],
        boundary_conditions=bcs, measurements={"strain_energy": {}},
        discretization={"cpd": {"h": h, "delta_factor": delta_factor, "overlap": 1.0}},
        lines={"axis": [[-sx / 2, 0.0, 0.0], [sx / 2, 0.0, 0.0]]},
    )
