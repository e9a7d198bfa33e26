"""The errata sheet: each finding about a printed equation in the lecture's notation — the printed and the
corrected equation as MathML, the differing terms, one sentence a lecturer can act on, and the counterexample
reduced to what matters with the printed and derived values there — as ``errata.md`` and ``errata.html``, with a
summary table and the numbered equations that have no claim, with the reason.

:func:`finding` runs where the claim was classified (it needs the SymPy expressions); :func:`markdown` and
:func:`sheet` (the page's body, :func:`harness.report.site.write_errata`) work from the JSON records alone."""

from __future__ import annotations

import json
import re
from html import escape
from pathlib import Path

import numpy as np
import sympy as sp

from harness.modeling.claims import as_matrix

KIND = {"erratum": "substantive", "notation typo": "notation", "convention-dependent": "convention",
        "follows from erratum": "follows", "engines disagree": "engines"}
UNCLAIMED = Path(__file__).resolve().parents[2] / "models" / "unclaimed.json"


# ----------------------------------------------------------------------------- the lecture's symbols
def definitions(claims) -> list[tuple[sp.Symbol, sp.Expr]]:
    """Printed symbols with the model's value: the parameter relations the claims declare (``m_S`` ↔
    ``rho_S l_S b_S h_S``)."""
    out = []
    for c in claims:
        if c.defines is None or c.quantity != "parameter" or c.reference is None:
            continue
        out += [(s, v) for s, v in zip(c.defined, as_matrix(c.derived_reference())) if isinstance(s, sp.Symbol)]
    return out


def lecture_form(expr, keep: set, relations) -> sp.Matrix:
    """``expr`` with the model's symbols that the printed equation does not use eliminated through the declared
    relations (``rho_S → m_S/(l_S b_S h_S)``, then ``b_S² → 12 I_zz^S/m_S − l_S²``), simplified for reading
    (:func:`_tidy`). Which symbol each relation eliminates is searched: the choice that leaves fewest foreign symbols
    wins."""
    from harness.derivation import cache
    from harness.report import equations

    expr = as_matrix(expr)
    relations = [(s, sp.sympify(v)) for s, v in relations if s in keep]

    def compute():
        best = _eliminate(expr.applyfunc(sp.expand), keep, relations)
        return best.applyfunc(_tidy)
    return cache.remembered("lecture-form", (Path(__file__), Path(equations.__file__)),
                            (expr, sorted(keep, key=sp.default_sort_key), relations), compute)


def _foreign(expr, keep) -> int:
    return len(expr.free_symbols - keep)


def _eliminate(expr, keep, relations, depth: int = 0):
    if not relations or depth > 4:
        return expr
    (symbol, value), rest = relations[0], relations[1:]
    options = [_eliminate(expr, keep, rest, depth + 1)]
    for x in sorted(value.free_symbols - keep, key=str):
        solved = _solve_power(value, symbol, x)
        if solved is None:
            continue
        power, solution = solved
        trial = expr.applyfunc(lambda e: sp.expand(e.subs(x**power, solution)))
        if any(x in e.free_symbols for e in trial):
            continue
        later = [(s, sp.expand(v.subs(x**power, solution))) for s, v in rest]
        options.append(_eliminate(trial, keep, later, depth + 1))
    return min(options, key=lambda m: (_foreign(m, keep), sum(sp.count_ops(e) for e in m)))


def _solve_power(value, symbol, x):
    y = sp.Dummy("y")
    for power in (1, 2):
        replaced = value.subs(x**power, y) if power > 1 else value.xreplace({x: y})
        if x in replaced.free_symbols or not replaced.has(y):
            continue
        solutions = sp.solve(sp.Eq(replaced, symbol), y, check=False)
        if len(solutions) == 1:
            return power, solutions[0]
    return None


def _tidy(e):
    """The shortest of ``e``, its simplification for reading (:meth:`harness.report.equations.Budget.simplify`: by
    size, not by time; a cascade under 1 CPU s had cut 4 of the lecture's corrections after 5-8 s of work, and one
    of 0.5 s would have been cut on a machine half as fast) and its common factors taken out."""
    from harness.report.equations import Budget

    candidates = [e, Budget().simplify(e)]
    try:
        candidates.append(sp.factor_terms(sp.expand(e)))
    except Exception:  # noqa: BLE001 - tidying is cosmetic
        pass
    return min(candidates, key=sp.count_ops)


# ----------------------------------------------------------------------------- one finding
def finding(system, verdict, claims) -> dict:
    """The errata-sheet fields of a classified claim that does not simply hold."""
    from harness.compare import claims as claims_module
    from harness.compare.errata import ingredients_of
    from harness.report.equations import claim_math, wide_math

    claim = verdict.claim
    out: dict = {"printed_mathml": claim_math(claim, claim.printed)}
    kind = claim.quantity.split(":")[0]
    if verdict.classification == "notation typo":
        renaming = {sp.Symbol(k, real=True): sp.Symbol(v, real=True) for k, v in verdict.renaming.items()}
        corrected = as_matrix(claim.printed).xreplace(renaming)
        out["corrected_mathml"] = claim_math(claim, corrected)
        pairs = ", ".join(f"{k} → {v}" for k, v in verdict.renaming.items())
        names = ", ".join(verdict.renaming)
        verb = "is not a symbol" if len(verdict.renaming) == 1 else "are not symbols"
        out["sentence"] = f"{claim.equation}: {names} {verb} of this example; the equation holds after renaming {pairs}."
        return out
    if verdict.classification == "follows from erratum":
        out["sentence"] = (f"{claim.equation} is right as written in its symbols; it fails only through the printed "
                           f"{', '.join(verdict.blame)}: with that corrected, {claim.equation} holds.")
        return out
    if verdict.classification != "erratum" or verdict.state is None:
        return out
    subst = verdict.substitution or {}
    relations = definitions(claims)
    printed_model = as_matrix(claim.printed).xreplace(subst)
    derived = as_matrix(claims_module._derived(system, claim))
    if kind == "equilibrium":
        return out
    reading, derived = closest_reading(system, claim, printed_model, derived)
    if kind == "eom":
        derived = _scaled_like(printed_model, derived, system, claim)
    ingredient_symbols = {s for c in ingredients_of(claim, claims) for s in c.defined}
    keep = set(as_matrix(claim.printed).free_symbols) | {s for s, _ in relations if s in ingredient_symbols}
    printed_shown = as_matrix(claim.printed)
    if ingredient_symbols:  # with the corrected ingredients: show them by name, as printed
        printed_shown = printed_shown.xreplace({k: v for k, v in subst.items() if k not in ingredient_symbols})
    keep |= set(printed_shown.free_symbols)
    corrected = lecture_form(derived, keep, relations)
    if printed_shown.shape != corrected.shape and len(printed_shown) == len(corrected):
        printed_shown = printed_shown.reshape(*corrected.shape)
    out["corrected_mathml"] = claim_math(claim, corrected, named=True)
    delta = lecture_form(derived - printed_model.reshape(*derived.shape), keep, relations)
    out["difference"] = str(delta if delta.shape != (1, 1) else delta[0])
    out["difference_mathml"] = wide_math(delta, "<mi>Δ</mi>", named=True)
    out["sentence"] = (along_the_line(system, claim, printed_model, derived) or
                       sentence(claim, printed_shown, corrected, verdict))
    if reading:
        out["sentence"] += f" (Read in the coordinates of its convention “{reading}”, where it comes closest.)"
    out["counterexample_reduced"] = reduced_counterexample(system, claim, verdict, delta, relations)
    return out


def closest_reading(system, claim, printed, derived) -> tuple[str | None, sp.Matrix]:
    """The convention that counts coordinates otherwise (``conventions=``) under which the printed quantity differs
    from the derived one in the fewest entries, and the derived quantity read in its coordinates
    (:meth:`~harness.modeling.claims.CoordinateChange.back`); ``(None, derived)`` where none comes closer than the
    text as printed. A wrong entry of ``M`` printed with a coordinate counted the other way round is then explained
    alone, not with the coupling entries whose sign the convention accounts for. Entries are compared at random
    values (:func:`~harness.derivation.identities.same_at_random_values`)."""
    from harness.derivation.identities import same_at_random_values
    from harness.modeling.claims import coordinate_change

    kind = claim.quantity.split(":")[0]

    def differing(candidate):
        if kind == "eom":
            candidate = _scaled_like(printed, candidate, system, claim)
        if len(candidate) != len(printed):
            return len(printed) + 1
        return sum(not same_at_random_values(p, d) for p, d in zip(printed, candidate))

    best = (differing(derived), None, derived)
    for name, substitution in claim.conventions.items():
        change = coordinate_change(system, substitution)
        read = change.back(system, kind, derived, claim.index) if change is not None else None
        count = differing(read) if read is not None else best[0]
        if count < best[0]:
            best = (count, name, read)
    return best[1], best[2]


def _scaled_like(printed, derived, system, claim):
    """A derived residual row scaled to the printed row's q̈ coefficients (a printed equation may be divided
    through)."""
    from harness.compare.errata import row_factor, rows

    scaled = [e * row_factor(system, r, e, own) for r, e, own in zip(printed, derived, rows(claim, len(derived)))]
    return sp.Matrix(scaled).reshape(*derived.shape)


def along_the_line(system, claim, printed, derived) -> str | None:
    """For the force of a spring or damper: the sentence when the derived force is the printed one's component
    along the element's line ``r`` (``r rᵀ f / rᵀ r``), tested at random values of every symbol."""
    from harness.derivation.identities import same_at_random_values
    from harness.derivation.bodies import element_vector, point_element

    kind, _, name = claim.quantity.partition(":")
    if kind != "force":
        return None
    r, _ = element_vector(system, point_element(system, name))
    projected = r * (r.T * printed)[0] / (r.T * r)[0]
    if not same_at_random_values(projected, derived):
        return None
    return (f"{claim.equation}: a {type(point_element(system, name)).__name__.lower()} acts along its line: only the "
            f"component of the printed force along r (r rᵀ f / rᵀ r) is its force; the printed vector also has the "
            f"component across the line.")


SHORT = 160   # characters of an expression a sentence may quote


def sentence(claim, printed, corrected, verdict) -> str:
    """One sentence: a wrong sign, the entries that differ, or the terms that should read otherwise."""
    where = claim.equation
    if sp.expand(printed + corrected).is_zero_matrix if hasattr(printed, "is_zero_matrix") else False:
        return f"{where}: the sign is wrong: the printed expression is the negative of the derived one."
    if printed.shape != (1, 1) and printed.shape == corrected.shape:
        wrong = [(i, j) for i in range(printed.rows) for j in range(printed.cols)
                 if sp.expand(printed[i, j] - corrected[i, j]) != 0]
        if 0 < len(wrong) <= 2:
            parts = []
            for i, j in wrong:
                at = f"({i + 1}, {j + 1})" if printed.cols > 1 else f"{i + 1}"
                phrase = _entry_phrase(printed[i, j], corrected[i, j])
                if phrase is not None:
                    parts.append(f"in entry {at}, {phrase}")
                elif len(str(corrected[i, j])) > SHORT:
                    parts.append(f"entry {at} differs (the corrected expression is shown in full)")
                else:
                    parts.append(f"entry {at} should read {corrected[i, j]}, not {printed[i, j]}")
            return f"{where}: " + "; ".join(parts) + "."
    if printed.shape == (1, 1) == corrected.shape:
        phrase = _entry_phrase(printed[0], corrected[0])
        if phrase is not None:
            return f"{where}: {phrase}."
    return f"{where}: the printed expression differs from the derived one by {_short(corrected - printed)}."


def _entry_phrase(printed, corrected) -> str | None:
    """What is wrong with one printed entry, in words: its sign, a factor, or at most two terms (of the expanded
    sums) that should read otherwise, are missing or do not belong; None when it is none of these."""
    if sp.expand(printed + corrected) == 0:
        return f"the sign is wrong (it is {corrected})"
    ratio = sp.cancel(printed / corrected) if corrected != 0 else None
    if ratio is not None and (ratio.is_Symbol or (1 / ratio).is_Symbol):
        return f"the factor {ratio} does not belong" if ratio.is_Symbol else f"a factor {1 / ratio} is missing"
    have = set(sp.Add.make_args(sp.expand(printed)))
    want = set(sp.Add.make_args(sp.expand(corrected)))
    extra, lacking = have - want, want - have
    if 0 < len(extra) <= 2 and 0 < len(lacking) <= 2:
        return f"{_terms(extra)} should read {_sum(lacking)}"
    if not extra and 0 < len(lacking) <= 2:
        return f"{_terms(lacking)} {'is' if len(lacking) == 1 else 'are'} missing"
    if not lacking and 0 < len(extra) <= 2:
        return f"{_terms(extra)} {'does' if len(extra) == 1 else 'do'} not belong"
    return None


def _sum(terms) -> str:
    """Terms of an expanded sum as SymPy prints their sum (``a - b``, in its canonical order, not the set's)."""
    return str(sp.Add(*terms))


def _terms(terms) -> str:
    return f"the term{'' if len(terms) == 1 else 's'} {_sum(terms)}"


def _short(m):
    text = str(m[0] if m.shape == (1, 1) else m)
    return text if len(text) < 200 else text[:200] + " …"


def _g(x: float) -> str:
    return f"{x:.4g}"


def reduced_counterexample(system, claim, verdict, delta, relations) -> dict:
    """The counterexample state restricted to what the difference depends on, with the printed and the derived
    value of the claimed quantity there."""
    from harness.compare.claims import _derived, _lambdify
    from harness.derivation.lambdified import lambdify
    from harness.engines import symbolic
    from harness.modeling.claims import symbols

    state = verdict.state
    used = {str(s) for s in as_matrix(delta).free_symbols}
    used |= {str(s) for _, v in relations for s in sp.sympify(v).free_symbols} if used & {
        str(s) for s, _ in relations} else set()
    out = {"coordinates": {}, "parameters": {}, "inputs": {}}
    for c, q, qd in zip(system.coordinates, state.q, state.qd):
        if c.name in used or not used:
            out["coordinates"][c.name] = _g(q)
        if c.rate.name in used:
            out["coordinates"][c.rate.name] = _g(qd)
    out["parameters"] = {k: _g(v) for k, v in state.params.items() if k in used}
    out["inputs"] = {k: _g(v) for k, v in state.u.items() if k in used}
    try:
        ref = symbolic.evaluate(state)
        args = (state.q, state.qd, ref.qdd, state.p, state.u_vec)
        if claim.quantity == "eom":
            out["accelerations (derived)"] = {c.accel.name: _g(a) for c, a in zip(system.coordinates, ref.qdd)}
        printed = lambdify(symbols(system), as_matrix(claim.printed).xreplace(verdict.substitution or {}))
        derived = _lambdify(system, _derived(system, claim))
        out["printed value"] = [_g(float(x)) for x in np.asarray(printed(*args), float).ravel()]
        out["derived value"] = [_g(float(x)) for x in np.asarray(derived(*args), float).ravel()]
    except Exception:  # noqa: BLE001 - the values are an aid; the counterexample itself stands
        pass
    return out


# ----------------------------------------------------------------------------- the sheet
def unclaimed(records, lecture: set[str] | None) -> list[dict]:
    """Numbered equations of chapters 3–5 and appendix A without a claim, with the reason; listed only where
    ``records`` hold the claims of every lecture system that has some (``lecture``:
    :meth:`harness.catalogue.Catalogue.lecture_claims`): a run over some systems, or over one's own models, would
    list the equations the others claim."""
    if not lecture or not lecture <= {r["system"] for r in records}:
        return []
    try:
        table = json.loads(UNCLAIMED.read_text())
    except (OSError, ValueError):
        return []
    labels = " ".join(r["equation"] for r in records)
    return [e for e in table if f"({e['eq']})" not in labels and not _in_range(e["eq"], labels)]


LECTURE = "Mathematical Modeling"


def title(records, lecture: set[str] | None) -> str:
    """The sheet's title: the lecture's errata, unless ``records`` hold systems from outside the lecture's
    catalogue (:func:`_outside`)."""
    return "Errata of the printed equations" if _outside(records, lecture) else f"Errata of the lecture {LECTURE}"


def _outside(records, lecture: set[str] | None) -> str:
    """The line naming the systems of ``records`` that are not the lecture's (one's own models: a paper's
    system); empty when there are none (``lecture``: its systems that list printed equations; None: not known,
    all taken as the lecture's)."""
    outside = [] if lecture is None else sorted({r["system"] for r in records} - lecture)
    return (f"Printed equations from outside the lecture (each system's model names its source): "
            f"{', '.join(outside)}.") if outside else ""


def _partial(records, lecture: set[str] | None) -> str:
    """Why the numbered equations without a claim are not listed, where the records hold some lecture systems'
    claims but not all; empty otherwise (one's own models only: the lecture's coverage is not theirs)."""
    present = {r["system"] for r in records}
    if not lecture or lecture <= present or not lecture & present:
        return ""
    missing = sorted(lecture - present)
    named = ", ".join(missing[:4]) + (f" and {len(missing) - 4} more" if len(missing) > 4 else "")
    return (f"Listed when the printed equations of every lecture system are classified: these hold "
            f"{len(lecture & present)} of the {len(lecture)} systems that list some; not classified yet: {named} "
            f"(`harness claims NAME … --out FOLDER` adds them to the report's folder).")


def _in_range(eq: str, labels: str) -> bool:
    """Whether a claim label such as ``(A.162)-(A.165)`` covers ``eq``."""
    import re

    for a, b in re.findall(r"\(([0-9A]+\.\d+)[a-z]?\)-\(([0-9A]+\.\d+)[a-z]?\)", labels):
        pa, na = a.rsplit(".", 1)
        pb, nb = b.rsplit(".", 1)
        pe, ne = re.match(r"([0-9A]+)\.(\d+)", eq).groups()
        if pa == pb == pe and int(na) <= int(ne) <= int(nb):
            return True
    return False


FINDINGS = ("erratum", "notation typo", "convention-dependent", "follows from erratum", "engines disagree")


def _counts(records) -> dict:
    out: dict = {}
    for r in records:
        out[r["classification"]] = out.get(r["classification"], 0) + 1
    return out


def _correction(r) -> str:
    if r["classification"] == "notation typo":
        return ", ".join(f"{k} → {v}" for k, v in (r.get("renaming") or {}).items())
    if r["classification"] == "follows from erratum":
        return "follows from " + ", ".join(r.get("blame") or [])
    if r["classification"] == "convention-dependent":
        return f"holds with: {r.get('convention')}"
    return r.get("sentence") or ""


NO_FINDINGS = "none: every printed equation checked holds as printed"


def markdown(records, lecture: set[str] | None = None) -> str:
    """``errata.md``: the sheet in Markdown (``lecture``: see :func:`unclaimed`)."""
    counts = _counts(records)
    symbolic = sum(1 for r in records if r.get("decided_by") == "symbolic")
    outside = _outside(records, lecture)
    lines = ["# Printed equations, checked" if outside else "# Printed equations of the lecture, checked", "",
             *([outside, ""] if outside else []),
             "Each printed equation is evaluated on hypothesis states (random states and parameters) against our "
             "derivation and, where an engine gives the quantity, Pinocchio and MuJoCo; `printed − derived` is also "
             "tested for being identically zero, by a decision on the circle (s² + c² = 1) that is the same on every "
             "machine (*decided by*). Generated by `harness claims --out reports`.",
             "", f"{len(records)} printed equations: " + ", ".join(f"{v} {k}" for k, v in sorted(counts.items()))
             + f"; {symbolic} decided symbolically.", "",
             "## Findings", "", "| equation | system | kind | correction |", "|---|---|---|---|"]
    findings = [r for r in records if r["classification"] in FINDINGS]
    lines += [f"| {r['equation']} | {r['system']} | {KIND.get(r['classification'], r['classification'])} | "
              f"{_correction(r)} |" for r in findings] or [f"| {NO_FINDINGS} | | | |"]
    lines += ["", "## All printed equations", "", "| system | equation | quantity | classification | decided by |",
              "|---|---|---|---|---|"]
    lines += [f"| {r['system']} | {r['equation']} | {r['quantity']} | {r['classification']} | "
              f"{r.get('decided_by') or ''} |" for r in records]
    if findings:
        lines += ["", "## Details", ""]
    for r in findings:
        lines += [f"### {r['system']} {r['equation']}: {r['classification']}", ""]
        if r.get("sentence"):
            lines += [r["sentence"], ""]
        lines += [f"- printed: `{r['printed']}`"]
        if r.get("where"):
            lines.append(f"- checked {r['where']}")
        if r.get("renaming"):
            lines.append(f"- holds after renaming {_correction(r)}")
        if r.get("difference"):
            lines.append(f"- derived − printed: `{r['difference']}`")
        if r["classification"] not in ("notation typo", "follows from erratum"):
            lines.append(f"- derived: `{r['corrected']}`")
        if r["convention"]:
            lines.append(f"- holds with the convention: {r['convention']}")
        if r.get("blame"):
            lines.append(f"- ingredients printed wrong: {', '.join(r['blame'])}")
        reduced = r.get("counterexample_reduced")
        if reduced:
            lines.append(f"- counterexample: {_reduced_text(reduced)}")
        elif r.get("counterexample"):
            lines.append(f"- minimal counterexample: {r['counterexample']}")
        if r["note"]:
            lines.append(f"- transcription note: {r['note']}")
        lines.append("")
    missing = unclaimed(records, lecture)
    if missing:
        lines += ["## Numbered equations without a claim", "", "| equation | reason |", "|---|---|"]
        lines += [f"| ({e['eq']}) | {e['reason']} |" for e in missing]
    elif partial := _partial(records, lecture):
        lines += ["## Numbered equations without a claim", "", partial]
    return "\n".join(lines) + "\n"


def _reduced_text(reduced: dict) -> str:
    parts = []
    for key in ("coordinates", "inputs", "parameters", "accelerations (derived)"):
        values = reduced.get(key) or {}
        if values:
            parts.append(", ".join(f"{k} = {v}" for k, v in values.items()))
    text = "; ".join(parts) or "any state"
    if "printed value" in reduced:
        text += f"; printed {reduced['printed value']} vs derived {reduced['derived value']}"
    return text


STYLE = ("table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 6px;text-align:left}"
         ".diff math{background:#fde2e2}.act{font-weight:bold}.note{color:#555;font-size:90%}")
"""The errata sheet's own style, inside the site's page ``errata.html`` (:func:`harness.report.site.write_errata`)."""


def _anchor(record) -> str:
    """The id of a finding's section: its system and equation, letters, digits and dots only."""
    return re.sub(r"[^A-Za-z0-9.]+", "-", f"{record['system']}-{record['equation']}").strip("-")


def sheet(records, lecture: set[str] | None = None) -> str:
    """The errata sheet: summary table, each finding with printed and corrected equation as MathML, the
    numbered equations without a claim (``lecture``: see :func:`unclaimed`)."""
    counts = _counts(records)
    findings = [r for r in records if r["classification"] in FINDINGS]
    outside = _outside(records, lecture)
    body = [f"<h1>{escape(title(records, lecture)).replace(LECTURE, f'<i>{LECTURE}</i>')}</h1>",
            *([f"<p>{escape(outside)}</p>"] if outside else []),
            f"<p>{len(records)} printed equations checked: "
            + ", ".join(f"{v} {escape(k)}" for k, v in sorted(counts.items())) + ".</p>",
            "<h2>Summary</h2><table><tr><th>equation</th><th>system</th><th>kind</th><th>correction</th></tr>"]
    body += [f"<tr><td><a href='#{_anchor(r)}'>{escape(r['equation'])}</a></td><td>{escape(r['system'])}</td>"
             f"<td>{escape(KIND.get(r['classification'], r['classification']))}</td>"
             f"<td>{escape(_correction(r))}</td></tr>" for r in findings]
    if not findings:
        body.append(f"<tr><td colspan='4'>{NO_FINDINGS}</td></tr>")
    body.append("</table><h2>Findings</h2>")
    if not findings:
        body.append(f"<p>{NO_FINDINGS}</p>")
    for r in findings:
        body.append(f"<section id='{_anchor(r)}'><h3>{escape(r['equation'])} ({escape(r['system'])}): "
                    f"{escape(r['classification'])}</h3>")
        if r.get("where"):
            body.append(f"<p>checked {escape(r['where'])}</p>")
        if r.get("sentence"):
            body.append(f"<p class='act'>{escape(r['sentence'])}</p>")
        if r.get("printed_mathml"):
            body.append(f"<p>printed {escape(r['equation'])}:</p>{r['printed_mathml']}")
        if r.get("corrected_mathml"):
            body.append(f"<p>corrected {escape(r['equation'])}:</p>{r['corrected_mathml']}")
        if r.get("difference_mathml"):
            body.append(f"<p class='diff'>derived − printed, Δ:</p><div class='diff'>{r['difference_mathml']}</div>")
        if r.get("counterexample_reduced"):
            body.append(f"<p>counterexample: {escape(_reduced_text(r['counterexample_reduced']))}</p>")
        if r["note"]:
            body.append(f"<p class='note'>transcription note: {escape(r['note'])}</p>")
        body.append("</section>")
    missing = unclaimed(records, lecture)
    if missing:
        body.append("<h2>Numbered equations without a claim</h2><table><tr><th>equation</th><th>reason</th></tr>")
        body += [f"<tr><td>({escape(e['eq'])})</td><td>{escape(e['reason'])}</td></tr>" for e in missing]
        body.append("</table>")
    elif partial := _partial(records, lecture):
        body.append(f"<h2>Numbered equations without a claim</h2><p>{escape(partial)}</p>")
    return "\n".join(body)
