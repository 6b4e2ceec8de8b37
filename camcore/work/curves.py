"""Curves: tables, inverses and the characteristics sweep (a curve's build is its kind's cost,
camcore.curves.kinds)."""

from __future__ import annotations

#: columns of a curve table (t, s, v, a, j, q) and of an inverse answer (s, t, v, a)
TABLE_COLUMNS = 6
INVERSE_COLUMNS = 4
#: one combination of a characteristics sweep: its spec validated and its curve built, then its
#: share of finding every curve's values together (camcore.curves.batch); measured on a 2-core
#: machine: 65 ms for the 16 × 32 grid of curve 4 (512 rows, 200 curves, the rest refused at
#: ~0.02 ms each), so 0.3 ms per curve (0.9 ms when each curve was done alone); 0.3 ms × 1.5
CHARACTERISTICS_SWEEP_ROW_S = 1.5 * 0.3e-3
#: drawing the design chart of 512 rows: 0.12 s PNG or SVG, matplotlib loaded (0.5 s the first
#: time, as every chart); 0.2 s × 1.5
DESIGN_CHART_S = 1.5 * 0.2
