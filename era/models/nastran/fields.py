"""A bulk-data deck's text as cards: small field (8 characters), large field (16 characters, a star after the name
and on its continuations), free field (commas); continuation lines ("+", "*", a blank first field, a leading
comma), "$" comments, INCLUDE relative to the including file (quoted paths, also over several lines), tabs to the
next 8th column. Executive and case control before BEGIN BULK are skipped, except the case control's SPC and MPC
sets; reading stops at ENDDATA. A file without BEGIN BULK is bulk data throughout (an included .blk file)."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ...errors import DataError
from .values import BulkCard

_BEGIN_BULK = re.compile(r"^\s*BEGIN\s+(?:BULK|SUPER)", re.I)
_CASE_SPC = re.compile(r"^\s*SPC\s*=\s*(\d+)", re.I)
_CASE_MPC = re.compile(r"^\s*MPC\s*=\s*(\d+)", re.I)
_INCLUDE = re.compile(r"^\s*INCLUDE\b(.*)$", re.I)
_ENDDATA = re.compile(r"^\s*ENDDATA\b", re.I)
_MAX_DEPTH = 20


@dataclass(frozen=True)
class BulkData:
    """The cards of a deck and what its case control says about them.

    cards : every bulk-data card in the order read (includes expanded in place);
    case_spc : the SPC set the case control selects (the first one when subcases select several), None when it
        selects none (then every SPC and SPC1 card applies);
    notes : sentences about what was read differently from the deck's own solution (e.g. several SPC sets);
    path : the deck's main file;
    case_mpc : the MPC set the case control selects (the first), None when it selects none.
    """

    cards: tuple[BulkCard, ...]
    case_spc: int | None
    notes: tuple[str, ...]
    path: str
    case_mpc: int | None = None


def read_bulk(path) -> BulkData:
    """Read a deck (``.bdf``, ``.dat``, ``.nas``) and the files it includes into cards.

    Raises DataError naming the file and line when a file is missing, an INCLUDE has no path, or the includes
    nest deeper than 20 files (a file that includes itself)."""
    path = Path(path)
    lines = _file_lines(path, path, None)
    start = next((k for k, (_, _, text) in enumerate(lines) if _BEGIN_BULK.match(_strip_comment(text))), None)
    sets: list[int] = []
    mpcs: list[int] = []
    if start is not None:
        for _, _, text in lines[:start]:
            for pattern, found in ((_CASE_SPC, sets), (_CASE_MPC, mpcs)):
                m = pattern.match(_strip_comment(text))
                if m:
                    found.append(int(m.group(1)))
        lines = lines[start + 1:]
    notes = []
    if len(set(sets)) > 1:
        notes.append(f"The case control selects SPC sets {', '.join(map(str, dict.fromkeys(sets)))}; "
                     f"set {sets[0]} (the first) is used.")
    if len(set(mpcs)) > 1:
        notes.append(f"The case control selects MPC sets {', '.join(map(str, dict.fromkeys(mpcs)))}; "
                     f"set {mpcs[0]} (the first) is used.")
    cards = _cards(_expand(lines, path, path, 0))
    return BulkData(tuple(cards), sets[0] if sets else None, tuple(notes), str(path), mpcs[0] if mpcs else None)


def _file_lines(path: Path, root: Path, where: str | None) -> list[tuple[str, int, str]]:
    """(file shown in messages, line number, text) of one file; ``where`` says who included it."""
    try:
        raw = path.read_bytes()
    except OSError:
        by = f" (included at {where})" if where else ""
        raise DataError(f"The Nastran file {path}{by} cannot be read: it does not exist or is not a file. "
                        "Give the deck's path; INCLUDE paths are relative to the file that includes them.") from None
    shown = _shown(path, root)
    return [(shown, k + 1, text) for k, text in enumerate(raw.decode("latin-1").splitlines())]


def _shown(path: Path, root: Path) -> str:
    try:
        return path.resolve().relative_to(root.resolve().parent).as_posix()
    except ValueError:
        return path.name


def _strip_comment(text: str) -> str:
    cut = text.find("$")
    return text if cut < 0 else text[:cut]


def _expand(lines, path: Path, root: Path, depth: int):
    """Yield (file, line, text) of bulk lines with INCLUDE files read in place; stop at ENDDATA."""
    k = 0
    while k < len(lines):
        shown, number, text = lines[k]
        k += 1
        body = _strip_comment(text).rstrip()
        if not body.strip():
            continue
        if _ENDDATA.match(body):
            return True
        if _BEGIN_BULK.match(body):      # in an included file that starts the bulk data itself
            continue
        m = _INCLUDE.match(body)
        if m is None:
            yield shown, number, body
            continue
        name, k = _include_path(m.group(1), lines, k, f"{shown}, line {number}")
        if depth >= _MAX_DEPTH:
            raise DataError(f"{shown}, line {number}: INCLUDE nests deeper than {_MAX_DEPTH} files (a file that "
                            "includes itself?). Remove the circular INCLUDE.")
        target = Path(name.replace("\\", "/"))
        target = target if target.is_absolute() else path.parent / target
        inner = _file_lines(target, root, f"{shown}, line {number}")
        ended = yield from _expand(inner, target, root, depth + 1)
        if ended:
            return True
    return False


def _include_path(rest: str, lines, k: int, where: str) -> tuple[str, int]:
    """The path of an INCLUDE (quoted, possibly continued on the next lines, or bare) and the next line index."""
    text = rest.strip()
    if not text:
        raise DataError(f"{where}: INCLUDE without a file name. Write INCLUDE 'file.bdf'.")
    if text[0] not in "'\"":
        return text.split()[0], k
    quote, text = text[0], text[1:]
    while quote not in text:
        if k >= len(lines):
            raise DataError(f"{where}: the INCLUDE path has no closing quote. Close it with {quote}.")
        text += _strip_comment(lines[k][2]).strip()
        k += 1
    return text[:text.index(quote)], k


def _split(body: str) -> tuple[str, list[str], bool]:
    """(first field, data fields, large) of one line in any of the three formats."""
    if "," in body:
        tokens = [t.strip() for t in body.split(",")]
        first = tokens[0]
        large = first.endswith("*") or first.startswith("*")
        width = 4 if large else 8
        data = tokens[1:] if len(tokens) > width + 2 else (tokens[1:width + 1] + [""] * width)[:width]
        return first, data, large
    body = body.expandtabs(8).ljust(80)
    first = body[:8].strip()
    large = first.endswith("*") or first.startswith("*")
    if large:
        return first, [body[8 + 16 * i:24 + 16 * i].strip() for i in range(4)], True
    return first, [body[8 + 8 * i:16 + 8 * i].strip() for i in range(8)], False


def _cards(lines) -> list[BulkCard]:
    cards: list[BulkCard] = []
    name, fields, start, last = None, [], ("", 0), 0
    for shown, number, body in lines:
        first, data, _ = _split(body)
        if first == "" or first[0] in "+*":
            if name is None:
                raise DataError(f"{shown}, line {number}: a continuation line with no card before it. "
                                "Start the card with its name in the first field.")
            fields += data
            last = number
            continue
        if name is not None:
            cards.append(_card(name, fields, start, last))
        name, fields, start, last = first.rstrip("*").upper(), list(data), (shown, number), number
    if name is not None:
        cards.append(_card(name, fields, start, last))
    return cards


def _card(name: str, fields: list[str], start, last: int) -> BulkCard:
    while fields and fields[-1] == "":
        fields.pop()
    return BulkCard(name, tuple(fields), start[0], start[1], last)
