"""The verdict of explain() and its words: whether the named set may be named, and the message for the report."""

from __future__ import annotations

import numpy as np

from ..core.correlation import pair_modes
from ..words import counted, listed
from .effects import short_place
from .measured import MeasuredModes
from .protocol import Modes
from .search import Search


def too_few_data(fm: MeasuredModes, found: Search) -> str | None:
    """A sentence when the data hold no more numbers than the named set has unknowns (its parameters, the
    stiffness factor and, for located effects, their places): it then fits them whatever the truth, and no name
    is warranted (one sensor on a cantilever: k frequencies, unit shapes that say nothing). None otherwise."""
    p, k = fm.shapes.shape
    n_data = k * p                      # k frequencies and k unit-norm shapes of p − 1 free components each
    n_places = sum(1 for r in found.named if len(r.locations) > 1 or r.location is not None)
    n_unknown = (0 if found.fit is None else len(found.fit.params)) + n_places
    if n_data > n_unknown:
        return None
    names = " + ".join(r.name for r in found.named)
    return (f"The data are {n_data} numbers ({counted(k, 'mode')} at {counted(p, 'sensor')}), no more than the "
            f"{n_unknown} unknowns of the best candidate ({names}, its stiffness factor"
            f"{' and its place' if n_places else ''}): it fits them whatever the truth, so the "
            "data cannot name it or tell it from the others; more sensors or more modes are needed.")


def modes_the_model_lacks(model: Modes, measured: MeasuredModes, n_model: int, min_mac: float = 0.6,
                          close: float = 0.03) -> str | None:
    """A sentence when the model with the named effects (``model``) leaves a measured mode without a partner
    (pairing by frequency and MAC, era.pair_modes) though it has that mode's shape (MAC ≥ min_mac) at a mode
    another measured mode pairs with: the structure has the mode twice where the model has it once (a tuned
    mass, a local mode): physics outside the library, so nothing may be named. A mode without a partner that no
    model shape resembles (noise, a sensor fault), or one of a nearly repeated pair (another measured mode within
    ``close``, relative: at few sensors the two shapes of such a pair are hardly told apart), is left aside.
    None otherwise."""
    f_model, s_model = model.modes(n_model)
    p = pair_modes(measured.frequency_hz, measured.shapes, f_model, s_model, max_freq_error=0.5)
    f = measured.frequency_hz
    alone = [i for i in range(measured.n_modes) if i not in set(p.measured_index.tolist())
             and np.min(np.abs(np.delete(f, i) - f[i]), initial=np.inf) > close * f[i]]
    if not alone or not p.n_pairs:
        return None
    a, s = measured.shapes[:, alone], s_model[:, p.model_index]
    mac = (a.T @ s) ** 2 / np.outer(np.sum(a**2, axis=0), np.maximum(np.sum(s**2, axis=0), 1e-300))
    twice = [i for i, row in zip(alone, mac) if row.max() >= min_mac]
    if not twice:
        return None
    hz = listed(f"{f[i]:.3f} Hz" for i in twice)
    one = len(twice) == 1
    return (f"The measured {'mode' if one else 'modes'} at {hz} {'has' if one else 'have'} no partner in the model, "
            f"though the model has {'its' if one else 'their'} shape (MAC ≥ {min_mac:g}) at another measured mode: "
            "the structure has a mode the model and every candidate lack (a tuned mass, a local mode), so nothing "
            "is named.")


def verdict_of(ranking, found: Search, min_probability: float, min_log_bayes: float) -> tuple:
    """(verdict, a sentence to put first in the message or None) from the step-1 ranking and the search."""
    if found.named and found.not_needed:
        return "ambiguous", (f"{listed(r.name for r in found.named)} together fit the test, but "
                             f"{listed(found.not_needed)} is not needed beside the other"
                             f"{'s' if len(found.named) > 2 else ''}: the data cannot tell which effects are "
                             "really there.")
    if found.named:
        if found.named[-1].adequate:
            return "explained", None
        last = found.rankings[-1][0]
        if (len(found.rankings) > len(found.named) and last.name != "none" and last.adequate
                and last.log_bayes_factor >= min_log_bayes):
            return "ambiguous", None
        return "unexplained", None
    best = ranking[0]
    none = next(r for r in ranking if r.name == "none")
    if best.name == "none" or (best.log_bayes_factor < min_log_bayes and none.adequate):
        return ("no_significant_discrepancy" if none.adequate else "unexplained"), None
    return ("ambiguous" if best.adequate else "unexplained"), None


def message_for(verdict, effects, ranking, found, g_b, g_a, miss, fm, fit, comac_a, unpaired) -> str:
    top = "Ranking: " + ", ".join(f"{r.name} {r.probability:.0%}" for r in ranking[:3])
    if verdict == "unexplained":
        top += " (probabilities relative to the library only; none of these fits within the error levels)"
    gaps = (f"Gap before: max |Δf| {g_b.max_abs_freq_error_pct:.2f} %, min MAC {g_b.min_mac:.3f}; after: "
            f"max |Δf| {g_a.max_abs_freq_error_pct:.2f} %, min MAC {g_a.min_mac:.3f}.")
    where = ""
    if len(miss):
        where = (" The residual lives mostly in the modes at "
                 + ", ".join(f"{fm.frequency_hz[i]:.3f} Hz (model {fit.freq_error_pct[i]:+.2f} %, MAC {fit.mac[i]:.3f})"
                             for i in miss[:4]) + (f" and {len(miss) - 4} more" if len(miss) > 4 else ""))
        low = np.flatnonzero(comac_a < 0.9)
        where += (" and at sensors " + ", ".join(str(i + 1) for i in low) if low.size else "") + "."
    aside = (f" {counted(len(unpaired), 'measured mode')} had no model partner and "
             f"{'was' if len(unpaired) == 1 else 'were'} set aside." if unpaired else "")
    partial = ""
    if verdict != "explained" and found.named:
        t = found.named[-1].test
        partial = (" The best the library can do, " + " then ".join(
            f"{r.name}{' ' + short_place(r.location) if r.location is not None else ''}" for r in found.named)
            + f", leaves max |Δf| {found.named[-1].max_abs_freq_error_pct:.2f} % and min MAC "
            f"{found.named[-1].min_mac:.3f} (frequency χ² {t.chi2_freq:.0f} over {fm.n_modes} modes), beyond "
            "the error levels, so nothing is named.")
    if verdict == "explained" and len(effects) > 1:
        head = (f"{len(effects)} effects explain the test data, most important first: "
                + " ".join(f"({i + 1}) {e.description}" for i, e in enumerate(effects)))
    else:
        head = {
            "explained": effects[0].description if effects else "",
            "no_significant_discrepancy": "The nominal model (with a global stiffness factor) agrees with the "
                                          "test within its error levels; no candidate effect is needed.",
            "ambiguous": "Several candidate effects explain the data about equally well; more sensors or modes "
                         "are needed to tell them apart.",
            "unexplained": "No candidate effect makes the model agree with the test within its error levels: the "
                           "missing physics is outside the library.",
        }[verdict]
    return f"{head}{partial} {top}. {gaps}{where}{aside}"
