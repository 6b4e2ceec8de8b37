"""What every answer carries on the wire, from the app or from the connection itself.

Kept apart from the app's modules: the protocol (service.protocol) answers at the door before any
app exists, and ``python -m service``, the parent of several workers, imports it without importing
the app (FastAPI, numpy, camcore) it does not serve.
"""

from __future__ import annotations

#: on every answer: browsers must not guess a type other than the one declared (an SVG plot,
#: a CSV table, an error body)
SECURITY_HEADERS: list[tuple[bytes, bytes]] = [(b"x-content-type-options", b"nosniff")]
#: seconds a client is told to wait (``Retry-After``) after a 503
RETRY_AFTER_S = 1
