"""Figure: neo-Hookean block (004 Eq 18, K = 2450, G = 940 MPa) compressed 20 % in MPM
against the closed form (interfaces.analytic.hyperelastic).

Left: axial Cauchy stress against the measured stretch of the block over a quasi-static
run (plane strain, x free, dead load ramped over 40 periods, grid damping), sampled at
16 points, with the closed-form curve (dotted: the small-strain linear law of the same
K and G, which the neo-Hookean material used to be run as). Right: an undamped run of
the same block: work of the loads against strain (V0 W) plus kinetic energy. Writes docs/finite_strain/compression.png.

Usage: ``PYTHONPATH=. python docs/finite_strain/compression.py``
"""
from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mpm  # noqa: E402
from interfaces import (Body, BoundaryCondition, Case, NeoHookean, Rectangle,  # noqa: E402
                        isotropic_from_KG)
from interfaces.analytic.hyperelastic import (neo_hookean_compression,  # noqa: E402
                                              nominal_stress_for_stretch)
from mpm.options import merge  # noqa: E402
from mpm.solver import Model, _Runner  # noqa: E402

MAT = NeoHookean(K=2450.0, G=940.0, rho=1e-9)


def block(ramp_time=None) -> Case:
    P = nominal_stress_for_stretch(MAT, 0.8)
    return Case(name="compression", analysis="plane_strain", thickness=1.0, materials={"m": MAT},
                bodies=[Body("b", Rectangle(0.0, 0.0, 4.0, 4.0), "m")],
                boundary_conditions=[
                    BoundaryCondition("traction", "b", "ymin", ("y",), (-P,), ramp_time=ramp_time),
                    BoundaryCondition("traction", "b", "ymax", ("y",), (P,), ramp_time=ramp_time),
                    BoundaryCondition("fixed", "b", "xmin", ("x",), (0.0,))])


def row_stretch(pt, axis: int) -> float:
    x0, x = pt.x0[:, axis], pt.x[:, axis]
    lo, hi = x0 <= x0.min() + 1e-9, x0 >= x0.max() - 1e-9
    return float((x[hi].mean() - x[lo].mean()) / (x0[hi].mean() - x0[lo].mean()))


def main() -> None:
    opts = {"cell": 0.5, "ppc": 2, "progress": False}
    T1 = Model(block(), merge(block(), opts)).T1
    case = block(40 * T1)
    model = Model(case, merge(case, opts))
    run = _Runner(model)
    n = int(math.ceil(48 * T1 / model.dt / 16))
    lam, syy = [], []
    for _ in range(16):
        run._advance(n)
        lam.append(row_stretch(model.particles, 1))
        syy.append(float(model.particles.stress[:, 1].mean()))
    curve = neo_hookean_compression(MAT, np.linspace(0.78, 1.0, 100))
    und = mpm.solve(block(), damping="none", ramp_time=8 * T1, max_time=10 * T1, **opts)
    h = und.diagnostics["history"]
    t = np.asarray(h["time"]) / T1
    work = np.asarray(h["work_ext"]) + np.asarray(h["work_bc"])
    stored = np.asarray(h["strain"]) + np.asarray(h["kinetic"])
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(curve.stretch, curve.sigma_axial, "k-", label="closed form (plane strain, x free)")
    lin = isotropic_from_KG(MAT.K, MAT.G)
    E_ps = lin.E / (1.0 - lin.nu**2)          # plane strain, x free
    ax[0].plot(curve.stretch, E_ps * (curve.stretch - 1.0), ":", color="0.5",
               label="small-strain linear, same K, G")
    ax[0].plot(lam, syy, "o", color="C1", label="MPM, mean particle stress")
    ax[0].set_xlabel("stretch lambda_y")
    ax[0].set_ylabel("sigma_yy (MPa)")
    ax[0].legend()
    ax[0].set_title("neo-Hookean block, 004 Eq 18")
    ax[1].plot(t, work, "k-", label="work of the loads")
    ax[1].plot(t, stored, "--", color="C0", label="strain (V0 W) + kinetic")
    ax[1].plot(t, np.asarray(h["kinetic"]), ":", color="C2", label="kinetic")
    ax[1].set_xlabel("t / T1")
    ax[1].set_ylabel("energy (N mm)")
    err = np.max(np.abs(work - stored)) / work[-1]
    ax[1].set_title(f"undamped run: max |W - U - KE| = {100 * err:.2f} % of W")
    ax[1].legend()
    fig.tight_layout()
    out = Path(__file__).with_name("compression.png")
    fig.savefig(out, dpi=110)
    print(out, "energy error", err)


if __name__ == "__main__":
    main()
