"""Which passages near a band's edge the plate tracer minimises exactly (camcore.cams.parallel.trace).

A passage whose sampled distance is near Rr is minimised between its neighbouring samples by Newton,
unless the distance's Lipschitz bound ((d_a + d_b − s)/2 between two samples an arc s apart: it
changes no faster than the path moves) keeps it above Rr − ε. Checked two ways:

* every passage the bound lets through has its exact minimum (Newton, crossings.distance_minima) at
  Rr − ε or more: the bound never decides otherwise than the minimum would;
* the plates traced with the bound and without it (every edge passage minimised) have the same free
  points and the same contours, bit for bit.

The passages themselves (neighbours.Chains: groups of centres along each chain ruled out by their
balls) are checked against a brute-force table of every query against every centre, and a point's
free state as the walk asks it (Newton spared once a sampled centre covers the point) against the
covered test that minimises every edge passage.
"""

from __future__ import annotations

import numpy as np
import pytest

from camcore.cams.parallel import ParallelCam, make_parallel_cam
from camcore.cams.parallel.crossings import distance_minima
from camcore.cams.parallel.neighbours import GROUP, QUERY_BLOCK, Chains
from camcore.cams.parallel.trace import PlateSamples, trace_plate

#: the README's cam, an 8-stop cam with two rollers a plate, and a 6-stop cam of two plates
#: (stops, C, Rp, Rr, θh, curve, plates, rollers per plate)
CAMS = [(4, 100.0, 60.0, 12.0, 120.0, "MS", 3, None), (4, 100.0, 60.0, 8.0, 120.0, "MT", 2, 8),
        (6, 100.0, 50.0, 8.0, 90.0, "asymmetric-cycloid", 2, None)]


def _cam(spec: tuple) -> ParallelCam:  # type: ignore[type-arg]
    *geometry, plates, rollers = spec
    return make_parallel_cam(*geometry, plates=plates, rollers_per_plate=rollers)


@pytest.mark.parametrize("spec", CAMS, ids=["readme", "8-rollers", "6-stops"])
def test_a_passage_the_bound_lets_through_stays_free_at_its_exact_minimum(spec):
    cam = _cam(spec)
    s = PlateSamples(cam, 0, 722)
    assert s.arc_to_next is not None  # these paths turn by hundredths of a radian a step
    rr = cam.roller_radius_mm
    # every envelope point of the plate, against every passage within reach
    side, chain, j = (a.reshape(-1) for a in np.indices(s.env.x.shape))
    qx, qy = s.env.x[side, chain, j], s.env.y[side, chain, j]
    qi, c, dist, tau = s.passages(qx, qy, chain * s.length + j)
    # the passages the bound decided: their distance is still the sampled one (not minimised)
    samples_tau = s.tau[np.rint(tau / s.step).astype(np.intp) % s.length]
    edge = dist >= rr - s.eps
    sampled = edge & (tau == samples_tau)
    let_through = sampled & ~s._may_dip(qx[qi], qy[qi], c, np.rint(tau / s.step).astype(np.intp) % s.length, dist)
    assert let_through.sum() > 100  # the bound decides many passages on these cams
    exact, _ = distance_minima(cam, s.alpha0[c[let_through]], qx[qi[let_through]], qy[qi[let_through]],
                               tau[let_through], tau[let_through] - s.step, tau[let_through] + s.step)
    assert np.all(exact >= rr - s.eps)


@pytest.mark.parametrize("spec", CAMS, ids=["readme", "8-rollers", "6-stops"])
def test_the_plates_are_the_same_with_and_without_the_bound(spec, monkeypatch):
    cam = _cam(spec)
    with_bound = [trace_plate(cam, p, 722) for p in range(cam.plates)]
    init = PlateSamples.__init__

    def without_bound(self, *args):  # type: ignore[no-untyped-def]
        init(self, *args)
        self.arc_to_next = None

    monkeypatch.setattr(PlateSamples, "__init__", without_bound)
    for (contour, s), (contour0, s0) in zip(with_bound, (trace_plate(cam, p, 722) for p in range(cam.plates))):
        assert s0.arc_to_next is None
        assert contour.pieces == contour0.pieces  # the same floats: dataclass equality compares them exactly
        assert np.array_equal(s.free, s0.free)


def _brute_minima(qx, qy, x, y, length, reach):  # type: ignore[no-untyped-def]
    """Every (query, point, d²) with d² < reach² and d² no more than its neighbours' along its chain."""
    d2 = (x[None, :] - qx[:, None]) ** 2 + (y[None, :] - qy[:, None]) ** 2
    chains = x.size // length
    rows = d2.reshape(qx.size, chains, length)
    padded = np.pad(rows, ((0, 0), (0, 0), (1, 1)), constant_values=np.inf)  # a chain's ends: one neighbour
    keep = (rows < reach * reach) & (rows <= padded[:, :, :-2]) & (rows <= padded[:, :, 2:])
    q, c, j = np.nonzero(keep)
    return {(int(a), int(b * length + k), float(rows[a, b, k])) for a, b, k in zip(q, c, j)}


def test_the_chains_nearest_passes_are_the_brute_force_ones():
    rng = np.random.default_rng(7)
    length, chains = 5 * GROUP + 3, 3  # a short group at each chain's end
    # wavy loops of uneven spacing, so groups differ in size and some are near every query block
    t = np.sort(rng.uniform(0, 2 * np.pi, (chains, length)), axis=1)
    r = 40 + 8 * np.sin(5 * t) + np.arange(chains)[:, None] * 3
    x, y = (r * np.cos(t)).reshape(-1), (r * np.sin(t)).reshape(-1)
    qx, qy = rng.uniform(-55, 55, 2 * QUERY_BLOCK + 17), rng.uniform(-55, 55, 2 * QUERY_BLOCK + 17)
    reach = 9.0
    qi, m, d2 = Chains(x, y, length, reach).minima(qx, qy)
    found = {(int(a), int(b), float(c)) for a, b, c in zip(qi, m, d2)}
    assert len(found) == qi.size  # no pair twice
    expected = _brute_minima(qx, qy, x, y, length, reach)
    assert len(expected) > 300  # many queries have passes within reach, some several
    assert found == expected  # the same pairs and the same squared distances, bit for bit
    # one query: its passes in the order of the centres (the walk's exits take the first of equals)
    one_i, one_m, _ = Chains(x, y, length, 30.0).minima(qx[:1], qy[:1])
    assert one_m.size > 1 and np.all(np.diff(one_m) > 0) and np.all(one_i == 0)


@pytest.mark.parametrize("spec", CAMS, ids=["readme", "8-rollers", "6-stops"])
def test_the_walks_free_points_are_the_fully_minimised_ones(spec):
    cam = _cam(spec)
    s = PlateSamples(cam, 0, 722)
    side, chain, j = (a.reshape(-1) for a in np.indices(s.env.x.shape))
    for row in range(2):  # every point as the walk asks it: Newton spared where a sampled centre covers
        for c in range(s.alpha0.size):
            s.is_free(row, c, np.arange(s.length))
    covered = s.covered(s.env.x[side, chain, j], s.env.y[side, chain, j], chain * s.length + j)
    assert 0 < covered.sum() < covered.size
    assert np.array_equal(s.free.reshape(-1) == 0, covered)
