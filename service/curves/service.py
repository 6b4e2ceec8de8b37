"""The service's bridge to camcore: specs in, arrays out, with bounded caches.

Route functions call these methods and return what they give; all numpy work and
all limit checks live here, none in the routes.
"""

from __future__ import annotations

from typing import Any

import numpy as np

import camcore
from camcore.curves import CURVE_KINDS, Curve, build_curve
from camcore.curves.kinds import LawCost
from camcore.errors import LimitExceededError, NonMonotoneError
from camcore.results import as_dict
from camcore.work import WorkEstimate, WorkTerm, curve_work, law_cost, per_item_work
from service.cache import LRUCache, held_bytes
from service.curves.specs import CurveSpec, MakinoCurveSpec
from service.errors import within
from service.responses import encode_cost, encode_table, encode_value
from service.settings import Settings

#: columns of a curve table (t, s, v, a, j, q) and of an inverse answer (s, t, v, a)
TABLE_COLUMNS = 6
INVERSE_COLUMNS = 4

#: rows of a table worth a thread-pool hop: below this, on a curve already built, the work
#: (0.07 ms for 101 rows of MS, ~1 ms for 1001 rows of a degree-20 Bezier) costs less than
#: the hop does under load, and with the GIL a thread would not run beside the loop anyway
QUICK_TABLE_ROWS = 1_001


class CurveService:
    """Builds curves from specs (cached) and answers tables, characteristics, inverses."""

    def __init__(self, settings: Settings):
        self.settings = settings
        self.curves: LRUCache[Curve] = LRUCache(settings.curve_cache_size, settings.curve_cache_max_bytes,
                                                size_of=held_bytes)
        self.tables: LRUCache[bytes] = LRUCache(settings.table_cache_size, settings.table_cache_max_bytes)

    # ------------------------------------------------------------------ limits
    def check_limit(self, what: str, requested: int, limit: int, field: tuple[str | int, ...] = ()) -> None:
        """Raise LimitExceededError when ``requested`` is over ``limit``; ``field`` is the
        request field that asked for it (e.g. ("samples",))."""
        if requested > limit:
            raise LimitExceededError(what, requested, limit, field=field)

    # ------------------------------------------------------------------ work estimates
    def law(self, spec: CurveSpec, at: tuple[str | int, ...] = ("curve",)) -> LawCost:
        """What the spec's curve costs (camcore.work), before it is built; a spec over its
        kind's size limit is refused first (413)."""
        with within(*at):
            self._check_spec_size(spec)
        return law_cost(spec.type, spec.parameters())

    def curve_work(self, spec: CurveSpec, at: tuple[str | int, ...] = ("curve",)) -> WorkEstimate:
        return self.build_work(spec, self.law(spec, at), at)

    def characteristics_work(self, spec: CurveSpec) -> WorkEstimate:
        """The curve built with its characteristic values (no inverse tables), or nothing when cached."""
        return self.build_work(spec, self.law(spec), ("curve",), values_only=True)

    def build_work(self, spec: CurveSpec, law: LawCost, at: tuple[str | int, ...], inverse: bool = False,
                   values_only: bool = False) -> WorkEstimate:
        """Building the spec's curve: nothing when it is in the cache (with its inverse's start
        tables, if ``inverse``), else the law's build cost (``values_only``: without the inverse's
        tables, camcore.work.curve_work)."""
        cached = self.curves.peek(spec.cache_key())
        if cached is not None and (not inverse or cached.inverse_ready):
            return WorkEstimate((WorkTerm(at, "the curve, already built", 0.0),))
        return curve_work(law, at, values_only)

    def table_work(self, spec: CurveSpec, rows: int, csv: bool, field: tuple[str | int, ...]) -> WorkEstimate:
        """A table of ``rows`` rows (``field``: samples or t): the curve, evaluated and
        encoded at each row; over the row limit: 413 first."""
        law = self.law(spec)
        what = "table samples" if field == ("samples",) else "number of times t"
        self.check_limit(what, rows, self.settings.max_table_samples, field)
        return self.build_work(spec, law, ("curve",)) + per_item_work(
            rows, law.sample_s + encode_cost(TABLE_COLUMNS, csv), field, f"{rows} table rows")

    def inverse_work(self, spec: CurveSpec, values: int, method: str, table_step: float, csv: bool,
                     field: tuple[str | int, ...] = ("s",)) -> WorkEstimate:
        """An inverse of ``values`` S values (the table method also samples its table)."""
        self.check_limit("number of s values", values, self.settings.max_inverse_points, field)
        law = self.law(spec)
        work = self.build_work(spec, law, ("curve",), inverse=method == "exact") + per_item_work(
            values, 2 * law.sample_s + encode_cost(INVERSE_COLUMNS, csv), field, f"{values} inverse lookups")
        return work + self.inverse_table_work(law, method, table_step)

    @staticmethod
    def inverse_table_work(law: LawCost, method: str, table_step: float) -> WorkEstimate:
        """The catalog's table method samples a table at ``table_step`` first; exact: nothing."""
        if method != "table":
            return WorkEstimate()
        rows = int(1.0 / table_step) + 1
        return per_item_work(rows, law.sample_s, ("table_step",), f"an inverse table of {rows} rows")

    # ------------------------------------------------------------------ curves
    def curve(self, spec: CurveSpec, at: tuple[str | int, ...] = ("curve",)) -> Curve:
        """The curve of a spec (cached); ``at`` is the spec's field in the request, where
        an error in it is reported."""
        with within(*at):
            self._check_spec_size(spec)
            return self.curves.get_or_create(spec.cache_key(), lambda: self._build(spec))

    def size_limits(self) -> dict[str, int]:
        """The curve size limits by setting name, as camcore's builders take them."""
        return self._limits()

    def _limits(self) -> dict[str, int]:
        return {"max_bezier_degree": self.settings.max_bezier_degree,
                "max_curve_points": self.settings.max_curve_points}

    def _check_spec_size(self, spec: CurveSpec) -> None:
        """413 before any work when a spec is over its kind's size limit (CURVE_KINDS)."""
        limit = CURVE_KINDS[spec.type].limit
        if limit is not None:
            size = limit.size({limit.parameter: getattr(spec, limit.parameter)})
            self.check_limit(limit.what, size, self._limits()[limit.setting], (limit.parameter,))

    def _build(self, spec: CurveSpec) -> Curve:
        return build_curve(spec.type, spec.parameters(), spec.direction, self._limits())

    # A route answers quick work on the event loop and sends the rest to a worker thread.
    def is_built(self, spec: CurveSpec) -> bool:
        """Whether the spec's curve is in the cache (no building needed)."""
        return self.curves.peek(spec.cache_key()) is not None

    def is_quick_table(self, spec: CurveSpec, rows: int) -> bool:
        """Whether a table of ``rows`` is quick work: the curve is built and rows are few."""
        return rows <= QUICK_TABLE_ROWS and self.curves.peek(spec.cache_key()) is not None

    def is_quick_inverse(self, spec: CurveSpec, values: int, method: str) -> bool:
        """Whether an inverse is quick work: exact, for few values, on a built curve whose
        inverse has its start table (the catalog's table method builds a table each time)."""
        if method != "exact" or values > QUICK_TABLE_ROWS:
            return False
        curve = self.curves.peek(spec.cache_key())
        return curve is not None and curve.inverse_ready

    # ------------------------------------------------------------------ answers
    def characteristics(self, spec: CurveSpec) -> dict[str, Any]:
        answer = as_dict(self.curve(spec).characteristics)
        if isinstance(spec, MakinoCurveSpec):  # the parameters as built, those solved from a target among them
            answer["parameters"] = spec.solved_parameters()
        return answer

    def table_columns(self, spec: CurveSpec, samples: int | None, t: list[float] | None) -> dict[str, np.ndarray]:
        curve = self.curve(spec)
        if t is not None:
            self.check_limit("number of times t", len(t), self.settings.max_table_samples, ("t",))
            times = np.asarray(t, dtype=np.float64)
        else:
            assert samples is not None
            self.check_limit("table samples", samples, self.settings.max_table_samples, ("samples",))
            times = curve.sample_times(samples)
        return curve.evaluate(times).columns()

    def cached_table(self, spec: CurveSpec, samples: int, csv: bool) -> bytes:
        """A sampled table's encoded body (JSON or CSV), cached when it is small."""
        with within("curve"):
            self._check_spec_size(spec)
        self.check_limit("table samples", samples, self.settings.max_table_samples, ("samples",))

        def build() -> bytes:
            return encode_table(self.table_columns(spec, samples, None), csv)

        if samples > self.settings.table_cache_max_rows:
            return build()
        return self.tables.get_or_create((spec.cache_key(), samples, csv), build)

    def table_if_cached(self, spec: CurveSpec, samples: int, csv: bool) -> bytes | None:
        """The encoded table if it is in the cache (no computation: cheap enough for the
        event loop), else None: then :meth:`cached_table` builds it."""
        if samples > self.settings.table_cache_max_rows:
            return None
        return self.tables.get((spec.cache_key(), samples, csv))

    def inverse_columns(
        self, spec: CurveSpec, s: list[float], method: str, table_step: float, table_decimals: int | None
    ) -> dict[str, np.ndarray]:
        self.check_limit("number of s values", len(s), self.settings.max_inverse_points, ("s",))
        curve = self.curve(spec)
        s_arr = np.asarray(s, dtype=np.float64)
        if method == "table":
            span = curve.t_end - curve.t_start
            self.check_limit("inverse table rows", int(span / table_step) + 1, self.settings.max_table_samples,
                             ("table_step",))
            with within("curve", only=NonMonotoneError):  # the curve cannot be inverted
                vals = curve.inverse_table(s_arr, table_step, table_decimals)
            return {"s": s_arr, "t": vals.t, "v": vals.v, "a": vals.a}
        grows = not curve.inverse_ready
        with within("curve", only=NonMonotoneError):
            t, v, a = curve.inverse_with_rates(s_arr)
        if grows:  # the curve now holds its inverse's start tables: count them in the cache's bytes
            self.curves.remeasure(spec.cache_key())
        return {"s": s_arr, "t": t, "v": v, "a": a}

    def value(self, spec: CurveSpec, quantity: str, t: float | None, s: float | None) -> bytes:
        """One number as text: ``quantity`` (s, v, a, j, q) at the time t, as in a table;
        or, given s instead, the T of the exact inverse."""
        if s is not None:
            number = self.curve(spec).inverse(np.array([s]))[0]
        else:
            assert t is not None
            number = self.table_columns(spec, None, [t])[quantity][0]
        return encode_value(quantity, float(number))

    def catalog_entry(self, entry: camcore.CatalogEntry) -> dict[str, Any]:
        return {
            "id": entry.id,
            "aliases": list(entry.aliases),
            "name": entry.name,
            "family": entry.family,
            "source": entry.source,
            "makino_number": entry.makino_number,
            "parameters": entry.parameters,
            "characteristics": as_dict(entry.build().characteristics),
        }

    def catalog(self) -> list[dict[str, Any]]:
        return [self.catalog_entry(e) for e in camcore.CATALOG.values()]

    def cache_stats(self) -> dict[str, dict[str, int]]:
        return {"curves": self.curves.stats(), "tables": self.tables.stats()}
