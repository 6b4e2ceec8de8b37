"""One way for every result to become plain data.

Core results are frozen dataclasses whose fields carry their unit in the name and a
description in their metadata (``field(metadata=doc(...))``). The service
serves them as they are: it derives its answer schemas from :func:`answer_fields` and
its answers from :func:`as_dict`, so a result is defined once.

An :class:`Extremum` field ``x`` becomes two plain fields, ``x`` (the value) and
``t_x`` (where it occurs); arrays and tuples become lists; numpy scalars become Python
numbers; nested result dataclasses become nested dicts.
"""

from __future__ import annotations

import dataclasses
import functools
import operator
import types
import typing
from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Extremum:
    """A peak value and the T where it first occurs."""

    value: float
    t: float


def doc(text: str, name: str | None = None) -> dict[str, str]:
    """Field metadata with a description for the answer schema:
    ``name: float = field(metadata=doc("..."))``.

    Parameters
    ----------
    text : str
        The field's description, with its unit in brackets where it has one.
    name : str, optional
        The field's name in the answer when it cannot be the attribute's (a Python keyword:
        ``from_`` answers as ``from``).

    Returns
    -------
    dict of str to str
        ``{"description": text}`` (and ``"name"``), read back by :func:`answer_fields`.

    References
    ----------
    docs/architecture.md, one model per concept (core results are the models the service serves).
    """
    return {"description": text} if name is None else {"description": text, "name": name}


def _key(f: dataclasses.Field[Any]) -> str:
    """A field's name in the answer (see :func:`doc`)."""
    return str(f.metadata.get("name", f.name))


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, tuple | list):
        return [_plain(v) for v in value]
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return as_dict(value)
    return value


def as_dict(result: Any) -> dict[str, Any]:
    """A result dataclass as JSON-ready plain values (see the module docstring).

    Parameters
    ----------
    result : dataclass instance
        A core result (fields with ``metadata={"internal": True}`` are left out).

    Returns
    -------
    dict of str to Any
        Field name to plain value: an :class:`Extremum` ``x`` becomes ``x`` and ``t_x``,
        arrays and tuples become lists, numpy scalars Python numbers, nested results dicts.

    References
    ----------
    docs/architecture.md, one model per concept (core results are the models the service serves).
    """
    out: dict[str, Any] = {}
    for f in dataclasses.fields(result):
        if f.metadata.get("internal"):
            continue
        value = getattr(result, f.name)
        if isinstance(value, Extremum):
            out[_key(f)] = float(value.value)
            out[f"t_{_key(f)}"] = float(value.t)
        else:
            out[_key(f)] = _plain(value)
    return out


def table_columns(result: Any) -> dict[str, Any]:
    """The array fields of a table result, by name (internal fields left out).

    Parameters
    ----------
    result : dataclass instance
        A table result (its fields are the table's columns).

    Returns
    -------
    dict of str to Any
        Field name to value, as stored (arrays stay arrays), in field order.

    References
    ----------
    docs/architecture.md, one model per concept (core results are the models the service serves).
    """
    return {f.name: getattr(result, f.name) for f in dataclasses.fields(result)
            if not f.metadata.get("internal")}


def answer_fields(cls: type) -> list[tuple[str, Any, str | None, bool]]:
    """(name, Python type, description, required) of each plain field of a result class.

    The types are the dataclass's own annotations with :class:`Extremum` expanded into
    two floats and tuples into lists: what :func:`as_dict` produces.

    Parameters
    ----------
    cls : type
        A result dataclass.

    Returns
    -------
    list of tuple
        (name, Python type, description or None, required) per plain field, in the order
        :func:`as_dict` writes them.

    References
    ----------
    docs/architecture.md, one model per concept (core results are the models the service serves).
    """
    hints = typing.get_type_hints(cls)
    out: list[tuple[str, Any, str | None, bool]] = []
    for f in dataclasses.fields(cls):
        if f.metadata.get("internal"):
            continue
        hint = hints[f.name]
        text = f.metadata.get("description")
        required = f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
        if hint is Extremum:
            out.append((_key(f), float, text, required))
            out.append((f"t_{_key(f)}", float, f"where {_key(f)} occurs" if text is None else f"where it occurs: {text}",
                        required))
            continue
        out.append((_key(f), _listify(hint), text, required))
    return out


def _listify(hint: Any) -> Any:
    origin = typing.get_origin(hint)
    if origin is np.ndarray:
        # NDArray[np.bool_] → booleans, NDArray[np.intp] → integers, any other array → numbers
        scalar = typing.get_args(typing.get_args(hint)[1])[0] if len(typing.get_args(hint)) == 2 else None
        if scalar is np.bool_:
            return list[bool]
        if isinstance(scalar, type) and issubclass(scalar, np.integer):
            return list[int]
        return list[float]
    if origin is tuple:
        args = [a for a in typing.get_args(hint) if a is not Ellipsis]
        return list[args[0]] if args else list[Any]  # type: ignore[valid-type]
    if origin in (typing.Union, types.UnionType):
        return functools.reduce(operator.or_, (_listify(a) for a in typing.get_args(hint)))
    return hint
