"""A bounded, explicitly keyed LRU cache with hit and miss counters."""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Generic, TypeVar

V = TypeVar("V")


class LRUCache(Generic[V]):
    """Least-recently-used cache holding at most ``maxsize`` entries (0 disables it).

    With ``max_bytes``, values are ``bytes`` and the cache also keeps their total length
    under that bound (a value longer than the bound is not cached).
    """

    def __init__(self, maxsize: int, max_bytes: int | None = None):
        self.maxsize = maxsize
        self.max_bytes = max_bytes
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
        size = len(value) if self.max_bytes is not None else 0  # type: ignore[arg-type]
        if self.maxsize > 0 and (self.max_bytes is None or size <= self.max_bytes):
            with self._lock:
                if key not in self._data:
                    self.bytes += size
                self._data[key] = value
                self._data.move_to_end(key)
                while len(self._data) > self.maxsize or (self.max_bytes is not None and self.bytes > self.max_bytes):
                    _, old = self._data.popitem(last=False)
                    self.bytes -= len(old) if self.max_bytes is not None else 0  # type: ignore[arg-type]
        return value

    def stats(self) -> dict[str, int]:
        with self._lock:
            stats = {"size": len(self._data), "maxsize": self.maxsize, "hits": self.hits, "misses": self.misses}
            if self.max_bytes is not None:
                stats.update(bytes=self.bytes, max_bytes=self.max_bytes)
            return stats
