"""Solver options of :func:`mpm.solve`: defaults, merging with the case, validation."""
from __future__ import annotations

import math
import os

import numpy as np

from interfaces.errors import CaseError, check_flag, check_integer, check_number, check_vector

from .extrapolation import NODAL_DISPLACEMENT_CODES
from .multimaterial import DEFAULT_OPTIONS as MULTIMATERIAL
from .shape import SHAPE_CODES

#: core options (the multimaterial options of mpm.multimaterial.DEFAULT_OPTIONS are
#: passed through to build_pair_tables unchanged)
DEFAULTS: dict = {
    "cell": None,            # mm, scalar or per axis (required here or in case.discretization.mpm)
    "ppc": 2,                # particles per cell per axis
    "shape": "ugimp",        # ugimp | linear | b2 | cpdi | b2cpdi (mpm/cpdi.py)
    "cfl": 0.5,              # dt = cfl * min(cell) / max wave speed
    "dt": None,              # explicit time step (overrides cfl)
    "damping": "grid",       # grid | kinetic | none
    "alpha": None,           # grid damping (1/s); None = adaptive 2 omega (critical for the Rayleigh-quotient mode of the current deformation)
    "pic": None,             # fraction of the PIC (or XPIC(m)) velocity blended into FLIP
                             # (0 = pure FLIP); default 0, or 1 (pure XPIC) with xpic
    "xpic": 0,               # XPIC(m) order m >= 1 (004 Eq 35-44, mpm/xpic.py); 0 or None = off
    "xpic_correction": True,  # multimaterial XPIC with the Delta v term of the initial
                              # contact correction (004 Eq 37); false = "uncorrected"
    "update": "auto",        # auto | usl | musl | usf (auto: usl when every body edge lies on grid lines, else musl)
    "ramp_time": None,       # s; default: the traction ramp_time, else one estimated period T1
    "max_time": None,        # s; default ramp + 40 T1
    "tol": 1e-6,             # stop when kinetic / (strain + interface) energy < tol over half a period after the ramp
    "tol_energy": 1e-4,      # ... and the mean stored energy moves < tol_energy x itself between half periods
    "padding": 3,            # empty cells around the bodies
    "nodal_displacement": "linear",  # multimaterial nodes: linear (000 Eq 13 extrapolated from
                                     # the centroid to the node, mpm/extrapolation.py) | average (Eq 13)
    "grid_anchor": "bounds",  # node lines through: bounds (lower corner of the case) | origin | [x, y]
    "progress": None,        # None = auto (runs longer than ~5 s), True / False
    "vtk_dir": None,         # write a VTU series + .pvd there
    "vtk_frames": 20,        # number of VTU frames over the run
    "blowup": 20.0,          # divergence if kinetic + strain energy > blowup x (work done + tiny)
    "history_points": 2000,  # energy history samples kept in the Result
    "checkpoint": None,      # file (.npz) the run's state is saved to (mpm/checkpoint.py)
    "checkpoint_every": 300.0,  # s of wall time between checkpoints (and one on Ctrl-C)
    "resume": False,         # continue from the checkpoint file when it exists
    "initial_velocity": None,  # {body: [vx, vy(, vz)]} mm/s: bodies moving at t = 0 (an impact)
}


def merge(case, overrides: dict) -> dict:
    """Defaults <- case.discretization['mpm'] <- keyword overrides, then validated."""
    opts = dict(DEFAULTS)
    opts.update(case.options_for("mpm", **overrides))
    unknown = sorted(set(opts) - set(DEFAULTS) - set(MULTIMATERIAL))
    if unknown:
        raise CaseError(f"mpm option {unknown[0]!r} is unknown; options: "
                        f"{', '.join(sorted(set(DEFAULTS) | set(MULTIMATERIAL)))}")
    D = case.dimension
    if opts["cell"] is None:
        raise CaseError("discretization.mpm.cell (mm) is required: pass cell=... to mpm.solve "
                        "or set it in the case")
    cell = check_vector("mpm option cell", opts["cell"], D, broadcast=True)
    if np.any(cell <= 0):
        raise CaseError(f"mpm option cell must be > 0 (one value or {D}), got {opts['cell']!r}")
    opts["cell"] = cell
    shape = str(opts["shape"]).lower()
    if shape not in SHAPE_CODES:
        raise CaseError(f"mpm option shape must be one of {sorted(SHAPE_CODES)}, got {opts['shape']!r}")
    opts["shape"] = shape
    opts["cfl"] = check_number("mpm option cfl", opts["cfl"], low=0, high=1, low_open=True)
    if opts["dt"] is not None:
        opts["dt"] = check_number("mpm option dt", opts["dt"], low=0, low_open=True)
    damping = str(opts["damping"]).lower()
    if damping not in ("grid", "kinetic", "none"):
        raise CaseError(f"mpm option damping must be 'grid', 'kinetic' or 'none', got {opts['damping']!r}")
    opts["damping"] = damping
    if opts["alpha"] is not None:
        opts["alpha"] = check_number("mpm option alpha", opts["alpha"], low=0)
    _xpic_options(opts)
    upd = str(opts["update"]).lower()
    if upd not in ("auto", "usl", "usf", "musl"):
        raise CaseError(f"mpm option update must be 'auto', 'usl', 'musl' or 'usf', got {opts['update']!r}")
    opts["update"] = upd
    for key in ("ramp_time", "max_time"):
        if opts[key] is not None:
            opts[key] = check_number(f"mpm option {key}", opts[key], low=0, low_open=(key == "max_time"))
    opts["tol"] = check_number("mpm option tol", opts["tol"], low=0, high=1, low_open=True)
    opts["tol_energy"] = check_number("mpm option tol_energy", opts["tol_energy"], low=0, high=1,
                                      low_open=True)
    opts["padding"] = check_integer("mpm option padding", opts["padding"], low=2, high=100)
    opts["vtk_frames"] = check_integer("mpm option vtk_frames", opts["vtk_frames"], low=1, high=100000)
    opts["blowup"] = check_number("mpm option blowup", opts["blowup"], low=1, low_open=True)
    opts["history_points"] = check_integer("mpm option history_points", opts["history_points"],
                                           low=10, high=10**7)
    nd = str(opts["nodal_displacement"]).lower()
    if nd not in NODAL_DISPLACEMENT_CODES:
        raise CaseError(f"mpm option nodal_displacement must be one of "
                        f"{sorted(NODAL_DISPLACEMENT_CODES)}, got {opts['nodal_displacement']!r}")
    opts["nodal_displacement"] = nd
    opts["grid_anchor"] = _anchor(opts["grid_anchor"], D)
    if opts["max_time"] is not None and not math.isfinite(opts["max_time"]):
        raise CaseError("mpm option max_time must be finite")
    _checkpoint_options(opts)
    opts["initial_velocity"] = _initial_velocity(opts["initial_velocity"], case)
    return opts


def _initial_velocity(value, case) -> dict:
    """initial_velocity: None or {body name: D finite velocity components (mm/s)}."""
    if value is None:
        return {}
    names = [b.name for b in case.bodies]
    D = case.dimension
    if not isinstance(value, dict):
        raise CaseError("mpm option initial_velocity must map body names to velocities "
                        f"[{D} components] (mm/s), got {value!r}")
    out = {}
    for body, vel in value.items():
        if body not in names:
            raise CaseError(f"mpm option initial_velocity: unknown body {body!r}; bodies: "
                            f"{', '.join(names)}")
        try:
            arr = np.asarray(vel, float) if np.ndim(vel) == 1 else None
        except (TypeError, ValueError):
            arr = None
        if arr is None or arr.shape != (D,) or not np.all(np.isfinite(arr)):
            raise CaseError(f"mpm option initial_velocity.{body} must be {D} finite velocity "
                            f"components (mm/s), got {vel!r}")
        out[body] = arr.tolist()
    return out


#: largest XPIC order accepted (004 uses m = 5; each order costs one S+ S pass)
MAX_XPIC = 50


def _xpic_options(opts: dict) -> None:
    """xpic: None or an integer 0 <= m <= MAX_XPIC; xpic_correction: a boolean; pic: a
    fraction in [0, 1], default 1 with xpic (pure XPIC(m)) and 0 without (pure FLIP)."""
    m = opts["xpic"]
    if m is None or m is False:
        m = 0
    if isinstance(m, bool) or not isinstance(m, (int, np.integer, float)) or not math.isfinite(m) \
            or float(m) != int(m) or not 0 <= int(m) <= MAX_XPIC:
        raise CaseError(f"mpm option xpic must be an integer order m in 1..{MAX_XPIC} "
                        f"(0 or None: off), got {opts['xpic']!r}")
    opts["xpic"] = int(m)
    opts["xpic_correction"] = check_flag("mpm option xpic_correction", opts["xpic_correction"])
    if opts["pic"] is None:
        opts["pic"] = 1.0 if opts["xpic"] else 0.0
    opts["pic"] = check_number("mpm option pic", opts["pic"], low=0, high=1)


def _checkpoint_options(opts: dict) -> None:
    """checkpoint: a file path or None; checkpoint_every: s >= 0; resume: a boolean;
    progress: a boolean or None; vtk_dir: a folder path or None."""
    if opts["checkpoint"] is not None and not isinstance(opts["checkpoint"], (str, os.PathLike)):
        raise CaseError(f"mpm option checkpoint must be a file path, got {opts['checkpoint']!r}")
    opts["checkpoint_every"] = check_number("mpm option checkpoint_every", opts["checkpoint_every"],
                                            low=0, high=1e9)
    opts["resume"] = check_flag("mpm option resume", opts["resume"])
    if opts["progress"] is not None:
        opts["progress"] = check_flag("mpm option progress (or None: automatic)", opts["progress"])
    if opts["vtk_dir"] is not None and not isinstance(opts["vtk_dir"], (str, os.PathLike)):
        raise CaseError(f"mpm option vtk_dir must be a folder path, got {opts['vtk_dir']!r}")
    if opts["resume"] and not opts["checkpoint"]:
        raise CaseError("mpm option resume needs the checkpoint option (the file to continue from)")


def _anchor(value, D: int):
    """grid_anchor -> None (lower corner of the case bounds) or a point (D,)."""
    if isinstance(value, str):
        key = value.lower()
        if key == "bounds":
            return None
        if key == "origin":
            return np.zeros(D)
    elif value is None:
        return None
    else:
        try:
            return check_vector("mpm option grid_anchor", value, D, broadcast=True)
        except CaseError:
            pass
    raise CaseError(f"mpm option grid_anchor must be 'bounds', 'origin' or a point of {D} "
                    f"finite coordinates (mm) that node lines pass through, got {value!r}")
