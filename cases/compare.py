"""Run one case through several methods and compare every quantity to the reference.

The reference is the case's ``reference`` (the analytic model where one exists, FEM
for the CPD square); each method's relative difference to it is tabulated, written to
CSV and plotted (``cases.plots``).
"""
from __future__ import annotations

import csv
import io
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

from interfaces import Case

from .methods import failure_text, resolve_methods, run


#: model variants the table shows beside a quantity: (variant quantity, quantity, label)
VARIANTS = (("stiffness_eq40_42", "stiffness",
             "stiffness, 002 Eq 40-42 as printed (strips rigid in shear)"),)


@dataclass
class Comparison:
    """Results of several methods on one case, with differences to the reference."""

    case: Case
    results: dict
    reference: str | None
    failures: dict = field(default_factory=dict)

    def quantity_names(self) -> list[str]:
        names: list[str] = []
        for r in self.results.values():
            for k, v in r.quantities.items():
                if k not in names and _is_number(v):
                    names.append(k)
        return names

    def value(self, method: str, quantity: str) -> float:
        v = self.results[method].quantities.get(quantity, math.nan)
        return float(v) if _is_number(v) else math.nan

    def reference_for(self, quantity: str) -> str | None:
        """The method a quantity is compared to: the case's reference where it gives the
        quantity, else FEM (the static numerical reference) where it does."""
        for m in (self.reference, "fem"):
            if m is not None and m in self.results and math.isfinite(self.value(m, quantity)):
                return m
        return None

    def relative_difference(self, method: str, quantity: str) -> float:
        """(value - reference) / |reference| (see :meth:`reference_for`), NaN without one."""
        ref_method = self.reference_for(quantity)
        if ref_method is None or ref_method == method:
            return 0.0 if ref_method == method else math.nan
        ref = self.value(ref_method, quantity)
        val = self.value(method, quantity)
        if not math.isfinite(ref) or ref == 0 or not math.isfinite(val):
            return math.nan
        return (val - ref) / abs(ref)

    def rows(self) -> list[dict]:
        out = []
        for q in self.quantity_names():
            for m in self.results:
                out.append({"quantity": q, "method": m, "value": self.value(m, q),
                            "reference": self.reference_for(q) or "",
                            "relative_difference": self.relative_difference(m, q),
                            "time_s": self.results[m].timings.get("total", math.nan)})
        return out

    def to_csv(self, path=None) -> str:
        buf = io.StringIO()
        w = csv.DictWriter(buf, fieldnames=["quantity", "method", "value", "reference", "relative_difference", "time_s"])
        w.writeheader()
        for r in self.rows():
            w.writerow(r)
        if path is not None:
            Path(path).write_text(buf.getvalue())
        return buf.getvalue()

    def _variant_rows(self, methods) -> list[str]:
        """A row per model variant the analytic result gives (e.g. the DLS shear lag as
        printed in 002 beside the form with the strips' own shear), with each numerical
        method's difference to that variant."""
        rows = []
        for variant, quantity, label in VARIANTS:
            v = self.value("analytic", variant) if "analytic" in self.results else math.nan
            if not math.isfinite(v):
                continue
            cells = []
            for m in methods:
                x = self.value(m, quantity)
                txt = f"{v:.5g}" if m == "analytic" else "-" if not math.isfinite(x) else \
                    f"({100 * (x - v) / abs(v):+.2f}%)"
                cells.append(f"{txt:>24}")
            rows.append(f"{label}:")
            rows.append(f"{'':<22}" + "".join(cells))
        return rows

    def table(self) -> str:
        """Human-readable table: one row per quantity, one column per method."""
        methods = list(self.results)
        head = f"{'quantity':<22}" + "".join(f"{m:>24}" for m in methods)
        lines = [f"case {self.case.name}: {self.case.description}",
                 f"reference: {self.reference or 'none'} (fem for quantities the reference does not give); "
                 "(+x%) = difference to it", head, "-" * len(head)]
        from .plots import shared_quantities

        rows = shared_quantities(self) if len(self.results) > 1 else self.quantity_names()
        for q in rows:
            cells = []
            for m in methods:
                v = self.value(m, q)
                d = self.relative_difference(m, q)
                txt = "-" if math.isnan(v) else f"{v:.5g}"
                if m != self.reference_for(q) and math.isfinite(d):
                    txt += f" ({100 * d:+.2f}%)"
                cells.append(f"{txt:>24}")
            lines.append(f"{q:<22}" + "".join(cells))
        lines.extend(self._variant_rows(methods))
        lines.append("(every quantity of every method is in results.json and comparison.csv)")
        lines.append(f"{'time (s)':<22}" + "".join(f"{self.results[m].timings.get('total', math.nan):>24.3g}" for m in methods))
        for m, r in self.results.items():
            for w in r.diagnostics.get("warnings", []):
                lines.append(f"warning ({m}): {w}")
        for m, msg in self.failures.items():
            lines.append(f"{m}: not run: {msg}")
        return "\n".join(lines)


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def compare(case: Case, methods="all", options: dict | None = None, progress: bool = True,
            skip_unavailable: bool = True, finished: dict | None = None,
            on_result=None) -> Comparison:
    """Run ``methods`` (a list, comma string or ``"all"``) on ``case`` and compare.

    ``options`` maps a method name to keyword options of its ``solve``. With
    ``skip_unavailable`` a method that is unavailable, does not handle the case or
    fails (bad input, divergence, or any other exception: :func:`failure_text`) is
    reported in ``failures``, not raised.
    ``finished`` holds Results already computed (a resumed run: not run again);
    ``on_result(method, result)`` is called as each method finishes.
    """
    options = options or {}
    names = resolve_methods(case, methods)
    results, failures = {}, {}
    for m in names:
        if finished and m in finished:
            results[m] = finished[m]
            if progress:
                print(f"[{m}] kept from the interrupted run", file=sys.stderr, flush=True)
            continue
        if progress:
            print(f"[{m}] running {case.name} ...", file=sys.stderr, flush=True)
        try:
            results[m] = run(case, m, **options.get(m, {}))
        except Exception as e:
            # a method that is missing, does not handle this case yet, or failed (bad input,
            # divergence, or a defect): report it beside the others' results rather than
            # losing them (raise if asked to)
            if not skip_unavailable:
                raise
            failures[m] = failure_text(e)
            if progress:
                print(f"[{m}] not run: {failures[m]}", file=sys.stderr, flush=True)
            continue
        if on_result is not None:
            on_result(m, results[m])
        if progress:
            print(f"[{m}] done in {results[m].timings.get('total', float('nan')):.2f} s", file=sys.stderr, flush=True)
    reference = case.reference if case.reference in results else None
    return Comparison(case=case, results=results, reference=reference, failures=failures)
