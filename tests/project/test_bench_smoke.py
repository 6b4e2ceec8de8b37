"""CI smoke run of the benchmark suite: ``python -m bench --smoke`` must run and report every figure.

Targets are not checked here (tiny sizes, shared CI machines); see bench/README.md.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FIGURES = {
    "table_vs_sin_floor", "scalar_port_vs_table", "inverse_vs_table", "ms_table_vs_numpy", "cycloid_table_vs_mechanism",
    "json_vs_orjson_floor", "http_table_vs_ceiling", "http_cached_vs_bare", "http_p99_ms", "workers_scaling",
    "profile_rps",
    "characteristics_new_curve_rps", "sizing_rps", "base_circle_ms", "cold_start_vs_bare_fastapi", "sizing_sweep",
    "sweep_vs_single_sizings", "characteristics_sweep_vs_single", "readme_routes_ms",
}


@pytest.mark.bench
@pytest.mark.wrk
def test_bench_smoke_reports_every_figure() -> None:
    # the HTTP figures need wrk; make test installs it (scripts/install_test_tools.sh)
    assert shutil.which("wrk"), "wrk is missing: make test installs it (apt-get install wrk)"
    proc = subprocess.run([sys.executable, "-m", "bench", "--smoke"], cwd=ROOT, capture_output=True,
                          text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr[-4000:]
    result = json.loads(proc.stdout)
    assert result["mode"] == "smoke"
    assert result["machine"]["cpus"] >= 1
    figures = result["figures"]
    assert set(figures) == FIGURES
    # every figure is measured, none skipped
    for name, fig in figures.items():
        assert "skipped" not in fig, f"{name} skipped: {fig['skipped']}"
        assert {"median", "min", "max", "target", "met"} <= set(fig), name
        assert fig["min"] <= fig["median"] <= fig["max"], name
        assert fig["median"] > 0, name
    assert figures["scalar_port_vs_table"]["agrees_with_camcore"] is True
    # the peers are compared only after they agree with camcore (the figure asserts 1e-14 of the peaks)
    for peer in ("ms_table_vs_numpy", "cycloid_table_vs_mechanism"):
        assert figures[peer]["agreement_of_peak"] <= 1e-14, peer
    assert all(key in result["machine"]["cpu_features"] for key in ("AVX2", "AVX512F"))


def _medians(markdown: str, heading: str) -> dict[str, str]:
    """figure → median column of the first table after ``heading`` in a Markdown text."""
    section = markdown[markdown.index(heading):]
    rows = {}
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[0] in FIGURES:
            rows[cells[0]] = cells[1]
        elif rows and not line.startswith("|"):
            break
    return rows


def test_readme_figures_are_the_bench_readmes() -> None:
    """The README's figures are the latest run recorded in bench/README.md (no drift)."""
    readme = _medians((ROOT / "README.md").read_text(encoding="utf-8"), "## Performance")
    bench = _medians((ROOT / "bench" / "README.md").read_text(encoding="utf-8"), "## Latest figures")
    assert set(readme) == FIGURES
    assert readme == bench


@pytest.mark.bench
def test_cost_model_smoke_measures_every_case() -> None:
    from bench.cost_model import CASES

    proc = subprocess.run([sys.executable, "-m", "bench.cost_model", "--smoke"], cwd=ROOT, capture_output=True,
                          text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr[-4000:]
    result = json.loads(proc.stdout)
    assert result["mode"] == "smoke" and set(result["cases"]) == {case.name for case in CASES}
    for name, figure in result["cases"].items():
        # every case answered for real (200), its work timed inside the gate and estimated beforehand
        assert figure["estimate_s"] > 0 and 0 < figure["work_s_median"] <= figure["answer_s_median"], name
