"""The roller-gear cam's faces as B-spline patches, fitted to the exact geometry within a tolerance
that is measured: the numbers the CAD kernel builds the cam's solid from
(:mod:`camcore.export.roller_gear_solid`).

The cam's dimensions (the tori of the rib's top and of the body, the body's length) are chosen in
:mod:`camcore.cams.roller_gear.body`.

The patches
-----------
Each flank is Q(θ, r) between its crossings of the two tori, r_top(θ) and r_root(θ) (Newton on d −
R along the roller, dr/dθ by implicit differentiation), parametrised by θ and s ∈ [0, 1], r = r_top
+ s·(r_root − r_top). Across (s) it is the polynomial through k Chebyshev–Lobatto points (a Bézier
span of degree k − 1); along θ the cubic Hermite interpolant of the exact points and their exact
θ-derivatives, Q_θ + Q_r·dr/dθ (knots doubled, C1; tripled, C0, at the index law's break points, where
a derivative may jump). The rib's top and the body's exposed root are patches on their tori, between
the flanks' boundary curves (which they share, pole for pole) and, for the root, the body's end circles:
the points at (ψ, χ) linear across from one boundary to the other (ψ the azimuth, χ = atan2(z, C − ρ)
the angle round the torus' tube), differentiated along θ by the chain rule. Their across polynomials
have the degree that keeps them within :data:`TORUS_FIT` of the torus's own path, so that the edges
the kernel cuts out of them meet the flanks' corners.

The θ nodes of each smooth piece of the turn start :data:`START_INTERVALS` apart and are multiplied
until every patch is within the target at the middle of every interval (the Hermite error's peak for
a slowly varying fourth derivative), measured against the exact flank at the same (θ, s) for a flank
and as the distance from its torus for the others.

References
----------
.. [1] L. Piegl, W. Tiller, "The NURBS Book", 2nd ed., Springer (1997), ch. 2-3 (B-spline curves and
   surfaces, knot multiplicity and continuity) and ch. 9 (interpolation).
.. [2] C. de Boor, "A Practical Guide to Splines", Springer (1978), ch. IV: the cubic Hermite
   interpolant's error, h⁴/384·max|f⁗|.
.. [3] J.-P. Berrut, L. N. Trefethen, "Barycentric Lagrange interpolation", SIAM Review 46 (2004):
   Chebyshev–Lobatto points and the barycentric formula.
.. [4] Litvin and Fuentes (2004), ch. 6 (the flank as an envelope: camcore.cams.roller_gear).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import partial

import numpy as np

from ..._solvers import newton_roots
from ...curves.base import FloatArray
from ...curves.jumps import acceleration_jumps
from ...deadline import checkpoint
from ...errors import GeometryError, LimitExceededError
from ..turret import turret_motion
from ._splines import (
    bernstein_poles,
    distance_gradient,
    hermite,
    hermite_poles,
    lagrange,
    lobatto,
    to_cam_frame,
    torus_coordinates,
    torus_distance,
    torus_points,
)
from .body import check_request, half_length
from .geometry import FLANKS, Flank, RollerGearCam, flank_state

#: the index's intervals before refinement (each piece of it at that spacing), and the dwell's
#: spacing before refinement [rad]: there the flank is a surface of revolution, whose Hermite error
#: is about ρ·h⁴/384 (4e-3 mm at ρ = 60 mm, h = π/8)
START_INTERVALS = 4
DWELL_SPACING = math.pi / 8
#: the share of the tolerance the θ interpolation may use at an interval's middle: the Hermite
#: error peaks there for a slowly varying fourth derivative; the rest is left for what lies
#: between the sampled points (measured by the tests with points drawn at random)
FIT_SHARE = 0.5
#: the share of the tolerance the flanks' across polynomial may use at the θ nodes
ACROSS_SHARE = 0.2
#: the torus patches' across polynomial, from its path, at most, relative to C: the kernel cuts the
#: rib's root edges out of them, and their ends must meet the flanks' corners within its
#: confusion (1e-7 mm) for the faces to share them
TORUS_FIT = 1e-10
#: the rib's edges must turn round the cam axis with the cam, dψ/dθ ≤ −this at every node (−1 in the
#: dwell), so the patches hung on them between nodes do not fold either
AZIMUTH_RATE = 0.05
#: the most points across a patch (degree 23: OpenCASCADE takes degree 25 at most)
MAX_ACROSS = 24
MIN_ACROSS = 4  # the fewest points across a flank
#: the root's crossing is looked for along the roller up to this share of the way to where its axis
#: meets the cam axis (r = C/cos α), where the contact's formula ends
REACH = 0.999
#: how far a piece's end nodes are moved into the piece for the index law's formulas [rad]: at a break
#: point the law evaluates its right-hand piece, and at θh still its last (the turret would not stand
#: in the dwell), where the acceleration may jump; the point moves by φ'·1e-13 rad, ~1e-11 mm
INSIDE = 1e-13

Band = str  # "forward", "back" (flanks), "top", "below", "above" (the tori)
BANDS, TORI = ("forward", "back", "top", "below", "above"), ("top", "below", "above")


@dataclass(frozen=True)
class Patch:
    """A non-rational tensor-product B-spline surface: u along the cam angle, v across."""

    band: Band
    part: str  # "index" or "dwell"
    poles: FloatArray  # (nu, nv, 3) [mm]
    u_knots: FloatArray  # [rad]
    u_mults: np.ndarray
    v_degree: int
    u_degree: int = 3  # cubic Hermite along the cam angle


@dataclass(frozen=True)
class RibSurfaces:
    """The cam's fitted faces and the dimensions they were fitted to (module notes)."""

    patches: tuple[Patch, ...]
    center_distance_mm: float
    top_radius_mm: float  # R_top: the rib's top torus
    root_radius_mm: float  # R_root: the body's torus
    half_length_mm: float  # H
    rib_half_extent_mm: float  # the rib's largest |z|
    fit_deviation_mm: float  # the largest deviation measured at the intervals' middles
    across_points: dict[Band, int]
    theta_nodes: int  # over the turn, breaks counted once

    @property
    def throat_radius_mm(self) -> float:
        """C − R_root: the body's smallest radius [mm]."""
        return self.center_distance_mm - self.root_radius_mm

    @property
    def end_radius_mm(self) -> float:
        """The body's radius at its ends, z = ±H [mm]."""
        return self.center_distance_mm - math.sqrt(self.root_radius_mm ** 2 - self.half_length_mm ** 2)


# ----------------------------------------------------------------------------- the flanks
@dataclass(frozen=True)
class _Rib:
    cam: RollerGearCam
    top_mm: float
    root_mm: float
    #: each flank's crossings at the cam angles asked for before (the fit asks again for the same nodes)
    known: dict[bytes, tuple[FloatArray, FloatArray]] = field(default_factory=dict, compare=False, repr=False)

    def turret(self, theta: FloatArray, side: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """φ, φ', φ'' at θ, moved by ``side``·INSIDE (+1 at a piece's start, −1 at its end, 0 inside)."""
        return turret_motion(self.cam.indexer, theta + side * INSIDE)

    def crossings(self, flank: Flank, theta: FloatArray, side: FloatArray) -> tuple[FloatArray, FloatArray]:
        """r where the flank crosses the rib's top and the body at each θ, shape (n, 2), and dr/dθ
        (module notes): the top's between the turret axis (r = 0: d ≤ Rr there) and the roller's
        middle, the root's between its middle and where its axis reaches the cam axis, all by one
        bracketed Newton."""
        key = flank.encode() + theta.tobytes() + side.tobytes()
        if key in self.known:
            return self.known[key]
        turret = self.turret(theta, side)
        c, n = self.cam.center_distance_mm, theta.size
        alpha = turret[0] - self.cam.behind_rad(flank)
        radius = np.repeat([self.top_mm, self.root_mm], n)  # lanes: the top's at each θ, then the root's
        at = np.tile(np.arange(n), 2)

        def value_and_slope(r: FloatArray, lane: np.ndarray) -> tuple[FloatArray, FloatArray]:
            s = flank_state(self.cam, flank, theta[at[lane]], r[:, None], tuple(x[at[lane]] for x in turret))
            gradient = distance_gradient(c, s.p[:, 0])
            return torus_distance(c, s.p[:, 0]) - radius[lane], np.einsum("...i,...i->...", gradient, s.q_r[:, 0])

        lanes = np.arange(2 * n)
        # the crossings lie at the ends of the roller or beyond (at them in the dwell, to rounding), so
        # each bracket starts from the roller's middle
        middle = np.full(n, self.cam.roller_pitch_radius_mm)
        lo, hi = np.concatenate([np.zeros(n), middle]), np.concatenate([middle, REACH * c / np.cos(alpha)])
        (f_lo, _), (f_hi, _) = value_and_slope(lo, lanes), value_and_slope(hi, lanes)
        if not ((f_lo <= 0) & (f_hi >= 0)).all():
            raise GeometryError(
                "The flanks do not reach the body: near the index's fastest point the pressure angle along the "
                "rollers (checks.max_pressure_angle_along_roller_deg) turns the contact round them and off towards "
                "the cam axis before it meets the body's surface; a longer indexing_angle_deg lowers it.",
                field=("indexing_angle_deg",))
        r = newton_roots(value_and_slope, lo, hi, f_lo, f_hi, lanes).reshape(2, n).T
        s = flank_state(self.cam, flank, theta, r, turret)
        gradient = distance_gradient(c, s.p)
        slope = -np.einsum("...i,...i->...", gradient, s.q_theta) / np.einsum("...i,...i->...", gradient, s.q_r)
        self.known[key] = (r, slope)
        return r, slope

    def flank(self, flank: Flank, theta: FloatArray, side: FloatArray, across: FloatArray
              ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Points (n, k, 3) and θ-derivatives of the flank between its crossings, at s = across,
        in the cam's frame, and the regularity there."""
        (top, root), (dtop, droot) = (x.T for x in self.crossings(flank, theta, side))
        r = top[:, None] + across[None, :] * (root - top)[:, None]
        dr = dtop[:, None] + across[None, :] * (droot - dtop)[:, None]
        s = flank_state(self.cam, flank, theta, r, self.turret(theta, side))
        derivative = to_cam_frame(theta, s.q_theta + s.q_r * dr[..., None])
        return s.q, derivative, s.regularity


# ----------------------------------------------------------------------------- one piece of the turn
Rows = dict[Band, tuple[FloatArray, FloatArray]]  # a band's points (n, k, 3) and θ-derivatives


@dataclass
class _Piece:
    """One smooth piece of the turn: its nodes and each band's exact rows there."""

    start: float
    end: float
    intervals: int
    rows: Rows | None = None
    regularity: float = 1.0
    z_extent: float = 0.0

    def nodes(self) -> tuple[FloatArray, FloatArray]:
        """The cam angles and the side each is evaluated from (the piece's own formulas at its ends)."""
        t = np.linspace(self.start, self.end, self.intervals + 1)
        side = np.zeros(t.size)
        side[0], side[-1] = 1.0, -1.0
        return t, side


def _flank_rows(rib: _Rib, t: FloatArray, side: FloatArray, across: FloatArray) -> tuple[Rows, float]:
    rows: Rows = {}
    regularity = math.inf
    for f in FLANKS:
        p, dp, reg = rib.flank(f, t, side, across)
        rows[f] = (p, dp)
        regularity = min(regularity, float(reg.min()))
    return rows, regularity


def _path(c_mm: float, radius_mm: float, t: FloatArray, start: tuple[FloatArray, ...], end: tuple[FloatArray, ...],
          across: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Points of the torus d = R linear in (ψ, χ) from ``start`` to ``end`` (ψ, χ, dψ/dθ, dχ/dθ at each θ)."""
    w = across[None, :]
    psi, chi, dpsi, dchi = (a[:, None] + w * (b - a)[:, None] for a, b in zip(start, end, strict=True))
    return torus_points(c_mm, radius_mm, psi, chi, dpsi, dchi)


def _torus_rows(rib: _Rib, t: FloatArray, flanks: Rows, across: Mapping[Band, FloatArray], half_mm: float,
                exact_ends: bool = True) -> Rows:
    """The rib's top and the body's root below and above the rib, from the flanks' boundary rows."""
    c = rib.cam.center_distance_mm
    ends = {}
    for f in FLANKS:
        p, dp = flanks[f]
        ends[f] = (torus_coordinates(c, t, p[:, 0], dp[:, 0]), torus_coordinates(c, t, p[:, -1], dp[:, -1]))
    lo, hi = math.asin(-half_mm / rib.root_mm), math.asin(half_mm / rib.root_mm)
    (b_psi, _, b_dpsi, _), (f_psi, _, f_dpsi, _) = ends["back"][1], ends["forward"][1]
    zero = np.zeros_like(t)
    rows = {
        "top": _path(c, rib.top_mm, t, ends["forward"][0], ends["back"][0], across["top"]),
        "below": _path(c, rib.root_mm, t, (b_psi, zero + lo, b_dpsi, zero), ends["back"][1], across["below"]),
        "above": _path(c, rib.root_mm, t, ends["forward"][1], (f_psi, zero + hi, f_dpsi, zero), across["above"]),
    }
    if exact_ends:  # the shared boundaries: the flanks' own rows, and the end planes, to the bit
        rows["below"][0][:, 0, 2], rows["above"][0][:, -1, 2] = -half_mm, half_mm  # not R·sin(asin(H/R))
        for band, column, flank, source in (("top", 0, "forward", 0), ("top", -1, "back", 0),
                                            ("below", -1, "back", -1), ("above", 0, "forward", -1)):
            for value, exact in zip(rows[band], flanks[flank], strict=True):
                value[:, column] = exact[:, source]
    return rows


def _middles(rows: Rows, t: FloatArray, band: Band, across: FloatArray, at: FloatArray) -> FloatArray:
    """A band's fitted surface at the middles of the θ intervals and at ``at`` across."""
    p, dp = rows[band]
    mid = 0.5 * (t[1:] + t[:-1])
    return np.einsum("aj,ijx->iax", lagrange(across, at), hermite(t, p, dp, mid))


def _across_test(across: FloatArray) -> FloatArray:
    """Where a band is checked across: its nodes and the middles between them."""
    return np.sort(np.concatenate([across, 0.5 * (across[1:] + across[:-1])]))


# ----------------------------------------------------------------------------- the fit
def _choose_across(error: Callable[[FloatArray], float], target: float, smallest: int, what: str) -> FloatArray:
    for k in range(smallest, MAX_ACROSS + 1):
        nodes = lobatto(k)
        if error(nodes) <= target:
            return nodes
    raise LimitExceededError(f"points across the {what}", MAX_ACROSS + 1, MAX_ACROSS, field=("solid", "tolerance_mm"))


def _pieces(cam: RollerGearCam) -> list[_Piece]:
    """The smooth pieces of the turn: the index split where the law's acceleration jumps (the flank's
    θ-derivative jumps there with β's), then the dwell; a jump of the jerk only (MS's break points)
    bends the flank's curvature, which the refinement follows."""
    curve = cam.indexer.curve
    index = math.radians(cam.indexer.indexing_angle_deg)
    inside = [j.t for j in acceleration_jumps(curve, 1.0) if curve.t_start < j.t < curve.t_end]
    breaks = index * (np.array([curve.t_start, *inside, curve.t_end]) - curve.t_start) / (curve.t_end - curve.t_start)
    spacing = index / START_INTERVALS
    pieces = [_Piece(float(a), float(b), max(2, math.ceil((b - a) / spacing)))
              for a, b in itertools.pairwise(breaks)]
    pieces.append(_Piece(index, 2 * math.pi, max(2, math.ceil((2 * math.pi - index) / DWELL_SPACING))))
    return pieces


MAX_THETA_NODES = 20_000  # θ nodes over the turn, at most, unless the caller says otherwise
#: how much an interval count grows at least and at most in one refinement: by the fourth root of
#: the deviation over the target (the Hermite error goes as h⁴), 15 % more
GROWTH = (1.25, 4.0)


def _flank_deviation(rib: _Rib, piece: _Piece, across: FloatArray) -> tuple[float, float]:
    """Fit the flanks on the piece's nodes; their largest deviation at the intervals' middles, and the
    part of it along θ alone (at the across nodes, where the across polynomial is exact) [mm]."""
    t, side = piece.nodes()
    rows, regularity = _flank_rows(rib, t, side, across)
    mid, test = 0.5 * (t[1:] + t[:-1]), _across_test(across)
    exact, between = _flank_rows(rib, mid, np.zeros(mid.size), test)
    piece.rows, piece.regularity = rows, min(regularity, between)
    piece.z_extent = max(float(np.abs(v[0][..., 2]).max()) for v in (*rows.values(), *exact.values()))
    error = [np.linalg.norm(_middles(rows, t, f, across, test) - exact[f][0], axis=-1) for f in FLANKS]
    return max(float(e.max()) for e in error), max(float(e[:, ::2].max()) for e in error)  # nodes: even columns


def _torus_deviation(rib: _Rib, piece: _Piece, across: Mapping[Band, FloatArray], half_mm: float) -> float:
    """Fit the tori's patches on the piece's nodes; their largest distance from their torus at the
    intervals' middles [mm]."""
    assert piece.rows is not None
    t, _ = piece.nodes()
    rows = _torus_rows(rib, t, piece.rows, across, half_mm)
    piece.rows = {**piece.rows, **rows}
    c, worst = rib.cam.center_distance_mm, 0.0
    for band, radius in (("top", rib.top_mm), ("below", rib.root_mm), ("above", rib.root_mm)):
        points = _middles(rows, t, band, across[band], _across_test(across[band]))
        worst = max(worst, float(np.abs(torus_distance(c, points) - radius).max()))
    return worst


def _probe(pieces: list[_Piece]) -> tuple[FloatArray, FloatArray]:
    t, side = zip(*(p.nodes() for p in pieces), strict=True)
    return np.concatenate(t), np.concatenate(side)


def fit_rib_surfaces(cam: RollerGearCam, tolerance_mm: float, root_clearance_mm: float = 0.0,
                     body_length_mm: float | None = None, max_theta_nodes: int = MAX_THETA_NODES) -> RibSurfaces:
    """The roller-gear cam's faces as B-spline patches within a tolerance of the exact flanks (module notes).

    Parameters
    ----------
    cam : RollerGearCam
        The cam (:func:`camcore.cams.roller_gear.make_roller_gear_cam`); its index law must start at rest.
    tolerance_mm : float
        The flanks' largest deviation from the exact flank [mm]: each patch is fitted to half of it at
        the middles of its intervals.
    root_clearance_mm : float
        How far the body's torus lies beyond the circle of the rollers' outer rims [mm].
    body_length_mm : float, optional
        The body's length along the cam axis; default the rib's extent plus half a roller radius at
        each end [mm].
    max_theta_nodes : int
        The most cam angles the patches may take over the turn [-].

    Returns
    -------
    RibSurfaces
        The patches (flanks, the rib's top, the body's root below and above the rib; index and dwell
        each), the tori's radii, the body's half length, the deviation measured.

    Raises
    ------
    InvalidParameterError
        A tolerance or clearance out of range, an index law not starting at rest, a body shorter
        than the rib.
    GeometryError
        A body without a throat, flanks that fold (undercut) or cross.
    LimitExceededError
        More cam angles than ``max_theta_nodes`` (field solid.tolerance_mm).

    References
    ----------
    Piegl and Tiller (1997), ch. 2, 3, 9; de Boor (1978), ch. IV; Berrut and Trefethen (2004).
    """
    top, root = check_request(cam, tolerance_mm, root_clearance_mm)
    rib, pieces, target = _Rib(cam, top, root), _pieces(cam), FIT_SHARE * tolerance_mm

    def refine(piece: _Piece, deviation: float) -> None:
        piece.intervals = math.ceil(piece.intervals * min(GROWTH[1], max(GROWTH[0], 1.15 * (deviation / target) ** 0.25)))
        checkpoint()  # one refinement at most between two checks
        if (count := sum(p.intervals for p in pieces) + 1) > max_theta_nodes:
            raise LimitExceededError("rib surface cam angles", count, max_theta_nodes, field=("solid", "tolerance_mm"))

    def fit_flanks(nodes: FloatArray) -> tuple[FloatArray, float]:
        """Every piece's flanks within the target: more cam angles where the error along θ is more than
        half of it, else more points across, every piece again (the across polynomial is shared)."""
        deviation, piece_index = 0.0, 0
        while piece_index < len(pieces):
            total, along = _flank_deviation(rib, pieces[piece_index], nodes)
            if total <= target:
                deviation, piece_index = max(deviation, total), piece_index + 1
            elif along > 0.5 * target:
                refine(pieces[piece_index], along)
            elif nodes.size < MAX_ACROSS:
                nodes, deviation, piece_index = lobatto(nodes.size + 1), 0.0, 0
                checkpoint()
            else:
                raise LimitExceededError("points across the flanks", MAX_ACROSS + 1, MAX_ACROSS,
                                         field=("solid", "tolerance_mm"))
        return nodes, deviation

    flank_across, deviation = fit_flanks(_choose_across(lambda nodes: _flank_across_error(rib, pieces, nodes),
                                                        ACROSS_SHARE * tolerance_mm, MIN_ACROSS, "flanks"))
    extent = max(p.z_extent for p in pieces)
    half = half_length(cam, root, extent, body_length_mm, tolerance_mm)
    across: dict[Band, FloatArray] = dict.fromkeys(FLANKS, flank_across)
    for band in TORI:
        across[band] = _choose_across(partial(_torus_across_error, rib, pieces, half, band),
                                      TORUS_FIT * cam.center_distance_mm, 2, f"{band} patch")
    while True:  # the tori's patches on the flanks' nodes, more where they need them, the flanks again
        torus_deviation, refined = 0.0, False
        for piece in pieces:
            while (d := _torus_deviation(rib, piece, across, half)) > target:
                refine(piece, d)
                _flank_deviation(rib, piece, flank_across)
                refined = True
            torus_deviation = max(torus_deviation, d)
        if not refined:
            break
        flank_across, deviation = fit_flanks(flank_across)
        across.update(dict.fromkeys(FLANKS, flank_across))
    deviation = max(deviation, torus_deviation)
    if max(p.z_extent for p in pieces) >= half:
        raise GeometryError("the rib reaches past the body's ends.", field=("solid", "body_length_mm"))
    _check_shape(rib, pieces)
    return RibSurfaces(_patches(pieces, across), cam.center_distance_mm, top, root, half, extent, deviation,
                       {band: int(nodes.size) for band, nodes in across.items()},
                       sum(p.intervals for p in pieces) + 1)


def _flank_across_error(rib: _Rib, pieces: list[_Piece], nodes: FloatArray) -> float:
    """The flanks' across polynomial through ``nodes`` at the middles between them, at every piece's
    starting nodes [mm]."""
    t, side = _probe(pieces)
    test = 0.5 * (nodes[1:] + nodes[:-1])
    rows, _ = _flank_rows(rib, t, side, nodes)
    exact, _ = _flank_rows(rib, t, side, test)
    basis = lagrange(nodes, test)
    return max(float(np.linalg.norm(np.einsum("aj,ijx->iax", basis, rows[f][0]) - exact[f][0], axis=-1).max())
               for f in FLANKS)


def _torus_across_error(rib: _Rib, pieces: list[_Piece], half_mm: float, band: Band, nodes: FloatArray) -> float:
    """A torus patch's across polynomial through ``nodes`` against its path, at every piece's nodes [mm]."""
    t = np.concatenate([p.nodes()[0] for p in pieces])
    flanks = {f: tuple(np.concatenate([p.rows[f][i] for p in pieces if p.rows]) for i in (0, 1)) for f in FLANKS}
    test = 0.5 * (nodes[1:] + nodes[:-1])
    fitted = _torus_rows(rib, t, flanks, dict.fromkeys(TORI, nodes), half_mm, exact_ends=False)[band][0]  # type: ignore[arg-type]
    exact = _torus_rows(rib, t, flanks, dict.fromkeys(TORI, test), half_mm, exact_ends=False)[band][0]  # type: ignore[arg-type]
    return float(np.linalg.norm(np.einsum("aj,ijx->iax", lagrange(nodes, test), fitted) - exact, axis=-1).max())


def _check_shape(rib: _Rib, pieces: list[_Piece]) -> None:
    """Refuse flanks that fold (undercut) or cross (no rib between them)."""
    c = rib.cam.center_distance_mm
    if min(p.regularity for p in pieces) <= 0:
        raise GeometryError(
            "The flanks fold (undercut, see checks.undercut): a rib the rollers cut into has no solid; a longer "
            "indexing_angle_deg or a smaller turret turn per index unfolds them.", field=("indexing_angle_deg",))
    for p in pieces:
        assert p.rows is not None
        chi = {f: np.arctan2(p.rows[f][0][..., 2], c - np.hypot(p.rows[f][0][..., 0], p.rows[f][0][..., 1]))
               for f in FLANKS}
        if not (chi["forward"] > chi["back"]).all():
            raise GeometryError("The flanks cross: the rollers leave no rib between them (roller_radius_mm too large "
                                "for the rollers' spacing).", field=("roller_radius_mm",))
        t, _ = p.nodes()
        for f in FLANKS:
            for column in (0, -1):  # the rib's edges on the tori: the top's and the body's patches hang on them
                turn = torus_coordinates(c, t, p.rows[f][0][:, column], p.rows[f][1][:, column])[2]
                if turn.max() > -AZIMUTH_RATE:
                    raise GeometryError(
                        "The rib's edge runs back round the cam axis: near the body's throat (radius "
                        f"{c - rib.root_mm:.6g} mm) the contact moves round the axis against the cam's turn, and the "
                        "body's surface beside the rib would fold; a larger center_distance_mm (a wider throat) or a "
                        "longer indexing_angle_deg avoids it.", field=("center_distance_mm",))


def _patches(pieces: list[_Piece], across: Mapping[Band, FloatArray]) -> tuple[Patch, ...]:
    """Each band's index and dwell patches: Hermite along θ, Bézier across."""
    parts = {"index": pieces[:-1], "dwell": pieces[-1:]}
    patches = []
    for band in BANDS:
        for part, members in parts.items():
            data = []
            for p in members:
                assert p.rows is not None
                t, _ = p.nodes()
                data.append((t, *p.rows[band]))
            poles, knots, mults = hermite_poles(data)
            patches.append(Patch(band, part, bernstein_poles(poles), knots, mults, across[band].size - 1))
    return tuple(patches)
