"""A sweep with several curves (000 Fig 13: micro- and nanoparticle composites against D
in one sweep): every curve's points, records, table, CSV, plot and resume."""
import json

import pytest

from cases.cli import main, parse_curves
from cases.sweep import sweep
from interfaces import CaseError

D = [0.0, 1e2, 1e3, 1e5, float("inf")]
CURVES = {"micro": {}, "nano": {"radius": 7e-4, "side": 1e-3}}


def test_nano_curve_is_the_micro_curve_shifted_by_the_size_ratio():
    """Composite spheres with an imperfect interface depend on D only through D a / E
    (000 Sec 3): the nanoparticle at D equals the microparticle at D / 1000."""
    sw = sweep("particulate", "D", D, methods="analytic", workers=1, curves=CURVES)
    assert sw.labels == ["micro", "nano"]
    micro = sw.series("analytic", "bulk_modulus", 0)
    nano = sw.series("analytic", "bulk_modulus", 1)
    assert nano[3] == pytest.approx(micro[1], rel=1e-12)             # 1e5 nano = 1e2 micro
    assert nano[0] == pytest.approx(micro[0], rel=1e-12)             # debonded: no size effect
    assert nano[-1] == pytest.approx(micro[-1], rel=1e-12)           # perfect: no size effect
    assert nano[2] < micro[2]                                        # smaller particle, weaker bond


def test_curves_recorded_tabled_and_resumed(tmp_path):
    rec = tmp_path / "rec"
    first = sweep("particulate", "D", D[:2], methods="analytic", workers=1, record_dir=rec, curves=CURVES)
    names = sorted(p.name for p in (rec / "points").iterdir())
    assert names == [f"point_{k:03d}.json" for k in range(4)]
    assert json.loads((rec / "points" / "point_002.json").read_text())["curve"] == "nano"
    (rec / "points" / "point_003.json").unlink()                      # as if interrupted there
    again = sweep("particulate", "D", D[:2], methods="analytic", workers=1, record_dir=rec, resume=True,
                  curves=CURVES)
    def quantities(sw):
        return [p["analytic"]["quantities"] for p in sw.points]
    assert quantities(again) == quantities(first)
    with pytest.raises(CaseError, match="differs in curves"):
        sweep("particulate", "D", D[:2], methods="analytic", workers=1, record_dir=rec, resume=True,
              curves={"micro": {}})
    text = first.table(["bulk_modulus"])
    assert "micro: (case defaults)" in text and "nano: radius=0.0007, side=0.001" in text
    rows = first.to_csv().splitlines()
    assert rows[0] == "curve,D,method,quantity,value"
    assert rows[-1].startswith("nano,100.0,analytic,")


def test_cli_curve_option(tmp_path, capsys):
    out = tmp_path / "sw"
    assert main(["sweep", "particulate", "--param", "D", "--values", "0,1e3,inf", "--methods", "analytic",
                 "--curve", "micro:radius=0.7", "--curve", "nano:radius=7e-4,side=1e-3",
                 "--x", "log", "--out", str(out)]) == 0
    assert "nano: radius=0.0007, side=0.001" in capsys.readouterr().out
    assert (out / "particulate_sweep_D.png").stat().st_size > 1000
    assert main(["sweep", "--resume", str(out)]) == 0                # the curves come from the record


def test_curve_parsing_and_refusals():
    assert parse_curves(["a:x=1,2,3,y=inf"]) == {"a": {"x": [1, 2, 3], "y": float("inf")}}
    for bad, msg in ((["nolabel"], "LABEL:KEY=VALUE"), (["a:x=1", "a:x=2"], "given twice"),
                     ([":x=1"], "LABEL:KEY=VALUE")):
        with pytest.raises(CaseError, match=msg):
            parse_curves(bad)
    with pytest.raises(CaseError, match="sets the swept parameter D"):
        sweep("particulate", "D", D, methods="analytic", workers=1, curves={"a": {"D": 1.0}})
    with pytest.raises(CaseError, match="radius"):                    # a curve's bad override is the case's error
        sweep("particulate", "D", D, methods="analytic", workers=1, curves={"a": {"radius": 2.0}})
