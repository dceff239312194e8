"""Command-line arguments shared by the 002 Fig 10 / Fig 11 scripts of this folder."""
from __future__ import annotations

import argparse
from pathlib import Path


def parse(doc: str, **extra) -> tuple[argparse.Namespace, Path]:
    """--mpm-cell, --fem-h (mm), --height (mm of the strip), --out, plus ``extra``
    (name: (type, default)); returns the arguments and the created output folder."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    for name, (kind, default) in extra.items():
        ap.add_argument(f"--{name}", type=kind, default=default)
    ap.add_argument("--mpm-cell", type=float, default=0.5)
    ap.add_argument("--fem-h", type=float, default=0.5)
    ap.add_argument("--height", type=float, default=2.0)
    ap.add_argument("--out", default="docs/wave")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    return args, out
