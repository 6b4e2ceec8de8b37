"""The camcore HTTP service (FastAPI), a thin layer over the ``camcore`` library."""

from .app import create_app
from .settings import Settings

__all__ = ["Settings", "create_app"]
