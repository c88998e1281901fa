"""Scenes: a file or a dictionary in any scene form, validated by the Rust library."""

import json as _json
import math as _math

from . import _rattle


def _plain(value):
    """JSON for numpy scalars and arrays inside a scene dictionary."""
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"{type(value).__name__} is not a JSON value")


def _finite_copy(value, path, non_finite, lists=False):
    """``value`` with each non-finite float replaced by 1.0 (JSON has no NaN), its path and
    value appended to ``non_finite``: the scene is validated with them put back. With
    ``lists`` (a scene in the structure form), inside lists too (``structure.bodies[0].mass``).
    """
    if isinstance(value, dict):
        return {
            k: _finite_copy(v, f"{path}.{k}" if path else str(k), non_finite, lists)
            for k, v in value.items()
        }
    if lists and isinstance(value, list):
        return [_finite_copy(v, f"{path}[{i}]", non_finite, lists) for i, v in enumerate(value)]
    if isinstance(value, float) and not _math.isfinite(value):
        non_finite.append((path, value))
        return 1.0
    return value


class Scene:
    """A scene: one unit or a chain of cells (the unit form), or a structure of bodies,
    springs, dashpots and stops (the structure form).

    Build it with :meth:`from_file`, :meth:`from_dict` or :meth:`paper`; it is validated on
    construction and immutable. The format is the command's scene file, in either form. The
    unit form::

        {"name": "paper",
         "unit": {"outer_mass": 2.0, "inner_mass": 1.0,
                  "outer_stiffness": 6.0, "inner_stiffness": 3.0},
         "base": {"amplitude": 1.0},
         "stops": {"gap": 0.5, "restitution": 0.8},
         "damping": {"outer": 0.0, "inner": 0.0}}

    ``unit`` and ``base`` are required, ``stops`` and ``damping`` optional (``cells`` or
    ``chain`` make a chain); unknown fields are refused. A base motion may carry harmonics,
    ``"base": {"amplitude": 0.9, "harmonics": [{"order": 2, "amplitude": 0.3, "phase": 0.5}]}``
    (orders 2 to 16; ``docs/scenes.md``): such a scene runs as its structure (bodies
    ``outer``, ``inner``; in a chain ``outer0``, ``inner0``, …) and its :attr:`form` is
    ``"structure"``. Forces of a structure take ``harmonics`` likewise. A document with a ``structure`` field
    is in the structure form (``docs/structure.md``)::

        {"name": "impact-oscillator",
         "structure": {"bodies": [{"name": "x", "mass": 1.0}],
                       "springs": [{"between": ["frame", "x"], "stiffness": 1.0}],
                       "dashpots": [{"between": ["frame", "x"], "damping": 0.1}],
                       "stops": [{"between": ["frame", "x"], "gap_plus": 0.5,
                                  "restitution": 0.8}]},
         "forcing": {"forces": [{"on": "x", "amplitude": 1.0, "phase": 0.0}]},
         "observe": "x"}

    :attr:`form` says which (``"cells"`` or ``"structure"``). A structure is taken by every
    function as the command takes one, but :func:`orbit` without a signature refuses it with a
    :class:`ValueError` naming the function, and :func:`map` without ``x`` and ``y`` asks for
    them.
    """

    __slots__ = ("_native",)

    def __init__(self, native):
        """Wraps a native scene; use the ``from_*`` constructors instead."""
        if not isinstance(native, _rattle.NativeScene):
            raise TypeError("use Scene.from_file, Scene.from_dict or Scene.paper")
        self._native = native

    @classmethod
    def from_file(cls, path):
        """Reads and validates the scene file at ``path`` (JSON, in either form), as
        ``rattle … PATH`` does.

        Raises :class:`FileNotFoundError`/:class:`OSError` when the file cannot be read and
        :class:`ValueError` when it is not a valid scene (the command's message: file, field
        path and allowed range).
        """
        return cls(_rattle.NativeScene.load(str(path)))

    @classmethod
    def from_dict(cls, d):
        """Validates a scene given as a dictionary of the scene file's shape, in either form
        (the structure form when it has a ``structure`` field).

        Raises :class:`ValueError` naming the field path (e.g. ``stops.restitution``,
        ``structure.bodies[0].mass``) and its allowed range, as the command does for a file
        (the origin is called ``dict``).
        """
        if not isinstance(d, dict):
            raise TypeError(f"a scene is a dict, not {type(d).__name__}")
        non_finite = []
        base = d.get("base")
        lists = "structure" in d or (isinstance(base, dict) and "harmonics" in base)
        finite = _finite_copy(d, "", non_finite, lists=lists)
        text = _json.dumps(finite, default=_plain)
        return cls(_rattle.NativeScene.from_dict_json(text, non_finite))

    @classmethod
    def paper(cls):
        """The command's built-in scene: the paper's unit with gap 0.5 and restitution 0.8."""
        return cls(_rattle.NativeScene.paper())

    @property
    def name(self):
        """The scene's name."""
        return self._native.name

    @property
    def form(self):
        """The scene's form: ``"cells"`` (a unit or a chain of cells) or ``"structure"``."""
        return self._native.form

    @property
    def effects(self):
        """The active effects, as outputs list them: ``["stops"]``, ``["stops", "damping"]``…
        (a structure's as its records' heading lists them: ``stops`` when it has stops,
        ``damping`` when it has a dashpot, ``harmonics`` when its forcing has harmonics)."""
        return list(self._native.effects)

    def to_dict(self):
        """The scene as a dictionary of the scene file's shape."""
        return _json.loads(self._native.to_json())

    def __eq__(self, other):
        return isinstance(other, Scene) and self.to_dict() == other.to_dict()

    def __hash__(self):
        return hash(self._native.to_json())

    def __repr__(self):
        return f"Scene.from_dict({self.to_dict()!r})"


def _native_scene(scene):
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a rattle.Scene, not {type(scene).__name__}")
    return scene._native
