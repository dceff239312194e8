"""The interpenetration measures of 004 Fig 6 (mpm/interpenetration.py): a particle is inside
another material when its centre lies in the deformed domain F_q [-l, l]^D of a particle
q of that material; the bodies' area over the area of the container of rigid walls."""
import numpy as np
import pytest

from mpm.interpenetration import cut_off_from_own_material, inside_other_material

S = 0.5                      # particle spacing
HALF = np.full(2, 0.5 * S)


def _block(x0: float, y0: float, n: int = 4) -> np.ndarray:
    g = (np.arange(n) + 0.5) * S
    return np.array([(x0 + a, y0 + b) for a in g for b in g])


def _count(a: np.ndarray, b: np.ndarray, F=None) -> int:
    x = np.vstack([a, b])
    field = np.repeat([0, 1], [len(a), len(b)])
    F = np.broadcast_to(np.eye(2), (len(x), 2, 2)) if F is None else F
    return int(inside_other_material(x, field, F, HALF).sum())


def test_touching_blocks_do_not_interpenetrate_and_overlapping_ones_do():
    a = _block(0.0, 0.0)
    assert _count(a, _block(4 * S, 0.0)) == 0                  # domains touch along x = 2
    assert _count(a, _block(4 * S - 0.4 * S, 0.0)) == 0        # overlap < half a particle
    # overlap of 0.6 spacing: the facing columns (4 + 4 particles) have centres inside
    assert _count(a, _block(4 * S - 0.6 * S, 0.0)) == 8
    # same material: never counted
    x = np.vstack([a, a + 0.1])
    assert not inside_other_material(x, np.zeros(len(x), int), np.broadcast_to(np.eye(2), (len(x), 2, 2)),
                                     HALF).any()


def test_cut_off_counts_particles_carried_into_another_material_not_sheared_domains():
    """Two touching 4 x 4 blocks: none cut off. A particle of the left block moved one
    spacing into the right one (centre on a right-block particle's row, between two of its
    columns) is cut off; one moved half a spacing is not, though its centre then lies in
    a right-block particle's domain."""
    a, b = _block(0.0, 0.0), _block(4 * S, 0.0)
    field = np.repeat([0, 1], [len(a), len(b)])
    assert not cut_off_from_own_material(np.vstack([a, b]), field).any()
    deep = a.copy()
    deep[-3] = (4.5 * S + 0.5 * S, 1.5 * S)       # the right column's second particle, into B
    hit = cut_off_from_own_material(np.vstack([deep, b]), field)
    assert np.flatnonzero(hit).tolist() == [len(a) - 3]
    shallow = a.copy()
    shallow[-3] = (4.0 * S + 0.1 * S, 1.5 * S)
    x = np.vstack([shallow, b])
    assert not cut_off_from_own_material(x, field).any()
    assert inside_other_material(x, field, np.broadcast_to(np.eye(2), (len(x), 2, 2)), HALF)[len(a) - 3]
    assert not cut_off_from_own_material(x[:1], field[:1]).any()      # a lone particle


def test_the_domain_follows_the_deformation_gradient():
    """A point off the undeformed square of q but inside its sheared domain counts, and
    the other way round."""
    xq = np.zeros((1, 2))
    xp = np.array([[0.45, 0.2]])           # beyond l = 0.25 along x
    F_id = np.eye(2)[None]
    F_shear = np.array([[[1.0, 1.0], [0.0, 1.0]]])      # x = X + Y: (0.45, 0.2) <- (0.25, 0.2)
    x = np.vstack([xq, xp])
    field = np.array([0, 1])
    assert not inside_other_material(x, field, np.vstack([F_id, F_id]), HALF).any()
    hit = inside_other_material(x, field, np.vstack([F_shear * 1.01, F_id]), HALF)
    assert hit.tolist() == [False, True]


def test_container_area_is_between_the_facing_domain_edges():
    """Walls one particle thick around a 2 x 1 region: the container is the region
    between their domains' facing edges, whatever their length or overlap at corners."""
    from interfaces.errors import CaseError
    from mpm.interpenetration import container_area
    names = ["left", "right", "floor", "lid"]
    col = np.arange(-1, 6) * S
    row = np.arange(-1, 10) * S
    x = np.vstack([np.c_[np.full(col.size, -0.5 * S), col],          # x in [-S, 0]
                   np.c_[np.full(col.size, 2.0 + 0.5 * S), col],     # x in [2, 2 + S]
                   np.c_[row, np.full(row.size, -0.5 * S)],          # y in [-S, 0]
                   np.c_[row, np.full(row.size, 1.0 + 0.5 * S)]])    # y in [1, 1 + S]
    field = np.repeat([0, 1, 2, 3], [col.size, col.size, row.size, row.size])
    sides = {"left": "left", "right": "right", "bottom": "floor", "top": "lid"}
    assert container_area(sides, names, x, field, np.full(2, S)) == pytest.approx(2.0, rel=1e-12)
    with pytest.raises(CaseError, match="left, right, bottom, top"):
        container_area({"left": "left"}, names, x, field, np.full(2, S))
    with pytest.raises(CaseError, match="do not enclose"):
        container_area(dict(sides, top="floor"), names, x, field, np.full(2, S))


def test_ellipse_compaction_reports_its_area_over_the_box(tmp_path):
    """Before the piston reaches the ellipses (5 %) their area is the undeformed one and
    the box is 1 x 1.9 mm. The last VTK frame carries the final particles with their F
    (CPDI and finite-strain runs): with particle domains grown to three times their size,
    so that neighbours of two ellipses overlap, it finds the same particles inside another
    ellipse as the result's fields."""
    import cases
    import meshio
    from cases.methods import run
    case = cases.build("ellipse_compaction", mpm_cell=0.1, strain=0.05, contact="DF")
    res = run(case, "mpm", progress=False, shape="cpdi", vtk_dir=str(tmp_path), vtk_frames=2)
    names = np.array([b.name for b in case.bodies])
    mat = res.fields["material"]
    ell = np.char.startswith(names[mat], "ellipse")
    F = res.fields["deformation_gradient"].reshape(-1, 3, 3)[:, :2, :2]
    assert np.any(np.abs(F - np.eye(2)) > 1e-6)                               # deformed
    last = meshio.read(sorted(tmp_path.glob("*.vtu"))[-1])
    np.testing.assert_array_equal(last.point_data["deformation_gradient"],
                                  res.fields["deformation_gradient"])
    np.testing.assert_array_equal(last.point_data["material"], mat)
    grown = np.full(2, 3 * 0.25 * 0.1)
    x = res.fields["position"] + res.fields["displacement"]
    from_result = inside_other_material(x[ell], mat[ell], F[ell], grown)
    F_frame = last.point_data["deformation_gradient"].reshape(-1, 3, 3)[:, :2, :2]
    from_frame = inside_other_material(last.points[ell, :2], mat[ell], F_frame[ell], grown)
    assert from_result.sum() > 0
    np.testing.assert_array_equal(from_frame, from_result)
    area = float(np.sum(res.fields["volume"][ell])) / case.thickness
    assert res.quantities["material_area_over_container"] == pytest.approx(area / 1.9, rel=2e-3)
    assert 0.5 < area / 1.9 < 0.55
