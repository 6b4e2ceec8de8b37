"""The shipped workbooks (clients/spreadsheets: indexer sizing, plate-cam check; .ods and .xlsx),
opened in headless LibreOffice Calc against a live server as a user opens them (links updated:
the update-links setting and the folder a trusted location, docs/ecosystem.md), two inputs
changed, recalculated, saved, and every figure compared with the operation's own POST on the
same inputs.

The POST body is made here from the saved sheet's input rows (request field in column D, value
in column B), by the naming the cell form documents, independently of the workbook's formulas.
A figure's text (column E) must be the JSON answer's value in its shortest round-trip form,
exactly; its number (column B) leaves LibreOffice with 15 significant digits (its export
precision), so it is compared within half a unit of the 15th digit.
"""

from __future__ import annotations

import importlib.util
import itertools
import shutil
import sys
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import httpx
import pytest

from tests.clients.test_spreadsheets_libreoffice import NS, _formula, _open_in_calc, _spreadsheet, near_15_digits
from tests.clients.test_spreadsheets_libreoffice import _cells as _text_cells
from tests.libreoffice import UPDATE_LINKS_ALWAYS, configure, run_basic, trusted_location

pytestmark = [pytest.mark.e2e, pytest.mark.libreoffice]

FOLDER = Path(__file__).resolve().parents[2] / "clients" / "spreadsheets"
_spec = importlib.util.spec_from_file_location("workbook_build", FOLDER / "build.py")
assert _spec is not None and _spec.loader is not None
build = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = build  # (its dataclasses look their module up there)
_spec.loader.exec_module(build)

OPERATION_PATHS = {"sizeIndexer": "/v1/indexers/sizing", "computeProfile": "/v1/profiles",
                   "sizeBaseCircle": "/v1/profiles/base-circle"}
#: two inputs a user changes, by request field: (English value, the value typed in German)
CHANGES = {
    "indexer-sizing": {"indexer.stops": 8, "load.parts.0.mass_kg": 80.5},
    "plate-cam-check": {"profile.base_radius_mm": 35.5, "profile.follower.roller_radius_mm": 12},
}
TABLE = f"{{{NS['table']}}}"
OFFICE = f"{{{NS['office']}}}"


def _rows(fods: Path) -> list[list[dict[str, str]]]:
    """Every cell of the first sheet: its value, its shown text and its formula (repeated
    cells expanded)."""
    rows = []
    sheet = ET.parse(fods).getroot().find(".//table:table", NS)
    assert sheet is not None
    for row in sheet.iterfind("table:table-row", NS):
        cells: list[dict[str, str]] = []
        for cell in row.iterfind("table:table-cell", NS):
            value = cell.get(f"{OFFICE}value") or cell.get(f"{OFFICE}string-value") or \
                cell.get(f"{OFFICE}boolean-value") or ""
            shown = "\n".join("".join(p.itertext()) for p in cell.iterfind("text:p", NS))
            entry = {"value": value, "shown": shown, "formula": cell.get(f"{TABLE}formula", "")}
            cells += [entry] * min(int(cell.get(f"{TABLE}number-columns-repeated", "1")), 16)
        for _ in range(min(int(row.get(f"{TABLE}number-rows-repeated", "1")), 2)):
            rows.append(cells)
    return rows


def _cell(rows: list[list[dict[str, str]]], name: str) -> dict[str, str]:
    column, row = ord(name[0]) - ord("A"), int(name[1:])
    cells = rows[row - 1]
    return cells[column] if column < len(cells) else {"value": "", "shown": "", "formula": ""}


def _macro_opening(sources: list[tuple[Path, Path]], url: str, changes: dict[str, dict[str, Any]]) -> str:
    """Basic: open each source as a user does (links according to the settings), point it at the
    service, change its two inputs, recalculate, save it as flat XML."""
    body = ["  Dim load(1) As New com.sun.star.beans.PropertyValue",
            '  load(0).Name = "Hidden" : load(0).Value = True',
            '  load(1).Name = "UpdateDocMode" : load(1).Value = com.sun.star.document.UpdateDocMode.ACCORDING_TO_CONFIG',
            "  Dim save(0) As New com.sun.star.beans.PropertyValue",
            '  save(0).Name = "FilterName" : save(0).Value = "OpenDocument Spreadsheet Flat XML"']
    for source, target in sources:
        workbook = _workbook(source)
        body += [f'  doc = StarDesktop.loadComponentFromURL("{source.resolve().as_uri()}", "_blank", 0, load())',
                 "  sheet = doc.Sheets.getByIndex(0)",
                 f'  sheet.getCellRangeByName("B{build.Layout.URL_ROW}").String = "{url}"']
        for row, item, _ in build.Layout(workbook).input_rows():
            if item.path in changes.get(workbook.name, {}):
                body.append(f'  sheet.getCellRangeByName("B{row}").Value = {changes[workbook.name][item.path]!r}')
        # LibreOffice grants the file's link updates a moment after loading it (measured: a
        # recalculation at once left every figure Err:540, one after 1 s none): recalculate
        # until the first figure is no longer Err:540, for at most 20 s
        first_figure = f"E{build.Layout(workbook).output_rows()[0][0]}"
        body += ["  tries = 0", "  Do", "    doc.calculateAll()",
                 f'    If sheet.getCellRangeByName("{first_figure}").getError() <> 540 Or tries >= 80 Then Exit Do',
                 "    Wait 250", "    tries = tries + 1", "  Loop",
                 f'  doc.storeToURL("{target.resolve().as_uri()}", save())', "  doc.close(True)"]
    return "\n".join(body)


def _workbook(path: Path) -> Any:
    return next(w for w in build.WORKBOOKS if path.stem.startswith(w.name))


def _body(fields: list[tuple[str, Any]]) -> dict[str, Any]:
    """The JSON body of dotted request fields (list items by index), written for this test."""
    body: dict[str, Any] = {}
    for path, value in fields:
        node: Any = body
        parts = path.split(".")
        for part, after in itertools.pairwise(parts):
            key: Any = int(part) if part.isdigit() else part
            if isinstance(node, list):
                while len(node) <= key:
                    node.append({})
                node = node[key]
            else:
                node = node.setdefault(key, [] if after.isdigit() else {})
        node[parts[-1]] = value
    return body


def _as_text(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    return value if isinstance(value, str) else repr(value)


def _input_value(cell: dict[str, str]) -> Any:
    """An input cell's value as the JSON body holds it (a number typed, or text)."""
    if cell["value"] == "" and cell["shown"] == "":
        return None
    try:
        number = float(cell["value"])
    except ValueError:
        return cell["shown"]
    return int(number) if number.is_integer() else number


def _check(saved: Path, base_url: str) -> dict[str, Any]:
    """Every figure of a saved workbook against its operations' POST answers; the answers."""
    workbook = _workbook(saved)
    layout = build.Layout(workbook)
    rows = _rows(saved)
    fields: dict[str, list[tuple[str, Any]]] = {op: [] for op in workbook.operations}
    for row, item, op in layout.input_rows():
        value = _input_value(_cell(rows, f"B{row}"))
        assert _cell(rows, f"D{row}")["shown"] == item.path
        if value is not None:
            for target in ([op] if op else workbook.operations):
                fields[target].append((item.path, value))
    for path, value in CHANGES[workbook.name].items():
        assert (path, value) in fields[workbook.operations[0]], f"{path} was not changed to {value}"
    answers = {}
    for op in workbook.operations:
        posted = httpx.post(base_url + OPERATION_PATHS[op], json=_body(fields[op]), timeout=30)
        assert posted.status_code == 200, posted.text
        answers[op] = posted.json()
    for row, item in layout.output_rows():
        value: Any = answers[item.operation or workbook.operations[0]]
        for part in item.pick.split("."):
            value = value[part]
        text, shown = _cell(rows, f"E{row}"), _cell(rows, f"B{row}")
        assert text["value"] == _as_text(value) or (value is None and text["value"] == ""), (item.label, text, value)
        if item.kind == "number":
            assert near_15_digits(float(shown["value"]), value), (item.label, shown, value)
        else:
            assert shown["value"] == _as_text(value) or (value is None and shown["shown"] == ""), (item.label, shown)
    if workbook.chart is not None:
        _, first, last = layout.chart_rows()
        table: Any = answers[workbook.operations[0]]
        xs = _pick(table, workbook.chart.x_pick)
        ys = _pick(table, workbook.chart.y_pick)
        assert 0 < len(xs) <= last - first + 1
        for i, row in enumerate(range(first, last + 1)):
            x, y = _cell(rows, f"B{row}"), _cell(rows, f"C{row}")
            if i < len(xs):
                assert near_15_digits(float(x["value"]), xs[i]) and near_15_digits(float(y["value"]), ys[i]), i
            else:
                assert x["shown"] == y["shown"] == "#N/A"  # past the column: left out of the chart
    return answers


def _pick(answer: Any, path: str) -> Any:
    for part in path.split("."):
        answer = answer[part]
    return answer


def _grid(rows: list[list[dict[str, str]]], key: str) -> list[list[str]]:
    """One property of every cell, without the empty cells and rows a file keeps at its ends."""
    grid = [[cell[key] for cell in row] for row in rows]
    for row in grid:
        while row and row[-1] == "":
            row.pop()
    while grid and not grid[-1]:
        grid.pop()
    return grid


def _chart_ranges(saved: Path) -> list[str]:
    """The cell ranges the saved file's charts draw."""
    root = ET.parse(saved).getroot()
    chart_ns = "urn:oasis:names:tc:opendocument:xmlns:chart:1.0"
    return [series.get(f"{{{chart_ns}}}values-cell-range-address", "")
            for series in root.iter(f"{{{chart_ns}}}series")]


def _sources() -> list[Path]:
    return sorted(p for p in FOLDER.iterdir() if p.suffix in (".ods", ".xlsx"))


def test_the_folder_ships_each_workbook_as_ods_and_xlsx() -> None:
    assert [p.name for p in _sources()] == sorted(f"{w.name}.{ext}" for w in build.WORKBOOKS for ext in ("ods", "xlsx"))


def test_every_workbook_computes_what_the_operations_answer(base_url: str, tmp_path: Path) -> None:
    folder = tmp_path / "workbooks"
    shutil.copytree(FOLDER, folder, ignore=shutil.ignore_patterns("*.py", "__pycache__"))
    fresh = tmp_path / "fresh"
    build.build(fresh, fods_only=True)  # what the source writes now
    sources = sorted(folder.iterdir()) + sorted(fresh.iterdir())
    saved = [(source, tmp_path / "saved" / f"{source.stem}-{source.suffix[1:]}.fods") for source in sources]
    (tmp_path / "saved").mkdir()
    fresh_too = {key: [*folders, *trusted_location(fresh)[key]] for key, folders in trusted_location(folder).items()}
    configure(tmp_path / "profile", UPDATE_LINKS_ALWAYS | fresh_too)
    run_basic(tmp_path / "profile", _macro_opening(saved, base_url, CHANGES))

    for _, target in saved:
        _check(target, base_url)
    for workbook in build.WORKBOOKS:
        versions = {kind: _rows(tmp_path / "saved" / f"{workbook.name}-{kind}.fods") for kind in ("ods", "xlsx", "fods")}
        # the shipped files are the source's: the same formulas (ODS) and the same figures (all)
        ods, xlsx, source = versions["ods"], versions["xlsx"], versions["fods"]
        assert _grid(ods, "formula") == _grid(source, "formula")
        assert _grid(ods, "value") == _grid(xlsx, "value")
        if workbook.chart is not None:
            _, first, last = build.Layout(workbook).chart_rows()
            for kind in ("ods", "xlsx"):
                # the chart draws the point rows (the x values are its domain)
                assert _chart_ranges(tmp_path / "saved" / f"{workbook.name}-{kind}.fods") == [
                    f"{workbook.sheet}.C{first}:{workbook.sheet}.C{last}"], kind


def test_a_refused_input_shows_the_field_and_the_rule_in_the_figures(base_url: str, tmp_path: Path) -> None:
    folder = tmp_path / "workbooks"
    folder.mkdir()
    source = folder / "indexer-sizing.ods"
    shutil.copy(FOLDER / source.name, source)
    target = tmp_path / "refused.fods"
    configure(tmp_path / "profile", UPDATE_LINKS_ALWAYS | trusted_location(folder))
    run_basic(tmp_path / "profile", _macro_opening([(source, target)], base_url,
                                                   {"indexer-sizing": {"indexer.stops": 0}}))
    rows = _rows(target)
    layout = build.Layout(build.SIZING)
    shown = {_cell(rows, f"B{row}")["shown"] for row, _ in layout.output_rows()}
    # every figure says why, in the cell, instead of a bare Err:540
    assert shown == {"Error 422: indexer.stops: Input should be greater than or equal to 1"}, shown


def test_a_decimal_comma_locale_gives_the_same_figures(base_url: str, tmp_path: Path) -> None:
    """A German LibreOffice writes 0,1 where the URL needs 0.1 (the workbook SUBSTITUTEs it)
    and reads the answer's 0.1 with NUMBERVALUE(…; "."): the figures must be the same."""
    folder = tmp_path / "workbooks"
    folder.mkdir()
    for name in ("indexer-sizing.ods", "plate-cam-check.xlsx"):
        shutil.copy(FOLDER / name, folder / name)
    german = {("/org.openoffice.Setup/L10N", "ooSetupSystemLocale"): "de-DE",
              ("/org.openoffice.Office.Linguistic/General", "DefaultLocale"): "de-DE"}
    configure(tmp_path / "profile", UPDATE_LINKS_ALWAYS | trusted_location(folder) | german)
    saved = [(folder / name, tmp_path / f"{Path(name).stem}-de.fods") for name in sorted(p.name for p in folder.iterdir())]
    run_basic(tmp_path / "profile", _macro_opening(saved, base_url, CHANGES))
    for _, target in saved:
        rows = _rows(target)
        workbook = _workbook(target)
        decimal = next(path for path, value in CHANGES[workbook.name].items() if not float(value).is_integer())
        row = next(r for r, item, _ in build.Layout(workbook).input_rows() if item.path == decimal)
        assert "," in _cell(rows, f"B{row}")["shown"]  # the German display: the locale took effect
        _check(target, base_url)


def test_a_refusal_without_errors_text_is_a_bare_err_540_in_calc(base_url: str, tmp_path: Path) -> None:
    """What LibreOffice 7.4 shows for a 4xx answer (measured here; docs/ecosystem.md): the same
    Err:540 as for links that may not update, never the sentence; errors=text gives the line."""
    folder = tmp_path / "sheets"
    folder.mkdir()
    url = f"{base_url}/v1/cell/sizeIndexer?indexer.stops=0&pick=input_torque_nm"
    (folder / "refusal.fods").write_text(_spreadsheet(
        _formula(f'COM.MICROSOFT.WEBSERVICE("{url}")') + _formula(f'COM.MICROSOFT.WEBSERVICE("{url}&errors=text")')),
        encoding="utf-8")
    assert httpx.get(url).status_code == 422
    configure(tmp_path / "profile", UPDATE_LINKS_ALWAYS | trusted_location(folder))
    _open_in_calc(tmp_path / "profile", folder / "refusal.fods", tmp_path / "refusal.fods")
    ((status, text),) = _text_cells(tmp_path / "refusal.fods")
    assert status == ("", "Err:540")
    assert text[1].startswith("Error 422: indexer.stops: Input should be greater than or equal to 1")
