"""Result JSON and VTK output."""
import math

import meshio
import numpy as np

from interfaces import Result


def test_result_json_round_trip_and_vtk(tmp_path):
    pos = np.random.default_rng(0).random((10, 2))
    r = Result(method="fem", case_name="x", quantities={"stiffness": 12.5, "limit": math.inf},
               fields={"position": pos, "displacement": pos * 0.01, "material": np.arange(10) % 2},
               profiles={"axis": {"s": np.linspace(0, 1, 5), "uy": np.zeros(5)}}, timings={"total": 0.1})
    r.warn("test warning")
    back = Result.from_json(r.to_json())
    assert back.quantities == {"stiffness": 12.5, "limit": math.inf}
    np.testing.assert_allclose(back.fields["position"], pos)
    np.testing.assert_allclose(back.profiles["axis"]["s"], np.linspace(0, 1, 5))
    assert back.diagnostics["warnings"] == ["test warning"]
    path = r.to_vtk(tmp_path / "r.vtu")
    mesh = meshio.read(path)
    assert mesh.points.shape == (10, 3)
    np.testing.assert_allclose(mesh.point_data["displacement"][:, :2], pos * 0.01)
