"""The spreadsheet recipes of docs/ecosystem.md, run in headless LibreOffice Calc against a
live server: single cells through ``=WEBSERVICE()`` on ``GET /v1/curves/{name}/value``, and
a whole table by opening the CSV URL with the CSV filter.

Numbers leave LibreOffice 7.4 with 15 significant digits (its export precision), so a
number is compared to camcore's within half a unit of its 15th digit; the text a
WEBSERVICE cell receives is compared exactly.
"""

from __future__ import annotations

import csv
import math
import xml.etree.ElementTree as ET
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np
import pytest

import camcore
from tests.libreoffice import UPDATE_LINKS_ALWAYS, configure, convert, run_basic, trusted_location

pytestmark = [pytest.mark.e2e, pytest.mark.libreoffice]

MS = camcore.named_curve("MS")
NS = {"table": "urn:oasis:names:tc:opendocument:xmlns:table:1.0",
      "office": "urn:oasis:names:tc:opendocument:xmlns:office:1.0",
      "text": "urn:oasis:names:tc:opendocument:xmlns:text:1.0"}
CSV_FILTER = "Text - txt - csv (StarCalc):44,34,76,1"  # comma, double quote, UTF-8, from line 1
#: the same, writing: en-US, and (9th option false) numbers in full, not "as shown" (2.78E-16)
CSV_OUT = CSV_FILTER + ",,1033,false,true,false"


def near_15_digits(got: float, want: float) -> bool:
    """Whether ``got`` is ``want`` printed with 15 significant digits (half a unit of the
    15th digit, plus one ulp for reading the digits back)."""
    if want == 0:
        return got == 0
    half_unit = 0.5 * 10.0 ** (math.floor(math.log10(abs(want))) - 14)
    return abs(got - want) <= half_unit + math.ulp(want)


def _formula(text: str) -> str:
    """A cell with a formula in OpenFormula syntax (WEBSERVICE is COM.MICROSOFT.WEBSERVICE
    in a file; arguments separated by ';', cell A2 written [.A2])."""
    return f"<table:table-cell table:formula={quoteattr('of:=' + text)}/>"


def _number(value: float) -> str:
    return f'<table:table-cell office:value-type="float" office:value="{value!r}"/>'


def _spreadsheet(*rows: str) -> str:
    """A flat-XML spreadsheet (.fods), one sheet, these rows of cells."""
    body = "".join(f"<table:table-row>{row}</table:table-row>" for row in rows)
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<office:document xmlns:office="{NS['office']}" xmlns:table="{NS['table']}" xmlns:text="{NS['text']}"
 xmlns:of="urn:oasis:names:tc:opendocument:xmlns:of:1.2" office:version="1.3"
 office:mimetype="application/vnd.oasis.opendocument.spreadsheet">
 <office:body><office:spreadsheet><table:table table:name="cam">{body}</table:table></office:spreadsheet></office:body>
</office:document>
"""


def _sheet(url: str) -> str:
    """WEBSERVICE cells on /value, as a user types them: A1 the text of S at T = 0.3; B1
    its number (VALUE); C1 T of the exact inverse at S = 11/60 (NUMBERVALUE with '.');
    A2 an S typed in, B2 the T where S = A2 (the URL built from the cell)."""
    return _spreadsheet(
        _formula(f'COM.MICROSOFT.WEBSERVICE("{url}?t=0.3")')
        + _formula(f'VALUE(COM.MICROSOFT.WEBSERVICE("{url}?t=0.3"))')
        + _formula(f'NUMBERVALUE(COM.MICROSOFT.WEBSERVICE("{url}?s={11 / 60!r}");".")'),
        _number(0.1833) + _formula(f'VALUE(COM.MICROSOFT.WEBSERVICE("{url}?s="&[.A2]))'))


def _cells(fods: Path) -> list[list[tuple[str, str]]]:
    """Each cell of the first sheet as (the value LibreOffice stored, the text it shows),
    without the empty cells LibreOffice writes after the last one of a row."""
    rows = []
    for row in ET.parse(fods).getroot().iterfind(".//table:table/table:table-row", NS):
        cells = []
        for cell in row.iterfind("table:table-cell", NS):
            stored = cell.get(f"{{{NS['office']}}}value") or cell.get(f"{{{NS['office']}}}string-value") or ""
            shown = "".join(p.text or "" for p in cell.iterfind("text:p", NS))
            cells.append((stored, shown))
        while cells and cells[-1] == ("", ""):
            cells.pop()
        rows.append(cells)
    return rows


def _open_in_calc(profile: Path, source: Path, target: Path) -> None:
    """Open ``source`` as a user does (links updated according to the settings) and save
    it as ``target`` (.fods)."""
    run_basic(profile, f"""
  Dim load(1) As New com.sun.star.beans.PropertyValue
  load(0).Name = "Hidden" : load(0).Value = True
  load(1).Name = "UpdateDocMode" : load(1).Value = com.sun.star.document.UpdateDocMode.ACCORDING_TO_CONFIG
  doc = StarDesktop.loadComponentFromURL("{source.resolve().as_uri()}", "_blank", 0, load())
  Dim save(0) As New com.sun.star.beans.PropertyValue
  save(0).Name = "FilterName" : save(0).Value = "OpenDocument Spreadsheet Flat XML"
  doc.storeToURL("{target.resolve().as_uri()}", save())
  doc.close(True)""")
    assert target.exists(), "the macro did not save the spreadsheet"


def test_webservice_cells_give_the_numbers_once_links_may_update(base_url: str, tmp_path: Path) -> None:
    folder = tmp_path / "sheets"
    folder.mkdir()
    sheet = folder / "cam.fods"
    sheet.write_text(_sheet(f"{base_url}/v1/curves/MS/value"), encoding="utf-8")

    allowed = tmp_path / "allowed"
    configure(allowed / "profile", UPDATE_LINKS_ALWAYS | trusted_location(folder))
    _open_in_calc(allowed / "profile", sheet, allowed / "cam.fods")
    (a1, b1, c1), (_a2, b2) = _cells(allowed / "cam.fods")

    s_at_03 = float(MS.evaluate(np.array([0.3])).s[0])
    assert a1[0] == repr(s_at_03)  # the cell holds the answer's text, every digit
    assert round(float(a1[0]), 5) == 0.17789  # INDEXMAN MS table, T = 0.30
    assert near_15_digits(float(b1[0]), s_at_03)
    # INDEXMAN technical guide, worked example, exact method: S = 11/60 → T = 0.3040904
    assert near_15_digits(float(c1[0]), 0.3040903772609671)
    assert near_15_digits(float(b2[0]), float(MS.inverse(np.array([0.1833]))[0]))

    # without the two settings the cells stay an error: Err:540, "external links not updated"
    closed = tmp_path / "closed"
    configure(closed / "profile", {})
    _open_in_calc(closed / "profile", sheet, closed / "cam.fods")
    assert {shown for row in _cells(closed / "cam.fods") for _, shown in row} == {"Err:540", "0.1833"}
    # and --convert-to never updates links (it loads every file with link updates off)
    converted = convert(sheet, "fods", tmp_path / "converted", profile=allowed / "profile")
    assert _cells(converted)[0] == [("", "Err:540")] * 3


def test_decimal_comma_locales_need_a_point_in_the_url_and_numbervalue(base_url: str, tmp_path: Path) -> None:
    """In a German LibreOffice a number joined to text is written 0,1833 (the service wants
    0.1833: SUBSTITUTE the comma) and VALUE reads only 0,30…: NUMBERVALUE(…; ".") reads both."""
    url = f"{base_url}/v1/curves/MS/value"
    folder = tmp_path / "sheets"
    folder.mkdir()
    (folder / "de.fods").write_text(_spreadsheet(
        _number(0.1833)
        + _formula(f'NUMBERVALUE(COM.MICROSOFT.WEBSERVICE("{url}?s="&SUBSTITUTE([.A1];",";"."));".")')
        + _formula(f'VALUE(COM.MICROSOFT.WEBSERVICE("{url}?t=0.3"))')), encoding="utf-8")
    german = {("/org.openoffice.Setup/L10N", "ooSetupSystemLocale"): "de-DE",
              ("/org.openoffice.Office.Linguistic/General", "DefaultLocale"): "de-DE"}
    configure(tmp_path / "profile", UPDATE_LINKS_ALWAYS | trusted_location(folder) | german)
    _open_in_calc(tmp_path / "profile", folder / "de.fods", tmp_path / "de.fods")
    ((a1, b1, c1),) = _cells(tmp_path / "de.fods")
    assert a1 == ("0.1833", "0,1833")  # the German display: the locale took effect
    assert near_15_digits(float(b1[0]), float(MS.inverse(np.array([0.1833]))[0]))
    assert c1 == ("", "Err:502")  # VALUE("0.17788…") is not a number in German


def test_the_csv_url_opens_as_a_table_with_the_csv_filter(base_url: str, tmp_path: Path) -> None:
    url = f"{base_url}/v1/curves/MS/table?samples=101&format=csv"
    out = convert(url, f"csv:{CSV_OUT}", tmp_path / "out", profile=tmp_path / "profile", infilter=CSV_FILTER)
    with out.open(encoding="utf-8", newline="") as f:
        header, *rows = list(csv.reader(f))
    assert header == ["t", "s", "v", "a", "j", "q"] and len(rows) == 101
    want = MS.evaluate(MS.sample_times(101)).columns()
    for i, row in enumerate(rows):
        for name, text in zip(header, row):
            assert near_15_digits(float(text), float(want[name][i])), (i, name, text, want[name][i])
