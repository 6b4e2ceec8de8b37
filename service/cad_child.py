"""The CAD kernel's process (issue 34): ``python -m service.cad_child FD``, started by
:mod:`service.cad_pool`, never imported by a worker.

It loads the OpenCASCADE bindings, says ``ready`` on the connection it was handed (file
descriptor ``FD``), then writes one solid per message it receives, ``(format, KernelSolid,
deadline_s)``, answering ``("ok", bytes)`` or ``("error", module, class, args, attributes)``
for an exception (camcore's errors do not unpickle by themselves: their ``__init__`` takes
other arguments than their ``args``). It exits when the connection closes. Its imports are
camcore's and the kernel's only: the service's web stack stays out of its memory.
"""

from __future__ import annotations

import sys
from multiprocessing.connection import Connection
from typing import Any


def serve(conn: Connection) -> None:
    from camcore.deadline import Deadline, running_until
    from camcore.export import SOLID_FORMATS
    from camcore.export.solid import load_kernel

    load_kernel()
    conn.send(("ready",))
    while True:
        try:
            message: Any = conn.recv()
        except EOFError:
            return
        fmt, solid, deadline_s = message
        try:
            with running_until(Deadline(deadline_s)):
                conn.send(("ok", SOLID_FORMATS[fmt].write(solid)))
        except Exception as exc:  # noqa: BLE001  # every failure goes back to the worker, which raises it
            try:
                conn.send(("error", type(exc).__module__, type(exc).__qualname__, exc.args, dict(vars(exc))))
            except Exception:  # noqa: BLE001  # an exception that does not pickle: its text
                conn.send(("error", "builtins", "RuntimeError", (f"{type(exc).__name__}: {exc}",), {}))


if __name__ == "__main__":
    serve(Connection(int(sys.argv[1])))
