"""The design chart of a characteristics sweep (Makino 1977, fig. 3): over two parameters,
contours of Vm and Am (the designer reads off which T1, T3 give the Vm wanted and what Am it
costs); over one, Vm and Am as curves."""

from __future__ import annotations

from typing import Any

import numpy as np

from service.plots.charts import _LOCK, _figure, _render, _style

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
    with _LOCK:
        fig = _figure(7.0, 5.6)
        ax = fig.subplots()
        if len(names) == 1:
            _one(ax, np.asarray(columns[names[0]], dtype=float), vm, am, names[0])
        else:
            _two(ax, columns, names, (len(vary[names[0]]), len(vary[names[1]])), vm, am)
        fig.suptitle(f"Characteristic values over {' and '.join(names)}", fontsize=11)
        return _render(fig, fmt, dpi)


def _one(ax: Any, x: np.ndarray, vm: np.ndarray, am: np.ndarray, name: str) -> None:
    order = np.argsort(x, kind="stable")
    ax.plot(x[order], vm[order], color=_VM_COLOR, marker="o", markersize=3, label="Vm")
    ax.set_xlabel(name, fontsize=9)
    ax.set_ylabel("Vm", fontsize=9, color=_VM_COLOR)
    _style(ax)
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
    _style(ax)
    ax.legend(fontsize=8, loc="upper left")
