"""A line-by-line pure-Python port of Makino's subroutine CURVE (one T per call).

This is the baseline of the ``scalar_port_vs_table`` figure: what a spreadsheet macro or
a direct transcription of the Fortran does — constants once (INIT = 1, lines 75-124),
then one call per T through the IF chain of the variable part (lines 146-234).
Only the common-constant and variable parts are ported; the per-curve parameter part
(lines 13-74) is replaced by passing T0..T7 (the universal curve), since the numbered
curves there are just different T1..T6.

Reference: H. Makino, "Universal Cam Curve and Its Application" (1977), appendix 1
(Makino (1977) in docs/sources.md).
"""

from __future__ import annotations

import math


class MakinoCurve:
    """SUBROUTINE CURVE with INIT = 1 done in ``__init__`` and INIT = 0/2 in :meth:`curve`."""

    def __init__(self, t, v0=0.0, v7=0.0, s0=0.0, s7=1.0):
        pi = 4.0 * math.atan(1.0)  # line 15
        t0, t1, t2, t3, t4, t5, t6, t7 = (float(x) for x in t)
        ratio = 1.0  # line 22
        # 91 CONTINUE (lines 75-82)
        c1 = 2.0 * (t1 - t0) / pi
        c2 = t2 - t1
        c3 = 2.0 * (t3 - t2) / pi
        c4 = t4 - t3
        c5 = 2.0 * (t5 - t4) / pi
        c6 = t6 - t5
        c7 = 2.0 * (t7 - t6) / pi
        if v7 - v0 == 0.0:  # lines 84-86
            ratio = (c3 + c2 + c1) / (c7 + c6 + c5)
        # lines 88-91
        amp = (s7 - s0 - v0 * (t7 - t0)) / (
            -ratio * (c7 * c7 + 0.5 * c6 * c6 - c5 * c5 + (t6 - t5) * (t7 - t6) + c5 * (t7 - t4))
            + c3 * c3 + 0.5 * c2 * c2 - c1 * c1 + c3 * (t7 - t3) + (t2 - t1) * (t7 - t2) + c1 * (t7 - t0)
        )
        amm = ratio * amp
        # 93 CONTINUE (lines 93-108)
        v1 = c1 * amp + v0
        v2 = c2 * amp + v1
        v3 = c3 * amp + v2
        v4 = v3
        v5 = -c5 * amm + v4
        v6 = -c6 * amm + v5
        v7 = -c7 * amm + v6
        s1 = -c1 * c1 * amp + v1 * (t1 - t0) + s0
        s2 = 0.5 * c2 * c2 * amp + c2 * v1 + s1
        s3 = c3 * c3 * amp + v2 * (t3 - t2) + s2
        s4 = c4 * v3 + s3
        s5 = c5 * c5 * amm + v5 * (t5 - t4) + s4
        s6 = -0.5 * c6 * c6 * amm + c6 * v5 + s5
        s7 = -c7 * c7 * amm + v6 * (t7 - t6) + s6
        self.__dict__.update(locals())
        del self.__dict__["self"]
        self.qmp = 0.0
        self.qmm = 0.0

    def curve(self, t, init=0):
        """S, V, A, AJK (= J), Q at one T (lines 146-234); init = 2 is the return stroke."""
        d = self.__dict__
        t0, t1, t2, t3, t4, t5, t6, t7 = d["t0"], d["t1"], d["t2"], d["t3"], d["t4"], d["t5"], d["t6"], d["t7"]
        c1, c3, c5, c7 = d["c1"], d["c3"], d["c5"], d["c7"]
        amp, amm = d["amp"], d["amm"]
        if init == 2:  # 200 CONTINUE
            tt = t
            t = 1.0 - tt
        # 300 CONTINUE
        if t < t0:  # 400
            s = d["s0"]
            v = d["v0"]
            a = 0.0
            ajk = 0.0
        elif t >= t0 and t < t1:  # 401
            p = (t - t0) / c1
            s = -c1 * c1 * amp * math.sin(p) + d["v1"] * (t - t0) + d["s0"]
            v = -c1 * amp * math.cos(p) + d["v1"]
            a = amp * math.sin(p)
            ajk = amp * math.cos(p) / c1
        elif t >= t1 and t < t2:  # 402
            p = t - t1
            s = 0.5 * amp * p * p + d["v1"] * p + d["s1"]
            v = amp * p + d["v1"]
            a = amp
            ajk = 0.0
        elif t >= t2 and t < t3:  # 403
            p = (t - t2) / c3
            s = -c3 * c3 * amp * (math.cos(p) - 1.0) + d["v2"] * (t - t2) + d["s2"]
            v = c3 * amp * math.sin(p) + d["v2"]
            a = amp * math.cos(p)
            ajk = -amp * math.sin(p) / c3
        elif t >= t3 and t < t4:  # 404
            s = d["v3"] * (t - t3) + d["s3"]
            v = d["v3"]
            a = 0.0
            ajk = 0.0
        elif t >= t4 and t < t5:  # 405
            p = (t - t4) / c5
            s = c5 * c5 * amm * math.sin(p) + d["v5"] * (t - t4) + d["s4"]
            v = c5 * amm * math.cos(p) + d["v5"]
            a = -amm * math.sin(p)
            ajk = -amm * math.cos(p) / c5
        elif t >= t5 and t < t6:  # 406
            p = t - t5
            s = -0.5 * amm * p * p + d["v5"] * p + d["s5"]
            v = -amm * p + d["v5"]
            a = -amm
            ajk = 0.0
        elif t >= t6 and t < t7:  # 407
            p = (t - t6) / c7
            s = c7 * c7 * amm * (math.cos(p) - 1.0) + d["v6"] * (t - t6) + d["s6"]
            v = -c7 * amm * math.sin(p) + d["v6"]
            a = -amm * math.cos(p)
            ajk = amm * math.sin(p) / c7
        else:  # 408: T >= T7
            s = d["s7"] + d["v7"] * (t - t7)
            v = d["v7"]
            a = 0.0
            ajk = 0.0
        # 490 CONTINUE
        if init != 0:
            v = -v
            ajk = -ajk
        q = v * a  # 499
        self.qmp = max(self.qmp, q)
        self.qmm = min(self.qmm, q)
        return s, v, a, ajk, q


def table(t_values, break_points):
    """The spreadsheet way: one CURVE call per row. Returns lists S, V, A, J."""
    cam = MakinoCurve(break_points)
    s_col, v_col, a_col, j_col = [], [], [], []
    for t in t_values:
        s, v, a, ajk, _q = cam.curve(t)
        s_col.append(s)
        v_col.append(v)
        a_col.append(a)
        j_col.append(ajk)
    return s_col, v_col, a_col, j_col
