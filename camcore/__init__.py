"""camcore: cam motion curves, indexer sizing and plate-cam profiles (pure numpy).

Anyone can ``import camcore`` in a notebook or a batch job and get the numbers the
service gives. The packages: :mod:`camcore.curves` (motion laws, characteristic values,
inverses, the catalog), :mod:`camcore.indexer` (cam indexers), :mod:`camcore.profile`
(plate cams), :mod:`camcore.dynamics` (residual vibration of followers and indexer loads),
:mod:`camcore.export` (contour files); results become plain data through :mod:`camcore.results`.
"""

from . import curves, dynamics, export, indexer, profile
from .curves import (
    CATALOG,
    CURVE_KINDS,
    CatalogEntry,
    Characteristics,
    Curve,
    CurveValues,
    PolynomialCurve,
    ReturnCurve,
    UniversalCurve,
    build_curve,
    lookup,
    makino_curve,
    named_curve,
    named_polynomial,
    polynomial_from_boundary,
    universal_curve,
)
from .errors import (
    CamError,
    DegenerateCurveError,
    GeometryError,
    InvalidBreakPointsError,
    InvalidParameterError,
    LimitExceededError,
    NonMonotoneError,
    StrokeClosureError,
    StrokeRangeError,
    UnknownCurveError,
)
from .indexer import Indexer, Load, LoadPart, accuracy_mm, size
from .results import Extremum, as_dict

__version__ = "0.1.0"

__all__ = [
    "CATALOG", "CURVE_KINDS", "CamError", "CatalogEntry", "Characteristics", "Curve", "CurveValues",
    "DegenerateCurveError", "Extremum", "GeometryError", "Indexer", "InvalidBreakPointsError",
    "InvalidParameterError", "LimitExceededError", "Load", "LoadPart", "NonMonotoneError", "PolynomialCurve",
    "ReturnCurve", "StrokeClosureError", "StrokeRangeError", "UniversalCurve", "UnknownCurveError", "__version__",
    "accuracy_mm", "as_dict", "build_curve", "curves", "dynamics", "export", "indexer", "lookup", "makino_curve",
    "named_curve", "named_polynomial", "polynomial_from_boundary", "profile", "size", "universal_curve",
]
