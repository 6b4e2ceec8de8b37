"""A bounded, explicitly keyed LRU cache with hit and miss counters, and the measure of
what a cached object really holds."""

from __future__ import annotations

import sys
import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Any, Generic, TypeVar

import numpy as np

V = TypeVar("V")


#: leaves of the object graph: their own size, nothing reachable (exact types: a subclass may hold more)
_LEAVES = frozenset({str, bytes, int, float, complex, bool, type(None)})


def held_bytes(value: Any) -> int:
    """Bytes an object holds: numpy arrays' buffers and every Python object reachable
    through attributes, containers and cached properties, each counted once."""
    seen: set[int] = set()
    total = 0
    stack = [value]
    size_of = sys.getsizeof
    while stack:
        item = stack.pop()
        key = id(item)
        if key in seen:
            continue
        kind = type(item)
        if kind in _LEAVES:  # most of a curve: its coefficients as Python floats
            seen.add(key)
            total += size_of(item)
            continue
        if isinstance(item, type):
            continue
        seen.add(key)
        if isinstance(item, np.ndarray):
            total += item.nbytes + size_of(item) if item.base is None else size_of(item)
            if item.base is not None:
                stack.append(item.base)
            continue
        total += size_of(item)
        if isinstance(item, dict):
            stack.extend(item.keys())
            stack.extend(item.values())
        elif isinstance(item, (list, tuple, set, frozenset)):
            stack.extend(item)
        elif not isinstance(item, (str, bytes, int, float, complex, bool)):
            attributes = getattr(item, "__dict__", None)
            if attributes is not None:
                stack.append(attributes)
            for name in getattr(kind, "__slots__", ()):
                if hasattr(item, name):
                    stack.append(getattr(item, name))
    return total


class LRUCache(Generic[V]):
    """Least-recently-used cache holding at most ``maxsize`` entries (0 disables it).

    With ``max_bytes``, the cache also keeps the total size of its values under that bound
    (a value larger than the bound is not cached); ``size_of`` measures a value (default
    ``len``, for bytes), and :meth:`remeasure` measures an entry again after it grew (a
    curve that built its inverse tables).
    """

    def __init__(self, maxsize: int, max_bytes: int | None = None, size_of: Callable[[V], int] = len):  # type: ignore[assignment]
        self.maxsize = maxsize
        self.max_bytes = max_bytes
        self.size_of = size_of
        self._sizes: dict[Hashable, int] = {}
        self.bytes = 0
        self.hits = 0
        self.misses = 0
        self._data: OrderedDict[Hashable, V] = OrderedDict()
        self._lock = threading.Lock()

    def peek(self, key: Hashable) -> V | None:
        """The cached value or None, counted neither as a hit nor a miss (order unchanged)."""
        with self._lock:
            return self._data.get(key)

    def get(self, key: Hashable) -> V | None:
        """The cached value (counted as a hit), or None without counting a miss.

        For a caller that answers hits on the event loop and builds a miss elsewhere
        with :meth:`get_or_create` (which then counts the miss).
        """
        with self._lock:
            if key in self._data:
                self._data.move_to_end(key)
                self.hits += 1
                return self._data[key]
        return None

    def get_or_create(self, key: Hashable, create: Callable[[], V]) -> V:
        with self._lock:
            if key in self._data:
                self._data.move_to_end(key)
                self.hits += 1
                return self._data[key]
            self.misses += 1
        value = create()  # outside the lock: building may take a while, and may raise
        size = self.size_of(value) if self.max_bytes is not None else 0
        if self.maxsize > 0 and (self.max_bytes is None or size <= self.max_bytes):
            with self._lock:
                self.bytes += size - self._sizes.get(key, 0)
                self._sizes[key] = size
                self._data[key] = value
                self._data.move_to_end(key)
                self._evict()
        return value

    def remeasure(self, key: Hashable) -> None:
        """Measure an entry again (it grew since it was cached), evicting others as needed."""
        if self.max_bytes is None:
            return
        value = self.peek(key)
        if value is None:
            return
        size = self.size_of(value)
        with self._lock:
            if key in self._data:
                self.bytes += size - self._sizes.get(key, 0)
                self._sizes[key] = size
                self._evict()

    def _evict(self) -> None:
        """Drop least recently used entries until both bounds hold (call under the lock)."""
        while self._data and (len(self._data) > self.maxsize
                              or (self.max_bytes is not None and self.bytes > self.max_bytes)):
            old_key, _ = self._data.popitem(last=False)
            self.bytes -= self._sizes.pop(old_key, 0)

    def stats(self) -> dict[str, int]:
        with self._lock:
            stats = {"size": len(self._data), "maxsize": self.maxsize, "hits": self.hits, "misses": self.misses}
            if self.max_bytes is not None:
                stats.update(bytes=self.bytes, max_bytes=self.max_bytes)
            return stats
