"""Answer schemas derived from camcore's result classes (one definition per concept).

camcore defines each result once, as a dataclass whose fields carry units in their names
and descriptions in their metadata; :func:`answer_model` turns one into the Pydantic
model the route declares, with exactly the fields :func:`camcore.results.as_dict`
produces. A field is required unless the result class gives it a default (it may then be
``None``); arrays become lists of numbers.
"""

from __future__ import annotations

import dataclasses
import functools
import operator
import typing
from typing import Any

from pydantic import BaseModel, Field, create_model

from camcore.results import answer_fields
from service.specs import DeferredModel


def answer_model(result_class: type, name: str, doc: str | None = None) -> type[BaseModel]:
    """The Pydantic answer model of a camcore result dataclass.

    Parameters
    ----------
    result_class : type
        A camcore result dataclass.
    name : str
        The schema's name in the OpenAPI document (stable: generated clients use it).
    doc : str, optional
        The schema's description (default: the result class's docstring).
    """
    fields: dict[str, Any] = {}
    for field_name, hint, description, required in answer_fields(result_class):
        hint = _nested(hint, name)
        fields[field_name] = (hint, Field(description=description) if required else Field(None, description=description))
    model = create_model(name, __base__=DeferredModel, __doc__=doc or result_class.__doc__, **fields)
    model.__module__ = __name__
    return model


def _nested(hint: Any, outer: str) -> Any:
    """A nested result class becomes its own answer model (named after the outer one's
    field type: ``TorqueTable`` in ``SizingAnswer`` is ``TorqueTableAnswer``); ``X | None`` stays optional."""
    if dataclasses.is_dataclass(hint) and isinstance(hint, type):
        return answer_model(hint, f"{hint.__name__}Answer")
    args = typing.get_args(hint)
    if typing.get_origin(hint) is list and args:
        return list[_nested(args[0], outer)]  # type: ignore[misc]
    if args and any(dataclasses.is_dataclass(a) for a in args):
        return functools.reduce(operator.or_, (_nested(a, outer) for a in args))
    return hint
