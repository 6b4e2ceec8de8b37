"""A plate's exact contour: the pieces of its rollers' envelopes that bound it round the cam axis.

The plate is what its rollers leave of the plane about the cam axis: the part, holding the axis,
that no roller covers at any cam angle. Its contour is made of stretches of the rollers'
envelopes (:mod:`.envelope`): an envelope point lies on the contour where no roller at any cam
angle comes nearer to it than its radius (it is *free*), and a stretch ends where it enters
another roller's band — at the crossing of the two envelopes, a corner of the plate — or, where
two rollers share a circle (the dwell: one roller handing over to the next), anywhere the two
run together.

The method, per plate:

1. Every roller's envelope, both sides, at the sampled cam angles (``samples`` per turn; one
   roller followed over ``stops`` turns is a chain that closes, :mod:`.envelope`); the roller
   centres at those angles cut into groups of neighbours along each chain (:mod:`.neighbours`).
2. Whether a point is free, asked only of the points the walk passes: every passage of a roller
   within Rr + (the centres' spacing) of it is found through the groups; a passage whose nearest
   sampled centre is nearer than Rr − ε covers it; one whose nearest sampled centre is no
   nearer than that has its distance minimised exactly between its neighbouring samples (Newton
   on the cam angle, exact derivatives of the path), so a point is free exactly, not only at
   the samples. Newton is spared where the distance's Lipschitz bound already keeps the passage
   out: between two samples an arc s apart it cannot fall below (d_a + d_b − s)/2, and where
   another passage's sampled centre already covers the point.
3. The walk starts at the envelope point nearest the axis that is free (nothing lies nearer the
   axis than the plate's contour, so it is on it) and goes along its envelope the way that keeps
   the plate on its left (counter-clockwise round the axis: along the tangent on side +1, against
   it on side −1), free point after free point. Where the next point is covered, the crossing of
   this envelope with the covering roller's is solved by Newton on both cam angles (2 × 2, exact
   tangents) between the two points, and the walk goes on along the other envelope from there;
   where the two envelopes run together there is no single crossing, and the hand-over is at
   the last free point (Newton stops on the common stretch, or the point's foot on the other
   envelope, at most ε away).
4. The walk ends when it comes to a stretch it has walked: that loop is the contour.

References
----------
.. [1] R. T. Farouki, C. A. Neff, "Analytic properties of plane offset curves", Computer Aided
   Geometric Design 7 (1990) 83-99 (the envelope of a moving circle, its cusps).
.. [2] J. Nocedal, S. J. Wright, *Numerical Optimization*, 2nd ed. (2006), ch. 11 (Newton's
   method for nonlinear equations).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ...curves.base import FloatArray
from ...deadline import checkpoint
from ...errors import GeometryError
from .crossings import COVER_SHARE, bracketed_crossings, crossings, distance_minima, feet
from .envelope import EnvelopePoints, EnvelopeTrack, both_sides, centres, envelope, track
from .geometry import ParallelCam
from .neighbours import Chains

#: a crossing is a corner of the plate when the two envelopes' tangents differ by more than this
#: (a hand-over where two envelopes run together is none: there they part by less than 2ε)
CORNER_RAD = 1e-6
#: the walk asks this many points ahead at a time at first, doubling up to the most
FIRST_CHUNK, MOST_CHUNK = 32, 256
#: a path's length between two samples over their chord, at most, where the path turns by no more
#: than MOST_TURN_RAD between them (a circular arc turning by φ is (φ/2)/sin(φ/2) its chord: 1.0102
#: at 0.49 rad); the traced paths turn by hundredths of a radian a step, and a path that all but stops
#: (a cusp, its tangent turned round) is not bounded so
ARC_OVER_CHORD = 1.0102
MOST_TURN_RAD = 0.49


class TooCoarse(GeometryError):
    """The sampled cam angles are too far apart to follow the contour here (a roller's path that
    all but stops, its envelope sweeping round the roller within one step): trace it finer."""


@dataclass(frozen=True)
class Piece:
    """One stretch of the contour: a roller's envelope between two of its cam angles.

    ``roller``: the roller (its index in the plate's layer at τ = 0) and ``alpha0_rad`` its arm
    angle at τ = 0; ``side``: ±1 (:mod:`.envelope`); the contour runs from ``tau_start_rad`` to
    ``tau_end_rad`` (increasing on side +1, decreasing on side −1; τ is the roller's own cam
    angle, any real value); ``corner``: the piece begins at a corner of the plate (a crossing with
    the piece before it), not where two envelopes run together.
    """

    roller: int
    alpha0_rad: float
    side: int
    tau_start_rad: float
    tau_end_rad: float
    corner: bool


@dataclass(frozen=True)
class PlateContour:
    """A plate's exact contour: its pieces in order, counter-clockwise round the cam axis."""

    cam: ParallelCam
    plate: int
    pieces: tuple[Piece, ...]

    def at(self, piece: int, tau: FloatArray) -> EnvelopePoints:
        """The contour's points on one piece at its cam angles τ [rad]."""
        p = self.pieces[piece]
        return envelope(self.cam, p.alpha0_rad, float(p.side), np.asarray(tau, dtype=np.float64))


@dataclass(frozen=True)
class _Exit:
    """Where the walk leaves an envelope (its cam angle there) and goes on: the next envelope's
    (side row, chain), its cam angle there, and whether the two meet at a corner."""

    tau: float
    row: tuple[int, int]
    entry: float
    corner: bool


class PlateSamples:
    """Every roller envelope of a plate at the sampled cam angles, and which points are free.

    Arrays have the shape (2, chains, L): row 0 is side −1, row 1 side +1; chain c is roller c of
    the layer followed over ``stops`` turns; sample j of a chain is its cam angle τ = j·Δ
    (Δ = 2π/samples), the layer's roller c + ⌊j/samples⌋·(rollers per plate / stops) at the cam
    angle θ = τ mod 2π. ``free`` holds −1 where not yet asked, 0 covered, 1 free
    (:meth:`is_free` asks).

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    plate : int
        0 … plates − 1 [-].
    samples : int
        Cam angles per turn [-].
    """

    def __init__(self, cam: ParallelCam, plate: int, samples: int):
        self.cam, self.plate, self.samples = cam, plate, samples
        chains = cam.rollers_per_plate // cam.stops
        self.alpha0 = cam.start_angles(plate)[:chains]
        self.step = 2 * math.pi / samples
        self.length = cam.stops * samples
        self.tau: FloatArray = np.arange(self.length, dtype=np.float64) * self.step
        self.env = both_sides(cam, self.alpha0[:, None], self.tau[None, :])
        self.free = np.full(self.env.x.shape, -1, dtype=np.int8)
        px, py = self.env.px[0], self.env.py[0]
        self.px, self.py = px.reshape(-1), py.reshape(-1)
        rr = cam.roller_radius_mm
        self.eps = COVER_SHARE * cam.center_distance_mm
        spacing = np.hypot(np.roll(px, -1, axis=1) - px, np.roll(py, -1, axis=1) - py)
        # a path comes nearer than Rr between two samples only if a sample is within Rr + spacing
        self.reach = rr + float(spacing.max()) + self.eps
        self.chains = Chains(self.px, self.py, self.length, self.reach)
        # the path's length from each sample to the next, at most (None: a path turns too far within a
        # step to bound it by its chord, and every passage near the band's edge is minimised)
        tx, ty = self.env.tx[0], self.env.ty[0]
        turn = np.arctan2(tx * np.roll(ty, -1, axis=1) - ty * np.roll(tx, -1, axis=1),
                          tx * np.roll(tx, -1, axis=1) + ty * np.roll(ty, -1, axis=1))
        self.arc_to_next: FloatArray | None = (spacing.reshape(-1) * ARC_OVER_CHORD
                                               if float(np.abs(turn).max()) <= MOST_TURN_RAD else None)

    def roller(self, chain: NDArray[np.intp] | int, j: NDArray[np.intp] | int) -> NDArray[np.intp]:
        """The layer's roller at sample j of a chain [-]."""
        g = self.alpha0.size
        return np.asarray((np.asarray(chain) + (np.asarray(j) // self.samples) * g) % self.cam.rollers_per_plate,
                          dtype=np.intp)

    def passages(self, qx: FloatArray, qy: FloatArray, own: NDArray[np.intp] | None, settle: bool = True
                 ) -> tuple[NDArray[np.intp], NDArray[np.intp], FloatArray, FloatArray]:
        """Each passage of a roller within reach of each point: (point, chain, least distance [mm], its τ
        [rad]). ``own`` (chain·L + j of each point, or None) is the point's own roller position, whose
        passage touches it at Rr and is left out. ``settle=False`` leaves the sampled distances of a point's
        passages once one of its sampled centres covers it (enough to tell whether it is covered)."""
        rr = self.cam.roller_radius_mm
        qi, flat, d2 = self.chains.minima(qx, qy)
        if own is not None:
            mine = flat == own[qi]
            qi, flat, d2 = qi[~mine], flat[~mine], d2[~mine]
        dist: FloatArray = np.sqrt(d2)
        chain, j = np.divmod(flat, self.length)
        tau: FloatArray = self.tau[j]
        # deep inside a band the sample tells; near its edge, the exact minimum between the samples
        edge = dist >= rr - self.eps
        if not settle:
            hit = np.zeros(qx.shape, dtype=bool)
            hit[qi[~edge]] = True
            edge &= ~hit[qi]
        if edge.any() and self.arc_to_next is not None:
            edge[edge] = self._may_dip(qx[qi[edge]], qy[qi[edge]], chain[edge], j[edge], dist[edge])
        if edge.any():
            t: FloatArray = tau[edge]
            dmin, tmin = distance_minima(self.cam, self.alpha0[chain[edge]], qx[qi[edge]], qy[qi[edge]], t,
                                          t - self.step, t + self.step)
            better = dmin < dist[edge]
            dist[np.flatnonzero(edge)[better]] = dmin[better]
            tau = tau.copy()
            tau[np.flatnonzero(edge)[better]] = tmin[better]
        return qi, chain, dist, tau

    def _may_dip(self, qx: FloatArray, qy: FloatArray, chain: NDArray[np.intp], j: NDArray[np.intp],
                 dist: FloatArray) -> NDArray[np.bool_]:
        """Whether each passage's path may come nearer than Rr − ε to its point between the samples
        either side of its nearest one: the distance changes no faster than the path moves, so between
        two samples d_a, d_b an arc s apart it stays above (d_a + d_b − s)/2 (the same passages as the
        exact minimum finds above Rr − ε stay free; only the others are minimised)."""
        assert self.arc_to_next is not None
        length = self.length
        here = chain * length + j
        before = chain * length + (j - 1) % length  # a chain closes after L samples
        after = chain * length + (j + 1) % length
        d_before = np.hypot(self.px[before] - qx, self.py[before] - qy)
        d_after = np.hypot(self.px[after] - qx, self.py[after] - qy)
        low = np.minimum(d_before + dist - self.arc_to_next[before], dist + d_after - self.arc_to_next[here]) * 0.5
        return low < self.cam.roller_radius_mm - self.eps

    def covered(self, qx: FloatArray, qy: FloatArray, own: NDArray[np.intp] | None, settle: bool = True
                ) -> NDArray[np.bool_]:
        """Whether a roller comes nearer than Rr − ε to each point [-] (``settle``: :meth:`passages`)."""
        qi, _c, d, _t = self.passages(qx, qy, own, settle)
        out = np.zeros(qx.shape, dtype=bool)
        out[qi[d < self.cam.roller_radius_mm - self.eps]] = True
        return out

    def is_free(self, side: int, chain: int, j: NDArray[np.intp]) -> NDArray[np.bool_]:
        """Whether the points j (any integers: a chain closes after L) of a row are free, asked once."""
        jj = np.asarray(j) % self.length
        state = self.free[side, chain, jj]
        ask = np.flatnonzero(state < 0)
        if ask.size:
            q = jj[ask]
            hit = self.covered(self.env.x[side, chain, q], self.env.y[side, chain, q], chain * self.length + q,
                               settle=False)
            state = state.copy()
            state[ask] = np.where(hit, 0, 1)
            self.free[side, chain, q] = state[ask]
        return state == 1


def _travel(e: EnvelopePoints | EnvelopeTrack, i: int, sign: int) -> tuple[float, float]:
    """The unit direction the walk runs along envelope point i."""
    s = sign * (1.0 if float(e.stretch[i]) >= 0 else -1.0)
    return s * float(e.tx[i]), s * float(e.ty[i])


class _Walk:
    """The walk round a plate (module notes, steps 3 and 4)."""

    def __init__(self, s: PlateSamples):
        self.s = s
        self.exits: dict[tuple[int, int, float, int, int], _Exit] = {}
        self.reach = GeometryError(
            f"Plate {s.plate} reaches the turret's axis (center_distance_mm {s.cam.center_distance_mm!r}): its "
            "rollers leave the cam room past the turret's shaft; fewer stops or more rollers per plate bring them "
            "round to the cam.")

    def start(self) -> tuple[int, int, int]:
        """The free sample nearest the axis: (side row, chain, j)."""
        s = self.s
        order = np.argsort(np.hypot(s.env.x, s.env.y).reshape(-1))
        for b in range(0, order.size, FIRST_CHUNK):
            side, chain, j = np.unravel_index(order[b:b + FIRST_CHUNK], s.free.shape)
            for k in range(j.size):
                if s.is_free(int(side[k]), int(chain[k]), np.array([j[k]]))[0]:
                    return int(side[k]), int(chain[k]), int(j[k])
        raise self.reach

    def last_free(self, side: int, chain: int, first: int, sign: int) -> int | None:
        """From sample ``first``, the last of the free ones that run from it the walk's way (an integer
        past the chain's ends if need be): ``first − sign`` when ``first`` itself is covered; None: free
        all the way round."""
        s = self.s
        done, size = 0, FIRST_CHUNK
        while done < s.length:
            ks = first + sign * (done + np.arange(min(size, s.length - done)))
            ok = s.is_free(side, chain, ks)
            if not ok.all():
                return int(ks[int(np.argmin(ok))] - sign)
            done += ks.size
            size = min(2 * size, MOST_CHUNK)
        return None

    def exit(self, side: int, chain: int, t_last: float, q: int, sign: int) -> _Exit:
        """Where the walk leaves a row between its last free cam angle ``t_last`` and the covered
        sample ``q`` after it, and where it goes on (solved once: the walk's last exit is its first)."""
        key = (side, chain, t_last, q, sign)
        if key not in self.exits:
            self.exits[key] = self._exit(side, chain, t_last, q, sign)
        return self.exits[key]

    def _exit(self, side: int, chain: int, t_last: float, q: int, sign: int) -> _Exit:
        s, cam = self.s, self.s.cam
        t_covered = q * s.step
        q = q % s.length
        qx, qy = s.env.x[side, chain, q:q + 1], s.env.y[side, chain, q:q + 1]
        _qi, c, d, u0 = s.passages(qx, qy, np.array([chain * s.length + q]))
        hit = d < cam.roller_radius_mm - s.eps
        c, u0 = c[hit], u0[hit]
        if c.size == 0:  # covered, yet no passage within reach: cannot be (ε is below the reach)
            raise TooCoarse(f"Plate {s.plate}: its contour could not be followed past a covered point.")
        # the side of the covering roller's band the walk enters: where the point lies from its path
        px, py, p1x, p1y, *_ = centres(cam, s.alpha0[c], u0)
        side_b = np.where((qx[0] - px) * (-p1y) + (qy[0] - py) * p1x > 0, 1.0, -1.0)
        n = c.size
        a_side = 1.0 if side == 1 else -1.0
        # where the two envelopes run together the walk hands over at its last free point, to that
        # point's foot on the other envelope
        here = track(cam, s.alpha0[chain], a_side, np.array([t_last]))
        x, y = float(here.x[0]), float(here.y[0])
        found = feet(cam, s.alpha0[c], side_b, x, y, u0, s.step)
        crossing = not np.isfinite(found).any()
        if not crossing:
            k = int(np.argmax(np.isfinite(found)))
            t_out, u_in = t_last, float(found[k])
        else:  # else they cross between the last free point and the first covered one
            lo, hi = min(t_last, t_covered), max(t_last, t_covered)
            alpha = np.concatenate([np.full(n, s.alpha0[chain]), s.alpha0[c]])
            sides = np.concatenate([np.full(n, a_side), side_b])
            ok, t, u = crossings(cam, alpha, sides, np.full(n, 0.5 * (t_last + t_covered)), np.full(n, lo),
                                 np.full(n, hi), u0, s.step)
            if not ok.any():  # nearly parallel: the crossing by a bracketed root of the depth
                ok, t, u = bracketed_crossings(cam, s.alpha0[chain], a_side, t_last, t_covered, s.alpha0[c], u0,
                                               s.step)
            if not ok.any():
                raise TooCoarse(f"Plate {s.plate}: two rollers' envelopes neither cross nor run together where "
                                    "one leaves the contour; sample the turn more finely.")
            k = int(np.argmin(np.where(ok, sign * (t - t_last), np.inf)))
            t_out, u_in = float(t[k]), float(u[k])
        b_row, b_chain = (1 if side_b[k] > 0 else 0), int(c[k])
        ends = track(cam, np.array([s.alpha0[chain], s.alpha0[b_chain]]), np.array([a_side, float(side_b[k])]),
                     np.array([t_out, u_in]))
        ta, tb = _travel(ends, 0, sign), _travel(ends, 1, 1 if b_row == 1 else -1)
        turn = math.atan2(ta[0] * tb[1] - ta[1] * tb[0], ta[0] * tb[0] + ta[1] * tb[1])
        return _Exit(t_out, (b_row, b_chain), u_in, crossing and abs(turn) > CORNER_RAD)

    def pieces(self) -> list[Piece]:
        """The contour's pieces, from the free sample nearest the axis round to where the walk
        comes back."""
        s = self.s
        side, chain, j = self.start()
        sign = 1 if side == 1 else -1
        last = self.last_free(side, chain, j, sign)
        if last is None:  # one envelope, free all the way round
            return [Piece(int(s.roller(chain, 0)), float(s.alpha0[chain]), sign, 0.0, sign * s.length * s.step,
                          False)]
        out = self.exit(side, chain, last * s.step, last + sign, sign)
        pieces: list[Piece] = []
        seen: dict[tuple[int, int, int], int] = {}
        for _ in range(2 * s.free.size):
            checkpoint()
            b_side, b_chain = out.row
            b_sign = 1 if b_side == 1 else -1
            u = out.entry
            first = (math.floor(u / s.step) + 1) if b_sign > 0 else (math.ceil(u / s.step) - 1)
            last = self.last_free(b_side, b_chain, first, b_sign)
            if last is None:
                raise TooCoarse(f"Plate {s.plate}: its contour could not be followed round the cam axis.")
            if last == first - b_sign:  # a piece shorter than a sample step: it leaves before the next sample
                nxt = self.exit(b_side, b_chain, u, first, b_sign)
            else:
                nxt = self.exit(b_side, b_chain, last * s.step, last + b_sign, b_sign)
            key = (b_side, b_chain, last % s.length)
            pieces.append(Piece(int(s.roller(b_chain, 0)), float(s.alpha0[b_chain]), b_sign, u, nxt.tau, out.corner))
            if key in seen:
                return pieces[seen[key] + 1:]
            seen[key] = len(pieces) - 1
            out = nxt
        raise TooCoarse(f"Plate {s.plate}: its contour could not be followed round the cam axis.")


def trace_plate(cam: ParallelCam, plate: int, samples: int) -> tuple[PlateContour, PlateSamples]:
    """A plate's exact contour and its rollers' envelope samples.

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    plate : int
        0 … plates − 1 [-].
    samples : int
        Cam angles per turn at which the envelopes are sampled [-].

    Returns
    -------
    (PlateContour, PlateSamples)
        The contour (pieces, counter-clockwise round the axis) and the samples (points, free or not).

    Raises
    ------
    GeometryError
        The rollers sweep over the cam axis, or the plate reaches the turret's axis.
    TooCoarse
        The sampled cam angles are too far apart to follow the contour somewhere.

    References
    ----------
    Module notes; Farouki and Neff (1990), offset curves.
    """
    s = PlateSamples(cam, plate, samples)
    if s.covered(np.zeros(1), np.zeros(1), None)[0]:
        raise GeometryError(f"The rollers of plate {plate} sweep over the cam axis: nothing is left of the plate.")
    return PlateContour(cam, plate, tuple(_Walk(s).pieces())), s
