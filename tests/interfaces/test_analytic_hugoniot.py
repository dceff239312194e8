"""Shock Hugoniot of the Mie-Grueneisen solid (004 Sec 4.3, Eq 51), nickel of 004 Fig 7."""
import math

import numpy as np
import pytest

from interfaces import CaseError
from interfaces.analytic import MODELS, PROFILES, ShockHugoniot

NICKEL = dict(K=188e3, rho=8.87e-9, S1=1.44, gamma0=2.0)   # MPa, tonne/mm^3
SPEEDS = (1e4, 4.6e5, 1.84e6, 3.0e6)                          # mm/s; 1.84e6 = 004's impact


def test_hydrodynamic_hugoniot_is_the_linear_us_up_fit():
    """Eq 51 is built on U_s = C0 + S1 u_p: the jump conditions solved through the
    pressure of Eq 51 (with the energy of the jump) must give that line back."""
    h = ShockHugoniot(**NICKEL)
    C0 = math.sqrt(188e3 / 8.87e-9)
    assert h.bulk_wave_speed == pytest.approx(C0, rel=1e-15)
    for up in SPEEDS:
        assert h.state(up).shock_speed == pytest.approx(C0 + 1.44 * up, rel=1e-12)


def test_gruneisen_parameter_does_not_move_the_hugoniot():
    """The Eq 51 reference curve is the Hugoniot itself, so gamma0 only matters off it."""
    a = ShockHugoniot(**NICKEL).curve(SPEEDS)
    b = ShockHugoniot(**{**NICKEL, "gamma0": 0.5}).curve(SPEEDS)
    np.testing.assert_allclose(a["pressure"], b["pressure"], rtol=1e-11)


@pytest.mark.parametrize("Y", [0.0, 1500.0])
def test_rankine_hugoniot_jump_conditions(Y):
    h = ShockHugoniot(**NICKEL, Y=Y)
    for up in SPEEDS:
        s = h.state(up)
        rho = NICKEL["rho"] / s.volume_ratio
        assert NICKEL["rho"] * s.shock_speed == pytest.approx(rho * (s.shock_speed - up), rel=1e-12)   # mass
        assert s.longitudinal_stress == pytest.approx(NICKEL["rho"] * s.shock_speed * up, rel=1e-12)  # momentum
        work = 0.5 * s.longitudinal_stress * (1.0 - s.volume_ratio) / NICKEL["rho"]                   # energy
        assert s.specific_internal_energy == pytest.approx(work, rel=1e-10)
        assert s.longitudinal_stress - s.pressure == pytest.approx(2.0 * Y / 3.0, rel=1e-9, abs=1e-6)


def test_weak_shock_is_a_sound_wave():
    s = ShockHugoniot(**NICKEL).state(1.0)      # 1 mm/s
    assert s.shock_speed == pytest.approx(ShockHugoniot(**NICKEL).bulk_wave_speed, rel=1e-6)
    assert s.pressure == pytest.approx(NICKEL["rho"] * s.shock_speed * 1.0, rel=1e-9)


def test_registered_model_and_profile():
    q = MODELS["shock_hugoniot"](**NICKEL, impact_speed=1.84e6)
    sym = MODELS["shock_hugoniot"](**NICKEL, impact_speed=3.68e6, impact="symmetric")
    assert q["pressure"] == pytest.approx(sym["pressure"], rel=1e-14)
    assert q["pressure"] == pytest.approx(118381.4, rel=1e-6)     # rho0 (C0 + S1 u_p) u_p
    curve = PROFILES["shock_hugoniot"](**NICKEL, impact_speed=1.84e6, n_points=5)["hugoniot"]
    assert curve["particle_speed"][-1] == pytest.approx(1.5 * 1.84e6)
    assert np.all(np.diff(curve["shock_speed"]) > 0)


@pytest.mark.parametrize("bad,match", [
    (dict(impact_speed=-1.0), "impact_speed must be > 0"),
    (dict(impact_speed=1e6, impact="oblique"), "impact must be 'wall' or 'symmetric'"),
    (dict(impact_speed=1e6, speed=2.0), "analytic.speed is not a parameter of model 'shock_hugoniot'"),
    (dict(impact_speed=1e6, K=-5.0), "K must be > 0"),
])
def test_bad_input_is_named(bad, match):
    with pytest.raises(CaseError, match=match):
        MODELS["shock_hugoniot"](**{**NICKEL, **bad})
