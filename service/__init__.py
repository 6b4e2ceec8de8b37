"""The camcore HTTP service (FastAPI), a thin layer over the ``camcore`` library.

``service.app.create_app`` builds the app and ``service.main:app`` is the served one; this
package imports neither, so ``python -m service`` (the parent of the workers) starts without
importing the app it does not serve.
"""
