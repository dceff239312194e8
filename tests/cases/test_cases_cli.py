"""The imperfect command line, comparisons and sweeps (analytic method: fast)."""
import json
import re
import math

import pytest

import cases
from cases.cli import main, parse_value
from cases.compare import compare
from cases.sweep import sweep


def test_list_and_show(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    for name in cases.names():
        assert name in out
    assert main(["show", "dls", "--set", "Dt=5"]) == 0
    assert 'Dt = 5.0' in capsys.readouterr().out


def test_parse_value():
    assert parse_value("inf") == math.inf
    assert parse_value("5") == 5 and isinstance(parse_value("5.0"), float)
    assert parse_value("1,2,inf") == [1, 2, math.inf]
    assert parse_value("vertical") == "vertical"
    # the papers' names: --set variant=000 must not become the number 0
    assert parse_value("000") == "000" and parse_value("002") == "002"
    assert parse_value("0") == 0 and parse_value("0.25") == 0.25 and parse_value("-3") == -3


def test_run_analytic_writes_results_csv_and_png(tmp_path, capsys):
    out = tmp_path / "dls"
    assert main(["run", "dls", "--methods", "analytic", "--set", "Dt=inf", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "beta_l" in text
    data = json.loads((out / "results.json").read_text())
    q = data["results"]["analytic"]["quantities"]
    assert q["beta_l"] == pytest.approx(22.8, abs=0.05)  # 002 Sec 3.4
    assert (out / "comparison.csv").read_text().startswith("quantity,method")
    assert (out / "dls_comparison.png").stat().st_size > 1000


def test_bad_override_and_unsupported_method_are_one_line_errors(tmp_path, capsys):
    assert main(["run", "dls", "--set", "Dt=-1", "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err.strip() == "error: dls: Dt must be >= 0, got -1"
    assert main(["run", "inclusion", "--methods", "mpm", "--out", str(tmp_path)]) == 2
    assert "does not support case 'inclusion'" in capsys.readouterr().err


def test_compare_relative_differences_against_reference():
    """(value - reference) / |reference| per quantity; FEM is the reference for a quantity
    the case's reference does not give; a method is never compared with itself."""
    from cases.compare import Comparison
    from interfaces import Result

    case = cases.build("dls", Dt=5.0)
    res = {"analytic": Result("analytic", "dls", quantities={"stiffness": 200.0}),
           "fem": Result("fem", "dls", quantities={"stiffness": 190.0, "strain_energy": 4.0}),
           "mpm": Result("mpm", "dls", quantities={"stiffness": 210.0, "strain_energy": 5.0})}
    comp = Comparison(case=case, results=res, reference="analytic")
    assert comp.relative_difference("fem", "stiffness") == pytest.approx(-0.05)
    assert comp.relative_difference("mpm", "stiffness") == pytest.approx(0.05)
    assert comp.reference_for("strain_energy") == "fem"
    assert comp.relative_difference("mpm", "strain_energy") == pytest.approx(0.25)
    assert math.isnan(comp.relative_difference("analytic", "strain_energy"))
    table = comp.table()
    assert "(-5.00%)" in table and "(+25.00%)" in table


def test_run_exit_code_when_a_requested_method_does_not_run(tmp_path, capsys):
    """A method that cannot run the case is refused up front (exit 2); one that fails
    while the others ran gives exit 3 with the others' outputs written."""
    assert main(["run", "particulate", "--methods", "analytic,cpd", "--out", str(tmp_path / "p")]) == 2
    assert "method 'cpd' does not support case 'particulate'" in capsys.readouterr().err
    assert main(["run", "dls", "--methods", "analytic,fem", "--option", "fem.solver=nonsense",
                 "--out", str(tmp_path / "d")]) == 3
    err = capsys.readouterr().err
    assert "did not run: fem" in err
    assert (tmp_path / "d" / "results.json").exists()


def test_list_advertises_only_methods_that_run(capsys, monkeypatch):
    """3D MPM runs the particulate composite, so the list shows it; a method whose
    package refuses a case (its ``supports``) is not advertised for it."""
    import mpm
    assert main(["list"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("particulate"))
    assert "mpm" in line
    monkeypatch.setattr(mpm, "supports", lambda case: "not this one" if case.analysis == "3d" else None)
    assert main(["list"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("particulate"))
    assert "mpm" not in line


def test_out_that_cannot_be_written_is_refused_before_computing(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    assert main(["run", "dls", "--methods", "analytic", "--out", str(f)]) == 2
    assert "is a file, not a folder" in capsys.readouterr().err
    own = tmp_path / "mine"
    own.mkdir()
    (own / "notes.txt").write_text("keep me")
    assert main(["run", "dls", "--methods", "analytic", "--out", str(own)]) == 2
    assert "holds other files (notes.txt)" in capsys.readouterr().err
    assert (own / "notes.txt").read_text() == "keep me"
    again = tmp_path / "again"
    assert main(["run", "dls", "--methods", "analytic", "--out", str(again)]) == 0
    assert main(["run", "dls", "--methods", "analytic", "--set", "Dt=2", "--out", str(again)]) == 0
    assert "Dt = 2" in (again / "case.toml").read_text()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]   # no staging left


def _eq40_42(Dt, t=0.6, E=10000.0, G=500.0, l=25.0, W=10.0, L=5.0):
    """002 Eq 40-42 (identical strips) written out for the 002 specimen, with the mid-bond
    jump counting the strips' own shear as the case's model does: 1/Dt -> 1/Dt + t/(2 G)
    in the slip term (the R of Eq A.4 for t1 = t2 = t)."""
    beta = math.sqrt(6 * G / (t * t * E * (1 + 2 * G / (t * Dt))))
    bl = beta * l
    slip = 3 * E * t * beta / (4 * l) * (1 / Dt + t / (2 * G)) / math.sinh(bl / 2)
    C = l / (3 * t * W * E) * (1 + (math.tanh(bl / 2) + 9 * math.tanh(bl / 4)) / (4 * bl) + slip)
    return 1 / (C + 3 * L / (2 * t * W * E))


def test_sweep_stiffness_rises_with_Dt_like_002_fig5(tmp_path):
    """Shear lag on the 002 specimen (002 Fig 5), each point against Eq 40-42 written out
    above (measured: equal to 4e-16; 429 N/mm at Dt = 1 up to 3583 N/mm at Dt = inf)."""
    values = [1.0, 5.0, 50.0, math.inf]
    sw = sweep("dls", "Dt", values, methods="analytic", workers=1)
    k = [sw.value(i, "analytic", "stiffness") for i in range(4)]
    assert all(a < b for a, b in zip(k, k[1:]))
    for Dt, ki in zip(values, k):
        assert ki == pytest.approx(_eq40_42(Dt), rel=1e-12), Dt
    from cases.plots import plot_sweep

    assert plot_sweep(sw, tmp_path / "s.png", x_transform="inverse").stat().st_size > 1000


def test_sweep_process_pool_matches_serial():
    a = sweep("dcb", "Dn", [0.1, 1.0], methods="analytic", workers=1)
    b = sweep("dcb", "Dn", [0.1, 1.0], methods="analytic", workers=2)
    assert [p["analytic"]["quantities"] for p in a.points] == [p["analytic"]["quantities"] for p in b.points]


def test_sweep_on_dask_local_cluster_matches_process_pool():
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False) as cluster:
        a = sweep("dcb", "Dn", [0.1, 1.0], methods="analytic", dask_address=cluster.scheduler_address)
    b = sweep("dcb", "Dn", [0.1, 1.0], methods="analytic", workers=2)
    assert [p["analytic"]["quantities"] for p in a.points] == [p["analytic"]["quantities"] for p in b.points]


def test_show_params_lists_set_parameters_with_units(capsys):
    assert main(["show", "two_layer", "--params"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"^Dt\s+5\.0\s+MPa/mm$", out, flags=re.M)
    assert re.search(r"^mpm_cell\s+0\.25\s+mm$", out, flags=re.M)
    assert "cheap settings: --set fem_h=1.0 --set mpm_cell=1.0" in out and "  but " not in out
    assert main(["show", "dcb", "--params"]) == 0
    assert "cheap settings: --set fem_h=0.3 --set mpm_cell=0.3\n  but mpm takes about 4 minutes" \
        in capsys.readouterr().out
    for name in cases.names():              # every case's parameters have a unit entry
        assert main(["show", name, "--params"]) == 0
    capsys.readouterr()


def _fem_raises(monkeypatch, error: Exception) -> None:
    """cases.compare runs fem as raising ``error``, every other method as usual."""
    import cases.compare as C
    real = C.run

    def run(case, method, **options):
        if method == "fem":
            raise error
        return real(case, method, **options)
    monkeypatch.setattr(C, "run", run)


def test_a_method_failing_unexpectedly_is_reported_and_the_others_kept(tmp_path, monkeypatch, capsys):
    """An exception that is not a CaseError / SolverError (a defect, or a library giving
    up: scikit-fem's inverse mapping on a 25 m bond line) costs that method only: run
    reports its type, message and line, keeps the other methods' results, exits 3."""
    _fem_raises(monkeypatch, RuntimeError("inverse mapping did not converge"))
    comp = compare(cases.build("dls"), "fem,analytic", progress=False)
    assert set(comp.results) == {"analytic"}
    assert re.fullmatch(r"RuntimeError: inverse mapping did not converge \(at test_cases_cli\.py:\d+\)",
                        comp.failures["fem"])
    assert main(["run", "dls", "--methods", "fem,analytic", "--out", str(tmp_path / "o")]) == 3
    err = capsys.readouterr().err
    assert "[fem] not run: RuntimeError: inverse mapping did not converge" in err
    assert (tmp_path / "o" / "results.json").exists()


def test_a_method_out_of_memory_says_to_coarsen_and_the_others_are_kept(monkeypatch):
    _fem_raises(monkeypatch, MemoryError())
    comp = compare(cases.build("dls"), "fem,analytic", progress=False)
    assert set(comp.results) == {"analytic"}
    assert comp.failures["fem"] == "out of memory: use a coarser discretization (element_size, cell, h)"
