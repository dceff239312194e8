"""Closed-form reference models for imperfect interfaces (pure numpy/scipy).

* double lap shear by generalized shear lag, general two-material form and the
  identical-strip closed form (002 Eq 40-42, 50, 51, Appendix A; ERRATA 3-4);
* double cantilever beam on an elastic foundation (002 Eq 46-47, Appendix B);
* normal-incidence wave energy transmission through a spring interface
  (002 Eq 48, ERRATA 6, and the general two-material form; Eq 49 pulse);
* composite-spheres bulk modulus with a spring interface (000 Sec 3, Hashin);
* composite-cylinders transverse (plane-strain) bulk modulus with a spring interface;
* interphase -> interface parameters (002 Eq 52);
* homogeneous compression of a neo-Hookean block (004 Eq 18; plane strain, uniaxial
  stress and strain), the reference of the finite-strain MPM tests;
* the shock Hugoniot of a Mie-Grueneisen solid (004 Sec 4.3, Eq 51).

``registry.MODELS`` / ``registry.PROFILES`` map the model names used in
``case.analytic`` to functions returning scalar quantities / profile curves;
``solve(case)`` returns a :class:`interfaces.Result` with ``method="analytic"``.
Units: mm, N, MPa, s, tonne/mm^3; Dn, Dt in MPa/mm.
"""
from interfaces.analytic.composite_cylinders import (CompositeCylinders, composite_cylinders_bulk_modulus,
                                                      plane_strain_bulk_modulus)
from interfaces.analytic.composite_spheres import (CompositeSpheres, bulk_shear_from_young_poisson,
                                                    composite_spheres_bulk_modulus, hashin_bulk_modulus,
                                                    sphere_in_cube_volume_fraction)
from interfaces.analytic.dcb import (DoubleCantileverBeam, dcb_compliance, dcb_deflection,
                                     dcb_kb_from_stiffness, dcb_stiffness)
from interfaces.analytic.dls import (DoubleLapShear, dls_axial_stress, dls_beta_l_max, dls_compliance,
                                     dls_identical_beta, dls_identical_compliance, dls_identical_stiffness,
                                     dls_long_bond_stiffness, dls_shear_stress, dls_stiffness)
from interfaces.analytic.hugoniot import ShockHugoniot, ShockState
from interfaces.analytic.hyperelastic import (neo_hookean_compression, nominal_stress_for_stretch,
                                              stretch_for_nominal_stress)
from interfaces.analytic.interphase import interphase_to_interface
from interfaces.analytic.registry import MODELS, PROFILES, model_names
from interfaces.analytic.solve import solve
from interfaces.analytic.waves import (bar_wave_speed, dilatational_wave_speed, impedance,
                                       pulse_transmission, wave_amplitude_ratios, wave_reflection,
                                       wave_transmission, wave_transmission_identical)

__all__ = [
    "CompositeCylinders", "composite_cylinders_bulk_modulus", "plane_strain_bulk_modulus",
    "CompositeSpheres", "bulk_shear_from_young_poisson", "composite_spheres_bulk_modulus",
    "hashin_bulk_modulus", "sphere_in_cube_volume_fraction",
    "DoubleCantileverBeam", "dcb_compliance", "dcb_deflection", "dcb_kb_from_stiffness", "dcb_stiffness",
    "DoubleLapShear", "dls_axial_stress", "dls_beta_l_max", "dls_compliance", "dls_identical_beta",
    "dls_identical_compliance", "dls_identical_stiffness", "dls_long_bond_stiffness",
    "dls_shear_stress", "dls_stiffness",
    "ShockHugoniot", "ShockState", "interphase_to_interface",
    "neo_hookean_compression", "nominal_stress_for_stretch", "stretch_for_nominal_stress",
    "MODELS", "PROFILES", "model_names",
    "bar_wave_speed", "dilatational_wave_speed", "impedance", "pulse_transmission",
    "wave_amplitude_ratios", "wave_reflection", "wave_transmission", "wave_transmission_identical",
    "solve",
]

