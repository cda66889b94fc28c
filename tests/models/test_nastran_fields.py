"""The bulk-data reader's text layer: Nastran's numbers, the three field formats, continuations, comments,
INCLUDE, BEGIN BULK and the case control's SPC set, and errors that name the file, line and card."""

from __future__ import annotations

import pytest

from era.errors import DataError
from era.models.nastran.fields import read_bulk
from era.models.nastran.values import nastran_real


@pytest.mark.parametrize("text, value", [("1.-3", 1e-3), ("-2.5+4", -2.5e4), ("7.E3", 7e3), ("1.0D-3", 1e-3),
                                         (".5", 0.5), ("3.0000+7", 3e7), ("2.5900-3", 2.59e-3), ("12", 12.0),
                                         ("-.25E-2", -0.0025), ("+4.", 4.0)])
def test_nastran_reals(text, value):
    assert nastran_real(text) == pytest.approx(value, rel=1e-15)


@pytest.mark.parametrize("text", ["1.2.3", "abc", "1e", "--1.", "", "1.-"])
def test_not_reals(text):
    assert nastran_real(text) is None


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(text)
    return p


def test_small_large_and_free_field_give_the_same_fields(tmp_path):
    small = ("GRID           7       0    1.25  -2.5+4    1.-3       0\n"
             "CONM2         21      11       0    2.59     0.0     0.0     0.0        +C1\n"
             "+C1        1.-3     0.0    2.-3     0.0     0.0    3.-3\n")
    large = ("GRID*                  7               0            1.25          -2.5+4\n"
             "*                   1.-3               0\n"
             "CONM2*               21              11               0            2.59\n"
             "*                    0.0             0.0             0.0\n"
             "*                   1.-3             0.0            2.-3             0.0\n"
             "*                    0.0            3.-3\n")
    free = "GRID,7,0,1.25,-2.5+4,1.-3,0\nCONM2,21,11,0,2.59,0.0,0.0,0.0,,+\n+,1.-3,0.0,2.-3,0.0,0.0,3.-3\n"
    read = [read_bulk(_write(tmp_path, f"{k}.bdf", t)).cards for k, t in enumerate((small, large, free))]
    for cards in read:
        assert [c.name for c in cards] == ["GRID", "CONM2"]
        assert cards[0].fields == ("7", "0", "1.25", "-2.5+4", "1.-3", "0")
        assert cards[1].fields == ("21", "11", "0", "2.59", "0.0", "0.0", "0.0", "", "1.-3", "0.0", "2.-3", "0.0",
                                   "0.0", "3.-3")


def test_comments_blank_continuations_tabs_and_the_end(tmp_path):
    text = ("$ a comment line\n"
            "PARAM,WTMASS,0.00259 $ trailing comment\n"
            "CBAR    1\t1\t1\t2\t0.\t1.\t0.\n"     # tabs move to the next 8th column
            "        \t\t0.1\n"                     # a continuation with a blank first field
            "\n"
            "ENDDATA\n"
            "GRID    99\n")                          # after ENDDATA: not read
    cards = read_bulk(_write(tmp_path, "d.bdf", text)).cards
    assert [c.name for c in cards] == ["PARAM", "CBAR"]
    assert cards[0].fields == ("WTMASS", "0.00259")
    assert cards[1].fields[:8] == ("1", "1", "1", "2", "0.", "1.", "0.", "")
    assert cards[1].fields[8:] == ("", "", "0.1")
    assert (cards[1].line, cards[1].last_line) == (3, 4)


def test_executive_and_case_control_are_skipped_but_the_spc_set_is_kept(tmp_path):
    text = ("SOL 103\nCEND\nTITLE = GRID 1 is not a card here\nSUBCASE 1\n  SPC = 2\n  METHOD = 1\n"
            "BEGIN BULK\nGRID,1\nENDDATA\n")
    bulk = read_bulk(_write(tmp_path, "d.dat", text))
    assert [c.name for c in bulk.cards] == ["GRID"] and bulk.case_spc == 2 and bulk.notes == ()
    two = read_bulk(_write(tmp_path, "e.dat", text.replace("METHOD = 1", "SUBCASE 2\nSPC=3")))
    assert two.case_spc == 2 and "SPC sets 2, 3" in two.notes[0]


def test_include_relative_to_the_including_file_quoted_and_over_two_lines(tmp_path):
    _write(tmp_path, "main.bdf", "BEGIN BULK\nINCLUDE 'parts/plate.bdf'\nGRID,3\nENDDATA\n")
    _write(tmp_path, "parts/plate.bdf", "GRID,1\nINCLUDE 'more/\n  mat.bdf'\n")   # relative to parts/
    _write(tmp_path, "parts/more/mat.bdf", "MAT1,1,2.1+11,,0.3\n")
    bulk = read_bulk(tmp_path / "main.bdf")
    assert [(c.name, c.file) for c in bulk.cards] == [("GRID", "parts/plate.bdf"), ("MAT1", "parts/more/mat.bdf"),
                                                      ("GRID", "main.bdf")]


def test_a_missing_include_names_the_including_line(tmp_path):
    _write(tmp_path, "main.bdf", "GRID,1\nINCLUDE 'nowhere.bdf'\n")
    with pytest.raises(DataError, match=r"nowhere\.bdf \(included at main\.bdf, line 2\)"):
        read_bulk(tmp_path / "main.bdf")


def test_an_include_circle_is_refused(tmp_path):
    _write(tmp_path, "a.bdf", "INCLUDE 'a.bdf'\n")
    with pytest.raises(DataError, match="nests deeper"):
        read_bulk(tmp_path / "a.bdf")


def test_a_continuation_without_a_card_is_an_error_with_its_line(tmp_path):
    with pytest.raises(DataError, match=r"d\.bdf, line 2: a continuation line"):
        read_bulk(_write(tmp_path, "d.bdf", "$ nothing\n+       1.0\n"))
