"""One bulk-data field as a number: Nastran's integers and reals ("1.-3", "-2.5+4", "7.E3", "1.0D-3"), with an
error that names the file, the line, the card and the field when a field is not what the card needs."""

from __future__ import annotations

import re
from dataclasses import dataclass

from ...errors import DataError

# a mantissa with a decimal point or digits, then an exponent written with E/D or only with its sign ("1.-3")
_REAL = re.compile(r"^([+-]?(?:\d+\.?\d*|\.\d+))(?:[EeDd]([+-]?\d+)|([+-]\d+))?$")
_INT = re.compile(r"^[+-]?\d+$")


def nastran_real(text: str) -> float | None:
    """The value of a Nastran real field, or None when ``text`` is not one ("1.-3" -> 0.001, "-2.5+4" -> -25000,
    "7.E3" -> 7000, "1.0D-3" -> 0.001; an integer "3" is read as 3.0)."""
    m = _REAL.match(text.strip())
    if not m:
        return None
    exponent = m.group(2) or m.group(3)
    return float(m.group(1) + (f"e{exponent}" if exponent else ""))


@dataclass(frozen=True)
class BulkCard:
    """One bulk-data entry with its continuations.

    name : the card's name in upper case without the large-field star ("GRID");
    fields : its data fields (Nastran's fields 2-9, 12-19, ... of the small-field layout), stripped text, "" when
        blank; continuation markers are left out;
    file, line : where it starts (for messages); last_line : its last continuation line (0: the card is one line).
    """

    name: str
    fields: tuple[str, ...]
    file: str
    line: int
    last_line: int = 0

    def where(self) -> str:
        """ "deck.bdf, line 12, GRID 7": the place and the card's first field, for messages."""
        first = f" {self.fields[0]}" if self.fields and self.fields[0] else ""
        return f"{self.file}, line {self.line}, {self.name}{first}"

    def text(self, i: int) -> str:
        """Field ``i`` (0: the first data field) as text, "" when blank or absent."""
        return self.fields[i].strip() if i < len(self.fields) else ""

    def blank(self, i: int) -> bool:
        return self.text(i) == ""

    def integer(self, i: int, what: str, default: int | None = None) -> int:
        """Field ``i`` as an integer; ``default`` when blank (a required field has none: blank is an error)."""
        t = self.text(i)
        if not t:
            if default is None:
                raise self.error(f"{what} is blank; the card needs it")
            return default
        if not _INT.match(t):
            raise self.error(f"{what} '{t}' is not an integer")
        return int(t)

    def real(self, i: int, what: str, default: float | None = None) -> float:
        """Field ``i`` as a real in any Nastran notation; ``default`` when blank (None: required)."""
        t = self.text(i)
        if not t:
            if default is None:
                raise self.error(f"{what} is blank; the card needs it")
            return default
        v = nastran_real(t)
        if v is None:
            raise self.error(f"{what} '{t}' is not a number")
        return v

    def optional_real(self, i: int, what: str) -> float | None:
        """Field ``i`` as a real, or None when blank."""
        return None if self.blank(i) else self.real(i, what)

    def components(self, i: int, what: str, default: str | None = None) -> str:
        """Field ``i`` as Nastran component digits ("123456", "0" for a scalar point); sorted, unique."""
        t = self.text(i) or (default if default is not None else "")
        if not t:
            raise self.error(f"{what} is blank; the card needs component digits such as 123456")
        if not re.fullmatch(r"[0-6]+", t):
            raise self.error(f"{what} '{t}' is not a set of component digits 1 to 6")
        return "".join(sorted(set(t)))

    def error(self, message: str) -> DataError:
        return DataError(f"{self.where()}: {message}. Correct the card in the deck and load it again.")
