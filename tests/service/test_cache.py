"""The bounded LRU cache: entry and byte bounds, hit/miss counts, results unchanged."""

from __future__ import annotations

from service.cache import LRUCache


def test_entry_bound_evicts_least_recently_used() -> None:
    cache: LRUCache[int] = LRUCache(2)
    assert cache.get_or_create("a", lambda: 1) == 1
    assert cache.get_or_create("b", lambda: 2) == 2
    assert cache.get_or_create("a", lambda: -1) == 1  # hit: the cached value, not a rebuild
    cache.get_or_create("c", lambda: 3)  # evicts b, the least recently used
    assert cache.get_or_create("b", lambda: 20) == 20
    assert cache.stats() == {"size": 2, "maxsize": 2, "hits": 1, "misses": 4}


def test_byte_bound_keeps_the_total_under_the_limit() -> None:
    cache: LRUCache[bytes] = LRUCache(100, max_bytes=10)
    cache.get_or_create("a", lambda: b"12345")
    cache.get_or_create("b", lambda: b"12345")
    assert cache.stats()["bytes"] == 10
    cache.get_or_create("c", lambda: b"123")  # 13 bytes > 10: the oldest entry goes
    stats = cache.stats()
    assert stats["bytes"] == 8 and stats["size"] == 2
    cache.get_or_create("huge", lambda: b"x" * 11)  # larger than the bound: answered, not cached
    assert cache.stats()["bytes"] == 8 and cache.get_or_create("huge", lambda: b"again") == b"again"


def test_disabled_cache_still_answers() -> None:
    cache: LRUCache[int] = LRUCache(0)
    assert cache.get_or_create("a", lambda: 1) == 1
    assert cache.get_or_create("a", lambda: 2) == 2
    assert cache.stats()["size"] == 0


def test_peek_counts_nothing_and_keeps_the_order() -> None:
    cache: LRUCache[int] = LRUCache(2)
    cache.get_or_create("a", lambda: 1)
    cache.get_or_create("b", lambda: 2)
    assert cache.peek("a") == 1 and cache.peek("c") is None
    cache.get_or_create("c", lambda: 3)  # "a" is still the least recently used: it goes
    assert cache.peek("a") is None and cache.peek("b") == 2
    assert cache.stats() == {"size": 2, "maxsize": 2, "hits": 0, "misses": 3}


def test_spec_cache_key_is_made_once_and_follows_a_changed_copy() -> None:
    from service.curves.specs import NamedCurveSpec

    spec = NamedCurveSpec(name="MS")
    key = spec.cache_key()
    assert key == spec.model_dump_json() and spec.cache_key() is key  # the same string object: made once
    changed = spec.model_copy(update={"direction": "return"})
    assert changed.cache_key() == NamedCurveSpec(name="MS", direction="return").model_dump_json() != key
    assert spec.model_copy().cache_key() == key
