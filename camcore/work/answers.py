"""Writing an answer: numbers encoded as JSON or CSV, a chart drawn."""

from __future__ import annotations

#: encoding cost per number, measured 0.025 µs (JSON, orjson) and 0.2 µs (CSV), ×1.5
ENCODE_S_PER_VALUE = {"json": 1.5 * 2.5e-8, "csv": 1.5 * 2e-7}
#: rendering one chart, measured with 2 001 points: SVG 0.20-0.35 s, PNG at 300 dpi 0.39-0.75 s;
#: the estimate is 0.35 s plus, for PNG, 0.45 s × (dpi/300)², ×1.15
RENDER_S = 0.35
PNG_AT_300_DPI_S = 0.45


def encode_cost(values: int, csv: bool) -> float:
    """Seconds to encode numbers as CSV or JSON.

    Parameters
    ----------
    values : int
        Numbers written [-].
    csv : bool
        CSV (else JSON) [-].

    Returns
    -------
    float
        [s].

    References
    ----------
    The measurements beside :data:`ENCODE_S_PER_VALUE`.
    """
    return values * ENCODE_S_PER_VALUE["csv" if csv else "json"]


def chart_s(fmt: str, dpi: int) -> float:
    """Seconds to draw and encode one chart.

    Parameters
    ----------
    fmt : {"svg", "png"}
        The image format.
    dpi : int
        PNG resolution [1/in].

    Returns
    -------
    float
        [s].

    References
    ----------
    The measurements beside :data:`RENDER_S`.
    """
    png = PNG_AT_300_DPI_S * (dpi / 300) ** 2 if fmt == "png" else 0.0
    return 1.15 * (RENDER_S + png)
