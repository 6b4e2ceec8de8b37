"""The camcore HTTP service (FastAPI), a thin layer over the ``camcore`` library."""

from service.app import create_app
from service.settings import Settings

__all__ = ["Settings", "create_app"]
