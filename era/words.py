"""Counts in words for the sentences era writes (readers' descriptions, conversions, refusals): "1 channel",
"2 channels", never "channel(s)"."""

from __future__ import annotations


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
