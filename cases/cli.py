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
from . import fit
from .compare import compare
from .methods import OUT_OF_MEMORY, supported_methods
from .output import RUN_OUTPUTS, check_output_dir, staged_output
from .plots import plot_comparison, plot_sweep
from .resume import RunRecord
from .sweep import load_spec, sweep


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


def parse_curves(items) -> dict:
    """``--curve nano:radius=7e-4,side=1e-3`` -> {"nano": {"radius": 7e-4, "side": 1e-3}}.

    The overrides split at commas that start a new ``key=``, so a list value
    (``key=1,2,3``) stays whole."""
    out: dict = {}
    for item in items or []:
        label, sep, rest = item.partition(":")
        if not sep or not label.strip():
            raise CaseError(f"--curve expects LABEL:KEY=VALUE[,KEY=VALUE...], got {item!r}")
        if label.strip() in out:
            raise CaseError(f"--curve {label.strip()!r} is given twice")
        parts = [x for x in re.split(r",(?=\s*[A-Za-z_][A-Za-z0-9_.]*\s*=)", rest) if x.strip()]
        out[label.strip()] = parse_assignments(parts)
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
    width = max(len(n) for n in registry.names()) + 1
    for n in registry.names():
        case = registry.build(n)
        print(f"{n:<{width}} [{','.join(supported_methods(case))}] {registry.summary(n)}")
    return 0


def cmd_show(args) -> int:
    if args.params:
        if args.case.endswith(".toml"):
            raise CaseError("--params lists a named case's --set parameters; a case file has none")
        registry.parameters(args.case)       # unknown names refused with the list
        print(registry.describe_parameters(args.case))
        return 0
    case = load_case(args.case, parse_assignments(args.set))
    print(case.to_toml())
    return 0


def cmd_run(args) -> int:
    out = check_output_dir(args.resume or args.out, RUN_OUTPUTS)   # refuse an impossible --out first
    record = RunRecord(out)
    if args.resume:
        if args.case or args.set or args.option:
            raise CaseError("--resume DIR continues the recorded run; give no case, --set or --option")
        spec = record.load()
        case, options = spec["case"], spec["options"]
        args.methods, args.no_vtk, args.series = spec["methods"], spec["no_vtk"], spec["series"]
    elif not args.case:
        raise CaseError("run needs a case (a name from imperfect list or a .toml file), or --resume DIR")
    else:
        case = load_case(args.case, parse_assignments(args.set))
        options = parse_options(args.option)
        record.start(case, args.methods, options, args.no_vtk, args.series)
    options = record.with_mpm_checkpoint(options, resume=bool(args.resume))
    with staged_output(out) as stage:
        series = _series_option(args, case, options, stage)
        comp = compare(case, args.methods, options=options,
                       finished=record.finished() if args.resume else None,
                       on_result=record.save_result)
        if not comp.results:                  # nothing ran: say why, write nothing
            raise CaseError("; ".join(f"{m}: {msg}" for m, msg in comp.failures.items()))
        if series and "mpm" in comp.results:  # the frames move with the folder
            diag = comp.results["mpm"].diagnostics
            diag["vtk_series"] = str(out / series.name / Path(diag.get("vtk_series", "series.pvd")).name)
        (stage / "case.toml").write_text(case.to_toml())
        payload = {"case": case.name, "reference": comp.reference,
                   "results": {m: r.to_dict(include_fields=False) for m, r in comp.results.items()},
                   "not_run": comp.failures}
        (stage / "results.json").write_text(json.dumps(payload, indent=1))
        comp.to_csv(stage / "comparison.csv")
        for m, r in comp.results.items():
            if "position" in r.fields and not args.no_vtk:
                r.to_vtk(stage / f"{case.name}_{m}.vtu")
        png = plot_comparison(comp, stage / f"{case.name}_comparison.png")
    print(comp.table())
    print(f"\nwrote {out / 'results.json'}, {out / 'comparison.csv'}, {out / png.name}"
          + (f", {out / series.name}/ (MPM frames)" if series and "mpm" in comp.results else ""))
    if comp.failures:
        print(f"error: {len(comp.failures)} of {len(comp.failures) + len(comp.results)} requested methods "
              f"did not run: {', '.join(comp.failures)} (reasons above)", file=sys.stderr)
        return 3
    return 0


def _series_option(args, case, options: dict, stage: Path) -> Path | None:
    """--series N: MPM writes N VTU frames and a .pvd into OUT/<case>_mpm_vtk/."""
    if not args.series:
        return None
    if args.series < 1:
        raise CaseError(f"--series must be a number of frames >= 1, got {args.series}")
    folder = stage / f"{case.name}_mpm_vtk"
    mpm = options.setdefault("mpm", {})
    if "vtk_dir" in mpm:
        raise CaseError("give --series or --option mpm.vtk_dir, not both")
    mpm["vtk_dir"] = str(folder)
    mpm.setdefault("vtk_frames", args.series)
    return folder


def cmd_sweep(args) -> int:
    spec = _sweep_spec(args)
    out = check_output_dir(args.resume or args.out)
    sw = sweep(spec["case"], spec["param"], spec["values"], methods=spec["methods"], fixed=spec["fixed"],
               options=spec["options"], workers=args.workers, dask_address=args.dask,
               record_dir=out, resume=bool(args.resume), progress=True, curves=spec.get("curves"))
    sw.to_json(out / "sweep.json")
    sw.to_csv(out / "sweep.csv")
    wanted = [q.strip() for q in args.quantities.split(",")] if args.quantities else None
    png = plot_sweep(sw, out / f"{sw.case_name}_sweep_{sw.param}.png", x_transform=args.x, quantities=wanted)
    print(sw.table(wanted or _shared_sweep_quantities(sw)))
    for e in sw.errors():
        print(f"error: {e}")
    print(f"\nwrote {out / 'sweep.json'}, {out / 'sweep.csv'}, {png}")
    if sw.errors():
        print(f"error: {len(sw.errors())} method runs of the sweep failed (listed above); the other "
              "points are recorded", file=sys.stderr)
        return 3
    return 0


def _sweep_spec(args) -> dict:
    """What to sweep: from the command line, or from the record being resumed (the
    command line may repeat it; a difference is refused by the sweep)."""
    if args.resume:
        spec = load_spec(args.resume)
        spec["values"] = [parse_value(str(v)) for v in spec["values"]]
        spec["fixed"] = _decoded(spec["fixed"])
        spec["curves"] = {label: _decoded(over) for label, over in spec.get("curves", {}).items()}
        given = {"case": args.case, "param": args.param}
        for k, v in given.items():
            if v is not None and v != spec[k]:
                raise CaseError(f"--resume {args.resume}: the recorded sweep has {k} {spec[k]!r}, not {v!r}")
        if args.values is not None:
            values = _values(args.values)
            if values != spec["values"]:
                raise CaseError(f"--resume {args.resume}: the recorded sweep has values {spec['values']}")
        return spec
    missing = [n for n, v in (("CASE", args.case), ("--param", args.param), ("--values", args.values)) if v is None]
    if missing:
        raise CaseError(f"sweep needs {', '.join(missing)} (or --resume DIR to continue a recorded sweep)")
    return {"case": args.case, "param": args.param, "values": _values(args.values), "methods": args.methods,
            "fixed": parse_assignments(args.set), "options": parse_options(args.option),
            "curves": parse_curves(args.curve)}


def _decoded(over: dict) -> dict:
    """Overrides as recorded in a sweep spec (inf and names stored as strings)."""
    return {k: parse_value(str(v)) if isinstance(v, str) else v for k, v in over.items()}


def _values(text: str) -> list:
    values = parse_value(text)
    return values if isinstance(values, list) else [values]


def _shared_sweep_quantities(sw) -> list[str]:
    """Quantities that at least two methods give (all of them for a single method)."""
    if len(sw.methods) < 2:
        return sw.quantity_names()
    count = {q: sum(any(math.isfinite(v) for v in sw.series(m, q)) for m in sw.methods)
             for q in sw.quantity_names()}
    shared = [q for q, c in count.items() if c >= 2]
    return shared or sw.quantity_names()


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="imperfect", description="Imperfect interfaces: one case, several methods.")
    sub = p.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="list the named cases and the methods that support them")
    s = sub.add_parser("show", help="print a resolved case as TOML")
    s.add_argument("case")
    s.add_argument("--set", action="append", metavar="KEY=VALUE")
    s.add_argument("--params", action="store_true", help="list the case's --set parameters with defaults and units")
    r = sub.add_parser("run", help="run a case across methods and plot agreement")
    r.add_argument("case", nargs="?", help="a case name (imperfect list) or a .toml case file")
    r.add_argument("--methods", default="all", help="comma list of analytic,fem,mpm,cpd or 'all'")
    r.add_argument("--set", action="append", metavar="KEY=VALUE", help="case parameter override")
    r.add_argument("--option", action="append", metavar="METHOD.KEY=VALUE", help="solver option, e.g. mpm.cell=0.2")
    r.add_argument("--out", default="out")
    r.add_argument("--resume", metavar="DIR", help="continue the interrupted run whose --out was DIR "
                   "(finished methods are kept, MPM continues from its checkpoint)")
    r.add_argument("--no-vtk", action="store_true", help="no VTU file of each method's final state")
    r.add_argument("--series", type=int, default=0, metavar="N",
                   help="MPM: also write N VTU frames over the run and a .pvd into OUT/<case>_mpm_vtk/")
    w = sub.add_parser("sweep", help="run a case over parameter values, every method, in parallel")
    w.add_argument("case", nargs="?", help="a case name (not needed with --resume)")
    w.add_argument("--param")
    w.add_argument("--values", help="comma list, e.g. 1,2,5,inf")
    w.add_argument("--resume", metavar="DIR", help="continue the sweep recorded in DIR (runs only the missing points)")
    w.add_argument("--methods", default="all")
    w.add_argument("--set", action="append", metavar="KEY=VALUE")
    w.add_argument("--curve", action="append", metavar="LABEL:KEY=VALUE[,KEY=VALUE]",
                   help="run the sweep once more per curve with these case overrides, one plot "
                        "(e.g. --curve micro:radius=0.7 --curve nano:radius=7e-4,side=1e-3)")
    w.add_argument("--option", action="append", metavar="METHOD.KEY=VALUE")
    w.add_argument("--workers", type=int, default=None)
    w.add_argument("--dask", default=None, metavar="ADDRESS", help="send the runs to a Dask scheduler")
    w.add_argument("--quantities", default=None, help="comma list of quantities to plot (default: shared ones)")
    w.add_argument("--x", choices=["linear", "inverse", "log"], default="linear", help="x axis of the plot")
    w.add_argument("--out", default="out", help="folder for sweep.json/csv/png and the per-point records")
    fit.add_parser(sub)
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    handler = {"list": cmd_list, "show": cmd_show, "run": cmd_run, "sweep": cmd_sweep,
               "fit": fit.cmd_fit}[args.command]
    try:
        return handler(args)
    except (CaseError, SolverError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except BrokenPipeError:                  # output piped into head, less, ...: not an error
        sys.stderr.close()
        return 0
    except MemoryError:
        print(f"error: {OUT_OF_MEMORY}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        if args.command == "sweep":
            hint = f"; finished points are kept: imperfect sweep --resume {args.resume or args.out}"
        elif args.command == "run":
            hint = (f"; finished methods and the MPM state are kept: imperfect run --resume "
                    f"{args.resume or args.out}")
        else:
            hint = "; no output was written"
        print(f"\ninterrupted{hint}", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
