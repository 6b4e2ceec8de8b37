"""``service.main:app`` — the app with settings from the environment.

Start-up makes some 150 000 objects (modules, model classes, schemas, routes) that all live as long
as the app: the cyclic garbage collector is held off while they are made (each of its passes would
only find them alive) and then told to leave them out of its later passes (:func:`gc.freeze`), so a
worker starts sooner and its later collections walk only what requests make.
"""

import gc

gc.disable()
try:
    from service.app import create_app
    from service.settings import Settings

    app = create_app(Settings())
finally:
    gc.freeze()
    gc.enable()
