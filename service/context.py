"""What every operation of one worker shares: its settings, its work gate, its curves and caches.

One :class:`Context` is made by ``create_app`` and kept on ``app.state.context``; each
operation's functions take it as their first argument (service.operations).
"""

from __future__ import annotations

from dataclasses import dataclass

from camcore.profile import ProfileChecks
from service.admission import WorkGate
from service.answer_budget import AnswerBudget
from service.cache import LRUCache
from service.cad_pool import CadPool
from service.curves.library import CurveLibrary
from service.replies import REPLIES_MAX_BYTES, Reply, reply_size
from service.settings import Settings

#: bytes the cached sizing answers may hold (one is ~10 kB with its 181-row torque table)
SIZING_CACHE_MAX_BYTES = 8 * 1024 * 1024


@dataclass
class Context:
    """The state of one worker's operations."""

    settings: Settings
    gate: WorkGate
    curves: CurveLibrary
    #: a cam's checks over the whole turn, by its spec (they do not depend on samples or format)
    profile_checks: LRUCache[ProfileChecks]
    #: encoded sizing answers by request: a spreadsheet recalculating asks the same again
    sizings: LRUCache[bytes]
    #: the CAD kernel's processes (STEP, STL solids)
    cad: CadPool
    #: the bytes of answers held for open downloads
    answers: AnswerBudget
    #: replies by request, of answers their operations gave from their own caches (service.replies)
    replies: LRUCache[Reply]

    @classmethod
    def create(cls, settings: Settings) -> Context:
        return cls(settings=settings, gate=WorkGate(settings), curves=CurveLibrary(settings),
                   profile_checks=LRUCache(settings.profile_checks_cache_size),
                   sizings=LRUCache(settings.sizing_cache_size, SIZING_CACHE_MAX_BYTES),
                   cad=CadPool(settings.cad_processes, settings.cad_max_tasks, settings.cad_idle_s,
                               settings.work_deadline_s),
                   answers=AnswerBudget(settings.max_answer_bytes_in_flight),
                   replies=LRUCache(settings.reply_cache_size, REPLIES_MAX_BYTES, size_of=reply_size))

    def cache_stats(self) -> dict[str, dict[str, int]]:
        """Every cache's hit and miss counts (the health answer)."""
        return {**self.curves.cache_stats(), "profile_checks": self.profile_checks.stats(),
                "sizings": self.sizings.stats(), "replies": self.replies.stats()}
