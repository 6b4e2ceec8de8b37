"""Makino's special curves designed from a target: curve 4 from its peak velocity Vm, curve 1
from its feed-speed ratio V7/V3 (Makino 1977, §5.1 and §5.3).

Curve 4 (break points 0, T1, T1, T3, 1 − T3, 1 − T1, 1 − T1, 1, equal areas) reaches Vm on
the constant-velocity stretch, so Vm = Amp·(C1 + C3) = Amp·2·T3/π. Its acceleration
stretch [0, T3] falls behind the constant speed Vm by D = ∫₀^T3 τ·A(τ) dτ, and the
deceleration by the same (symmetry), so 1 = Vm − 2D. With the quarter-sine integrals
∫₀^T1 τ·sin(πτ/2T1) dτ = 4T1²/π² and, with L = T3 − T1,
∫_T1^T3 τ·cos(π(τ − T1)/2L) dτ = 2L·T3/π − 4L²/π²:

    Vm = 1 / (1 − 2L − (4/π)(T1² − L²)/T3).

At T1 = k·T3 (L = (1 − k)·T3) this is Vm(T3) = 1/(1 − c·T3) with
c = 2(1 − k) + (4/π)(2k − 1) > 0 for 0 ≤ k ≤ 1 (linear in k, 2 − 4/π at k = 0, 4/π at
k = 1): Vm grows strictly with T3, from 1 (T3 → 0) to 1/(1 − c/2) at T3 = 0.5, and
1/Vm is linear in T3. So the target has exactly one T3, T3 = (1 − 1/Vm)/c, in closed
form: no root finding is needed (the tests check it against the built curve's Vm found
by its extrema, and every row of appendix 3-2).

References
----------
.. [1] Makino (1977), §5.1 (curve 4: "with T1 = 0.25·T3, T1 and T3 follow uniquely from
   Vm"), fig. 3 and appendix 3-2; §5.3, eq. (16) (curve 1: V7 = (1 − z)·V3).
"""

from __future__ import annotations

from collections.abc import Mapping

from .._checks import finite
from ..errors import InvalidParameterError
from .universal import PI

#: T1/T3 when curve 4 is designed from Vm and no ratio is given (Makino §5.1, the MCV family)
DEFAULT_T1_OVER_T3 = 0.25
#: curve 4's largest T3 (T4 = 1 − T3 ≥ T3)
MAX_T3 = 0.5


def curve_4_slope(t1_over_t3: float) -> float:
    """c of curve 4's Vm(T3) = 1/(1 − c·T3) at T1 = k·T3.

    Parameters
    ----------
    t1_over_t3 : float
        k = T1/T3, 0 < k ≤ 1 [-].

    Returns
    -------
    float
        c = 2(1 − k) + (4/π)(2k − 1) [-], between 2 − 4/π and 4/π.

    References
    ----------
    Makino (1977), §5.1 (curve 4); the module docstring derives it.
    """
    k = t1_over_t3
    return 2.0 * (1.0 - k) + 4.0 / PI * (2.0 * k - 1.0)


def curve_4_vm(t1: float, t3: float) -> float:
    """Curve 4's peak velocity Vm from its break points, in closed form.

    Parameters
    ----------
    t1, t3 : float
        Curve 4's T1 and T3, 0 < T1 ≤ T3 ≤ 0.5 [-].

    Returns
    -------
    float
        Vm = 1 / (1 − 2L − (4/π)(T1² − L²)/T3), L = T3 − T1 [-].

    References
    ----------
    Makino (1977), §5.1, fig. 3, appendix 3-2; the module docstring derives it.
    """
    lag = t3 - t1
    return 1.0 / (1.0 - 2.0 * lag - 4.0 / PI * (t1 * t1 - lag * lag) / t3)


def curve_4_vm_range(t1_over_t3: float) -> tuple[float, float]:
    """The peak velocities curve 4 can have at T1 = k·T3: (1, Vm at T3 = 0.5].

    Parameters
    ----------
    t1_over_t3 : float
        k = T1/T3, 0 < k ≤ 1 [-].

    Returns
    -------
    (float, float)
        1 (reached only as T3 → 0, not attained) and the largest Vm, 1/(1 − c/2) [-].

    References
    ----------
    Makino (1977), §5.1 (curve 4); the module docstring derives it.
    """
    return 1.0, 1.0 / (1.0 - curve_4_slope(t1_over_t3) * MAX_T3)


def curve_4_from_vm(vm: float, t1_over_t3: float = DEFAULT_T1_OVER_T3) -> tuple[float, float]:
    """Curve 4's T1 and T3 that give the peak velocity Vm with T1 = k·T3.

    Parameters
    ----------
    vm : float
        Target peak velocity, 1 < Vm ≤ Vm(T3 = 0.5) [-] (Vm = 1 is the constant-velocity
        limit T3 → 0).
    t1_over_t3 : float
        k = T1/T3, 0 < k ≤ 1 [-] (default 1/4, Makino's §5.1).

    Returns
    -------
    (float, float)
        T1 and T3 [-].

    Raises
    ------
    InvalidParameterError
        k outside (0, 1], or Vm outside the range attainable with that k (named in the message).

    Notes
    -----
    1/Vm = 1 − c·T3 is linear and strictly decreasing in T3 (c > 0), so the one solution
    is T3 = (1 − 1/Vm)/c.

    References
    ----------
    Makino (1977), §5.1 ("T1 and T3 follow uniquely from Vm"); the module docstring derives it.
    """
    vm = finite("vm", vm)
    k = finite("t1_over_t3", t1_over_t3)
    if not 0 < k <= 1:
        raise InvalidParameterError(f"t1_over_t3 must satisfy 0 < T1/T3 ≤ 1 (curve 4 needs 0 < T1 ≤ T3), got {k!r}.",
                                    field=("t1_over_t3",))
    low, high = curve_4_vm_range(k)
    if not low < vm <= high:
        raise InvalidParameterError(
            f"curve 4 with T1/T3 = {k:g} reaches 1 < Vm ≤ {high:.6g} (Vm → 1 as T3 → 0, the largest at T3 = 0.5); "
            f"vm = {vm!r} is out of reach.", field=("vm",))
    t3 = min((1.0 - 1.0 / vm) / curve_4_slope(k), MAX_T3)  # min: Vm = high may round T3 an ulp past 0.5
    return k * t3, t3


def rapid_feed_z(v_ratio: float) -> float:
    """Curve 1's z from the speed ratio V7/V3 = 1 − z (Makino eq. 16).

    Parameters
    ----------
    v_ratio : float
        V7/V3, the cutting-feed speed over the rapid-feed speed, 0 ≤ V7/V3 < 1 [-].

    Returns
    -------
    float
        z = 1 − V7/V3 [-].

    Raises
    ------
    InvalidParameterError
        V7/V3 outside [0, 1).

    References
    ----------
    Makino (1977), §5.3, eq. (16).
    """
    v_ratio = finite("v_ratio", v_ratio)
    if not 0 <= v_ratio < 1:
        raise InvalidParameterError(
            f"v_ratio = V7/V3 = 1 − z must satisfy 0 ≤ v_ratio < 1 (0 < z ≤ 1), got {v_ratio!r}.", field=("v_ratio",))
    return 1.0 - v_ratio


#: the target parameters each special curve may take instead of its own, and the own ones they replace
TARGETS: dict[int, tuple[tuple[str, ...], tuple[str, ...]]] = {4: (("vm", "t1_over_t3"), ("t1", "t3")),
                                                               1: (("v_ratio",), ("z",))}


def solve_targets(number: int, params: Mapping[str, float | None]) -> dict[str, float | None]:
    """Makino curve ``number``'s parameters with its targets replaced by the solved ones.

    Parameters
    ----------
    number : int
        Makino's classification number [-].
    params : mapping
        The parameters given [-] (None: not given); curve 4 may give ``vm`` (and
        ``t1_over_t3``) instead of ``t1``, ``t3``; curve 1 ``v_ratio`` instead of ``z``.

    Returns
    -------
    dict
        The parameters without the targets, with the solved ones (``t1``, ``t3``; ``z``).

    Raises
    ------
    InvalidParameterError
        A target given with the parameters it replaces, ``t1_over_t3`` without ``vm``, a
        target of another curve, or a target out of reach.

    References
    ----------
    Makino (1977), §5.1 and §5.3, eq. (16).
    """
    given = {k: v for k, v in params.items() if v is not None}
    out: dict[str, float | None] = dict(params)
    every_target = {name for targets, _ in TARGETS.values() for name in targets}
    targets, replaced = TARGETS.get(number, ((), ()))
    foreign = sorted(set(given) & (every_target - set(targets)))
    if foreign:
        raise InvalidParameterError(f"Makino curve {number} takes no target {', '.join(foreign)}.",
                                    field=(foreign[0],))
    for name in every_target:
        out.pop(name, None)
    if not set(given) & set(targets):
        return out
    if number == 4 and "vm" not in given:
        raise InvalidParameterError("t1_over_t3 goes with vm (curve 4 designed from its Vm).", field=("t1_over_t3",))
    both = sorted(set(given) & set(replaced))
    if both:
        raise InvalidParameterError(f"give {targets[0]} or {', '.join(replaced)}, not both: "
                                    f"{', '.join(replaced)} are solved from the target.", field=(both[0],))
    if number == 4:
        out["t1"], out["t3"] = curve_4_from_vm(given["vm"], given.get("t1_over_t3", DEFAULT_T1_OVER_T3))
    else:
        out["z"] = rapid_feed_z(given["v_ratio"])
    return out
