"""Registry, solve(case) and input validation of interfaces.analytic."""
import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import interfaces.analytic as an
from interfaces import Body, Case, IsotropicElastic, Rectangle, Result
from interfaces.errors import CaseError

DLS = dict(t1=0.6, E1=1e4, G1=500.0, t2=0.8, E2=5e3, G2=300.0, l=25.0, W=10.0, L=5.0, Dt=10.0)
DCB = dict(a=25.0, h=0.6, W=10.0, E_xx=1e4, Dn=1.0, kb=7808.0)
WAVE = dict(f=1e5, Dn=3e4, rho=15e-9, E=410e3)
CSA = dict(E_p=7e4, nu_p=0.25, E_m=2400.0, nu_m=0.33, a=0.7, cube_side=1.0, octant=True, Dn=1e5, Dt=1e5)
PARAMS = {"dls_shear_lag": DLS, "dcb_beam_foundation": DCB, "wave_transmission": WAVE, "composite_spheres": CSA}


def test_model_names():
    assert an.model_names() == sorted(["dls_shear_lag", "dcb_beam_foundation", "wave_transmission",
                                       "composite_spheres", "composite_cylinders", "shock_hugoniot",
                                       "gap_closure"])
    assert set(an.PROFILES) == set(an.MODELS)


def test_models_return_the_underlying_functions_values():
    q = an.MODELS["dls_shear_lag"](**DLS)
    m = an.DoubleLapShear(**DLS)
    assert q["stiffness"] == m.stiffness and q["compliance"] == m.compliance and q["beta_l"] == m.beta_l
    q = an.MODELS["dls_shear_lag"](t=0.6, E_yy=1e4, G_xy=500.0, l=25.0, W=10.0, L=5.0)  # identical strips
    assert q["stiffness"] == pytest.approx(an.dls_identical_stiffness(0.6, 1e4, 500.0, 25.0, 10.0, 5.0), rel=1e-10)
    assert round(q["beta_l"], 1) == 22.8
    q = an.MODELS["dcb_beam_foundation"](**DCB)
    assert q["stiffness"] == an.dcb_stiffness(**DCB) and q["compliance"] == an.dcb_compliance(**DCB)
    q = an.MODELS["wave_transmission"](**WAVE)
    Z = an.impedance(15e-9, E=410e3)
    assert q["transmitted_energy"] == an.wave_transmission(1e5, 3e4, Z)
    assert q["transmitted_energy"] + q["reflected_energy"] == pytest.approx(1.0, rel=1e-14)
    q2 = an.MODELS["wave_transmission"](f=1e5, Dn=3e4, Z1=Z, Z2=3 * Z)
    assert q2["transmitted_energy"] == an.wave_transmission(1e5, 3e4, Z, 3 * Z)
    qp = an.MODELS["wave_transmission"](**WAVE, measure="pulse_energy")
    assert qp["transmitted_energy"] == an.pulse_transmission(1e5, 3e4, Z)["transmitted_energy"]
    assert qp["transmitted_energy"] + qp["reflected_energy"] == pytest.approx(1.0, rel=1e-9)
    qk = an.MODELS["wave_transmission"](**WAVE, measure="pulse_peak", nonlinear=True, pulse="tensile")
    assert qk["transmitted_energy"] == an.pulse_transmission(1e5, 3e4, Z)["peak_ratio_squared"]
    qc = an.MODELS["wave_transmission"](**WAVE, nonlinear=True, pulse="compressive")
    assert qc["transmitted_energy"] == 1.0 and qc["pulse_transmitted_energy"] == 1.0
    with pytest.raises(CaseError, match="analytic.measure must be one of"):
        an.MODELS["wave_transmission"](**WAVE, measure="peak")
    q3 = an.MODELS["wave_transmission"](f=1e5, Dn=3e4, rho=15e-9, E=410e3, rho2=5e-9, v2=3e6)
    assert q3["Z2"] == pytest.approx(5e-9 * 3e6, rel=1e-15)
    q = an.MODELS["composite_spheres"](**CSA)
    Kp, _ = an.bulk_shear_from_young_poisson(7e4, 0.25)
    Km, Gm = an.bulk_shear_from_young_poisson(2400.0, 0.33)
    phi = an.sphere_in_cube_volume_fraction(0.7, 1.0, octant=True)
    assert q["bulk_modulus"] == an.composite_spheres_bulk_modulus(Kp, Km, Gm, phi, 0.7, 1e5)
    assert q["bulk_modulus_debonded"] < q["bulk_modulus"] < q["bulk_modulus_perfect"]
    assert q["phi"] == pytest.approx(0.1796, abs=5e-5)
    qb = an.MODELS["composite_spheres"](K_p=Kp, K_m=Km, G_m=Gm, a=0.7, b=0.7 / phi ** (1 / 3), Dn=1e5)
    assert qb["bulk_modulus"] == pytest.approx(q["bulk_modulus"], rel=1e-13)


@pytest.mark.parametrize("name", sorted(PARAMS))
def test_profiles_are_finite_arrays(name):
    prof = an.PROFILES[name](**PARAMS[name])
    for curves in prof.values():
        lengths = {len(v) for v in curves.values()}
        assert len(lengths) == 1
        for key, v in curves.items():
            assert isinstance(v, np.ndarray)
            if key not in ("jump_n", "traction_n"):
                assert np.all(np.isfinite(v)), (name, key)
    if "interface_jump" in prof:
        assert {"s", "x", "y", "jump_n", "jump_t"} <= set(prof["interface_jump"])


def test_dls_interface_jump_profile_placement_and_values():
    prof = an.PROFILES["dls_shear_lag"](**DLS, P=100.0, origin=(3.0, 5.0), axis=(0.0, 2.0), n_points=11)
    ij = prof["interface_jump"]
    np.testing.assert_allclose(ij["x"], 3.0)
    np.testing.assert_allclose(ij["y"], 5.0 + ij["s"])
    m = an.DoubleLapShear(**DLS)
    np.testing.assert_allclose(ij["jump_t"], m.shear_stress(ij["s"], 100.0) / 10.0, rtol=1e-15)
    assert np.all(np.isnan(ij["jump_n"]))


def test_dcb_interface_jump_is_twice_the_deflection_for_a_rigid_foundation():
    d = dict(DCB, kb=math.inf)
    ij = an.PROFILES["dcb_beam_foundation"](**d, P=0.1)["interface_jump"]
    m = an.DoubleCantileverBeam(**d)
    np.testing.assert_allclose(ij["jump_n"], 2 * m.deflection(ij["s"], 0.1), rtol=1e-13)
    np.testing.assert_allclose(ij["traction_n"], d["Dn"] * ij["jump_n"], rtol=1e-13)


def _case(analytic):
    return Case(name="probe", analysis="plane_stress", materials={"m": IsotropicElastic(1000.0, 0.3)},
                bodies=[Body("b", Rectangle(0.0, 0.0, 1.0, 1.0), "m")], analytic=analytic)


@pytest.mark.parametrize("name", sorted(PARAMS))
def test_solve_case_through_toml_and_json(name):
    case = Case.from_toml(_case({"model": name, **PARAMS[name]}).to_toml())
    res = an.solve(case)
    assert isinstance(res, Result) and res.method == "analytic" and res.case_name == "probe"
    assert res.quantities == an.MODELS[name](**PARAMS[name])
    back = Result.from_json(res.to_json())
    for k, v in res.quantities.items():
        assert back.quantities[k] == pytest.approx(v, rel=1e-15)
    assert set(back.profiles) == set(res.profiles)


def test_solve_overrides_and_errors():
    case = _case({"model": "dls_shear_lag", **DLS})
    assert an.solve(case, Dt=math.inf, profiles=False).quantities["stiffness"] == pytest.approx(
        an.dls_stiffness(**dict(DLS, Dt=math.inf)), rel=1e-15)
    assert an.solve(case, profiles=False).profiles == {}
    with pytest.raises(CaseError, match="no analytic model"):
        an.solve(_case(None))
    with pytest.raises(CaseError, match="analytic.model must be one of"):
        an.solve(_case({"model": "nope"}))
    with pytest.raises(CaseError, match="analytic.Dx is not a parameter of model 'dls_shear_lag'"):
        an.solve(case, Dx=1.0)
    with pytest.raises(CaseError, match="analytic.a is required"):
        an.MODELS["dcb_beam_foundation"](h=1.0, W=1.0, E_xx=1.0)
    with pytest.raises(CaseError, match="same parameter"):
        an.MODELS["dls_shear_lag"](**DLS, t=0.6)
    with pytest.raises(CaseError, match="exactly one of analytic.phi"):
        an.MODELS["composite_spheres"](**dict(CSA, phi=0.2))
    with pytest.raises(CaseError, match="Z1 or analytic.rho"):
        an.MODELS["wave_transmission"](f=1.0, Dn=1.0)
    with pytest.raises(CaseError, match="analytic.E or analytic.v"):
        an.MODELS["wave_transmission"](f=1.0, Dn=1.0, rho=1e-9)
    with pytest.raises(CaseError, match="analytic.E2 or analytic.v2"):
        an.MODELS["wave_transmission"](f=1.0, Dn=1.0, rho=1e-9, E=1e3, rho2=2e-9)
    with pytest.raises(CaseError, match=r"^analytic.Dt = 0 \(debonded\)"):
        an.PROFILES["dls_shear_lag"](**dict(DLS, Dt=0.0))
    with pytest.raises(CaseError, match="n_points"):
        an.PROFILES["dls_shear_lag"](**DLS, n_points=1)


# ---- bad inputs always give a CaseError naming the argument ---------------------------
TEXT = st.text(max_size=3).filter(lambda t: t.strip().lower() not in ("inf", "+inf"))  # "inf" is valid


def _bad(kind):
    text = TEXT
    common = st.one_of(st.just(math.nan), st.just(-math.inf), text, st.none(),
                       st.just([1.0, 2.0]), st.just(True))
    neg = st.floats(max_value=-1e-300, allow_nan=False, allow_infinity=False)
    if kind == "pos":          # > 0, finite
        return st.one_of(common, neg, st.just(0.0), st.just(math.inf))
    if kind == "pos_opt":      # > 0, finite, or None for "same as the other material"
        return st.one_of(common.filter(lambda v: v is not None), neg, st.just(0.0), st.just(math.inf))
    if kind == "pos_inf":      # > 0 or inf
        return st.one_of(common, neg, st.just(0.0))
    if kind == "nonneg":       # >= 0, finite
        return st.one_of(common, neg, st.just(math.inf))
    if kind == "iface":        # >= 0 or inf
        return st.one_of(common, neg)
    if kind.startswith("band"):  # a negative interface stiffness between the rigid-interphase limit and 0
        limit = float(kind.split(":")[1])
        return st.one_of(common, st.floats(min_value=0.999 * limit, max_value=-1e-9))
    if kind == "nu":
        return st.one_of(common, st.floats(min_value=0.5, max_value=1e6), st.floats(max_value=-1.0, min_value=-1e6))
    if kind == "phi":
        return st.one_of(common, neg, st.floats(min_value=1.0, max_value=1e6))
    raise AssertionError(kind)


def _dls_kw(t1, E1, G1, t2, E2, G2, l, W, L, Dt):
    return an.dls_stiffness(t1, E1, G1, t2, E2, G2, l, W, L, Dt)


CASES = [
    (_dls_kw, DLS, {"t1": "pos", "E1": "pos", "G1": "pos_inf", "t2": "pos", "E2": "pos", "G2": "pos_inf",
                    "l": "pos", "W": "pos", "L": "nonneg", "Dt": "band:-1184.2"}),
    (an.dls_identical_compliance, dict(t=0.6, E_yy=1e4, G_xy=500.0, l=25.0, W=10.0, Dt=5.0),
     {"t": "pos", "E_yy": "pos", "G_xy": "pos", "l": "pos", "W": "pos", "Dt": "iface"}),
    (an.dcb_stiffness, DCB, {"a": "pos", "h": "pos", "W": "pos", "E_xx": "pos", "kb": "pos_inf",
                             "Dn": "band:-390.4"}),
    (an.dcb_kb_from_stiffness, dict(k_perfect=0.15, a=25.0, h=0.6, W=10.0, E_xx=1e4),
     {"k_perfect": "pos", "a": "pos", "h": "pos", "W": "pos", "E_xx": "pos"}),
    (an.wave_transmission, dict(f=1e5, Dn=3e4, Z1=0.08, Z2=0.1), {"f": "pos", "Dn": "iface", "Z1": "pos", "Z2": "pos_opt"}),
    (an.pulse_transmission, dict(f=1e5, Dn=3e4, Z1=0.08, Z2=0.1), {"f": "pos", "Dn": "iface", "Z1": "pos", "Z2": "pos_opt"}),
    (an.wave_transmission_identical, dict(f=1e5, Dn=3e4, rho=15e-9, E=410e3),
     {"f": "pos", "Dn": "iface", "rho": "pos", "E": "pos"}),
    (an.composite_spheres_bulk_modulus, dict(K_p=4e4, K_m=2e3, G_m=900.0, phi=0.18, a=0.7, Dn=1e4),
     {"K_p": "pos", "K_m": "pos", "G_m": "pos", "phi": "phi", "a": "pos", "Dn": "band:-171428.5"}),
    (an.bulk_shear_from_young_poisson, dict(E=1e3, nu=0.3), {"E": "pos", "nu": "nu"}),
    (an.sphere_in_cube_volume_fraction, dict(radius=0.3, side=1.0), {"radius": "pos", "side": "pos"}),
    (an.interphase_to_interface, dict(t_i=0.01, E_i=500.0, G_i=200.0, E1=1e4, E2=2e3, G1=800.0, G2=700.0),
     {"t_i": "nonneg", "E_i": "pos_inf", "G_i": "pos_inf", "E1": "pos", "E2": "pos", "G1": "pos", "G2": "pos"}),
]
SLOTS = [(fn, valid, arg, kind) for fn, valid, kinds in CASES for arg, kind in kinds.items()]


@settings(max_examples=200, deadline=None)
@given(data=st.data())
def test_bad_inputs_raise_a_clear_case_error(data):
    fn, valid, arg, kind = data.draw(st.sampled_from(SLOTS))
    bad = data.draw(_bad(kind))
    kwargs = dict(valid)
    kwargs[arg] = bad
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy RuntimeWarning on the way to the error
        with pytest.raises(CaseError) as info:
            fn(**kwargs)
    assert arg in str(info.value)


@settings(max_examples=100, deadline=None)
@given(model=st.sampled_from(sorted(PARAMS)), data=st.data())
def test_bad_model_parameters_raise_a_clear_case_error(model, data):
    params = dict(PARAMS[model])
    numeric = [k for k, v in params.items() if isinstance(v, float) and k != "Dt"]
    arg = data.draw(st.sampled_from(numeric))
    bad = data.draw(st.one_of(st.just(math.nan), TEXT, st.just(-1.0), st.just(-math.inf)))
    params[arg] = bad
    with pytest.raises(CaseError) as info:
        an.MODELS[model](**params)
    assert f"analytic.{arg}" in str(info.value)


@settings(max_examples=60, deadline=None)
@given(y=st.one_of(st.floats(max_value=-1e-6, min_value=-1e6), st.floats(min_value=25.001, max_value=1e6),
                   st.just(math.nan), st.just(math.inf)))
def test_bad_profile_positions(y):
    with pytest.raises(CaseError, match="y must"):
        an.dls_shear_stress(y, **{k: v for k, v in DLS.items() if k != "L"})
