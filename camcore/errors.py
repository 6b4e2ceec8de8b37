"""Errors raised by camcore.

One base class, small subclasses, each with a one-line docstring. The service maps
these types to HTTP status codes in one table; the core never knows about HTTP.
Messages are sentences a machine designer understands.
"""

from __future__ import annotations


class CamError(Exception):
    """Base class of every error camcore raises on purpose.

    ``field`` names what the error is about, when the raiser knows: a path into the
    arguments of the call that raised it, such as ``("s", 3)`` for the fourth value of
    ``s``; empty when the error concerns the call as a whole. A caller may prefix it
    with where those arguments came from (the service maps it to a request field).
    """

    field: tuple[str | int, ...] = ()

    def __init__(self, *args: object, field: tuple[str | int, ...] = ()):
        super().__init__(*args)
        self.field = tuple(field)


class InvalidParameterError(CamError, ValueError):
    """A parameter is outside its range of validity."""


class InvalidBreakPointsError(InvalidParameterError):
    """The universal curve's break points T0..T7 are not in order or not finite."""


class StrokeClosureError(InvalidParameterError):
    """No acceleration amplitude or ratio m closes the stroke with the given ends."""


class StrokeRangeError(InvalidParameterError):
    """A displacement S asked of an inverse lookup lies outside the curve's stroke."""


class NonMonotoneError(InvalidParameterError):
    """The operation needs a monotone displacement and the curve or data are not."""


class DegenerateCurveError(InvalidParameterError):
    """User control points or measured points do not define a usable lift curve."""


class UnknownCurveError(CamError, LookupError):
    """No curve in the catalog has this name, alias or Makino number."""

    def __init__(self, name: str, suggestions: list[str]):
        self.name = name
        self.suggestions = suggestions
        hint = f" Did you mean: {', '.join(suggestions)}?" if suggestions else ""
        super().__init__(f"No curve named '{name}' in the catalog.{hint}", field=("name",))


class GeometryError(InvalidParameterError):
    """A cam or follower geometry that cannot be assembled or cannot run."""


class LimitExceededError(CamError):
    """The requested work is larger than a configured limit."""

    def __init__(self, what: str, requested: float, limit: float, field: tuple[str | int, ...] = ()):
        self.what = what
        self.requested = requested
        self.limit = limit
        shown = str(requested) if abs(requested) < 10**18 else "more than 10^18"
        super().__init__(f"{what} is {shown}, over the limit of {limit}.", field=field)


class WorkLimitError(LimitExceededError):
    """The estimated work of a request is over the work budget; the message says what
    drives it (``field``) so the caller knows what to reduce."""

    def __init__(self, seconds: float, budget_s: float, largest: str, field: tuple[str | int, ...] = ()):
        LimitExceededError.__init__(self, "estimated work [s]", round(seconds, 3), budget_s, field=field)
        message = (f"the estimated work of this request is {seconds:.3g} s, over the budget of {budget_s:g} s; "
                   f"most of it is {largest}: reduce that.")
        self.args = (message,)


class NonFiniteResultError(CamError):
    """A computation produced NaN or infinity for these inputs."""


class WorkStoppedError(CamError):
    """A computation was stopped before its end: past its deadline, or its caller left."""
