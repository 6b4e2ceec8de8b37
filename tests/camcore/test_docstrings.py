"""Every public function of camcore has a numpydoc docstring with units and sources.

Issue 14's gate "numpydoc with [units] and References on every public function of camcore",
as a test. The rules:

1. Which functions: every module-level function defined in camcore or a public module of it
   (``pkgutil.walk_packages`` over ``camcore.__path__``; a module whose dotted name has a
   part starting with ``_`` is private) whose name does not start with ``_``. A function
   re-exported elsewhere is checked once, in the module that defines it. New modules and
   functions are found by the walk, not listed here.
2. Each has a docstring with a summary line and these numpydoc sections (a title line
   underlined with dashes):

   - ``Parameters`` naming every parameter of the signature (``self``/``cls`` excepted;
     ``*args`` written ``*args``, ``**kwargs`` written ``**kwargs``), several may share an
     entry (``lo, hi : float``), and no entry names a parameter the signature lacks;
   - ``Returns`` unless the return annotation is ``None``;
   - ``References`` with at least one line of text.

3. Units: an entry of ``Parameters`` or ``Returns`` whose numpydoc type names a number
   (``float``, ``int``, ``array_like``, ``ndarray``, ``number``, ``complex``, with or without
   "optional", "sequence of", "or None", ...) carries its unit in square brackets in its
   type line or description: ``[mm]``, ``[deg]``, ``[rad]``, ``[s]``, ``[rpm]``, ``[N·m]``,
   ``[kg·m²]``, ``[kW]``, ``[arcsec]``, products and quotients of these (``[rad/s²]``,
   ``[mm/deg]``, ``[1/mm]``), or ``[-]`` for a dimensionless number (ratios, counts,
   indices, the dimensionless T, S, V, A, J of a curve). An entry that covers several
   quantities may list several: ``[arcsec, mm]``, ``[mm or deg]``. Entries whose type is an
   object (``Curve``, ``CamSpec``, ``callable``, ``mapping``, ``str``) or boolean (``bool``,
   ``ndarray of bool``) need no unit. A bracket that is not a unit (``[0, 1]``) does not count.
4. Methods: every public method and property defined on :class:`camcore.curves.curve.Curve`,
   :class:`camcore.indexer.kinematics.Indexer` and each follower class of
   :data:`camcore.profile.followers.FOLLOWERS` (with their camcore base classes) has a docstring
   of its own (an override documents what it does for its class; an inherited docstring does
   not count).

The checker itself is tested on small functions that break each rule, so a test here that
passes means the rules held, not that the checker saw nothing.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
from collections.abc import Callable, Iterator
from functools import cached_property
from types import ModuleType
from typing import Any

import camcore
from camcore.curves.curve import Curve
from camcore.indexer.kinematics import Indexer
from camcore.profile.followers import FOLLOWERS, FollowerModel

# ------------------------------------------------------------------------------ units
_ATOM = r"(?:mm|m|deg|rad|s|min|rpm|N|kg|kW|W|arcsec)"
_TERM = _ATOM + r"(?:[²³⁴]|\^-?\d+)?"
_PRODUCT = _TERM + r"(?:·" + _TERM + r")*"
_UNIT = r"(?:-|1/" + _PRODUCT + r"|" + _PRODUCT + r"(?:/" + _PRODUCT + r")?)"
#: a unit in brackets, or several separated by ", " or " or "
UNIT_IN_BRACKETS = re.compile(r"\[" + _UNIT + r"(?:(?:, | or )" + _UNIT + r")*\]")
#: a numpydoc type that names a number
NUMERIC_TYPE = re.compile(r"\b(?:floats?|ints?|integers?|array_like|ndarray|numbers?|complex)\b")
BOOLEAN_TYPE = re.compile(r"\bbool\b")

SECTION_UNDERLINE = re.compile(r"^-{3,}$")
METHOD_OWNERS: tuple[type, ...] = (Curve, Indexer, FollowerModel, *FOLLOWERS.values())


# ------------------------------------------------------------------------------ parsing
def sections(doc: str) -> dict[str, list[str]]:
    """numpydoc sections of a (dedented) docstring: title -> body lines."""
    lines = doc.splitlines()
    out: dict[str, list[str]] = {}
    title: str | None = None
    i = 0
    while i < len(lines):
        if i + 1 < len(lines) and lines[i].strip() and SECTION_UNDERLINE.match(lines[i + 1].strip()) \
                and not lines[i].startswith(" "):
            title = lines[i].strip()
            out[title] = []
            i += 2
            continue
        if title is not None:
            out[title].append(lines[i])
        i += 1
    return out


def entries(body: list[str]) -> list[tuple[str, str]]:
    """(header line, header and description joined) of each entry of a section."""
    out: list[tuple[str, str]] = []
    for line in body:
        if not line.strip():
            continue
        if not line.startswith(" "):
            out.append((line.strip(), line.strip()))
        elif out:
            header, text = out[-1]
            out[-1] = (header, text + " " + line.strip())
    return out


def _names_and_type(header: str, named: bool) -> tuple[list[str], str]:
    """The names and the type of an entry's header (``Returns`` entries may be a type only)."""
    if " : " in header:
        names, type_ = header.split(" : ", 1)
        return [n.strip() for n in names.split(",")], type_
    if header.endswith(" :"):
        return [n.strip() for n in header[:-2].split(",")], ""
    return ([n.strip() for n in header.split(",")], "") if named else ([], header)


def _unit_problems(section: str, body: list[str], named: bool) -> list[str]:
    problems = []
    for header, text in entries(body):
        names, type_ = _names_and_type(header, named)
        if NUMERIC_TYPE.search(type_) and not BOOLEAN_TYPE.search(type_) and not UNIT_IN_BRACKETS.search(text):
            what = ", ".join(names) if names else type_
            problems.append(f"{section} entry '{what}' ({type_}) has no unit in brackets ([mm], [deg], [-], ...)")
    return problems


def expected_parameters(func: Callable[..., Any]) -> list[str]:
    """The signature's parameters as a Parameters section names them."""
    out = []
    for p in inspect.signature(func).parameters.values():
        if p.name in ("self", "cls"):
            continue
        stars = {inspect.Parameter.VAR_POSITIONAL: "*", inspect.Parameter.VAR_KEYWORD: "**"}.get(p.kind, "")
        out.append(stars + p.name)
    return out


def returns_something(func: Callable[..., Any]) -> bool:
    annotation = inspect.signature(func).return_annotation
    return annotation not in (None, "None", type(None))


def function_problems(func: Callable[..., Any]) -> list[str]:
    """What the docstring of a public function lacks under rules 2 and 3 (empty: none)."""
    doc = inspect.getdoc(func)
    if not doc or not doc.strip():
        return ["no docstring"]
    problems = []
    secs = sections(doc)
    params = expected_parameters(func)
    if params:
        if "Parameters" not in secs:
            problems.append("no Parameters section")
        else:
            documented = [n for header, _ in entries(secs["Parameters"])
                          for n in _names_and_type(header, named=True)[0]]
            missing = [p for p in params if p not in documented]
            extra = [n for n in documented if n not in params]
            if missing:
                problems.append(f"Parameters lacks {', '.join(missing)}")
            if extra:
                problems.append(f"Parameters names {', '.join(extra)}, not in the signature")
            problems += _unit_problems("Parameters", secs["Parameters"], named=True)
    if returns_something(func):
        if "Returns" not in secs or not entries(secs["Returns"]):
            problems.append("no Returns section")
        else:
            problems += _unit_problems("Returns", secs["Returns"], named=False)
    if not any(line.strip() for line in secs.get("References", [])):
        problems.append("no References section")
    return problems


# ------------------------------------------------------------------------------ discovery
def public_modules() -> Iterator[ModuleType]:
    yield camcore
    for info in pkgutil.walk_packages(camcore.__path__, "camcore."):
        if any(part.startswith("_") for part in info.name.split(".")[1:]):
            continue
        yield importlib.import_module(info.name)


def public_functions() -> Iterator[tuple[str, Callable[..., Any]]]:
    """(dotted name, function) of every public module-level function camcore defines."""
    for module in public_modules():
        for name, obj in vars(module).items():
            if name.startswith("_"):
                continue
            func = inspect.unwrap(obj) if callable(obj) else obj  # see through functools wrappers
            if inspect.isfunction(func) and func.__module__ == module.__name__:
                yield f"{module.__name__}.{name}", func


def public_members(cls: type) -> Iterator[tuple[str, Any]]:
    """(qualified name, member) of the public methods and properties cls and its camcore bases define."""
    for owner in cls.__mro__:
        if not owner.__module__.startswith("camcore"):
            continue
        for name, member in vars(owner).items():
            if name.startswith("_"):
                continue
            if isinstance(member, staticmethod | classmethod):
                member = member.__func__
            if isinstance(member, property):
                member = member.fget
            elif isinstance(member, cached_property):
                member = member.func
            if inspect.isfunction(member):
                yield f"{owner.__module__}.{owner.__qualname__}.{name}", member


# ------------------------------------------------------------------------------ the gate
def test_public_modules_are_found() -> None:
    # the walk must reach every package of the library, or the gate checks nothing there
    names = {m.__name__ for m in public_modules()}
    for expected in ("camcore.export", "camcore.results", "camcore.curves.curve", "camcore.indexer.sizing",
                     "camcore.profile.followers"):
        assert expected in names
    assert "camcore" in names and not any(n.startswith("camcore._") for n in names)
    assert len(dict(public_functions())) >= 50


def test_every_public_function_has_numpydoc_with_units_and_references() -> None:
    offenders = {name: problems for name, func in public_functions() if (problems := function_problems(func))}
    report = "\n".join(f"{name}: {'; '.join(problems)}" for name, problems in sorted(offenders.items()))
    assert not offenders, f"{len(offenders)} public functions break the docstring rules:\n{report}"


def test_public_methods_of_curve_indexer_and_followers_have_docstrings() -> None:
    found: dict[str, Any] = {}
    for cls in METHOD_OWNERS:
        found.update(public_members(cls))
    assert "camcore.curves.curve.Curve.inverse" in found and "camcore.indexer.kinematics.Indexer.position" in found
    missing = sorted(name for name, member in found.items() if not (member.__doc__ or "").strip())
    assert not missing, f"{len(missing)} public methods without a docstring of their own:\n" + "\n".join(missing)


# ------------------------------------------------------------------------------ the checker can fail
def _complete(lift_mm: float, curve: object, *rest: float, **options: bool) -> float:
    """A complete docstring.

    Parameters
    ----------
    lift_mm : float
        A lift [mm].
    curve : Curve
        No unit: an object.
    *rest : float
        More values [-].
    **options : bool
        Switches.

    Returns
    -------
    float
        The result [mm].

    References
    ----------
    A source.
    """
    return lift_mm


def _no_references(angle_deg: float) -> float:
    """A summary.

    Parameters
    ----------
    angle_deg : float
        An angle [deg].

    Returns
    -------
    float
        The angle [deg].
    """
    return angle_deg


def _gaps(angle_deg: float, speed_rpm: float, rows: int) -> float:
    """A summary.

    Parameters
    ----------
    angle_deg : float
        An angle in [0, 360], which is a range, not a unit.
    rows : int
        A count without its unit.
    extra : float
        Not a parameter [mm].

    References
    ----------
    A source.
    """
    return angle_deg


def _unitless_result(x: float) -> float:
    """A summary.

    Parameters
    ----------
    x : float
        A length [mm].

    Returns
    -------
    float
        A length without its unit.

    References
    ----------
    A source.
    """
    return x


def _nothing_returned(x: float) -> None:
    """A summary.

    Parameters
    ----------
    x : float
        A ratio [-].

    References
    ----------
    A source.
    """


def test_checker_accepts_a_complete_docstring() -> None:
    assert function_problems(_complete) == []
    assert function_problems(_nothing_returned) == []  # None returned: no Returns section needed


def test_checker_names_what_is_missing() -> None:
    assert function_problems(_no_references) == ["no References section"]
    assert function_problems(lambda x: x) == ["no docstring"]
    problems = function_problems(_gaps)
    assert "Parameters lacks speed_rpm" in problems
    assert "Parameters names extra, not in the signature" in problems
    assert any("'angle_deg'" in p and "no unit" in p for p in problems)  # [0, 360] is no unit
    assert any("'rows'" in p and "no unit" in p for p in problems)
    assert "no Returns section" in problems
    assert function_problems(_unitless_result) == [
        "Returns entry 'float' (float) has no unit in brackets ([mm], [deg], [-], ...)"]


def test_unit_pattern() -> None:
    for good in ("[mm]", "[deg]", "[rad]", "[s]", "[rpm]", "[N·m]", "[kg·m²]", "[-]", "[rad/s²]", "[mm/deg³]",
                 "[1/mm]", "[arcsec, mm]", "[mm or deg]", "[kW]"):
        assert UNIT_IN_BRACKETS.fullmatch(good), good
    for bad in ("[0, 1]", "[T0, T7]", "[]", "[h, h', h'']", "[dimensionless]", "[mm, 1]"):
        assert not UNIT_IN_BRACKETS.fullmatch(bad), bad
