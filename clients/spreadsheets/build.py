"""Build the spreadsheets of this folder from their description here: one source for each
workbook's ODS (LibreOffice) and XLSX (Excel).

    python clients/spreadsheets/build.py            # writes *.ods and *.xlsx beside this file
    python clients/spreadsheets/build.py --fods DIR # only the flat-XML sources, into DIR

Each workbook is written as flat OpenDocument XML (.fods) with formulas in OpenFormula and its
chart inline, then converted by LibreOffice (``soffice --headless --convert-to``) to .ods and
.xlsx. Every figure is a ``WEBSERVICE()`` cell on the service's cell form (``GET
/v1/cell/{operation}?<fields>&pick=<answer field>&errors=text``):

- each input row names its request field (column D); column E writes it as a query parameter
  (``indexer.stops=6``; a blank input is left out), and one cell joins them (TEXTJOIN);
- each output row holds the service's text (column E: a number, TRUE/FALSE, or "Error 422:
  <field>: <rule>") and its number in column B (NUMBERVALUE with ".", so a decimal-comma
  locale reads it too; the error sentence is shown as it is);
- a chart's points come from one cell holding a whole column (one value per line), split into
  rows by SUBSTITUTE/FIND/MID, which LibreOffice and Excel both have.

Numbers go into the URL through SUBSTITUTE(cell; ","; "."): a German LibreOffice writes 0,1833.
Only the standard library is used, so this runs with any Python 3.11 and LibreOffice 7.4+.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

HERE = Path(__file__).resolve().parent
DEFAULT_URL = "http://localhost:8000"


@dataclass(frozen=True)
class Input:
    """An input row: what the user types, and the request field it is."""

    label: str
    path: str  # the request field's path: the cell form's query parameter name
    value: float | str | None
    unit: str = ""
    note: str = ""


@dataclass(frozen=True)
class Output:
    """An output row: one field of an operation's answer."""

    label: str
    pick: str
    unit: str = ""
    operation: str = ""  # the workbook's first operation when empty
    kind: str = "number"  # number, or text (shown as the service wrote it)


@dataclass(frozen=True)
class Chart:
    """A chart of one answer column over another, split into ``rows`` rows."""

    title: str
    x_pick: str
    y_pick: str
    x_label: str
    y_label: str
    rows: int


@dataclass(frozen=True)
class Workbook:
    name: str
    sheet: str
    title: str
    operations: tuple[str, ...]  # the first takes every input; the others take theirs (extra)
    inputs: tuple[Input, ...]
    outputs: tuple[Output, ...]
    extra: dict[str, tuple[Input, ...]] = field(default_factory=dict)
    chart: Chart | None = None
    help: str = ""


SIZING = Workbook(
    name="indexer-sizing",
    sheet="Sizing",
    title="camcore — cam indexer sizing",
    operations=("sizeIndexer",),
    inputs=(
        Input("stops", "indexer.stops", 6),
        Input("indexing angle", "indexer.indexing_angle_deg", 270, "deg", "input angle of one index"),
        Input("input speed", "indexer.speed_rpm", 60, "rpm", "give the speed or the cycle time, not both"),
        Input("cycle time", "indexer.cycle_time_s", None, "s", "one index and its dwell"),
        Input("curve", "indexer.curve.name", "MS", "", "MS, MT, TR, cycloid, 3-4-5, …"),
        Input("curve kind", "indexer.curve.type", "named"),
        Input("internal friction torque", "indexer.internal_friction_torque_nm", 2, "N·m", "at the input shaft"),
        Input("load inertia", "load.inertia_kgm2", None, "kg·m²", "instead of parts, if known"),
        Input("part 1: shape", "load.parts.0.shape", "disc", "", "disc, ring, block, point"),
        Input("part 1: mass", "load.parts.0.mass_kg", 50, "kg"),
        Input("part 1: diameter", "load.parts.0.diameter_mm", 600, "mm"),
        Input("part 1: inner diameter", "load.parts.0.inner_diameter_mm", None, "mm", "a ring"),
        Input("part 2: shape", "load.parts.1.shape", None, "", "blank: no second part"),
        Input("part 2: mass", "load.parts.1.mass_kg", None, "kg"),
        Input("part 2: diameter", "load.parts.1.diameter_mm", None, "mm"),
        Input("part 2: offset from the axis", "load.parts.1.offset_mm", None, "mm"),
        Input("friction coefficient", "load.friction_coefficient", 0.1),
        Input("friction radius", "load.friction_radius_mm", 200, "mm"),
        Input("service factor", "load.service_factor", 1.5),
        Input("gear ratio", "load.gear_ratio", 2, "", "output turns per dial turn"),
        Input("dwell torque", "load.dwell_torque_nm", 40, "N·m", "output torque while dwelling"),
        Input("motor: rated torque", "motor.rated_torque_nm", 3.2, "N·m"),
        Input("motor: peak torque", "motor.peak_torque_nm", 9.6, "N·m"),
        Input("motor: rotor inertia", "motor.rotor_inertia_kgm2", 0.00034, "kg·m²"),
        Input("motor: top speed", "motor.max_speed_rpm", 3000, "rpm"),
        Input("motor: reduction ratio", "motor.reduction_ratio", 10),
        Input("motor: reduction efficiency", "motor.reduction_efficiency", 0.95),
        Input("chart points per index", "table_samples", 61),
    ),
    outputs=(
        Output("input torque, peak", "input_torque_nm", "N·m"),
        Output("input power", "input_power_kw", "kW"),
        Output("output torque, peak", "output_torque_nm", "N·m"),
        Output("output torque × service factor", "design_output_torque_nm", "N·m"),
        Output("input torque, RMS over the cycle", "rms_input_torque_nm", "N·m"),
        Output("motor peak torque", "motor_peak_torque_nm", "N·m"),
        Output("motor utilisation, peak", "peak_utilisation"),
        Output("motor utilisation, RMS", "rms_utilisation"),
        Output("motor OK", "motor_ok", kind="text"),
        Output("motor: why not", "motor_reason", kind="text"),
    ),
    chart=Chart("Input torque over the input angle", "input_torque_table.input_angle_deg",
                "input_torque_table.input_torque_nm", "input angle [deg]", "input torque [N·m]", rows=80),
    help="Blue cells are inputs; every figure below is computed by camcore. A refused input "
         "shows as \"Error 422: <field>: <rule>\" in the figures.",
)

PLATE_CAM = Workbook(
    name="plate-cam-check",
    sheet="Check",
    title="camcore — plate cam check",
    operations=("computeProfile", "sizeBaseCircle"),
    inputs=(
        Input("follower", "profile.follower.type", "roller", "", "roller, knife-edge, flat-faced"),
        Input("roller radius", "profile.follower.roller_radius_mm", 10, "mm"),
        Input("offset", "profile.follower.offset_mm", None, "mm", "blank: none"),
        Input("base radius", "profile.base_radius_mm", 40, "mm"),
        Input("rise: angle", "profile.segments.0.angle_deg", 120, "deg"),
        Input("rise: lift", "profile.segments.0.lift_mm", 20, "mm"),
        Input("rise: curve", "profile.segments.0.curve.name", "MS"),
        Input("rise: curve kind", "profile.segments.0.curve.type", "named"),
        Input("rise", "profile.segments.0.type", "rise"),
        Input("dwell: angle", "profile.segments.1.angle_deg", 60, "deg"),
        Input("dwell", "profile.segments.1.type", "dwell"),
        Input("return: angle", "profile.segments.2.angle_deg", 120, "deg"),
        Input("return: lift", "profile.segments.2.lift_mm", 20, "mm"),
        Input("return: curve", "profile.segments.2.curve.name", "MS"),
        Input("return: curve kind", "profile.segments.2.curve.type", "named"),
        Input("return", "profile.segments.2.type", "return"),
        Input("dwell: angle", "profile.segments.3.angle_deg", 60, "deg", "the rest of the turn"),
        Input("dwell", "profile.segments.3.type", "dwell"),
    ),
    extra={"computeProfile": (Input("chart points per turn", "samples", 73, "", "every 5°"),),
           "sizeBaseCircle": (
        Input("pressure angle limit", "max_pressure_angle_deg", 30, "deg", "for the smallest base circle"),
    )},
    outputs=(
        Output("largest pressure angle", "checks.max_pressure_angle_deg", "deg"),
        Output("… at cam angle", "checks.max_pressure_angle_at_deg", "deg"),
        Output("smallest radius of curvature", "checks.min_radius_of_curvature_mm", "mm"),
        Output("… at cam angle", "checks.min_radius_of_curvature_at_deg", "deg"),
        Output("undercut", "checks.undercut", kind="text"),
        Output("smallest base radius for the pressure angle limit", "base_radius_mm", "mm", "sizeBaseCircle"),
        Output("… the limit that decides it", "active_constraint", operation="sizeBaseCircle", kind="text"),
    ),
    chart=Chart("Pressure angle over the cam angle", "cam_angle_deg", "pressure_angle_deg", "cam angle [deg]",
                "pressure angle [deg]", rows=80),
    help="Blue cells are inputs; every figure below is computed by camcore. A refused input "
         "shows as \"Error 422: <field>: <rule>\" in the figures.",
)

WORKBOOKS = (SIZING, PLATE_CAM)


# ----------------------------------------------------------------------------- layout
@dataclass(frozen=True)
class Layout:
    """Where a workbook's cells are (rows counted from 1)."""

    workbook: Workbook

    URL_ROW = 3
    FIRST_INPUT = 6

    def input_rows(self) -> list[tuple[int, Input, str]]:
        """Each input's row and the operation it belongs to ("" : every operation)."""
        rows = [(self.FIRST_INPUT + i, item, "") for i, item in enumerate(self.workbook.inputs)]
        for op, items in self.workbook.extra.items():
            rows += [(rows[-1][0] + 1, item, op) for item in items]
        return rows

    def prefix_rows(self) -> dict[str, int]:
        """The row of each operation's URL prefix (the URL up to ``pick=``)."""
        after = self.input_rows()[-1][0] + 2
        return {op: after + i for i, op in enumerate(self.workbook.operations)}

    def output_rows(self) -> list[tuple[int, Output]]:
        first = max(self.prefix_rows().values()) + 3
        return [(first + i, item) for i, item in enumerate(self.workbook.outputs)]

    def chart_rows(self) -> tuple[int, int, int]:
        """The chart's source row (two raw column cells) and its first and last point rows."""
        source = self.output_rows()[-1][0] + 2  # after a blank row; then a header row, then the points
        assert self.workbook.chart is not None
        return source, source + 2, source + 1 + self.workbook.chart.rows


# ----------------------------------------------------------------------------- flat ODS
NS = ('xmlns:office="urn:oasis:names:tc:opendocument:xmlns:office:1.0" '
      'xmlns:style="urn:oasis:names:tc:opendocument:xmlns:style:1.0" '
      'xmlns:text="urn:oasis:names:tc:opendocument:xmlns:text:1.0" '
      'xmlns:table="urn:oasis:names:tc:opendocument:xmlns:table:1.0" '
      'xmlns:draw="urn:oasis:names:tc:opendocument:xmlns:drawing:1.0" '
      'xmlns:fo="urn:oasis:names:tc:opendocument:xmlns:xsl-fo-compatible:1.0" '
      'xmlns:svg="urn:oasis:names:tc:opendocument:xmlns:svg-compatible:1.0" '
      'xmlns:chart="urn:oasis:names:tc:opendocument:xmlns:chart:1.0" '
      'xmlns:of="urn:oasis:names:tc:opendocument:xmlns:of:1.2" '
      'xmlns:xlink="http://www.w3.org/1999/xlink"')

STYLES = """<office:automatic-styles>
 <style:style style:name="wide" style:family="table-column"><style:table-column-properties style:column-width="6.5cm"/></style:style>
 <style:style style:name="narrow" style:family="table-column"><style:table-column-properties style:column-width="2.6cm"/></style:style>
 <style:style style:name="raw" style:family="table-column"><style:table-column-properties style:column-width="9cm"/></style:style>
 <style:style style:name="title" style:family="table-cell"><style:text-properties fo:font-size="14pt" fo:font-weight="bold"/></style:style>
 <style:style style:name="head" style:family="table-cell"><style:text-properties fo:font-weight="bold"/></style:style>
 <style:style style:name="input" style:family="table-cell"><style:table-cell-properties fo:background-color="#dde8f6"/></style:style>
 <style:style style:name="output" style:family="table-cell"><style:table-cell-properties fo:background-color="#e8f4e0"/><style:text-properties fo:font-weight="bold"/></style:style>
 <style:style style:name="quiet" style:family="table-cell"><style:text-properties fo:color="#808080"/></style:style>
</office:automatic-styles>"""


def _text(value: str, style: str = "") -> str:
    styled = f" table:style-name={quoteattr(style)}" if style else ""
    return f'<table:table-cell{styled} office:value-type="string"><text:p>{escape(value)}</text:p></table:table-cell>'


def _value(value: float | str | None, style: str) -> str:
    if value is None:
        return f'<table:table-cell table:style-name="{style}"/>'
    if isinstance(value, str):
        return _text(value, style)
    return (f'<table:table-cell table:style-name="{style}" office:value-type="float" office:value="{value!r}">'
            f"<text:p>{value!r}</text:p></table:table-cell>")


def _formula(formula: str, style: str = "") -> str:
    styled = f" table:style-name={quoteattr(style)}" if style else ""
    return f"<table:table-cell{styled} table:formula={quoteattr('of:=' + formula)}/>"


def _row(*cells: str) -> str:
    return f"<table:table-row>{''.join(cells)}</table:table-row>"


def _empty_row() -> str:
    return "<table:table-row><table:table-cell/></table:table-row>"


def as_query(row: int) -> str:
    """Column E of an input row: ``path=value`` with the value URL-encoded, a decimal comma
    made a point; nothing for a blank input."""
    return (f'IF([.B{row}]="";"";[.D{row}]&"="&'
            f'COM.MICROSOFT.ENCODEURL(SUBSTITUTE([.B{row}];",";".")))')


def number_or_message(raw: str) -> str:
    """The number of the service's text, or the text itself (an error, or a blank answer)."""
    return f'IF(OR({raw}="";LEFT({raw};6)="Error ");{raw};NUMBERVALUE({raw};"."))'


def nth_line(raw: str, n: str) -> str:
    """The n-th line (from 1) of a cell holding a column, as a number; #N/A past its end (a
    chart leaves it out). The line starts after the (n-1)-th line feed: SUBSTITUTE marks that
    one alone (its instance argument), FIND finds the mark."""
    start = f'IF({n}=1;1;FIND(CHAR(1);SUBSTITUTE({raw};CHAR(10);CHAR(1);{n}-1))+1)'
    line = f'MID({raw};{start};FIND(CHAR(10);{raw};{start})-{start})'
    return f'IFERROR(NUMBERVALUE({line};".");NA())'


def sheet_rows(workbook: Workbook) -> list[str]:
    layout = Layout(workbook)
    rows = [_row(_text(workbook.title, "title")), _row(_text(workbook.help, "quiet"))]
    rows.append(_row(_text("service URL", "head"), _value(DEFAULT_URL, "input"),
                     _text("where camcore runs (http://HOST:8000)", "quiet")))
    rows += [_empty_row(), _row(*(_text(h, "head") for h in ("input", "value", "unit", "request field",
                                                              "as a query parameter", "note")))]
    inputs = layout.input_rows()
    for row, item, _ in inputs:
        rows.append(_row(_text(item.label), _value(item.value, "input"), _text(item.unit), _text(item.path, "quiet"),
                         _formula(as_query(row), "quiet"), _text(item.note, "quiet")))
    rows.append(_empty_row())
    first_input = inputs[0][0]
    shared_last = max(row for row, _, op in inputs if op == "")
    for op, row in layout.prefix_rows().items():
        own = [r for r, _, o in inputs if o == op]
        joined = f"[.E{first_input}:.E{shared_last}]" + "".join(f";[.E{r}]" for r in own)
        rows.append(_row(_text(f"{op}: the URL up to pick=", "quiet"), _empty(), _empty(), _empty(),
                         _formula(f'[.$B${Layout.URL_ROW}]&"/v1/cell/{op}?"&COM.MICROSOFT.TEXTJOIN("&";1;{joined})'
                                  f'&"&errors=text&pick="', "quiet")))
    rows += [_empty_row(), _row(*(_text(h, "head") for h in ("figure", "value", "unit", "answer field",
                                                             "the service's answer")))]
    prefixes = layout.prefix_rows()
    for row, item in layout.output_rows():
        op = item.operation or workbook.operations[0]
        raw = f"[.E{row}]"
        shown = raw if item.kind == "text" else number_or_message(raw)
        rows.append(_row(_text(item.label), _formula(shown, "output"), _text(item.unit), _text(item.pick, "quiet"),
                         _formula(f'COM.MICROSOFT.WEBSERVICE([.$E${prefixes[op]}]&[.D{row}])', "quiet")))
    if workbook.chart is not None:
        chart = workbook.chart
        source, first, last = layout.chart_rows()
        prefix = f"[.$E${prefixes[workbook.operations[0]]}]"
        rows += [_empty_row(), _row(
            _text("chart: the answer's columns", "head"), _formula(f'COM.MICROSOFT.WEBSERVICE({prefix}&"{chart.x_pick}")',
                                                                  "quiet"),
            _formula(f'COM.MICROSOFT.WEBSERVICE({prefix}&"{chart.y_pick}")', "quiet"))]
        rows.append(_row(_text("point", "head"), _text(chart.x_label, "head"), _text(chart.y_label, "head")))
        for i, row in enumerate(range(first, last + 1), start=1):
            rows.append(_row(_value(i, "quiet"), _formula(nth_line(f"[.$B${source}]", f"[.A{row}]")),
                             _formula(nth_line(f"[.$C${source}]", f"[.A{row}]"))))
    return rows


def _empty() -> str:
    return "<table:table-cell/>"


def chart_frame(workbook: Workbook, sheet: str) -> str:
    """The chart, inline: a scatter of the point rows, placed right of the figures."""
    assert workbook.chart is not None
    chart = workbook.chart
    _, first, last = Layout(workbook).chart_rows()
    xs, ys = f"{sheet}.B{first}:{sheet}.B{last}", f"{sheet}.C{first}:{sheet}.C{last}"
    return f"""<draw:frame draw:z-index="0" draw:name="torque chart" svg:width="16cm" svg:height="9cm" svg:x="26cm" svg:y="1cm">
 <draw:object draw:notify-on-update-of-ranges="{xs} {ys}">
  <office:document office:version="1.3" office:mimetype="application/vnd.oasis.opendocument.chart">
   <office:body><office:chart>
    <chart:chart svg:width="16cm" svg:height="9cm" chart:class="chart:scatter">
     <chart:title><text:p>{escape(chart.title)}</text:p></chart:title>
     <chart:plot-area table:cell-range-address="{xs} {ys}" chart:data-source-has-labels="none">
      <chart:axis chart:dimension="x" chart:name="primary-x"><chart:title><text:p>{escape(chart.x_label)}</text:p></chart:title></chart:axis>
      <chart:axis chart:dimension="y" chart:name="primary-y"><chart:title><text:p>{escape(chart.y_label)}</text:p></chart:title></chart:axis>
      <chart:series chart:class="chart:scatter" chart:values-cell-range-address="{ys}">
       <chart:domain table:cell-range-address="{xs}"/>
      </chart:series>
     </chart:plot-area>
    </chart:chart>
   </office:chart></office:body>
  </office:document>
 </draw:object>
</draw:frame>"""


def fods(workbook: Workbook) -> str:
    """The workbook as flat OpenDocument XML."""
    sheet = workbook.sheet
    shapes = f"<table:shapes>{chart_frame(workbook, sheet)}</table:shapes>" if workbook.chart else ""
    columns = ('<table:table-column table:style-name="wide"/><table:table-column table:style-name="narrow"/>'
               '<table:table-column table:style-name="narrow"/><table:table-column table:style-name="wide"/>'
               '<table:table-column table:style-name="raw"/><table:table-column table:style-name="wide"/>')
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<office:document {NS} office:version="1.3" office:mimetype="application/vnd.oasis.opendocument.spreadsheet">
{STYLES}
<office:body><office:spreadsheet>
<table:table table:name="{sheet}">{shapes}{columns}
{chr(10).join(sheet_rows(workbook))}
</table:table>
</office:spreadsheet></office:body>
</office:document>
"""


# ----------------------------------------------------------------------------- conversion
def convert(source: Path, extension: str, outdir: Path) -> Path:
    """``soffice --headless --convert-to`` in a profile of its own (a running desktop office
    would otherwise take the job)."""
    soffice = shutil.which("soffice") or shutil.which("libreoffice")
    if soffice is None:
        raise SystemExit("LibreOffice (soffice) is needed to write .ods and .xlsx")
    filters = {"ods": "ods:calc8", "xlsx": "xlsx:Calc MS Excel 2007 XML"}
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run([soffice, f"-env:UserInstallation={Path(profile).as_uri()}", "--headless", "--norestore",
                        "--convert-to", filters[extension], "--outdir", str(outdir), str(source)],
                       check=True, capture_output=True, timeout=120, env={**os.environ, "SAL_USE_VCLPLUGIN": "svp"})
    made = outdir / f"{source.stem}.{extension}"
    if not made.exists():
        raise SystemExit(f"soffice wrote no {made}")
    return made


_FORMULA_CELL = re.compile(r'<table:table-cell ([^>]*?table:formula="[^"]*"[^>]*?)(?:/>|>.*?</table:table-cell>)',
                           re.DOTALL)
_CACHED = re.compile(r' (?:office:(?:value-type|value|string-value|boolean-value)|calcext:value-type)="[^"]*"')
_XLSX_CACHED = re.compile(r'<c ([^>]*)>(<f[^>]*>[^<]*</f>)<v>[^<]*</v>')


def without_cached_results(path: Path) -> None:
    """Drop the results LibreOffice cached when it converted the file (every WEBSERVICE cell
    Err:540: conversion never updates links). LibreOffice compiles a formula with a cached
    result only when it needs it, and grants a file's link updates at load only for the
    formulas it compiled then: with the cache, the figures stayed Err:540 on a trusted, allowed
    file. Excel is told to calculate everything on load (calcPr fullCalcOnLoad)."""
    with zipfile.ZipFile(path) as old:
        entries = [(info, old.read(info)) for info in old.infolist()]
    with zipfile.ZipFile(path, "w") as new:
        for info, data in entries:
            if info.filename == "content.xml":
                text = data.decode("utf-8")
                data = _FORMULA_CELL.sub(lambda m: f"<table:table-cell {_CACHED.sub('', m.group(1))}/>", text).encode()
            elif info.filename.startswith("xl/worksheets/sheet"):
                data = _XLSX_CACHED.sub(r"<c \1>\2", data.decode("utf-8")).encode()
            elif info.filename == "xl/workbook.xml":
                data = re.sub(r"<calcPr ", '<calcPr fullCalcOnLoad="1" ', data.decode("utf-8"), count=1).encode()
            new.writestr(info, data)  # same names, order and compression (mimetype first, stored)


def build(outdir: Path, fods_only: bool = False) -> list[Path]:
    """Write every workbook into ``outdir``: its .fods (``fods_only``) or its .ods and .xlsx."""
    outdir.mkdir(parents=True, exist_ok=True)
    written = []
    with tempfile.TemporaryDirectory() as tmp:
        for workbook in WORKBOOKS:
            source = (outdir if fods_only else Path(tmp)) / f"{workbook.name}.fods"
            source.write_text(fods(workbook), encoding="utf-8")
            if fods_only:
                written.append(source)
                continue
            for extension in ("ods", "xlsx"):
                written.append(convert(source, extension, outdir))
                without_cached_results(written[-1])
    return written


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fods", type=Path, help="write only the flat-XML sources, into this folder")
    args = parser.parse_args(argv)
    for path in build(args.fods or HERE, fods_only=args.fods is not None):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
