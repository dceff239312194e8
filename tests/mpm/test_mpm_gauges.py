"""The mean axial stress gauge of 004 Fig 5 and 6 (mpm/contact_gauge.py): the volume
average sum V_p sigma_p / sum V_p over the current particle volumes, as NairnMPM's global
average stress, not the plain mean over the particles."""
from types import SimpleNamespace

import numpy as np
import pytest

import cases
from mpm.contact_gauge import AxialStressGauge


def test_axial_stress_is_the_volume_average_over_the_current_particle_volumes():
    case = cases.build("compression_20", contact="LR")
    names = [b.name for b in case.bodies]
    # two particles of each stack body and one of the piston (not a member of the gauge)
    field = np.array([names.index("lower")] * 2 + [names.index("upper")] * 2
                     + [names.index("piston")])
    gauge = AxialStressGauge(case, field, [np.eye(4)] * len(names))
    # a particle compressed to J = 0.2 carries five times the stress of one at J = 1
    volume = np.array([1.0, 0.2, 1.0, 0.2, 7.0])
    syy = np.array([-300.0, -1500.0, -300.0, -1500.0, -1.0e6])
    stress = np.zeros((5, 4))
    stress[:, 1] = syy
    gauge.sample(0.0, SimpleNamespace(stress=stress, volume=volume))
    # the integral of sigma_yy over the stack's current volume, over that volume
    integral = 2.0 * (1.0 * -300.0 + 0.2 * -1500.0)
    assert gauge.quantities()["axial_stress"] == pytest.approx(integral / 2.4, rel=1e-14)
    assert gauge.quantities()["axial_stress"] != pytest.approx(syy[:4].mean(), rel=0.1)
