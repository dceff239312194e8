"""The neo-Hookean material of 004 Eq 18 and the closed-form homogeneous compression."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from interfaces import CaseError, NeoHookean
from interfaces.analytic.hyperelastic import neo_hookean_compression
from interfaces.materials import VOLUMETRIC_TERMS, material_from_dict

MAT = NeoHookean(K=2450.0, G=940.0)


def _random_F(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.eye(3) + 0.3 * rng.uniform(-1.0, 1.0, (3, 3))


@pytest.mark.parametrize("volumetric", VOLUMETRIC_TERMS)
def test_cauchy_stress_is_the_derivative_of_the_energy(volumetric):
    """sigma = (1/J) dW/dF F^T, dW/dF by central differences of W (Eq 18)."""
    mat = NeoHookean(K=2450.0, G=940.0, volumetric=volumetric)
    for seed in range(3):
        F = _random_F(seed)
        h = 1e-6
        dW = np.zeros((3, 3))
        for i in range(3):
            for j in range(3):
                E = np.zeros((3, 3))
                E[i, j] = h
                dW[i, j] = (mat.energy_density(F + E) - mat.energy_density(F - E)) / (2 * h)
        sigma_fd = dW @ F.T / np.linalg.det(F)
        np.testing.assert_allclose(mat.cauchy_stress(F), sigma_fd, rtol=1e-7, atol=1e-6)


def test_eq18_volumetric_term_and_small_strain_limit():
    """U(J) = K/2 ((J^2 - 1)/2 - ln J) by default; at small strain sigma = C eps with the
    isotropic stiffness of K and G."""
    J = 0.8
    assert float(MAT.volumetric_energy(J)) == pytest.approx(0.5 * 2450.0 * (0.5 * (J * J - 1) - np.log(J)))
    eps = 1e-7 * np.array([[1.0, 0.3, -0.2], [0.3, -2.0, 0.5], [-0.2, 0.5, 0.7]])
    sigma = MAT.cauchy_stress(np.eye(3) + eps)
    lam = MAT.K - 2.0 * MAT.G / 3.0
    linear = lam * np.trace(eps) * np.eye(3) + 2.0 * MAT.G * eps
    np.testing.assert_allclose(sigma, linear, rtol=1e-6, atol=1e-12 * MAT.K)


def test_volumetric_option_is_validated_and_read_from_toml():
    with pytest.raises(CaseError, match="volumetric must be one of eq18"):
        NeoHookean(K=1.0, G=1.0, volumetric="quadratic")
    mat = material_from_dict({"type": "neo_hookean", "K": 2.0, "G": 1.0,
                              "volumetric": "J_minus_1_squared"})
    assert float(mat.volumetric_stress(1.5)) == pytest.approx(1.0)


@pytest.mark.parametrize("lateral", ["plane_strain_free", "uniaxial_stress", "uniaxial_strain"])
def test_closed_form_compression_is_consistent(lateral):
    """Free lateral sides carry no stress, and the nominal stress is the work conjugate
    of the stretch: P_yy = dW/dlam along the path (lateral stresses do no work: zero, or
    at fixed stretch)."""
    lams = np.linspace(0.8, 1.0, 5)
    st = neo_hookean_compression(MAT, lams, lateral)
    if lateral != "uniaxial_strain":
        np.testing.assert_allclose(st.sigma_lateral, 0.0, atol=1e-9 * MAT.K)
        assert np.all(st.lateral_stretch[:-1] > 1.0)
    h = 1e-6
    dW = (neo_hookean_compression(MAT, lams + h, lateral).energy_density
          - neo_hookean_compression(MAT, lams - h, lateral).energy_density) / (2 * h)
    np.testing.assert_allclose(st.nominal_axial, dW, rtol=1e-6, atol=1e-6)
    assert st.sigma_axial[-1] == pytest.approx(0.0, abs=1e-9)


def test_uniaxial_strain_closed_form():
    """F = diag(1, lam, 1): sigma_yy = 2G/3 lam^(-5/3) (lam^2 - 1) + K/2 (lam - 1/lam)."""
    lam = 0.8
    st = neo_hookean_compression(MAT, lam, "uniaxial_strain")
    expected = 2 * MAT.G / 3 * lam ** (-5 / 3) * (lam**2 - 1) + MAT.K / 2 * (lam - 1 / lam)
    assert st.sigma_axial[0] == pytest.approx(expected, rel=1e-13)


def test_small_strain_methods_refuse_finite_strain_materials():
    """FEM and CPD solve small-strain linear elasticity (CPD from elastic constants): a
    neo-Hookean body is refused in one line, never run through its linear stiffness,
    and `imperfect list` / `--methods all` offer only mpm."""
    import fem
    import peridynamics
    from cases.library import bimaterial_square
    from cases.methods import supported_methods
    rubber = NeoHookean(K=2450.0, G=940.0)
    case = dataclasses.replace(bimaterial_square(), materials={"A": rubber, "B": rubber})
    for name, mod in (("fem", fem), ("cpd", peridynamics)):
        assert "finite-strain material; " + name in mod.supports(case)
        with pytest.raises(CaseError, match=f"{name}: materials.A is NeoHookean, a finite-strain material"):
            mod.solve(case)
    assert supported_methods(case) == ["mpm"]
