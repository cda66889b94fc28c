"""The confusion matrix of era.explain against blind truths: a test helper, no tests.

:func:`score` classes one explanation against what a truth hid (opensees_truth.TruthCase.truth); :func:`matrix`
runs a list of cases through an explain function and counts the four outcomes per family and effect type;
:func:`table` prints them.
"""

from __future__ import annotations

import numbers
import time
from collections import Counter

import era

OUTCOMES = ("named right", "set contains truth", "confident wrong", "honest")


def _place(loc):
    """A comparable place: a member (two node ids) as a frozenset, a node id as str, None as None."""
    if loc is None:
        return None
    if isinstance(loc, (tuple, list)):
        return frozenset(str(v) for v in loc) if len(loc) == 2 and all(isinstance(v, str) for v in loc) else \
            tuple(loc)
    return str(loc)


def places_of(effect) -> list:
    """The places a named effect's verdict leaves open, best first: its ``places`` [(place, probability), ...]
    when it has them (a verdict "one of these places"), else its location followed by the other places the
    report keeps in contention (``other_locations``). One place means a confident single place."""
    got = getattr(effect, "places", None)
    if got:
        return [_place(p[0] if isinstance(p, (tuple, list)) and len(p) == 2 and isinstance(p[1], numbers.Real) else p)
                for p in got]
    return [_place(effect.location)] + [_place(loc) for loc, _ in getattr(effect, "other_locations", ())]


def score(explanation, case) -> str:
    """One of OUTCOMES for ``explanation`` (an era Explanation, or None when explain refused in words) against
    ``case.truth["effects"]`` [(kind, place, size)], kind "outside" for an effect the library cannot name.

    The named effects are ``explanation.effects`` (whatever the verdict). Each is matched to a distinct true
    effect of the same kind (name); its places are :func:`places_of`.

    - "honest": nothing named (no effect; verdict "no_significant_discrepancy", "ambiguous", "unexplained", or a
      refusal in words). Right when the truth is none or outside the library; a miss, not an error, when the
      data cannot tell the hidden effect from the model-form scatter.
    - "confident wrong": some named effect has no true effect of its kind left to match (a wrong kind, an extra
      effect that is not there, anything named when the truth is none or outside), or its places do not hold
      the true place.
    - "set contains truth": every named effect matches, and at least one of them leaves several places open
      (a verdict "one of these places", or a best place with others still in contention) among which is the
      true one, first or not.
    - "named right": every named effect is a single confident name: one place (or none, for spread mass), the
      true effect's kind and place (no wrong extra; a subset of the hidden effects counts: the rest were not
      named, nothing wrong was).
    """
    named = tuple(getattr(explanation, "effects", ()) or ()) if explanation is not None else ()
    if not named:
        return "honest"
    left = [(kind, _place(place)) for kind, place, _ in case.truth["effects"] if kind != "outside"]
    if len(left) < len(case.truth["effects"]):
        return "confident wrong"
    in_set = False
    for e in named:
        places = places_of(e)
        match = next((t for t in left if t[0] == e.name and t[1] in places), None)
        if match is None:
            return "confident wrong"
        left.remove(match)
        in_set |= len(places) > 1
    return "set contains truth" if in_set else "named right"


def matrix(cases, explain_fn=None, verbose: bool = True) -> dict:
    """Run every case through ``explain_fn(case) -> Explanation`` (default ``era.explain(case.data,
    case.frame)``); an era.EraError is a refusal in words (scored "honest"), any other exception is recorded as
    "failed". Returns {"rows": [per case: name, family, label, seed, outcome, verdict, named, truth, seconds],
    "counts": {(family, label): Counter}, "families": {family: Counter}, "total": Counter}."""
    explain_fn = explain_fn or (lambda c: era.explain(c.data, c.frame))
    rows = []
    for c in cases:
        t = time.perf_counter()
        try:
            r = explain_fn(c)
            outcome, verdict = score(r, c), r.verdict
        except era.EraError as exc:
            r, outcome, verdict = None, "honest", f"refused: {exc}"[:60]
        except Exception as exc:       # noqa: BLE001 — a defect to count, not to hide
            r, outcome, verdict = None, "failed", f"{type(exc).__name__}: {exc}"[:60]
        named = [(e.name, "/".join(f"{'-'.join(sorted(p)) if isinstance(p, frozenset) else p}" for p in places_of(e)))
                 for e in (getattr(r, "effects", ()) or ())]
        row = dict(name=c.name, family=c.family, label=getattr(c, "label", ""), seed=c.seed, outcome=outcome,
                   verdict=verdict, named=named, truth=c.truth["effects"], seconds=time.perf_counter() - t)
        rows.append(row)
        if verbose:
            said = ", ".join(f"{n}@{p}" for n, p in named) or "-"
            print(f"  {outcome:18s} {c.name:60s} {verdict:26s} named [{said}] {row['seconds']:.1f} s", flush=True)
    counts, families = {}, {}
    for row in rows:
        counts.setdefault((row["family"], row["label"]), Counter())[row["outcome"]] += 1
        families.setdefault(row["family"], Counter())[row["outcome"]] += 1
    return dict(rows=rows, counts=counts, families=families, total=sum(families.values(), Counter()))


def table(result: dict, title: str = "") -> str:
    """The counts as a text table: one row per family and effect type, a subtotal per family, a total."""
    heads = ("right", "in set", "WRONG", "honest") + (("failed",) if result["total"]["failed"] else ())
    keys = OUTCOMES + (("failed",) if result["total"]["failed"] else ())
    lines = [title] if title else []
    lines.append(f"{'family':11s} {'effect':26s} " + " ".join(f"{h:>7s}" for h in heads) + "   cases")
    for fam, per in result["families"].items():
        for (f, label), cnt in result["counts"].items():
            if f == fam:
                lines.append(f"{fam:11s} {label:26s} " + " ".join(f"{cnt[k]:7d}" for k in keys)
                             + f"   {sum(cnt.values()):5d}")
        lines.append(f"{fam:11s} {'(all)':26s} " + " ".join(f"{per[k]:7d}" for k in keys)
                     + f"   {sum(per.values()):5d}")
    tot = result["total"]
    lines.append(f"{'total':11s} {'':26s} " + " ".join(f"{tot[k]:7d}" for k in keys) + f"   {sum(tot.values()):5d}")
    return "\n".join(lines)
