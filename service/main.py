"""``service.main:app`` — the app with settings from the environment."""

from .app import create_app
from .settings import Settings

app = create_app(Settings())
