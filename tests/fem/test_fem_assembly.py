"""The batched bulk assembly equals scikit-fem's BilinearForm assembly of the same integral."""
import numpy as np
import pytest

from cases.library import bimaterial_square, dls
from fem.assembly import bulk_stiffness, elasticity_form
from fem.discretization import discretize
from interfaces.case import Body, Case
from interfaces.geometry import Rectangle
from interfaces.materials import IsotropicElastic, TransverselyIsotropicElastic


def _cases():
    wood = TransverselyIsotropicElastic(E_A=10000, E_T=1000, G_A=500, nu_A=0.2, fiber=(0.6, 0.8))
    axi = Case(name="axi", analysis="axisymmetric", materials={"w": wood, "s": IsotropicElastic(E=200.0, nu=0.3)},
               bodies=[Body("core", Rectangle(0, 0, 1.0, 2.0), "w"), Body("sleeve", Rectangle(1.0, 0, 0.5, 2.0), "s")])
    from cases.curved import composite_spheres, inclusion   # gmsh: curved 6-node triangles
    return [(dls(Dt=5.0), 0.3), (bimaterial_square(interface="diagonal"), 0.25), (axi, 0.25),
            (inclusion(shape="ellipse", width=4.0), 0.5), (composite_spheres(), 0.2)]


@pytest.mark.parametrize("case,h", _cases())
@pytest.mark.parametrize("order", [1, 2])
def test_batched_bulk_stiffness_equals_scikit_fem_form(case, h, order):
    disc = discretize(case, h, order, 2 * order, 1e7)
    moduli = [case.material_of(b.name).stiffness(case.analysis) for b in case.bodies]
    K = bulk_stiffness(disc.basis, disc.element_body, moduli, disc.thickness, disc.axisymmetric)
    C = np.stack(moduli)[disc.element_body]
    pattern = np.argwhere(np.any(C != 0.0, axis=0))
    nq = disc.basis.X.shape[1]
    fields = {f"c{i}{j}": np.repeat(C[:, i, j][:, None], nq, axis=1) for i, j in pattern}
    K_ref = elasticity_form(pattern, disc.thickness, disc.axisymmetric).assemble(disc.basis, **fields)
    assert abs(K - K_ref).max() <= 1e-13 * abs(K_ref).max()
    assert abs(K - K.T).max() <= 1e-13 * abs(K).max()


@pytest.mark.parametrize("angle", [0.0, 30.0])
@pytest.mark.parametrize("order", [1, 2])
def test_jump_space_interface_energy_equals_002_element_matrices(angle, order):
    """The solver's interface stiffness on jump unknowns (interface frame) gives the same
    energy as the 002 Eq 15-19 element matrices on the element DOFs (fem.interface_element),
    for any displacement: checks node pairing, side orientation and frames."""
    from fem.interface_element import stiffness_batch
    from fem.solver import _interface_elements, _interface_operators
    case = dls(Dt=7.0, Dn=3.0, angle=angle)
    disc = discretize(case, 0.3, order, 2 * order, 1e7)
    ielems = _interface_elements(case, disc, [])
    pairs, jumps, K_jump, _ = _interface_operators(disc, ielems)
    rng = np.random.default_rng(5)
    for _ in range(3):
        u = rng.normal(size=disc.ndof)
        J = jumps @ u
        e_jump = 0.5 * J @ (K_jump @ J)
        e_elem = sum(0.5 * np.einsum("mi,mij,mj->", u[el.dofs],
                                     stiffness_batch(el.xy, el.Dn, el.Dt, thickness=case.thickness), u[el.dofs])
                     for el in ielems)
        assert e_jump == pytest.approx(e_elem, rel=1e-12)
