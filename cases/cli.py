"""The ``imperfect`` command line: list, show, run and sweep the named cases.

    imperfect list
    imperfect show dls --set Dt=5
    imperfect run dls --methods all --set Dt=5 --out out/dls
    imperfect sweep dls --param Dt --values 1,2,5,10,50,inf --methods fem,mpm,analytic --out out/sweep
"""
from __future__ import annotations

import argparse
import json
import math
import re
import sys
from pathlib import Path

from interfaces import Case, CaseError, SolverError

from . import registry
from .compare import compare
from .plots import plot_comparison, plot_sweep
from .sweep import sweep


def parse_value(text: str):
    """Parse a --set value: inf, numbers, true/false, comma lists, else the string.

    Digits with a leading zero (``variant=000``, ``002``) stay strings: they are names
    (the papers' numbers), and Python's own integer syntax rejects them too."""
    t = text.strip()
    if "," in t:
        return [parse_value(x) for x in t.split(",")]
    low = t.lower()
    if low in ("inf", "+inf", "infinity"):
        return math.inf
    if low in ("true", "false"):
        return low == "true"
    if re.fullmatch(r"[+-]?0\d+", t):
        return t
    for conv in (int, float):
        try:
            return conv(t)
        except ValueError:
            pass
    return t


def parse_assignments(items) -> dict:
    out = {}
    for item in items or []:
        if "=" not in item:
            raise CaseError(f"--set expects key=value, got {item!r}")
        k, v = item.split("=", 1)
        out[k.strip()] = parse_value(v)
    return out


def parse_options(items) -> dict:
    """``--option fem.order=1`` -> {"fem": {"order": 1}}."""
    out: dict = {}
    for k, v in parse_assignments(items).items():
        if "." not in k:
            raise CaseError(f"--option expects method.key=value, got {k!r}")
        m, key = k.split(".", 1)
        out.setdefault(m, {})[key] = v
    return out


def load_case(name: str, sets: dict) -> Case:
    if name.endswith(".toml"):
        if sets:
            raise CaseError("--set applies to named cases; edit the TOML file instead")
        try:
            return Case.from_toml(Path(name).read_text())
        except OSError as e:
            raise CaseError(f"cannot read case file {name}: {e.strerror}") from None
    return registry.build(name, **sets)


def cmd_list(args) -> int:
    for n in registry.names():
        case = registry.build(n)
        print(f"{n:<18} [{','.join(case.methods())}] {registry.summary(n)}")
    return 0


def cmd_show(args) -> int:
    case = load_case(args.case, parse_assignments(args.set))
    print(case.to_toml())
    return 0


def cmd_run(args) -> int:
    case = load_case(args.case, parse_assignments(args.set))
    comp = compare(case, args.methods, options=parse_options(args.option))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "case.toml").write_text(case.to_toml())
    payload = {"case": case.name, "reference": comp.reference,
               "results": {m: r.to_dict(include_fields=False) for m, r in comp.results.items()},
               "not_run": comp.failures}
    (out / "results.json").write_text(json.dumps(payload, indent=1))
    comp.to_csv(out / "comparison.csv")
    for m, r in comp.results.items():
        if "position" in r.fields and not args.no_vtk:
            r.to_vtk(out / f"{case.name}_{m}.vtu")
    png = plot_comparison(comp, out / f"{case.name}_comparison.png")
    print(comp.table())
    print(f"\nwrote {out / 'results.json'}, {out / 'comparison.csv'}, {png}")
    return 0 if comp.results else 1


def cmd_sweep(args) -> int:
    values = parse_value(args.values)
    values = values if isinstance(values, list) else [values]
    sw = sweep(args.case, args.param, values, methods=args.methods, fixed=parse_assignments(args.set),
               options=parse_options(args.option), workers=args.workers, dask_address=args.dask)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    sw.to_json(out / "sweep.json")
    sw.to_csv(out / "sweep.csv")
    wanted = [q.strip() for q in args.quantities.split(",")] if args.quantities else None
    png = plot_sweep(sw, out / f"{args.case}_sweep_{args.param}.png", x_transform=args.x, quantities=wanted)
    for q in sw.quantity_names():
        print(f"{q}:")
        print(f"  {args.param:>10} " + "".join(f"{m:>14}" for m in sw.methods))
        for i, v in enumerate(sw.values):
            print(f"  {v!s:>10} " + "".join(f"{sw.value(i, m, q):>14.5g}" for m in sw.methods))
    for e in sw.errors():
        print(f"error: {e}")
    print(f"\nwrote {out / 'sweep.json'}, {out / 'sweep.csv'}, {png}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="imperfect", description="Imperfect interfaces: one case, several methods.")
    sub = p.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="list the named cases and the methods that support them")
    s = sub.add_parser("show", help="print a resolved case as TOML")
    s.add_argument("case")
    s.add_argument("--set", action="append", metavar="KEY=VALUE")
    r = sub.add_parser("run", help="run a case across methods and plot agreement")
    r.add_argument("case", help="a case name (imperfect list) or a .toml case file")
    r.add_argument("--methods", default="all", help="comma list of analytic,fem,mpm,cpd or 'all'")
    r.add_argument("--set", action="append", metavar="KEY=VALUE", help="case parameter override")
    r.add_argument("--option", action="append", metavar="METHOD.KEY=VALUE", help="solver option, e.g. mpm.cell=0.2")
    r.add_argument("--out", default="out")
    r.add_argument("--no-vtk", action="store_true")
    w = sub.add_parser("sweep", help="run a case over parameter values, every method, in parallel")
    w.add_argument("case")
    w.add_argument("--param", required=True)
    w.add_argument("--values", required=True, help="comma list, e.g. 1,2,5,inf")
    w.add_argument("--methods", default="all")
    w.add_argument("--set", action="append", metavar="KEY=VALUE")
    w.add_argument("--option", action="append", metavar="METHOD.KEY=VALUE")
    w.add_argument("--workers", type=int, default=None)
    w.add_argument("--dask", default=None, metavar="ADDRESS", help="send the runs to a Dask scheduler")
    w.add_argument("--quantities", default=None, help="comma list of quantities to plot (default: shared ones)")
    w.add_argument("--x", choices=["linear", "inverse", "log"], default="linear", help="x axis of the plot")
    w.add_argument("--out", default="out")
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    handler = {"list": cmd_list, "show": cmd_show, "run": cmd_run, "sweep": cmd_sweep}[args.command]
    try:
        return handler(args)
    except (CaseError, SolverError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
