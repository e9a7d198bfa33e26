"""The margin report: how close each check came to its bound (``ratio = value / bound``), over every check of a
results document. A verdict is only as good as its margin: a check on a *margin* bound (round-off, integrator
tolerance) must stay at or below :data:`harness.checks.MARGIN` of it, or rounding on another machine may flip it;
a check above that is listed with its basis so that a reader sees why it may sit there (a *derived* bound) or
that it is a finding."""

from __future__ import annotations

import math

from harness.checks import MARGIN


def ratio_of(check: dict) -> float:
    """A check record's ratio as a number: ``"inf"``/``"nan"`` (non-finite, as JSON holds them) as infinite."""
    r = check.get("ratio")
    return math.inf if isinstance(r, str) else float(r or 0.0)


def rows(doc: dict) -> list[dict]:
    """One row per check with a positive bound (flags excluded): where, check, source, value, bound, ratio,
    basis, and whether its bound is derived. ``doc``: a results document (``systems``, each with its checks and
    its scenes') or the hard cases' (``cases``, :mod:`harness.hard`: the case as the system, no scene)."""
    groups = [(r["system"], "—", r.get("checks", [])) for r in doc.get("systems", [])]
    groups += [(r["system"], s.get("scene", "?"), s.get("checks", []))
               for r in doc.get("systems", []) for s in r.get("scenes") or []]
    groups += [(case["id"], "—", case.get("checks", [])) for case in doc.get("cases", [])]
    bounds = doc.get("bounds") or {}
    out = []
    for system, scene, checks in groups:
        for c in checks:
            bound = c.get("bound")
            if not isinstance(bound, (int, float)) or bound <= 0:
                continue
            basis = c.get("basis", "")
            out.append({"system": system, "scene": scene, "check": c.get("check", ""),
                        "source": c.get("source", ""), "value": c.get("value"), "bound": bound,
                        "ratio": ratio_of(c), "basis": basis,
                        "derived": bool((bounds.get(basis) or {}).get("derived")),
                        "reason": (bounds.get(basis) or {}).get("reason", "")})
    return sorted(out, key=lambda row: (-row["ratio"], row["system"], row["scene"], row["check"], row["source"]))


def above(doc: dict, margin: float = MARGIN) -> list[dict]:
    """The checks above ``margin`` of their bound, largest ratio first."""
    return [row for row in rows(doc) if row["ratio"] > margin]


def summary_line(doc: dict) -> str:
    all_rows, high = rows(doc), above(doc)
    thin = [row for row in high if not row["derived"]]
    return (f"margins: {len(high)} of {len(all_rows)} checks above {MARGIN:g} of their bound "
            f"({len(high) - len(thin)} on a derived bound, {len(thin)} on a margin bound)")


def figure_svg(doc: dict) -> str | None:
    """Histogram of log10(ratio) for margin and derived bounds, the lines at 0.1 and 1; None without checks."""
    from harness.report.figures import _matplotlib, _svg

    data = [row for row in rows(doc) if math.isfinite(row["ratio"])]
    if not data:
        return None
    plt = _matplotlib()
    import numpy as np

    floor = 1e-8
    fig, ax = plt.subplots(figsize=(7.0, 2.6))
    bins = np.linspace(-8, 1, 37)
    for derived, label, color in ((False, "margin bound (round-off, integrator)", "tab:blue"),
                                  (True, "derived bound", "tab:orange")):
        values = [math.log10(max(row["ratio"], floor)) for row in data if row["derived"] == derived]
        if values:
            ax.hist(values, bins=bins, alpha=0.7, label=f"{label}: {len(values)}", color=color)
    ax.axvline(math.log10(MARGIN), color="k", linestyle="--", linewidth=0.8)
    ax.axvline(0.0, color="tab:red", linewidth=1.0)
    ax.set_xlabel(f"log10(value / bound) — checks at 0 sit at {math.log10(floor):g}; dashed: {MARGIN:g}, "
                  "red: the bound")
    ax.set_ylabel("checks")
    ax.legend(loc="upper left", fontsize=7)
    fig.tight_layout()
    text = _svg(fig)
    plt.close(fig)
    return text


HOLDING = ("confirmed", "notation typo")
"""Claim classifications whose recorded errors are those of a check that holds (:func:`claim_rows`)."""


def claim_rows(claims: list[dict], margin: float = MARGIN) -> list[dict]:
    """Printed equations whose verdict sits near its boundary: a claim that holds with a source above ``margin`` of
    its tolerance (confirmed, or a notation typo: its errors are those under its renaming, where it holds), or a
    claim found wrong (erratum, convention-dependent as printed) whose smallest ratio over the sources is below
    ``1 / margin``; each ratio is the largest over the examples (``errors_over_tolerance``). Before, a notation
    typo's ratios under its renaming (1e-5–2e-4) were read as those of a wrong claim: all 13 were listed as wrong
    by less than 10×."""
    out = []
    for c in claims:
        ratios = {k: (math.inf if isinstance(v, str) else float(v))
                  for k, v in (c.get("errors_over_tolerance") or {}).items() if not k.startswith("Cqd (from")}
        if not ratios:
            continue
        if c.get("classification") in HOLDING:
            worst = max(ratios.values())
            near = worst > margin
        else:
            worst = min(ratios.values())
            near = worst < 1 / margin
        if near:
            out.append({"system": c.get("system"), "equation": c.get("equation"),
                        "classification": c.get("classification"), "ratio": worst,
                        "sources": ", ".join(f"{k} {v:.2g}" for k, v in sorted(ratios.items()))})
    return out
