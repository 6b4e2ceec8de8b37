"""Writing an answer: numbers encoded as JSON or CSV, a chart drawn."""

from __future__ import annotations

#: encoding cost per number, measured 0.025 µs (JSON, orjson) and 0.2 µs (CSV), ×1.5
ENCODE_S_PER_VALUE = {"json": 1.5 * 2.5e-8, "csv": 1.5 * 2e-7}
#: rendering one chart, measured with 2 001 points: SVG 0.20-0.35 s, PNG at 300 dpi 0.39-0.75 s
#: (2-vCPU Intel Xeon VM); a catalog curve's SVG 0.33-0.47 s on a slower 2-vCPU AMD EPYC VM
#: (2026-12-07, where 0.35 s × 1.15 fell short); the estimate is 0.45 s plus, for PNG,
#: 0.45 s × (dpi/300)², ×1.15
RENDER_S = 0.45
PNG_AT_300_DPI_S = 0.45
#: the residual-vibration spectra (up to 8 traces on a log axis with its minor grid): SVG
#: 0.36-0.62 s, PNG 0.29-0.59 s (2-5 curves, 101-2001 τ values)
SPECTRUM_RENDER_S = 0.55
#: a sizing sweep's chart: 0.06-0.07 s for one panel, 0.43 s for 4, 0.63 s for 9, 1.06 s for 16
#: (the largest of 3 runs, SVG or PNG, 1 to 4 curves, with fixed margins)
SWEEP_CHART_S = 0.05
SWEEP_PANEL_S = 0.065


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


def chart_s(fmt: str, dpi: int, render_s: float = RENDER_S) -> float:
    """Seconds to draw and encode one chart.

    Parameters
    ----------
    fmt : {"svg", "png"}
        The image format.
    dpi : int
        PNG resolution, in dots per inch [-].
    render_s : float
        The chart's own drawing time at 100 dpi [s] (:data:`RENDER_S`, :data:`SPECTRUM_RENDER_S`).

    Returns
    -------
    float
        [s].

    References
    ----------
    The measurements beside :data:`RENDER_S`.
    """
    png = PNG_AT_300_DPI_S * (dpi / 300) ** 2 if fmt == "png" else 0.0
    return 1.15 * (render_s + png)


def sweep_chart_s(panels: int) -> float:
    """Seconds to draw a sizing sweep's chart (×1.15, as every chart).

    Parameters
    ----------
    panels : int
        Panels of the chart, one per stops and indexing angle [-].

    Returns
    -------
    float
        [s].

    References
    ----------
    The measurements beside :data:`SWEEP_PANEL_S`.
    """
    return 1.15 * (SWEEP_CHART_S + SWEEP_PANEL_S * panels)
