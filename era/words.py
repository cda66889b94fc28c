"""Counts, lists and numbers in words for the sentences era writes (readers' descriptions, conversions, refusals):
"1 channel", "2 channels", never "channel(s)"; "samples 10 and 12", never "[10, 12]"; "Δt = 0.0000390625 s
(25600 Hz)", never "3.90625e-05"."""

from __future__ import annotations

import numpy as np


def counted(n: int, one: str, many: str | None = None) -> str:
    """``n`` and the noun that agrees with it: counted(1, "channel") -> "1 channel", counted(3, "channel") ->
    "3 channels"; ``many`` for an irregular plural (counted(2, "axis", "axes") -> "2 axes")."""
    n = int(n)
    return f"{n} {one if n == 1 else (many or one + 's')}"


def listed(items, quote: bool = False) -> str:
    """Items as a sentence lists them: "a", "a and b", "a, b and c" (``quote``: each in single quotes, as names
    a person typed are quoted: "'colour' and 'size'")."""
    words = [f"'{x}'" if quote else str(x) for x in items]
    if len(words) < 2:
        return "".join(words)
    return f"{', '.join(words[:-1])} and {words[-1]}"


def significant(x: float, digits: int = 6) -> str:
    """``x`` to ``digits`` significant digits, written out (no exponent, no trailing zeros): 3.90625e-05 ->
    "0.0000390625", 0.00060546875000399 -> "0.000605469", 25600.000000000004 -> "25600"."""
    return np.format_float_positional(float(x), precision=digits, unique=True, fractional=False, trim="-")


def sampling(dt: float, how: str = "") -> str:
    """A sampling interval as a person reads it: "Δt = 0.000605469 s (1651.61 Hz)" (dt in s; 6 significant digits,
    its rate beside it); ``how`` goes inside the brackets after the rate ("1651.61 Hz, from Delta_X")."""
    return f"Δt = {significant(dt)} s ({significant(1 / dt)} Hz{', ' + how if how else ''})"
