"""ERA within this server's limits: the H(0) size (ERA_MAX_HANKEL_ELEMENTS) and the order (ERA_MAX_ORDER).

era/ has its own, larger limits (era.core.hankel.MAX_HANKEL_ELEMENTS); these are what one shared server affords per
request, so a refusal names the setting and a size that fits.
"""

from __future__ import annotations

import math

import era
from era.choice import DEFAULT_MAX_ORDER
from era.core import order_cap

from .config import Settings

# max_order of an analysis that does not ask for one (and the one the dataset suggests) is era's default
# (era.choice.analysis.DEFAULT_MAX_ORDER, 200), capped by ERA_MAX_ORDER: above the stabilization diagram's 160 so the
# slider goes past the diagram, and low enough that H(0) of the usual sizes takes the truncated SVD of only these
# leading triplets (era.core.svd.choose_method: max_order ≤ min(H(0) shape) / 3; the grid example's 792 × 798 H(0)
# does). An analysis that needs more asks for it, up to ERA_MAX_ORDER.


def check_hankel(rows: int, cols: int, max_order: int | None, p: int, m: int, settings: Settings) -> None:
    """Raise era.HankelError when H(0) (rows·p × cols·m) is above the server's element limit, saying what fits,
    and era.OrderError when ``max_order`` is above min(rows·p, cols·m, ERA_MAX_ORDER)."""
    elements = rows * p * cols * m
    limit = settings.max_hankel_elements
    if elements > limit:
        what = (f"H(0) would be {rows * p} × {cols * m} = {elements:,} elements (rows·p × cols·m with p = {p} "
                f"outputs, m = {m} inputs), above this server's limit of {limit:,} (ERA_MAX_HANKEL_ELEMENTS).")
        if p * m > limit:
            raise era.HankelError(f"{what} Even rows = cols = 1 is too large: raise the limit or use fewer channels.")
        fit_rows = max(1, min(math.isqrt(limit // (p * m)), rows))
        fit_cols = max(1, min(cols, limit // (p * m * fit_rows)))
        raise era.HankelError(f"{what} For example rows = {fit_rows}, cols = {fit_cols} fits.")
    cap = order_cap(rows, cols, p, m, settings.max_order)
    if max_order is not None and max_order > cap:
        raise era.OrderError(
            f"max_order = {max_order} is above what this Hankel size and server allow: min(rows·p = {rows * p}, "
            f"cols·m = {cols * m}, server limit {settings.max_order}) = {cap}. Choose max_order ≤ {cap}.")


def default_max_order(rows: int, cols: int, p: int, m: int, settings: Settings) -> int:
    """The max_order of an analysis that names none: min(rows·p, cols·m, DEFAULT_MAX_ORDER, ERA_MAX_ORDER)."""
    return order_cap(rows, cols, p, m, min(DEFAULT_MAX_ORDER, settings.max_order))


def identify_within_limits(data: era.ResponseData, params: dict, settings: Settings) -> era.Identification:
    """era.identify with the stored parameters {rows, cols, row_shifts, col_shifts, max_order} after the server's
    limits are checked; max_order defaults to :func:`default_max_order`. Blocking (one SVD, or the truncated one
    of the leading max_order triplets when that is far below H(0)'s size: era.core.svd.choose_method)."""
    n, p, m = data.markov.shape
    rows, cols = params["rows"], params["cols"]
    check_hankel(rows, cols, params.get("max_order"), p, m, settings)
    max_order = params.get("max_order") or default_max_order(rows, cols, p, m, settings)
    ident = era.identify(data, rows, cols, params.get("row_shifts"), params.get("col_shifts"), max_order=max_order)
    if ident.max_order == 0:
        raise era.DataError("H(0) has rank 0: the records are zero (or round-off) throughout, so there is "
                            "nothing to identify. Check the file's channels and scaling.")
    return ident
