"""Operations declared once, and the routes made from them (service.operations.factory)."""

from service.operations.answers import Answer, Document, Payload, Raw, Table, Text, respond
from service.operations.formats import JSON, PNG, PNG_DRAWING, SVG, SVG_DRAWING, TEXT, Format, csv, download
from service.operations.operation import Alias, Operation

__all__ = [
    "JSON",
    "PNG",
    "PNG_DRAWING",
    "SVG",
    "SVG_DRAWING",
    "TEXT",
    "Alias",
    "Answer",
    "Document",
    "Format",
    "Operation",
    "Payload",
    "Raw",
    "Table",
    "Text",
    "csv",
    "download",
    "respond",
]
