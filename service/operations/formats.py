"""The formats an operation answers in: JSON, CSV, a chart, a file of camcore's registries.

An operation lists its formats, the first being its default. Each other format is chosen by
``?format=<name>``, by the file twin ``{path}.{name}`` (an operation of its own that answers
only that format, for generated clients: they read one media type per operation), and, for a
format that says so (CSV), by the request's ``Accept`` header.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from camcore.export import FileFormat
from service.media import CSV_MEDIA_TYPE, JSON_MEDIA_TYPE, TEXT_MEDIA_TYPE


@dataclass(frozen=True)
class Format:
    """One way an operation answers.

    Attributes
    ----------
    name : str
        The ``?format=`` value and the twin's suffix (``/v1/profiles.dxf``).
    media_type : str
        The answer's Content-Type.
    description : str
        One line for the document: what the answer holds.
    file_name : str or None
        The name a download suggests (Content-Disposition); None: no such header.
    attachment : bool
        A file to save (``attachment``) rather than a table to show (``inline``).
    accept : bool
        Also chosen when the request's Accept header names the media type.
    headers : dict
        Further headers of the answer (a chart's Cache-Control).
    """

    name: str
    media_type: str
    description: str
    file_name: str | None = None
    attachment: bool = False
    accept: bool = False
    headers: dict[str, str] = field(default_factory=dict)

    @property
    def bare_media_type(self) -> str:
        return self.media_type.split(";")[0]

    def answer_headers(self) -> dict[str, str]:
        """Content-Disposition (when the format names a file) and the format's own headers."""
        headers = dict(self.headers)
        if self.file_name is not None:
            kind = "attachment" if self.attachment else "inline"
            headers["Content-Disposition"] = f'{kind}; filename="{self.file_name}"'
        return headers

    @property
    def label(self) -> str:
        """What the format is called in a file twin's summary: ``… as DXF drawing``."""
        return LABELS.get(self.name, self.name.upper())

    def camel(self) -> str:
        """The name in an operation id: ``contour-csv`` → ``ContourCsv``."""
        return "".join(part.capitalize() for part in self.name.split("-"))


#: formats by what a reader calls them (a twin's summary); any other by its name in capitals
LABELS = {"json": "JSON", "csv": "CSV", "text": "text", "svg": "SVG image", "png": "PNG image",
          "dxf": "DXF drawing", "xyz": "X Y Z points", "contour-csv": "contour CSV", "step": "STEP solid",
          "stl": "STL mesh", "gcode": "G-code", "cam-table": "servo cam table"}

JSON = Format("json", JSON_MEDIA_TYPE, "the answer as JSON")
TEXT = Format("text", TEXT_MEDIA_TYPE, "one bare number (Python's shortest round-trip form)")
#: charts: the same query always draws the same chart
_CHART_HEADERS = {"Cache-Control": "public, max-age=3600"}
SVG = Format("svg", "image/svg+xml", "the chart as SVG", headers=_CHART_HEADERS)
PNG = Format("png", "image/png", "the chart as PNG", headers=_CHART_HEADERS)
#: a drawing answered by a computation (a sweep's chart): no caching header
SVG_DRAWING = Format("svg", "image/svg+xml", "the chart as SVG")
PNG_DRAWING = Format("png", "image/png", "the chart as PNG")


def csv(file_name: str = "table.csv", description: str = "the table as CSV: a header row, then one row per point, "
                                                           "one column per quantity") -> Format:
    """The table as CSV, shown inline with a file name; also on ``Accept: text/csv``."""
    return Format("csv", CSV_MEDIA_TYPE, description, file_name=file_name, accept=True)


def download(fmt: FileFormat[Any]) -> Format:
    """A file of one of camcore's export registries, as an attachment."""
    return Format(fmt.name, fmt.media_type, fmt.description, file_name=fmt.file_name, attachment=True)
