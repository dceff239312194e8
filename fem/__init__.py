"""Static FEM with imperfect interface elements (002 Sec 2.1-2.2) on scikit-fem.

``fem.interface_element`` is numpy-only and usable on its own; ``fem.solve`` (which
needs scikit-fem) is imported lazily on first use so that ``import fem`` stays light.
"""
from __future__ import annotations

__all__ = ["solve", "supports", "interface_element"]


def supports(case) -> str | None:
    """None when FEM can run ``case``, else the one-line reason (``imperfect list`` and
    ``--methods all`` ask it): FEM here is small-strain linear elasticity."""
    from interfaces.materials import small_strain_refusal
    return small_strain_refusal(case, "fem")


def __getattr__(name):
    if name == "solve":
        from .solver import solve
        return solve
    if name == "interface_element":
        from . import interface_element
        return interface_element
    raise AttributeError(f"module 'fem' has no attribute {name!r}")
