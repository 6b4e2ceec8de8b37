"""Cam motion curves: the laws, their evaluation, characteristic values and inverses.

Map: :mod:`.base` evaluates pieces, :mod:`.extrema` finds characteristic values,
:mod:`.inverse` and :mod:`.stroke` invert S → T, :mod:`.curve` joins them in
:class:`Curve`; one module per law (:mod:`.sections` and :mod:`.universal` for Makino's
universal curve, :mod:`.polynomial`, :mod:`.bezier`, :mod:`.points`, :mod:`.reverse`);
:mod:`.catalog` names the standard curves and :mod:`.kinds` builds any curve spec.
"""

from .base import CurveValues, PiecewiseCurve, Scale
from .bezier import BezierCurve
from .catalog import CATALOG, CatalogEntry, lookup, named_curve
from .curve import Curve
from .extrema import Characteristics
from .kinds import CURVE_KINDS, CurveKind, Law, build_curve
from .makino import MAKINO_SPECIAL, makino_curve
from .points import PointsCurve
from .polynomial import PolynomialCurve, named_polynomial, polynomial_from_boundary
from .reverse import ReturnCurve
from .universal import UniversalCurve, universal_curve

__all__ = [
    "CATALOG",
    "CURVE_KINDS",
    "MAKINO_SPECIAL",
    "BezierCurve",
    "CatalogEntry",
    "Characteristics",
    "Curve",
    "CurveKind",
    "CurveValues",
    "Law",
    "PiecewiseCurve",
    "PointsCurve",
    "PolynomialCurve",
    "ReturnCurve",
    "Scale",
    "UniversalCurve",
    "build_curve",
    "lookup",
    "makino_curve",
    "named_curve",
    "named_polynomial",
    "polynomial_from_boundary",
    "universal_curve",
]
