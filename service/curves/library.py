"""The curves of a worker: built from their laws (camcore.curves.kinds.Law), kept in a bounded
cache, with their size limits and their cost known before they are built.

Every operation that takes a curve builds it here, so each curve is built once per worker
whichever operation asked first, and a curve over its kind's size limit is refused (413) in
the same words everywhere.
"""

from __future__ import annotations

from collections.abc import Mapping

import orjson

from camcore.curves import CURVE_KINDS, Curve, Law, build_curve
from camcore.curves.kinds import LawCost
from camcore.errors import LimitExceededError
from camcore.work import WorkEstimate, WorkTerm, curve_work, law_cost
from service.cache import LRUCache, held_bytes
from service.errors import Location, within
from service.settings import Settings


def check_limit(what: str, requested: int, limit: int, field: Location = ()) -> None:
    """413 (LimitExceededError) when ``requested`` is over ``limit``; ``field`` is the request
    field that asked for it (e.g. ("samples",))."""
    if requested > limit:
        raise LimitExceededError(what, requested, limit, field=field)


def law_key(law: Law) -> bytes:
    """The cache key of a law: its kind, direction and parameters, as JSON."""
    return orjson.dumps((law.kind, law.direction, law.parameters), option=orjson.OPT_SORT_KEYS)


class CurveLibrary:
    """Curves from laws, cached (at most ``curve_cache_size`` curves and
    ``curve_cache_max_bytes``), with encoded tables cached beside them."""

    def __init__(self, settings: Settings):
        self.settings = settings
        self.curves: LRUCache[Curve] = LRUCache(settings.curve_cache_size, settings.curve_cache_max_bytes,
                                                size_of=held_bytes)
        self.tables: LRUCache[bytes] = LRUCache(settings.table_cache_size, settings.table_cache_max_bytes)

    @staticmethod
    def key(law: Law) -> bytes:
        """The cache key of a law's curve (and of its tables)."""
        return law_key(law)

    def size_limits(self) -> Mapping[str, int]:
        """The curve size limits by setting name, as camcore's builders take them."""
        return {"max_bezier_degree": self.settings.max_bezier_degree,
                "max_curve_points": self.settings.max_curve_points}

    def check_size(self, law: Law) -> None:
        """413 before any work when a law is over its kind's size limit (CURVE_KINDS)."""
        limit = CURVE_KINDS[law.kind].limit
        if limit is not None:
            size = limit.size({limit.parameter: law.parameters.get(limit.parameter)})
            check_limit(limit.what, size, self.size_limits()[limit.setting], (limit.parameter,))

    # ------------------------------------------------------------------ cost
    def cost(self, law: Law, at: Location = ("curve",)) -> LawCost:
        """What the law's curve costs (camcore.work), before it is built; a law over its kind's
        size limit is refused first (413). ``at``: where the law is in the request."""
        with within(*at):
            self.check_size(law)
        return law_cost(law.kind, law.parameters)

    def build_work(self, law: Law, cost: LawCost, at: Location, inverse: bool = False,
                   values_only: bool = False) -> WorkEstimate:
        """Building the law's curve: nothing when it is in the cache (with its inverse's start
        tables, if ``inverse``), else its cost (``values_only``: without the inverse's tables,
        camcore.work.curve_work)."""
        cached = self.curves.peek(law_key(law))
        if cached is not None and (not inverse or cached.inverse_ready):
            return WorkEstimate((WorkTerm(at, "the curve, already built", 0.0),))
        return curve_work(cost, at, values_only)

    def work(self, law: Law, at: Location = ("curve",)) -> WorkEstimate:
        """Building the law's curve (nothing when it is cached)."""
        return self.build_work(law, self.cost(law, at), at)

    # ------------------------------------------------------------------ curves
    def curve(self, law: Law, at: Location = ("curve",)) -> Curve:
        """The curve of a law (cached); an error in it is reported at ``at``."""
        with within(*at):
            self.check_size(law)
            return self.curves.get_or_create(
                law_key(law), lambda: build_curve(law.kind, law.parameters, law.direction, self.size_limits()))

    def built(self, law: Law) -> Curve | None:
        """The law's curve if it is in the cache (nothing is built, nothing counted)."""
        return self.curves.peek(law_key(law))

    def remeasure(self, law: Law) -> None:
        """The law's curve grew (its inverse's start tables): count it again in the cache's bytes."""
        self.curves.remeasure(law_key(law))

    def cache_stats(self) -> dict[str, dict[str, int]]:
        return {"curves": self.curves.stats(), "tables": self.tables.stats()}
