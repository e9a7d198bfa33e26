"""The catalogue of lecture systems: one module per system, each defining ``SYSTEM``.

A new system is one new module here; the catalogue, export, conformance tests and reports pick it up.
``HARNESS_MODELS_PATH`` (folders separated by ``os.pathsep``) adds folders searched after this one, so that a
system can live outside the repository; a module there cannot shadow a module here (the entry points refuse
one that tries: :func:`harness.catalogue.check_search_path`). The loader is
:class:`harness.catalogue.Catalogue` (a module that does not load is that module's failure, one line naming its
file); :data:`CATALOGUE` is this package's, and the functions below delegate to it.
"""

from harness.catalogue import MODELS_PATH_VARIABLE, Catalogue, search_path

__path__.extend(search_path())
CATALOGUE = Catalogue(__name__)
names, get, scenes, claims, failures, reload = (CATALOGUE.names, CATALOGUE.get, CATALOGUE.scenes, CATALOGUE.claims,
                                                CATALOGUE.failures, CATALOGUE.reload)
catalogue = CATALOGUE.systems
__all__ = ["CATALOGUE", "MODELS_PATH_VARIABLE", "catalogue", "claims", "failures", "get", "names", "reload", "scenes"]
