"""Input checks shared by the core and the service's specs (one rule, one place).

Each check returns the cleaned value or raises :class:`InvalidParameterError` with a
sentence that names the field and the rule. The error is a ``ValueError``, so the
service's Pydantic validators can call these checks directly and answer 422 with the
same sentence the library gives.
"""

from __future__ import annotations

import math
from typing import Any

from .errors import InvalidParameterError


def finite(name: str, value: Any) -> float:
    """``value`` as a finite float, or an error naming ``name``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"{name} must be a number, not {value!r}.") from None
    if not math.isfinite(x):
        raise InvalidParameterError(f"{name} must be a finite number, not {x!r}.")
    return x


def positive(name: str, value: Any) -> float:
    """A finite float > 0."""
    x = finite(name, value)
    if not x > 0:
        raise InvalidParameterError(f"{name} must be greater than 0, got {x!r}.")
    return x


def non_negative(name: str, value: Any) -> float:
    """A finite float ≥ 0."""
    x = finite(name, value)
    if x < 0:
        raise InvalidParameterError(f"{name} must be 0 or more, got {x!r}.")
    return x


def count(name: str, value: Any) -> int:
    """A whole number ≥ 1 (booleans refused)."""
    if isinstance(value, bool):
        raise InvalidParameterError(f"{name} must be a whole number ≥ 1, not {value!r}.")
    x = finite(name, value)
    if not x.is_integer() or x < 1:
        raise InvalidParameterError(f"{name} must be a whole number ≥ 1, got {value!r}.")
    return int(x)


def one_of(names: tuple[str, str], values: tuple[Any, Any], why: str) -> None:
    """Exactly one of two alternative fields is given (``why`` says what each means)."""
    if (values[0] is None) == (values[1] is None):
        raise InvalidParameterError(f"give exactly one of {names[0]} and {names[1]} ({why}).")
