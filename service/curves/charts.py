"""The curves' charts: S, V, A, J over T; the design chart of a characteristics sweep (Makino
1977, fig. 3); the residual-vibration spectra of several curves. Drawn with service.drawing."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from service.drawing import COLORS, LOCK, figure, mark, render, stacked_traces, style

if TYPE_CHECKING:  # pragma: no cover
    from camcore.curves import Characteristics, CurveValues

def svaj_chart(values: CurveValues, ch: Characteristics, title: str, fmt: str = "svg", dpi: int = 100) -> bytes:
    """S, V, A, J over T on four stacked axes sharing T, with Vm, Am±, Jm± marked."""
    with LOCK:
        fig = figure(8.0, 8.5)
        axes = fig.subplots(4, 1, sharex=True)
        t = values.t
        rows = [("s", "S (displacement)", values.s), ("v", "V (velocity)", values.v),
                ("a", "A (acceleration)", values.a), ("j", "J (jerk)", values.j)]
        stacked_traces(axes, t, rows)
        ax_s, ax_v, ax_a, ax_j = axes
        v_at = float(np.interp(ch.vm.t, t, values.v))
        mark(ax_v, ch.vm.t, v_at, f"Vm = {ch.vm.value:.4f} at T = {ch.vm.t:.4f}", COLORS["v"], above=v_at >= 0)
        if ch.am_pos.value > 0:
            mark(ax_a, ch.am_pos.t, ch.am_pos.value, f"Am+ = {ch.am_pos.value:.4f} at T = {ch.am_pos.t:.4f}",
                  COLORS["a"], above=True)
        if ch.am_neg.value < 0:
            mark(ax_a, ch.am_neg.t, ch.am_neg.value, f"Am− = {ch.am_neg.value:.4f} at T = {ch.am_neg.t:.4f}",
                  COLORS["a"], above=False)
        if ch.jm_pos.value > 0:
            mark(ax_j, ch.jm_pos.t, ch.jm_pos.value, f"Jm+ = {ch.jm_pos.value:.2f}", COLORS["j"], above=True)
        if ch.jm_neg.value < 0:
            mark(ax_j, ch.jm_neg.t, ch.jm_neg.value, f"Jm− = {ch.jm_neg.value:.2f}", COLORS["j"], above=False)
        ax_s.set_xlim(float(t[0]), float(t[-1]))
        ax_j.set_xlabel("T (dimensionless time)", fontsize=9)
        fig.suptitle(title, fontsize=11)
        return render(fig, fmt, dpi)



# ----------------------------------------------------------------------------- the design chart
_VM_COLOR = "#1f77b4"
_AM_COLOR = "#d62728"


def _am(columns: dict[str, Any]) -> np.ndarray:
    """Am = max |A| of each row (NaN where the row has no curve)."""
    return np.fmax(np.asarray(columns["am_pos"], dtype=float), -np.asarray(columns["am_neg"], dtype=float))


def design_chart(columns: dict[str, Any], vary: dict[str, list[float]], fmt: str, dpi: int = 100) -> bytes:
    """Vm and Am over the varied parameters (``vary``: name → values, the sweep's): contours over
    two, curves over one."""
    names = list(vary)
    vm = np.asarray(columns["vm"], dtype=float)
    am = _am(columns)
    with LOCK:
        fig = figure(7.0, 5.6)
        ax = fig.subplots()
        if len(names) == 1:
            _one(ax, np.asarray(columns[names[0]], dtype=float), vm, am, names[0])
        else:
            _two(ax, columns, names, (len(vary[names[0]]), len(vary[names[1]])), vm, am)
        fig.suptitle(f"Characteristic values over {' and '.join(names)}", fontsize=11)
        return render(fig, fmt, dpi)


def _one(ax: Any, x: np.ndarray, vm: np.ndarray, am: np.ndarray, name: str) -> None:
    order = np.argsort(x, kind="stable")
    ax.plot(x[order], vm[order], color=_VM_COLOR, marker="o", markersize=3, label="Vm")
    ax.set_xlabel(name, fontsize=9)
    ax.set_ylabel("Vm", fontsize=9, color=_VM_COLOR)
    style(ax)
    twin = ax.twinx()
    twin.plot(x[order], am[order], color=_AM_COLOR, marker="s", markersize=3, label="Am")
    twin.set_ylabel("Am = max |A|", fontsize=9, color=_AM_COLOR)
    twin.tick_params(labelsize=8)
    ax.legend(handles=[*ax.get_lines()[:1], *twin.get_lines()[:1]], fontsize=8, loc="upper left")


#: contour levels of Am per decade: Am spans decades (∝ 1/T3 for curve 4), so levels are ~evenly spaced in log Am
_PER_DECADE = (1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0)


def _levels(values: np.ndarray, log: bool) -> np.ndarray:
    """Round contour levels inside the finite values' range: 1-2-5 steps, or for ``log`` :data:`_PER_DECADE`."""
    from matplotlib.ticker import MaxNLocator

    finite = values[np.isfinite(values) & ((values > 0) if log else True)]
    if finite.size == 0 or finite.min() == finite.max():
        return np.array([])
    low, high = float(finite.min()), float(finite.max())
    if log:
        decades = range(int(np.floor(np.log10(low))), int(np.ceil(np.log10(high))) + 1)
        levels = np.array([m * 10.0 ** d for d in decades for m in _PER_DECADE])
    else:
        levels = np.asarray(MaxNLocator(10).tick_values(low, high), dtype=float)
    return levels[(levels > low) & (levels < high)]


def _two(ax: Any, columns: dict[str, Any], names: list[str], shape: tuple[int, int], vm: np.ndarray,
         am: np.ndarray) -> None:
    x_all, y_all = np.asarray(columns[names[0]], dtype=float), np.asarray(columns[names[1]], dtype=float)
    # rows are the product (first parameter slowest): a grid of nx × ny; its axes sorted, repeats dropped
    nx, ny = shape
    xs, ix = np.unique(x_all[::ny], return_index=True)
    ys, iy = np.unique(y_all[:ny], return_index=True)
    grid_vm = np.ma.masked_invalid(vm.reshape(nx, ny)[ix][:, iy].T)
    grid_am = np.ma.masked_invalid(am.reshape(nx, ny)[ix][:, iy].T)
    xx, yy = np.meshgrid(xs, ys)
    ax.plot(x_all[np.isnan(vm)], y_all[np.isnan(vm)], "x", color="#bbbbbb", markersize=3,
            label="no curve (see the row's error)")
    ax.plot(x_all[np.isfinite(vm)], y_all[np.isfinite(vm)], ".", color="#888888", markersize=2)
    if xs.size > 1 and ys.size > 1:
        vm_levels, am_levels = _levels(vm, False), _levels(am, True)
        if vm_levels.size:
            lines = ax.contour(xx, yy, grid_vm, levels=vm_levels, colors=_VM_COLOR, linewidths=1.0)
            ax.clabel(lines, fontsize=7, fmt="Vm %g")
        if am_levels.size:
            lines = ax.contour(xx, yy, grid_am, levels=am_levels, colors=_AM_COLOR, linewidths=1.0,
                               linestyles="dashed")
            ax.clabel(lines, fontsize=7, fmt="Am %g")
    ax.plot([], [], color=_VM_COLOR, label="Vm")
    ax.plot([], [], color=_AM_COLOR, linestyle="dashed", label="Am = max |A|")
    ax.set_xlabel(names[0], fontsize=9)
    ax.set_ylabel(names[1], fontsize=9)
    style(ax)
    ax.legend(fontsize=8, loc="upper left")


# ----------------------------------------------------------------------------- the vibration spectra
#: the log axis has no 0, and an undamped spectrum dips to 0 at its notches (the cycloid at
#: every integer τ ≥ 2): the axis starts a decade below the lowest trace's 10th percentile,
#: not below this, and the notches run to its bottom edge
FLOOR = 1e-9
SPECTRUM_COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")


def spectrum_chart(tau: np.ndarray, traces: list[tuple[str, np.ndarray]], title: str, label: str,
                   fmt: str = "svg", dpi: int = 100) -> bytes:
    """Each trace (name, amplitude over τ) on a log axis; see :data:`FLOOR` for where it starts."""
    lows = [float(np.percentile(np.maximum(values, FLOOR), 10)) for _, values in traces]
    bottom = max(FLOOR, 10.0 ** (np.floor(np.log10(min(lows))) - 1))
    top = max(float(np.max(values)) for _, values in traces)
    with LOCK:
        fig = figure(10.0, 6.0)
        ax: Any = fig.subplots(1, 1)
        for k, (name, values) in enumerate(traces):
            ax.plot(tau, np.maximum(values, bottom), color=SPECTRUM_COLORS[k % len(SPECTRUM_COLORS)], linewidth=1.2,
                    label=name)
        ax.set_yscale("log")
        ax.set_ylim(bottom, max(10.0 ** np.ceil(np.log10(max(top, bottom))), 10 * bottom))
        ax.set_xlim(float(tau.min()), float(tau.max()))
        ax.grid(True, which="major", color="#cccccc", linewidth=0.7)
        ax.grid(True, which="minor", color="#eeeeee", linewidth=0.5)
        ax.tick_params(labelsize=8)
        ax.set_xlabel("τ = th·fn (motion time / natural period of the follower)", fontsize=9)
        ax.set_ylabel(label, fontsize=9)
        ax.legend(fontsize=8, loc="upper right", frameon=True, framealpha=0.9)
        if any(float(np.min(values)) < bottom for _, values in traces):
            ax.set_title("a notch running to the bottom edge: a τ where the curve leaves (almost) nothing",
                         fontsize=8, color="#666666")
        fig.suptitle(title, fontsize=11)
        return render(fig, fmt, dpi)
