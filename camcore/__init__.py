"""camcore: cam motion curves, indexer sizing and plate-cam profiles (pure numpy).

Anyone can ``import camcore`` in a notebook or a batch job and get the numbers the
service gives.
"""

from .catalog import CATALOG, CatalogEntry, lookup, named_curve
from .curve import Characteristics, Curve, CurveValues, Extremum
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
from .polynomial import PolynomialCurve, named_polynomial, polynomial_from_boundary
from .transform import ReturnCurve
from .universal import UniversalCurve, makino_curve, universal_curve

__version__ = "0.1.0"

__all__ = [
    "CATALOG", "CamError", "CatalogEntry", "Characteristics", "Curve", "CurveValues",
    "DegenerateCurveError", "Extremum", "GeometryError", "InvalidBreakPointsError",
    "InvalidParameterError", "LimitExceededError", "NonMonotoneError", "PolynomialCurve",
    "ReturnCurve", "StrokeClosureError", "StrokeRangeError", "UniversalCurve",
    "UnknownCurveError", "lookup", "makino_curve", "named_curve", "named_polynomial",
    "polynomial_from_boundary", "universal_curve", "__version__",
]

from . import export, indexer, profile  # noqa: E402  (subpackages: indexer sizing, plate-cam profiles)
from .indexer import Indexer, Load, LoadPart, accuracy_mm, size  # noqa: E402

__all__ += ["Indexer", "Load", "LoadPart", "accuracy_mm", "export", "indexer", "profile", "size"]
