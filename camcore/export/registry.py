"""One entry of a download registry: a format's name, writer, media type, file name, cost.

Each kind of thing the library writes has a registry of its formats (:mod:`camcore.export`):
a contour, a solid, a toolpath, a motion table. The service reads its ``?format=`` values,
answer headers and OpenAPI media types from them, so a new format is one entry.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

T = TypeVar("T")


@dataclass(frozen=True)
class FileFormat(Generic[T]):
    """One download format: one entry of a registry.

    Attributes
    ----------
    name : str
        The format's name (the service's ``?format=`` value).
    media_type : str
        Its media (MIME) type, with the charset of a text format.
    file_name : str
        The file name a download suggests.
    description : str
        One line for users: what the file holds and what reads it.
    write : callable
        ``write(item) -> bytes``: the file's content.
    cost : callable
        ``cost(size) -> seconds``: the time to write an item of that size (contour points,
        toolpath elements, table rows: the registry says) on camcore.work's reference
        machine (an upper estimate).
    """

    name: str
    media_type: str
    file_name: str
    description: str
    write: Callable[[T], bytes]
    cost: Callable[[int], float]

    @property
    def is_text(self) -> bool:
        """Whether the file is text for every reader (``text/*``)."""
        return self.media_type.startswith("text/")
