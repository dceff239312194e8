"""Registry of the named cases: ``build(name, **overrides)`` and ``names()``."""
from __future__ import annotations

import inspect
import math
from typing import Callable

from interfaces import Case, CaseError

from . import contact, curved, library, shock

CASES: dict[str, Callable[..., Case]] = {
    "dls": library.dls,
    "two_layer": library.two_layer,
    "core_sleeve": library.core_sleeve,
    "dcb": library.dcb,
    "wave": library.wave,
    "particulate": library.particulate,
    "bimaterial_square": library.bimaterial_square,
    "cuboid": library.cuboid,
    "composite_spheres": curved.composite_spheres,
    "composite_cylinders": curved.composite_cylinders,
    "inclusion": curved.inclusion,
    "gap_contact": contact.gap_contact,
    "compression_20": contact.compression_20,
    "three_material_node": contact.three_material_node,
    "ellipse_compaction": contact.ellipse_compaction,
    "shock_bar": shock.shock_bar,
}


def names() -> list[str]:
    return list(CASES)


def parameters(name: str) -> dict:
    """The keyword overrides a case accepts, with their defaults."""
    fn = _builder(name)
    return {k: p.default for k, p in inspect.signature(fn).parameters.items()}


def _builder(name: str) -> Callable[..., Case]:
    if name not in CASES:
        raise CaseError(f"unknown case {name!r}; known cases: {', '.join(CASES)}")
    return CASES[name]


def build(name: str, **overrides) -> Case:
    """Build the named case with the papers' defaults and keyword overrides."""
    fn = _builder(name)
    allowed = parameters(name)
    for k in overrides:
        if k not in allowed:
            raise CaseError(f"{name} has no parameter {k!r} (parameters: {', '.join(allowed)})")
    for k, v in overrides.items():
        _check_override(name, k, v, allowed[k])
    try:
        return fn(**overrides)
    except CaseError as e:
        raise CaseError(f"{name}: {e}") from None
    except TypeError as e:  # wrong type of an override value
        raise CaseError(f"{name}: {e}") from None
    except (OverflowError, ZeroDivisionError, ValueError) as e:
        raise CaseError(f"{name}: the parameters give no valid specimen ({e}); check "
                        f"{', '.join(f'{k} = {v!r}' for k, v in overrides.items())}") from None


#: largest finite magnitude of a numeric case parameter (mm, MPa, N, s): beyond it the
#: geometry and the closed forms overflow double precision
MAX_PARAMETER = 1e30


def _check_override(name: str, key: str, value, default) -> None:
    """A parameter whose default is a number takes a number (inf only where the default
    is inf or the name is an interface parameter), of magnitude <= 1e30; booleans stay
    booleans. Names the parameter and the allowed range."""
    numeric = isinstance(default, (int, float)) and not isinstance(default, bool)
    if isinstance(default, bool):
        if not isinstance(value, bool):
            raise CaseError(f"{name}: {key} must be true or false, got {value!r}")
        return
    if not numeric and default is not None:
        return
    if default is None and not isinstance(value, (int, float)):
        return                       # optional parameter of its own kind (checked by the case)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise CaseError(f"{name}: {key} must be a number, got {value!r}")
    if math.isnan(value):
        raise CaseError(f"{name}: {key} must be a number, got NaN")
    infinite_ok = key.startswith(("D", "kb")) or (isinstance(default, float) and math.isinf(default))
    if math.isinf(value) and not (infinite_ok and value > 0):
        raise CaseError(f"{name}: {key} must be finite, got {value}")
    if math.isfinite(value) and abs(value) > MAX_PARAMETER:
        raise CaseError(f"{name}: {key} must be within +-{MAX_PARAMETER:g}, got {value:g}")


def summary(name: str) -> str:
    """First line of the builder's docstring."""
    return (inspect.getdoc(_builder(name)) or "").splitlines()[0]


#: units of the named cases' parameters (by name; "-" = dimensionless or a name)
UNITS = {"Dt": "MPa/mm", "Dn": "MPa/mm", "D": "MPa/mm", "Dn_compression": "MPa/mm", "zone_Dn": "MPa/mm",
         "kb": "MPa", "t": "mm", "l": "mm", "L": "mm", "W": "mm", "width": "mm", "height": "mm",
         "depth": "mm", "length": "mm", "a": "mm", "h": "mm", "radius": "mm", "side": "mm",
         "x_interface": "mm", "shift_x": "mm", "shift_y": "mm", "zone_y": "mm", "fem_h": "mm",
         "mpm_cell": "mm", "amplitude": "mm", "size": "mm", "E": "MPa", "stress": "MPa", "load": "N",
         "P": "N", "f": "Hz", "angle": "deg", "rho_g_cm3": "g/cm^3", "strain": "-",
         "b": "mm", "volume_fraction": "-", "outer": "mm", "gap": "mm", "K": "MPa", "G": "MPa",
         "rho": "t/mm^3", "speed": "mm/s", "fill": "-", "mu": "-", "push": "-",
         "impact_speed": "mm/s", "A1": "-", "A2": "-", "S1": "-", "gamma0": "-", "run": "-"}

#: settings that run every method of a case in seconds (for trying things out); the
#: double lap shear's 0.6 mm strips are four particle spacings at 0.3 mm cells (at 0.5 mm
#: one bond line sat mid-cell and the other on a node line: the specimen bent sideways
#: and MPM took over 20 minutes to settle)
CHEAP = {"dls": {"fem_h": 0.5, "mpm_cell": 0.3}, "two_layer": {"fem_h": 1.0, "mpm_cell": 1.0},
         "core_sleeve": {"fem_h": 0.5, "mpm_cell": 0.5},
         "dcb": {"fem_h": 0.3, "mpm_cell": 0.3}, "wave": {"mpm_cell": 2.0},
         "particulate": {"mpm_cell": 0.1}, "bimaterial_square": {"h": 0.05, "fem_h": 0.05},
         "cuboid": {"h": 0.1}, "three_material_node": {"push": 0.002},
         "ellipse_compaction": {"mpm_cell": 0.05, "strain": 0.5},
         "shock_bar": {"mpm_cell": 0.5, "length": 20.0, "height": 1.0}}


#: where a method is not cheap even at the cheap settings (shown by ``show --params``)
CHEAP_CAVEATS = {"dcb": "mpm takes about 4 minutes even there: the arms bend with a 1.6 ms period, "
                        "and settling takes 6 ms of model time, 180000 steps of 3.4e-8 s at 0.3 mm "
                        "cells (each arm two cells deep: MPM's stiffness is 6 % low there, 1.2 % "
                        "at 0.15 mm)"}


def describe_parameters(name: str) -> str:
    """The ``--set`` parameters of a case: default, unit, and the cheap settings."""
    params = parameters(name)
    lines = [f"{name}: {summary(name)}", f"{'parameter':<16}{'default':>14}  unit"]
    for k, v in params.items():
        shown = "inf" if isinstance(v, float) and math.isinf(v) else ("(derived)" if v is None else str(v))
        lines.append(f"{k:<16}{shown:>14}  {UNITS.get(k, '-')}")
    cheap = CHEAP.get(name)
    if cheap:
        lines.append("cheap settings: " + " ".join(f"--set {k}={v}" for k, v in cheap.items()))
    if name in CHEAP_CAVEATS:
        lines.append(f"  but {CHEAP_CAVEATS[name]}")
    lines.append("--set takes these parameters of the case's builder, not TOML field names; to change any "
                 f"other field: imperfect show {name} > case.toml, edit, imperfect run case.toml")
    return "\n".join(lines)
