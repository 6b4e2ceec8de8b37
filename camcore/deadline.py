"""Stopping a long computation cooperatively: its caller sets a deadline, the loops check it.

A caller (the service, a script) runs a computation inside :func:`running_until`; the
solvers' loops and the profile checks call :func:`checkpoint`, which raises
:class:`~camcore.errors.WorkStoppedError` once the deadline has passed or the caller has
cancelled it (its client has gone). The deadline travels in a context variable, so it
follows the computation into the thread that runs it (``contextvars.copy_context``) and
costs nothing when no deadline is set. Between two checkpoints a computation runs on:
each checkpoint sits where at most one profile check or one solver step has run since
the last one.

References
----------
.. [1] Python documentation, ``contextvars`` (context variables, ``copy_context``).
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

from .errors import WorkStoppedError


class Deadline:
    """A point in time (monotonic clock) after which a computation stops, or earlier
    when :meth:`cancel` is called (from any thread)."""

    def __init__(self, seconds: float):
        self.seconds = seconds
        self.expires_at = time.monotonic() + seconds
        self.reason: str | None = None

    def cancel(self, reason: str) -> None:
        """Stop the computation at its next checkpoint, saying why."""
        self.reason = reason

    def check(self) -> None:
        """Raise WorkStoppedError when cancelled or past the deadline."""
        if self.reason is not None:
            raise WorkStoppedError(self.reason)
        if time.monotonic() > self.expires_at:
            raise WorkStoppedError(f"the computation ran past its deadline of {self.seconds:g} s and was stopped.")


_CURRENT: ContextVar[Deadline | None] = ContextVar("camcore_deadline", default=None)


def checkpoint() -> None:
    """Raise if the current computation's deadline has passed or it was cancelled.

    Returns
    -------
    None

    Raises
    ------
    WorkStoppedError
        Past the deadline of the enclosing :func:`running_until`, or cancelled.

    References
    ----------
    Python documentation, ``contextvars.ContextVar.get``.
    """
    deadline = _CURRENT.get()
    if deadline is not None:
        deadline.check()


@contextmanager
def running_until(deadline: Deadline) -> Iterator[Deadline]:
    """Run the body under ``deadline``: every :func:`checkpoint` inside it checks it.

    Parameters
    ----------
    deadline : Deadline
        When to stop (and the handle to cancel it).

    Returns
    -------
    contextmanager
        Yields the deadline.

    References
    ----------
    Python documentation, ``contextvars.ContextVar.set`` and ``reset``.
    """
    token = _CURRENT.set(deadline)
    try:
        yield deadline
    finally:
        _CURRENT.reset(token)
