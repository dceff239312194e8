"""imperfect fit (002 Sec 3.4): Dt recovered from FEM-generated DLS stiffnesses, a range that
covers the true value under 2 % noise, Dn of the DCB, undetermined parameters and bad input."""
import json

import numpy as np
import pytest

import cases
import fem
from cases.cli import main
from cases.fit import fit
from interfaces.errors import CaseError, SolverError

LS = [5.0, 10.0, 25.0]      # bond lengths (mm) of the 002 wood-strand DLS
DT = 5.0


@pytest.fixture(scope="module")
def fem_stiffness():
    return [fem.solve(cases.build("dls", Dt=DT, l=l), h=0.2, fields=False).quantities["stiffness"] for l in LS]


def test_dt_recovered_from_fem_stiffnesses_with_the_analytic_model(fem_stiffness):
    r = fit("dls", "l", LS, fem_stiffness, ["Dt"], "analytic")
    assert r.parameters["Dt"] == pytest.approx(DT, rel=5e-3)        # measured -0.02 %
    lo, hi = r.ranges["Dt"]
    assert lo <= DT <= hi or abs(r.parameters["Dt"] / DT - 1) < 1e-3
    assert all(0.3 < s < 1.0 for s in r.sensitivities["Dt"])        # shorter bonds tell more (002 Eq 51)
    assert r.sensitivities["Dt"][0] > r.sensitivities["Dt"][-1]


def test_dt_recovered_with_fem_in_the_loop(fem_stiffness):
    r = fit("dls", "l", LS[:1], fem_stiffness[:1], ["Dt"], "fem", options={"h": 0.2}, noise=0.02)
    assert r.parameters["Dt"] == pytest.approx(DT, rel=1e-4)        # same model: exact up to brentq's xtol
    assert r.evaluations < 25


def test_two_percent_noise_range_contains_the_true_dt(fem_stiffness):
    rng = np.random.default_rng(7)
    inside = 0
    for _ in range(20):
        k = np.array(fem_stiffness) * (1.0 + 0.02 * rng.standard_normal(len(LS)))
        r = fit("dls", "l", LS, k, ["Dt"], "analytic", noise=0.02)
        lo, hi = r.ranges["Dt"]
        inside += lo <= DT <= hi
    assert inside >= 17                       # +-2 standard errors: ~95 % (measured 38/40 with another seed)


def test_dn_of_the_dls_is_reported_as_undetermined(fem_stiffness):
    r = fit("dls", "l", LS, fem_stiffness, ["Dt", "Dn"], "analytic", noise=0.02)
    assert r.undetermined == ["Dn"] and r.parameters["Dt"] == pytest.approx(DT, rel=5e-3)


def test_cli_fits_the_dcb_dn_and_writes_json_and_plot(tmp_path, capsys):
    from interfaces.analytic import solve as analytic
    ks = [analytic(cases.build("dcb", Dn=0.1, a=a)).quantities["stiffness"] for a in (15.0, 25.0, 35.0)]
    code = main(["fit", "dcb", "--stiffness", ",".join(f"{k:.6g}" for k in ks), "--values", "15,25,35",
                 "--noise", "0.02", "--out", str(tmp_path)])
    assert code == 0
    out = json.loads((tmp_path / "fit.json").read_text())
    assert out["parameters"]["Dn"] == pytest.approx(0.1, rel=1e-4)
    assert (tmp_path / "dcb_fit.png").stat().st_size > 0
    assert "Dn = 0.1" in capsys.readouterr().out


def test_bad_input_is_refused():
    with pytest.raises(CaseError, match="one value per --values"):
        fit("dls", "l", [5.0, 10.0], [400.0], ["Dt"])
    with pytest.raises(CaseError, match="--fit must list Dt and/or Dn"):
        fit("dls", "l", [5.0], [400.0], ["G"], noise=0.02)
    with pytest.raises(CaseError, match="--at: case dls has no parameter 'length'"):
        fit("dls", "length", [5.0], [400.0], ["Dt"], noise=0.02)
    with pytest.raises(CaseError, match="--noise is needed"):
        fit("dls", "l", [5.0], [400.0], ["Dt"])
    with pytest.raises(SolverError, match="above the perfect-interface end"):
        fit("dls", "l", [5.0], [1e6], ["Dt"], noise=0.02)


@pytest.mark.slow
def test_least_squares_with_fem_in_the_loop(fem_stiffness):
    rng = np.random.default_rng(3)
    k = np.array(fem_stiffness) * (1.0 + 0.02 * rng.standard_normal(len(LS)))
    r = fit("dls", "l", LS, k, ["Dt"], "fem", options={"h": 0.2}, noise=0.02)
    lo, hi = r.ranges["Dt"]
    assert lo <= DT <= hi
    exact = fit("dls", "l", LS, fem_stiffness, ["Dt"], "fem", options={"h": 0.2})
    assert exact.parameters["Dt"] == pytest.approx(DT, rel=1e-4)
