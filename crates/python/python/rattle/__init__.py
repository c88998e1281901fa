"""Steady states of an impacting mass-in-mass unit, two independent ways, from Python.

An inner mass rattles between two stops (``r = u_i - u_o = ±gap``) inside an outer mass whose
base moves as ``u_g cos(ωt)``. Two solvers that share no numerics describe it:

- the closed-form (Nigm–Shabana) orbits: :func:`orbit`;
- the exact event-driven simulator: :func:`simulate`;

and :func:`compare` and :func:`sweep` put them side by side; :func:`continue_branch` follows the
orbits of a signature in frequency, :func:`boundary` one of their events (a regime boundary) in
frequency and a scene parameter. ``simulate(..., trajectory=True)`` and
:func:`orbit_trajectory` give a cycle's time history, sampled from the closed form, as the
command's ``--trajectory`` and ``--impacts`` tables. Each function does what the
``rattle`` command of the same name does, on the same library calls, and its result's
``.to_dict()`` equals the command's ``--json`` output for the same inputs, number for number.

Errors: a bad scene or argument raises :class:`ValueError` (for a scene, the command's message:
the field's path and its allowed range); an unreadable scene file :class:`OSError`; a numerical
failure :class:`RuntimeError`. A frequency must be finite, > 0 and within the scene's bounds,
``[ω_fastest / 1e3, ω_slowest × 1e6]`` of its undamped natural frequencies (the paper's unit:
2.449e-3 to 1.225e6 rad/s), so that every call ends in bounded time; outside them the call
raises the command's :class:`ValueError` with the range. The computations release the GIL; a
sweep runs on the Rust thread pool (``RAYON_NUM_THREADS`` sets its size).

:func:`respond` is the exact response from rest to a non-periodic signal, and
:func:`transmission` the Welch estimate of the transmissibility under random base motion,
level by level, beside the linear response with the stops removed (on a Dask cluster with
``client=``), as ``rattle respond`` and ``rattle transmission``.

``simulate(..., lyapunov=True)`` adds the Lyapunov exponents of the motion, as
``rattle simulate --lyapunov``.

Chains of cells (a scene with ``"cells": N`` or ``"chain": [...]``) go through
:func:`simulate`, :func:`sweep` (every solver), :func:`orbit` with a signature (an impact
sequence of the chain's pairs, ``"0+ 1- 0- 1+"``: :class:`ChainOrbits`),
:func:`orbit_trajectory` (one row per cell), :func:`compare` (:class:`ChainComparison`) and
:func:`continue_branch` and :func:`boundary`, each as the command on the same chain;
:func:`orbit` without a signature takes a single unit and refuses a chain with a
:class:`ValueError` naming it.

Structures (a scene in the structure form: bodies, springs, dashpots, stops and forcing, with a
``structure`` field; :attr:`Scene.form` is ``"structure"``) go through :func:`simulate` (every
body's amplitude by name; the trajectory with a column per body and per stop; the Lyapunov
exponents), :func:`orbit` with a signature (an impact sequence of its stops:
:class:`StructureOrbits`), :func:`orbit_trajectory` (a column per body and per stop, as the
simulated trajectory's), :func:`compare` (:class:`StructureComparison`), :func:`sweep`
(every solver, whole or in parts), :func:`continue_branch` and :func:`boundary` (an impact
sequence of the stops, a parameter by its path such as ``"structure.stops[0].gap_plus"``),
:func:`map` over two of its numbers (``x=``, ``y=``) and :func:`basins` (over any two of its
bodies' displacements and velocities, ``x="u:NAME"``, ``y="v:NAME"``), each as the command on
the same structure. :func:`orbit` without a signature refuses a structure with a
:class:`ValueError` naming the function and the forms it takes, as the command refuses one;
:func:`map` without ``x`` and ``y`` asks for them.
"""

import json as _json
import math as _math

import numpy as _np

from . import _rattle, _tables

__all__ = [
    "Scene",
    "Record",
    "OrbitResult",
    "SignatureOrbits",
    "ChainOrbits",
    "StructureOrbits",
    "Simulation",
    "Comparison",
    "ChainComparison",
    "StructureComparison",
    "Sweep",
    "Table",
    "OrbitCycle",
    "Continuation",
    "orbit",
    "orbit_trajectory",
    "simulate",
    "compare",
    "sweep",
    "frequencies",
    "continue_branch",
    "boundary",
    "Boundary",
    "map",
    "basins",
    "merge",
    "Map",
    "Basins",
    "Response",
    "respond",
    "Transmission",
    "transmission",
    "DEFAULTS",
    "CONTINUATION_DEFAULTS",
    "BOUNDARY_DEFAULTS",
    "SAMPLES_PER_PERIOD",
    "LYAPUNOV_PERIODS",
]

__version__ = _rattle.__version__

#: The simulator's default accuracy knobs, as the command's: ``tol`` (relative tolerance of
#: contact times), ``steady_tol`` (of the periodicity test), ``max_periods`` (cap on forcing
#: periods), ``max_oscillations`` (cap on free oscillations of the fastest mode).
DEFAULTS = dict(_rattle.defaults())

_TOL = DEFAULTS["tol"]
_STEADY_TOL = DEFAULTS["steady_tol"]
_MAX_PERIODS = DEFAULTS["max_periods"]
_MAX_OSCILLATIONS = DEFAULTS["max_oscillations"]

#: The continuation's default settings, as the command's: ``max_step`` (largest step along a
#: branch, in α, impact phases and ω together), ``max_branches`` (cap on the branches
#: followed per start orbit) and ``max_depth`` (switching depth).
CONTINUATION_DEFAULTS = dict(_rattle.continuation_defaults())

#: The boundary's default settings, as the command's: ``omega_min`` and ``omega_max`` (the
#: frequency range of the event search and of the curve) and ``max_step`` (largest step along
#: the curve, in α, impact phases, ω and the parameter together).
BOUNDARY_DEFAULTS = dict(_rattle.boundary_defaults())

#: Uniform samples per forcing period of a trajectory by default, as the command's
#: ``--samples-per-period``.
SAMPLES_PER_PERIOD = 200

#: Forcing periods of the Lyapunov exponents' run by default, as the command's
#: ``--lyapunov-periods``.
LYAPUNOV_PERIODS = _rattle.LYAPUNOV_PERIODS


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


class Record:
    """A result: every field of the command's JSON document as an attribute.

    Nested objects are :class:`Record` too, lists stay lists, ``null`` is ``None``. A field
    whose name is a Python keyword (``class``) is also reachable with a trailing underscore
    (``class_``). :meth:`to_dict` gives the command's ``--json`` document.
    """

    def __init__(self, data):
        """Wraps one decoded JSON object."""
        self._data = data
        for key, value in data.items():
            wrapped = _wrap(value)
            self.__dict__[key] = wrapped
            if key in ("class", "from", "import", "in", "is", "not", "or", "and"):
                self.__dict__[key + "_"] = wrapped

    def to_dict(self):
        """The command's ``--json`` document for this result (a fresh copy)."""
        return _json.loads(_json.dumps(self._data))

    def keys(self):
        """The field names, in the command's order."""
        return list(self._data)

    def __eq__(self, other):
        return isinstance(other, Record) and self._data == other._data

    __hash__ = None

    def __repr__(self):
        fields = ", ".join(
            f"{k}={v!r}" for k, v in self._data.items() if not isinstance(v, (dict, list))
        )
        return f"{type(self).__name__}({fields}, …)"


def _wrap(value):
    if isinstance(value, dict):
        return Record(value)
    if isinstance(value, list):
        return [_wrap(v) for v in value]
    return value


class OrbitResult(Record):
    """``rattle orbit --json``: ``scene``, ``omega``, ``effects``, ``linear`` (the linear steady
    state: ``outer_amplitude``, ``inner_amplitude``, ``relative_amplitude``,
    ``transmittance_db``, ``unbounded``, ``touches_stops``) and ``orbits``, every two-impact
    orbit (``branch``, ``beta``, ``gap``, ``alpha``, the states at the impacts,
    ``outer_amplitude``, ``transmittance_db``, ``viable``, ``violations``,
    ``floquet_multipliers`` as ``[re, im]``, ``stable``)."""


class SignatureOrbits(Record):
    """``rattle orbit --signature SIG --json``: ``scene``, ``omega``, ``effects``,
    ``signature`` (canonical), ``period`` and ``orbits``, every orbit of that signature
    (``impact_phases``, ``alpha``, ``state_after_impact``, ``outer_amplitude``,
    ``transmittance_db``, ``viable``, ``violations``, ``floquet_multipliers``, ``stable``,
    ``energy_residual``)."""


class ChainOrbits(Record):
    """``rattle orbit CHAIN --signature SEQUENCE --json`` on a chain: ``scene``, ``omega``,
    ``effects``, ``cells``, ``sequence`` (the impact sequence of the chain's pairs, canonical,
    e.g. ``0+ 1- 0- 1+``), ``period`` and ``orbits``, every orbit of that sequence (each with
    its impact phases, states at the impacts, ``outer_amplitude`` and ``transmittance_db`` of
    the last cell, ``cell_outer_amplitudes`` of every cell, ``viable``, ``stable``,
    ``floquet_multipliers``, ``energy_residual``, as the command's JSON)."""


class StructureOrbits(Record):
    """``rattle orbit STRUCTURE --signature SEQUENCE --json`` on a structure: ``scene``,
    ``form`` (``"structure"``), ``omega``, ``effects``, ``observed`` (the body behind
    ``outer_amplitude`` and ``transmittance_db``), ``sequence`` (the impact sequence of its
    stops, canonical, e.g. ``0+ 0-``), ``period`` and ``orbits``, every orbit of that sequence
    (``alpha``, ``impact_phases``, ``relative_velocities_before``, ``outer_amplitude``,
    ``transmittance_db``, ``body_amplitudes`` by body name, ``viable``, ``stable``,
    ``floquet_multipliers``, ``energy_residual``, as the command's JSON)."""


class Table:
    """A table the command writes as a file (``--trajectory``, ``--impacts``), as columns.

    ``columns`` is a dict of read-only numpy arrays in the command's column order; each column
    is also an attribute (``table.t``, ``table.r``…). Numbers are ``float64`` (NaN where the
    command writes nothing), words (``kind``) ``object`` arrays of ``str``, the impact
    ``side`` ``int64`` (1 for ``r = +gap``, 2 for ``r = -gap``). ``len(table)`` is the number
    of rows; :meth:`to_pandas` a DataFrame when pandas is installed.

    A structure's tables have a column per body and per stop, named as the command names
    them: the trajectory ``t, kind, base, u_NAME…, v_NAME…, r_K…`` (``base`` NaN without a
    moving base), the impacts ``t, stop, side, relative_velocity_before, u_NAME…,
    v_NAME_before…`` (``stop`` and ``side`` ``int64``).
    """

    def __init__(self, columns):
        """Wraps ``(name, array)`` pairs; the tables come from :func:`simulate` and
        :func:`orbit_trajectory`."""
        self.columns = dict(columns)
        for column in self.columns.values():
            column.flags.writeable = False

    def __getattr__(self, name):
        columns = self.__dict__.get("columns", {})
        if name in columns:
            return columns[name]
        raise AttributeError(f"Table has no attribute or column {name!r}")

    def __len__(self):
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def to_pandas(self):
        """The columns as a :class:`pandas.DataFrame` (needs pandas, not installed with
        rattle: ``pip install pandas``)."""
        try:
            import pandas
        except ImportError as e:
            raise ImportError("Table.to_pandas needs pandas: pip install pandas") from e
        return pandas.DataFrame({name: column.copy() for name, column in self.columns.items()})

    def __repr__(self):
        return f"Table(columns={list(self.columns)}, rows={len(self)})"


class Simulation(Record):
    """``rattle simulate --json``: ``scene``, ``omega``, ``effects``, ``status``, ``regime``,
    ``period``, ``impacts_per_period``, ``outer_amplitude``, ``transmittance_db``,
    ``sticking``, ``stopped_by``, ``periods_run``, ``impacts``, ``signature``,
    ``floquet_multipliers``, ``orbit_error``; with ``simulate(..., lyapunov=True)`` also
    ``lyapunov_exponents``, ``lyapunov_uncertainty``, ``lyapunov_uncertainties``,
    ``lyapunov_collapsed``, ``lyapunov_periods``, ``lyapunov_regime`` (see :func:`simulate`).

    With ``simulate(..., trajectory=True)`` also ``trajectory`` and ``impact_table``
    (:class:`Table`, see :func:`simulate`; ``impacts`` is already the command's count of
    impacts). They are not part of :meth:`to_dict`: the command writes them to their own
    files. Without it, both are ``None``.

    On a structure, the command's structure record: also ``form`` (``"structure"``),
    ``observed`` (the body behind ``outer_amplitude`` and ``transmittance_db``),
    ``pair_impacts_per_period`` and ``pair_signatures`` (per stop), ``body_amplitudes``
    (every body's amplitude by name), ``amplitudes_of`` and ``family``."""

    def __init__(self, data, trajectory=None, impacts=None):
        """Wraps the command's document and, when sampled, the two trajectory tables."""
        super().__init__(data)
        self.__dict__["trajectory"] = trajectory
        self.__dict__["impact_table"] = impacts


class OrbitCycle:
    """One analytic orbit sampled over its cycle: what ``rattle orbit --signature SIG
    --orbit K --trajectory F.csv --impacts I.csv`` writes, see :func:`orbit_trajectory`.

    Attributes: ``trajectory`` and ``impact_table`` (:class:`Table`, named as on
    :class:`Simulation` so that the two solvers' cycles overlay with the same code), ``orbit`` (the orbit's
    record, as listed in ``orbits.orbits[index]``), ``index``, and ``orbits``, the
    :class:`SignatureOrbits` of every orbit of the signature at that frequency (the command's
    ``--json`` document; :class:`ChainOrbits` on a chain, :class:`StructureOrbits` on a
    structure).
    """

    def __init__(self, orbits, index, trajectory, impacts):
        """Wraps the parts; use :func:`orbit_trajectory`."""
        self.orbits = orbits
        self.index = index
        self.orbit = orbits.orbits[index]
        self.trajectory = trajectory
        self.impact_table = impacts

    def __repr__(self):
        # A unit's orbits list a signature, a chain's and a structure's an impact sequence.
        signature = self.orbits.__dict__.get("signature", self.orbits.__dict__.get("sequence"))
        return (
            f"OrbitCycle(signature={signature!r}, period={self.orbits.period}, "
            f"omega={self.orbits.omega!r}, index={self.index}, rows={len(self.trajectory)})"
        )


class Continuation(Record):
    """``rattle continue --json``: ``scene``, ``signature`` (canonical), ``period``,
    ``omega_start``, ``start_orbits`` (how many orbits of the signature were found there),
    ``followed_starts`` (which were followed; the others lie on a branch already followed),
    ``branches`` (each branch: its index, signature, period, the event it left from…),
    ``points`` (every point of every branch, branch by branch: ``branch``, ``omega``,
    ``alpha``, ``impact_phases``, ``outer_amplitude``, ``transmittance_db``, ``stable``,
    ``viable``, ``floquet_multipliers``), ``events`` (bifurcations, grazings…, each listed
    once) and ``ends`` (how each branch ends: ``branch``, ``omega``, ``reason``, and for
    ``reason == "joins"`` the branch it runs onto in ``joins``). On a chain also ``cells``,
    and each point's ``cell_outer_amplitudes`` (every cell's outer amplitude, from the base
    out); on a structure each point's ``body_amplitudes`` (every body's amplitude by name,
    ``outer_amplitude`` being the observed body's). :meth:`points_columns` gives the points
    as numpy arrays, :meth:`body_amplitudes` a structure's bodies'."""

    def body_amplitudes(self):
        """A structure's every body's amplitude at every point, as a dict of ``float64``
        arrays by body name in the scene's order (NaN where the command writes ``null``), in
        the order of :attr:`points`. The branches of a unit or a chain have no bodies:
        :class:`ValueError`."""
        points = self._data["points"]
        if points and "body_amplitudes" not in points[0]:
            raise ValueError(
                "Continuation.body_amplitudes: the branches of a unit or a chain have no "
                "bodies (a chain's points carry cell_outer_amplitudes)"
            )
        names = list(points[0]["body_amplitudes"]) if points else []
        return {
            name: _np.array(
                [
                    _np.nan if p["body_amplitudes"][name] is None else p["body_amplitudes"][name]
                    for p in points
                ],
                dtype=_np.float64,
            )
            for name in names
        }

    def points_columns(self):
        """The points as a dict of numpy arrays, for plotting: ``branch`` (``int64``),
        ``omega``, ``alpha``, ``outer_amplitude``, ``transmittance_db`` (``float64``, NaN where
        the command writes ``null``), ``stable`` and ``viable`` (``bool``), in the order of
        :attr:`points`."""
        points = self._data["points"]

        def number(key):
            return _np.array(
                [_np.nan if p[key] is None else p[key] for p in points], dtype=_np.float64
            )

        return {
            "branch": _np.array([p["branch"] for p in points], dtype=_np.int64),
            "omega": number("omega"),
            "alpha": number("alpha"),
            "outer_amplitude": number("outer_amplitude"),
            "transmittance_db": number("transmittance_db"),
            "stable": _np.array([p["stable"] for p in points], dtype=bool),
            "viable": _np.array([p["viable"] for p in points], dtype=bool),
        }


def _columns(rows):
    """A list of records (decoded JSON objects) as a dict of numpy arrays, one per field in the
    records' order, read generically: numbers ``float64`` (NaN for ``null``), ``true``/``false``
    ``bool``, ``[re, im]`` pairs ``complex128``, anything else (words, lists) an ``object``
    array."""
    names = []
    for row in rows:
        names.extend(k for k in row if k not in names)

    def column(values):
        present = [v for v in values if v is not None]
        if present and all(isinstance(v, bool) for v in present) and len(present) == len(values):
            return _np.array(values, dtype=bool)
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in present):
            return _np.array(
                [_np.nan if v is None else v for v in values], dtype=_np.float64
            )
        if present and all(
            isinstance(v, list) and len(v) == 2 and all(isinstance(x, (int, float)) for x in v)
            for v in present
        ):
            return _np.array(
                [_np.nan if v is None else complex(v[0], v[1]) for v in values],
                dtype=_np.complex128,
            )
        out = _np.empty(len(values), dtype=object)
        out[:] = values
        return out

    return {name: column([row.get(name) for row in rows]) for name in names}


class Boundary(Record):
    """``rattle boundary --json``: ``scene``, ``signature`` (canonical), ``period``, ``event``
    (the kind followed), ``param`` (the scene parameter's path), ``param_start`` and
    ``omega_start`` (where the curve starts: the scene's own value and the event there),
    ``points`` (along the curve: ``param_value``, ``omega``, ``outer_amplitude``,
    ``critical_multiplier`` as ``[re, im]``), ``at`` (the curve's ``omega`` solved at each
    value asked for: ``param_value``, ``omega``; one entry per crossing), ``special_points``
    (points of note along the curve, each with its ``kind``, as the command lists them) and
    ``ends`` (the first point's end, then the last point's: ``param_value``, ``omega``,
    ``reason``).

    :meth:`points_columns`, :meth:`at_columns`, :meth:`special_points_columns` and
    :meth:`ends_columns` give each list as numpy columns."""

    def points_columns(self):
        """The points as a dict of numpy arrays in the command's field order:
        ``param_value``, ``omega``, ``outer_amplitude`` (``float64``),
        ``critical_multiplier`` (``complex128``) and ``special`` (the kind of special point a
        point is, ``None`` elsewhere; ``float64`` NaN throughout when the curve has none)."""
        return _columns(self._data["points"])

    def at_columns(self):
        """The ``at`` entries as numpy arrays: ``param_value`` and ``omega`` (``float64``)."""
        return _columns(self._data["at"])

    def special_points_columns(self):
        """The special points as numpy arrays, one per field the command writes (``kind``
        an ``object`` array of ``str``, numbers ``float64``)."""
        return _columns(self._data["special_points"])

    def ends_columns(self):
        """The two ends as numpy arrays: ``param_value``, ``omega`` (``float64``) and
        ``reason`` (``object`` array of ``str``)."""
        return _columns(self._data["ends"])


class Comparison(Record):
    """``rattle compare --json``: ``scene``, ``omega``, ``simulated`` (the cycle from rest),
    ``analytic`` (the orbit of the simulated signature, or ``None``), ``analytic_error``,
    ``class`` (also ``class_``: ``agreement``, ``beyond`` or ``contradiction``),
    ``class_detail``, ``relative_difference``, ``multiplier_difference``,
    ``confirmed_orbits``."""


class ChainComparison(Record):
    """``rattle compare CHAIN --json`` on a chain: ``scene``, ``omega``, ``cells``,
    ``simulated`` (the cycle from rest: ``status``, ``period``, ``pair_signatures``,
    ``impacts_per_period``, ``pair_impacts_per_period``, ``outer_amplitude`` of the last cell,
    ``cell_outer_amplitudes``, ``floquet_multipliers``), ``analytic`` (the orbit of the
    simulated impact sequence: ``sequence``, ``period``, ``outer_amplitude``,
    ``cell_outer_amplitudes``, ``viable``, ``stable``, ``floquet_multipliers``,
    ``energy_residual``; or ``None``), ``analytic_error``, ``class`` (also ``class_``),
    ``reason`` (one word, ``None`` for an agreement), ``class_detail``,
    ``relative_difference``, ``multiplier_difference`` and ``confirmation`` (the simulator's
    Newton started on the analytic orbit)."""


class StructureComparison(Record):
    """``rattle compare STRUCTURE --json`` on a structure: ``scene``, ``form``
    (``"structure"``), ``omega``, ``effects``, ``observed``, ``simulated`` (the cycle from
    rest, every body's amplitude by name in ``body_amplitudes``), ``analytic`` (the orbit of
    the simulated impact sequence of its stops: ``sequence``, ``period``, ``outer_amplitude``,
    ``body_amplitudes``, ``viable``, ``stable``, ``floquet_multipliers``,
    ``energy_residual``; or ``None``), ``analytic_error``, ``class`` (also ``class_``),
    ``reason``, ``class_detail``, ``relative_difference``, ``multiplier_difference`` and
    ``confirmation``, as the command's JSON."""


class Sweep:
    """``rattle sweep --out FILE.json``: one row per frequency, as columns.

    Attributes: ``scene`` (dict), ``form`` (``"cells"`` or ``"structure"``), ``solver``,
    ``effects`` (``None`` for a structure: its document lists ``bodies`` and ``observed``
    instead, attributes too, ``None`` for a unit or a chain), ``points``, ``columns`` (a dict
    of numpy arrays in the command's column order), and each column by name
    (``sweep.omega``, ``sweep.simulated_transmittance_db``…). Column types, fixed whatever
    the data:

    - numbers, counts included (``orbits``, ``simulated_period``): ``float64``, NaN where the
      command writes ``null`` (a cell that does not apply, or a number that is not finite);
    - flags (``branch0_stable``…): ``bool``, ``False`` where the command writes ``null``
      (the matching number column is NaN there);
    - words (``simulated_regime``, ``class``, ``error``…): ``object``, ``str`` or ``None``;
    - lists of numbers (``linear_cell_outer_amplitudes``, ``simulated_cell_outer_amplitudes``,
      ``analytic_cell_outer_amplitudes``: every cell's outer amplitude from the base out;
      ``simulated_pair_impacts_per_period``: each contact pair's impacts per period): one
      ``str`` per row as the command writes it, the numbers separated by ``;`` (an empty
      element where one is not finite), or ``None`` (no finite number, or not applying); one
      element for a single unit. Read one
      with ``[float(x) if x else math.nan for x in cell.split(";")]``.

    A structure's sweep has its own columns, as the command writes them: ``omega``,
    ``linear_outer_amplitude`` and ``linear_transmittance_db`` (of the observed body),
    ``linear_touches_stops``, ``linear_body_amplitudes`` (every body's, a ``;``-separated
    list in the scene's order of bodies), ``simulated_regime``, ``simulated_status``,
    ``simulated_period``, ``simulated_impacts_per_period``,
    ``simulated_pair_impacts_per_period`` and ``simulated_pair_signatures`` (per stop),
    ``simulated_outer_amplitude``, ``simulated_transmittance_db``,
    ``simulated_body_amplitudes`` (every body's), ``simulated_polished``, ``class``,
    ``reason``, ``relative_difference``, ``multiplier_difference``, ``analytic_sequence``,
    ``error``. :meth:`body_amplitudes` reads a list column as one numpy column per body.

    :meth:`to_dict` is the command's JSON document (with ``null`` kept as ``None``),
    :meth:`to_pandas` a DataFrame of the columns when pandas is installed. ``Sweep(document)``
    reads the command's ``--out F.json`` file of a sweep (given as text) with the same
    columns; :func:`merge` gives the merged parts of a sweep so. Two sweeps are equal when
    their documents are.
    """

    def __init__(self, native):
        """Wraps a native sweep (use :func:`sweep`), or the command's ``--out F.json`` file
        of a sweep as text (a whole sweep's, e.g. the one :func:`merge` joins, or a part's)."""
        if isinstance(native, (str, bytes)):
            document = native.decode() if isinstance(native, bytes) else native
            data = _json.loads(document)
            rows = data.pop("results")
            self._native = None
            self._document = document
            header = data
            table = "structure-sweep" if header.get("form") == "structure" else "sweep"
            self.columns = _tables.columns(table, rows)
        else:
            self._native = native
            self._document = None
            header = _json.loads(native.header_json())
            self.columns = dict(native.columns())
            for column in self.columns.values():
                column.flags.writeable = False
        self.scene = header["scene"]
        self.form = header.get("form", "cells")
        self.solver = header["solver"]
        self.effects = header.get("effects")
        self.bodies = header.get("bodies")
        self.observed = header.get("observed")
        self.points = header["points"]

    def __getattr__(self, name):
        columns = self.__dict__.get("columns", {})
        if name in columns:
            return columns[name]
        if name.endswith("_") and name[:-1] in columns:
            return columns[name[:-1]]
        raise AttributeError(f"Sweep has no attribute or column {name!r}")

    def __len__(self):
        return len(self.columns["omega"])

    def __eq__(self, other):
        """Two sweeps are equal when their documents are."""
        return isinstance(other, Sweep) and other.document == self.document

    __hash__ = None

    @property
    def document(self):
        """The command's ``--out F.json`` file as text, byte for byte (for a part, with its
        ``shard``: :func:`merge` joins parts)."""
        if self._native is None:
            return self._document
        return self._native.document()

    def to_dict(self):
        """The command's JSON document: the header fields, then ``results``, one dict per
        frequency."""
        if self._native is None:
            return _json.loads(self._document)
        doc = _json.loads(self._native.header_json())
        doc["results"] = _json.loads(self._native.rows_json())
        return doc

    def body_amplitudes(self, column="simulated_body_amplitudes"):
        """A structure's list column of every body's amplitude (``simulated_body_amplitudes``
        or ``linear_body_amplitudes``) as a dict of ``float64`` arrays, one per body by name
        in the scene's order (NaN where the command writes nothing). A sweep of a unit or a
        chain has no bodies: :class:`ValueError`."""
        if self.bodies is None:
            raise ValueError(
                "Sweep.body_amplitudes: the sweep of a unit or a chain has no bodies "
                "(its list columns are per cell)"
            )
        if column not in ("simulated_body_amplitudes", "linear_body_amplitudes"):
            raise ValueError(
                f"column = {column!r} is not a column of every body's amplitude: must be "
                "'simulated_body_amplitudes' or 'linear_body_amplitudes'"
            )
        values = _np.full((len(self), len(self.bodies)), _np.nan)
        for i, cell in enumerate(self.columns[column]):
            if cell:
                values[i] = [float(x) if x else _math.nan for x in cell.split(";")]
        return {name: values[:, k].copy() for k, name in enumerate(self.bodies)}

    def to_pandas(self):
        """The columns as a :class:`pandas.DataFrame` (needs pandas, not installed with
        rattle: ``pip install pandas``)."""
        try:
            import pandas
        except ImportError as e:
            raise ImportError("Sweep.to_pandas needs pandas: pip install pandas") from e
        return pandas.DataFrame({name: column.copy() for name, column in self.columns.items()})

    def __repr__(self):
        return f"Sweep(scene={self.scene.get('name')!r}, solver={self.solver!r}, points={self.points})"


def orbit(scene, omega, signature=None, period=1, symmetric_only=False):
    """The analytic solver at one frequency, as ``rattle orbit --json``.

    Without ``signature``: the linear steady state and every two-impact orbit (symmetric
    branches 0 and 1, then the asymmetric ones unless ``symmetric_only``), each with its
    viability and Floquet stability; returns an :class:`OrbitResult`.

    With ``signature`` (the stops hit over one cycle in time order, ``+`` side 1, ``-`` side 2,
    any rotation, e.g. ``"+-"``, ``"++--"``) and ``period`` (forcing periods per cycle, 1 to 8):
    every orbit of that signature; returns :class:`SignatureOrbits`.

    On a chain of cells, ``signature`` is an impact sequence of the chain's pairs in time
    order, ``<pair><side>`` tokens with pairs numbered from 0 at the base (``"0+ 1- 0- 1+"``;
    a signature without numbers is pair 0's alone), as ``rattle orbit CHAIN --signature``;
    returns :class:`ChainOrbits`. Without a signature a chain is refused (the two-impact
    orbits are a single unit's).

    On a structure, ``signature`` is an impact sequence of its stops, ``<stop><side>`` tokens
    with stops numbered from 0 in file order (with one stop the sides alone, ``"+-"``), as
    ``rattle orbit STRUCTURE --signature``; returns :class:`StructureOrbits`. Without a
    signature a structure is refused by name.

    ``omega`` is the angular frequency of the forcing in rad/s (finite, > 0).
    """
    text = _rattle.orbit(_native_scene(scene), float(omega), signature, period, symmetric_only)
    data = _json.loads(text)
    if data.get("form") == "structure":
        return StructureOrbits(data)
    if "sequence" in data:
        return ChainOrbits(data)
    return SignatureOrbits(data) if signature is not None else OrbitResult(data)


def simulate(
    scene,
    omega,
    periods=None,
    tol=_TOL,
    steady_tol=_STEADY_TOL,
    max_periods=_MAX_PERIODS,
    max_oscillations=_MAX_OSCILLATIONS,
    trajectory=False,
    samples_per_period=SAMPLES_PER_PERIOD,
    lyapunov=False,
    lyapunov_periods=LYAPUNOV_PERIODS,
    sampled_periods=None,
):
    """The event-driven simulator from rest, as ``rattle simulate --json``.

    Runs until the motion is periodic (or a cap), or exactly ``periods`` forcing periods.
    ``tol`` is the relative tolerance of contact times (1e-15 to 1e-2), ``steady_tol`` that of
    the periodicity test (1e-14 to 1e-2), ``max_periods`` and ``max_oscillations`` the caps of
    a run until steady. Returns a :class:`Simulation`.

    With ``trajectory=True`` the result also carries, as :class:`Table`, what
    ``rattle simulate --trajectory F.csv --impacts I.csv --samples-per-period N`` writes:
    ``trajectory``, the final cycle sampled from the closed form (its ``period`` forcing
    periods; for a motion that is not periodic, the run's observed final stretch), with
    ``samples_per_period`` uniform samples per forcing period (1 to 100000, both ends of the
    stretch included) and each impact as two rows, before and after (columns ``t, kind, cell,
    base, u_o, u_i, v_o, v_i, r``; ``t`` in s with the base at ``u_g cos ωt``, ``kind`` one
    of ``sample``, ``before_impact``, ``after_impact``, ``after_stick``; a chain has one row
    per cell at each time, ``cell`` numbered from 0 at the base, 0 for the unit), and
    ``impact_table``, every impact of that stretch (``t, pair, side,
    relative_velocity_before, u_o, u_i, v_o_before, v_i_before``, displacements and
    velocities of the pair's cell). With ``sampled_periods=N`` (``--sampled-periods N``) the
    tables hold ``N`` forcing periods continued from where the run ended instead of the final
    cycle: with ``samples_per_period=1`` the ``sample`` rows are the stroboscopic (Poincaré)
    section at ``t = kT`` and ``impact_table`` the impact map, for a motion periodic or not
    (``N`` ≥ 1, ``N × samples_per_period`` ≤ 10 000 000).

    With ``lyapunov=True``, as ``rattle simulate --lyapunov --lyapunov-periods N``: after the
    run, the Lyapunov exponents over ``lyapunov_periods`` more forcing periods (at least 10;
    ignored without ``lyapunov``), from the simulator's exact tangent flow, in the result:
    ``lyapunov_exponents`` (the finite ones, descending, 1/s), ``lyapunov_uncertainty`` (of
    the largest, 1/s), ``lyapunov_uncertainties`` (of each), ``lyapunov_collapsed``
    (directions contracted by sticking, exponents −∞, not listed), ``lyapunov_periods`` and
    ``lyapunov_regime`` (``chaotic``, ``quasi-periodic`` or ``unsettled`` for a motion that
    did not repeat, ``None`` for a periodic one). The same numbers as the command, bit for bit.

    On a structure (``scene.form == "structure"``), as ``rattle simulate STRUCTURE``: the run
    from the structure's rest state, the record with ``form``, ``observed`` and every body's
    amplitude by name (``body_amplitudes``, from the polished cycle when ``amplitudes_of`` is
    ``"polished"``), ``pair_impacts_per_period`` and ``pair_signatures`` per stop; its
    ``trajectory`` has a column per body and per stop (``t, kind, base, u_NAME…, v_NAME…,
    r_K…``) and its ``impact_table`` the columns ``t, stop, side, relative_velocity_before,
    u_NAME…, v_NAME_before…``; with ``lyapunov=True``, two exponents per body.
    """
    text, tables = _rattle.simulate(
        _native_scene(scene),
        float(omega),
        periods,
        float(tol),
        float(steady_tol),
        max_periods,
        float(max_oscillations),
        samples_per_period if trajectory else None,
        lyapunov_periods if lyapunov else None,
        sampled_periods if trajectory else None,
    )
    if tables is None:
        return Simulation(_json.loads(text))
    rows, impacts = tables
    return Simulation(_json.loads(text), Table(rows), Table(impacts))


def orbit_trajectory(
    scene, omega, signature, period=1, orbit=0, samples_per_period=SAMPLES_PER_PERIOD
):
    """One analytic orbit's cycle sampled from the closed form, as
    ``rattle orbit --signature SIG --period P --orbit K --trajectory F.csv --impacts I.csv``.

    ``signature`` and ``period`` as in :func:`orbit`; ``orbit`` is which orbit of the signature
    (numbered from 0, in the order ``orbit(scene, omega, signature, period).orbits`` lists
    them); ``samples_per_period`` uniform samples per forcing period (1 to 100000), each impact
    adding two rows (before and after). The tables have the columns of
    ``simulate(..., trajectory=True)``, so the two solvers' cycles overlay directly. Returns
    an :class:`OrbitCycle`; an ``orbit`` out of range is a :class:`ValueError` naming
    ``orbit`` and how many orbits there are.

    On a chain of cells ``signature`` is an impact sequence of its pairs (e.g. ``"0+ 1- 0- 1+"``),
    as ``rattle orbit CHAIN --signature SEQUENCE --orbit K --trajectory F.csv``: ``orbits`` is
    then the :class:`ChainOrbits` of that sequence, the trajectory has one row per cell at each
    time (``cell`` numbered from 0 at the base) and each impact names its ``pair``.

    A function of its own rather than ``orbit(..., trajectory=True)``: it needs a signature
    and picks one orbit, where :func:`orbit` lists them all, with or without a signature; and
    its result has one type whatever the arguments.

    On a structure ``signature`` is an impact sequence of its stops (with one stop the sides
    alone, ``"+-"``), as ``rattle orbit STRUCTURE --signature SEQUENCE --orbit K --trajectory
    F.csv``: ``orbits`` is then the :class:`StructureOrbits` of that sequence, and the tables
    have the columns of a structure's ``simulate(..., trajectory=True)``, a column per body and
    per stop (``t, kind, base, u_NAME…, v_NAME…, r_K…``; the impacts ``t, stop, side,
    relative_velocity_before, u_NAME…, v_NAME_before…``).
    """
    native = _native_scene(scene)
    text, rows, impacts = _rattle.orbit_trajectory(
        native, float(omega), signature, period, orbit, samples_per_period
    )
    doc = _json.loads(text)
    if doc.get("form") == "structure":
        orbits = StructureOrbits(doc)
    elif "sequence" in doc:
        orbits = ChainOrbits(doc)
    else:
        orbits = SignatureOrbits(doc)
    return OrbitCycle(orbits, orbit, Table(rows), Table(impacts))


def compare(
    scene,
    omega,
    tol=_TOL,
    steady_tol=_STEADY_TOL,
    max_periods=_MAX_PERIODS,
    max_oscillations=_MAX_OSCILLATIONS,
):
    """Both solvers on the motion the unit settles on, as ``rattle compare --json``.

    The simulator runs from rest and polishes its cycle; the analytic orbit of that impact
    signature is solved from the simulated phases; the verdict says whether they agree.
    Accuracy knobs as :func:`simulate`. Returns a :class:`Comparison`.

    On a chain of cells: the simulated cycle's impacts, pair by pair in time order, are the
    impact sequence the analytic solver solves from the simulated impact times, as
    ``rattle compare CHAIN``; returns a :class:`ChainComparison`.

    On a structure: the same, every body compared (the stops' impacts are the sequence), as
    ``rattle compare STRUCTURE``; returns a :class:`StructureComparison`.
    """
    text = _rattle.compare(
        _native_scene(scene),
        float(omega),
        float(tol),
        float(steady_tol),
        max_periods,
        float(max_oscillations),
    )
    data = _json.loads(text)
    if data.get("form") == "structure":
        return StructureComparison(data)
    return ChainComparison(data) if "cells" in data else Comparison(data)


def sweep(
    scene,
    omegas,
    solver="both",
    tol=_TOL,
    steady_tol=_STEADY_TOL,
    max_periods=_MAX_PERIODS,
    max_oscillations=_MAX_OSCILLATIONS,
    shard=None,
):
    """A frequency sweep with one solver or both, in parallel, as ``rattle sweep``.

    ``omegas``: the frequencies, rad/s, any 1-D sequence (each finite, > 0 and within the
    scene's bounds, see the module's docstring); use
    :func:`frequencies` for the command's evenly spaced axis. ``solver``: ``"analytic"``
    (linear steady state and symmetric orbits), ``"event"`` (simulator from rest) or
    ``"both"`` (also the simulator started on every viable orbit, and a verdict). A frequency
    that fails gives a row with its ``error``, as in the command. Returns a :class:`Sweep`.

    On a chain of cells: ``"analytic"`` is the linear chain, ``"event"`` the chain from rest,
    ``"both"`` the linear chain and, at each frequency, the verdict of :func:`compare` on the
    chain; ``outer_amplitude`` and ``transmittance_db`` columns are the last cell's, the list
    columns hold every cell and pair.

    On a structure, as ``rattle sweep STRUCTURE``: ``"analytic"`` is the linear steady
    state, ``"event"`` the structure from rest (amplitudes from its polished cycle),
    ``"both"`` also the verdict of :func:`compare`; the rows have a structure's columns
    (``linear_outer_amplitude`` and ``simulated_outer_amplitude`` of the observed body,
    ``linear_body_amplitudes`` and ``simulated_body_amplitudes`` with every body's amplitude
    in the scene's order, ``simulated_pair_signatures`` per stop…; see :class:`Sweep`);
    ``shard`` cuts it as it cuts a unit's sweep.

    ``shard=(K, N)``: part ``K`` of ``N`` only (a contiguous block of ``omegas``), as
    ``rattle sweep --shard K/N``; :func:`merge` joins the parts into the whole sweep (a
    :class:`Sweep` equal to the one computed whole).
    """
    omegas = _np.ascontiguousarray(omegas, dtype=_np.float64)
    if omegas.ndim != 1:
        raise ValueError(f"omegas must be one-dimensional, not of shape {omegas.shape}")
    native = _rattle.sweep(
        _native_scene(scene),
        omegas,
        str(solver),
        float(tol),
        float(steady_tol),
        max_periods,
        float(max_oscillations),
        None if shard is None else tuple(shard),
    )
    return Sweep(native)


def frequencies(omega_min, omega_max, points):
    """``points`` evenly spaced frequencies from ``omega_min`` to ``omega_max``, ends included:
    the axis of ``rattle sweep --omega-min … --omega-max … --points …``, value for value
    (a ``float64`` array)."""
    return _rattle.frequencies(float(omega_min), float(omega_max), points)


def continue_branch(
    scene,
    signature,
    omega,
    omega_min,
    omega_max,
    period=1,
    orbit=None,
    switch=True,
    max_step=CONTINUATION_DEFAULTS["max_step"],
    max_branches=CONTINUATION_DEFAULTS["max_branches"],
    max_depth=CONTINUATION_DEFAULTS["max_depth"],
):
    """The branches through the orbits of a signature, followed in frequency, as
    ``rattle continue --json``.

    Every orbit of ``signature`` (over ``period`` forcing periods, as in :func:`orbit`) found
    at ``omega`` (or only the ``orbit``-th, numbered from 0 as :func:`orbit` lists them) is
    followed both ways within ``[omega_min, omega_max]`` (``omega`` inside it), its stability
    and viability tracked, and its events (branch points, period doublings, grazings…)
    located; with ``switch`` (the command without ``--no-switch``) the branches leaving at
    them are followed too. ``max_step`` is the largest step along a branch (in α, impact
    phases and ω together, ≥ 1e-9), ``max_branches`` the cap on the branches per start
    orbit (≥ 1), ``max_depth`` the switching depth (≥ 0; a start's branch has depth 0, one
    switched onto from a branch of depth d has d + 1; where the depth cuts, a branch without
    points ends ``max-depth``; the branches still queued once ``max_branches`` have been
    followed end ``branch-cap``). Each branch is followed once: one that runs onto a branch
    already followed, or onto its mirror image, ends ``joins`` with that branch. Returns a
    :class:`Continuation`.

    On a chain scene ``signature`` is an impact sequence of its pairs, ``"0+ 1- 0- 1+"``
    (pair index from 0 at the base, then the side), as in :func:`orbit`; the same
    continuation runs on the chain's equations (grazing and vanishing impact per pair), and
    the document gains ``cells`` and each point ``cell_outer_amplitudes`` (every cell's
    outer amplitude from the base out, the last being ``outer_amplitude``), as
    ``rattle continue CHAIN --json``. On a structure ``signature`` is an impact sequence of
    its stops (``"0+ 1-"``; with one stop ``"+-"`` reads as ``"0+ 0-"``), and each point
    gains ``body_amplitudes`` (:meth:`Continuation.body_amplitudes`), its
    ``outer_amplitude`` and ``transmittance_db`` being the observed body's.

    A bad argument is a :class:`ValueError` naming it (``omega_min``, ``max_step``,
    ``orbit``, a pair the chain lacks…); no orbit of the signature at ``omega`` a
    :class:`RuntimeError`.
    """
    text = _rattle.continue_branch(
        _native_scene(scene),
        signature,
        float(omega),
        float(omega_min),
        float(omega_max),
        period,
        orbit,
        bool(switch),
        float(max_step),
        max_branches,
        max_depth,
    )
    return Continuation(_json.loads(text))


def boundary(
    scene,
    signature,
    event,
    omega,
    param,
    min,
    max,
    period=1,
    at=None,
    omega_min=BOUNDARY_DEFAULTS["omega_min"],
    omega_max=BOUNDARY_DEFAULTS["omega_max"],
    max_step=BOUNDARY_DEFAULTS["max_step"],
):
    """A regime boundary: the curve of one event of a signature's orbits in (frequency, a
    scene parameter), as ``rattle boundary --json``.

    The event of kind ``event`` (``"fold"``, ``"branch-point"``, ``"period-doubling"``,
    ``"neimark-sacker"``, ``"grazing"`` or ``"vanishing-impact"``) nearest ``omega`` on the
    branches of the ``signature`` orbits (over ``period`` forcing periods, as in
    :func:`orbit`; on a chain an impact sequence of its pairs, ``"0+ 1- 0- 1+"``) found at
    ``omega``, continued in frequency within
    ``[omega_min, omega_max]`` at the scene's own value of ``param``, is followed in
    (ω, ``param``) both ways within ``[min, max]``, through turning points. ``param`` is a
    scene field by its JSON path (``"stops.gap"``, ``"stops.restitution"``,
    ``"unit.inner_stiffness"``, ``"damping.outer"``…; on a chain the whole chain's field or
    one cell's, ``"chain[1].stops.gap"``; on a structure a field of the structure form,
    ``"structure.stops[0].gap_plus"``, ``"structure.bodies[1].mass"``,
    ``"structure.springs[0].stiffness"``, ``"forcing.forces[0].amplitude"``…, the signature
    then an impact sequence of its stops, each point's ``outer_amplitude`` the observed
    body's); ``min`` and ``max`` lie in its physical range. ``at`` (values in ``[min, max]``) asks for the curve's ω solved exactly at those
    parameter values (one entry per crossing). ``max_step`` is the largest step along the
    curve. Returns a :class:`Boundary` (numpy columns from its ``*_columns`` methods).

    The record holds the points, the ``at`` entries, the ends and the special points (turning
    points, grazing and vanishing impact of the curve's orbit, strong resonances, crossings
    of other event curves), as the command's document. A bad argument is a
    :class:`ValueError` with the command's message naming it as this function's parameter (``event``, ``param``, ``min``, ``max``, ``at``, ``omega``,
    ``omega_min``, ``signature``, ``period``…, or the scene field out of its range); no orbit
    of the signature at ``omega``, no event of the kind on its branches, or a start that does
    not converge a :class:`RuntimeError` (``numerical failure: …``, the command's words). The
    computation releases the GIL.
    """
    text = _rattle.boundary(
        _native_scene(scene),
        {
            "signature": signature,
            "period": period,
            "event": event,
            "omega": float(omega),
            "param": param,
            "min": float(min),
            "max": float(max),
            "at": [] if at is None else [float(v) for v in at],
            "omega_min": float(omega_min),
            "omega_max": float(omega_max),
            "max_step": float(max_step),
        },
    )
    return Boundary(_json.loads(text))


class Response(Record):
    """``rattle respond --json``: ``scene``, ``bodies``, ``input`` (``"base"`` or
    ``"force"``), ``on``, ``duration``, ``signal`` (its ``kind``, parameters and derived
    numbers), ``time_scale``, ``impacts`` (``t``, ``pair``, ``side``,
    ``relative_velocity_before``), ``holds``, ``at`` and ``final_state`` (``t``,
    ``displacements``, ``velocities``, bodies in ``bodies``' order) and ``summary``
    (``impacts``, ``rms`` and ``peak`` by body name, ``energy_dissipated``, ``work``,
    ``final_energy``, ``energy_balance_residual``…).

    ``samples`` is the uniformly sampled response, a :class:`Table` with the columns
    ``rattle respond --out F.csv`` writes: ``t``, ``u_g`` (or ``F``), ``u:NAME…``,
    ``v:NAME…`` (as attributes too, with ``:`` read as ``_``: ``samples.u_outer``). It is
    not part of :meth:`to_dict`.
    """

    def __init__(self, data, samples):
        """Wraps the command's document and the sampled table."""
        super().__init__(data)
        self.__dict__["samples"] = samples


def respond(scene, signal, duration, at=None, on=None, samples=None):
    """The exact response from rest to a non-periodic signal, as ``rattle respond SCENE
    --signal SIGNAL --duration DURATION --at AT --on ON --json``, with the sampled response
    of ``--out F --samples SAMPLES``.

    ``signal`` is the command's ``--signal`` text: a ``.csv`` record (``t,u_g`` or ``t,F``
    with ``on`` the body), ``tone-burst:omega=W,cycles=N[,amplitude=A]``,
    ``sweep:from=W1,to=W2,rate=R[,amplitude=A][,steps=N]`` or
    ``random:band=LO-HI,rms=A,seed=S[,psd=FILE]`` (see ``docs/respond.md``). ``at``: times in
    ``[0, duration]`` at which to report the state. ``samples``: the sample intervals of the
    table (default: 64 per period of the fastest of the structure's natural frequencies and
    the signal's, at most 1 000 000). Returns a :class:`Response`, the command's document bit
    for bit; bad input raises ``ValueError`` naming the parameter or the signal's field.
    """
    text, columns = _rattle.respond(
        _native_scene(scene),
        str(signal),
        float(duration),
        None if at is None else [float(v) for v in at],
        on,
        samples,
    )
    table = Table(columns)
    for name, column in list(table.columns.items()):
        table.__dict__.setdefault(name.replace(":", "_"), column)
    return Response(_json.loads(text), table)


#: The data variables of :meth:`Transmission.to_xarray`, each over ``(level, omega)``: the
#: columns of a level's rows other than ``level`` and ``omega``.
TRANSMISSION_VARIABLES = (
    "h1_magnitude",
    "h1_phase",
    "h1_radius",
    "transmissibility",
    "coherence",
    "linear_magnitude",
    "linear_phase",
    "averages",
)


class Transmission(Record):
    """``rattle transmission --json``: ``scene``, ``observe`` (the observed body), ``settings``
    (every number the estimate used: ``signal``, ``band``, ``levels``, ``seeds``,
    ``sampling_step``, ``samples``, ``transient``, ``segment_samples``, ``overlap``,
    ``effective_averages``, ``frequency_spacing``, ``confidence``,
    ``simultaneous_confidence``…), ``linear`` (``natural_frequencies``,
    ``slowest_decay_rate``, ``attenuation_bands``) and ``levels``, one per level in the order
    given, each ``level``, ``records``, ``impacts``, ``segments``, ``effective_averages`` and
    ``rows`` (``level``, ``omega``, ``h1_magnitude``, ``h1_phase``, ``h1_radius``,
    ``transmissibility``, ``coherence``, ``linear_magnitude``, ``linear_phase``,
    ``averages``; ``None`` where the command writes ``null``).

    As numpy columns (not part of :meth:`to_dict`): ``table``, a :class:`Table` of every
    level's rows one after the other, the columns ``rattle transmission --out F.csv`` writes
    (``float64``, NaN for ``null``); ``tables``, one :class:`Table` per level, in
    ``levels``' order. :meth:`to_xarray` puts them on the axes ``(level, omega)``.
    """

    def __init__(self, data):
        """Wraps the command's document."""
        super().__init__(data)
        tables = [
            Table(_tables.columns("transmission", level["rows"])) for level in data["levels"]
        ]
        rows = [row for level in data["levels"] for row in level["rows"]]
        self.__dict__["table"] = Table(_tables.columns("transmission", rows))
        self.__dict__["tables"] = tables

    def to_xarray(self):
        """The estimate as an :class:`xarray.Dataset` with the dimensions ``(level, omega)``
        (needs xarray, not installed with rattle: ``pip install 'rattle[xarray]'`` or
        ``pip install xarray``).

        The coordinates are ``level`` (m, in the order given) and ``omega`` (rad/s, the
        frequencies every level is estimated at), with the levels' ``records``, ``impacts``,
        ``segments`` and ``effective_averages`` as further coordinates along ``level``; the
        data variables are :data:`TRANSMISSION_VARIABLES` (``h1_magnitude``, ``h1_phase``,
        ``h1_radius``, ``transmissibility``, ``coherence``, ``linear_magnitude``,
        ``linear_phase``, ``averages``), ``float64`` with NaN for ``null``. ``attrs`` hold
        ``scene``, ``observe`` and every setting the document states that is not ``null``
        (a list as an array)."""
        try:
            import xarray
        except ImportError as e:
            raise ImportError(
                "Transmission.to_xarray needs xarray: pip install 'rattle[xarray]' "
                "(or pip install xarray)"
            ) from e
        levels = self._data["levels"]
        omega = self.tables[0].columns["omega"].copy() if levels else _np.empty(0)
        shape = (len(levels), len(omega))
        variables = {
            name: (
                ("level", "omega"),
                _np.array([t.columns[name] for t in self.tables], dtype=_np.float64).reshape(
                    shape
                ),
            )
            for name in TRANSMISSION_VARIABLES
        }
        coords = {
            "level": _np.array([level["level"] for level in levels], dtype=_np.float64),
            "omega": omega,
        }
        for name, dtype in (
            ("records", _np.int64),
            ("impacts", _np.int64),
            ("segments", _np.int64),
            ("effective_averages", _np.float64),
        ):
            coords[name] = ("level", _np.array([level[name] for level in levels], dtype=dtype))
        attrs = {"scene": self._data["scene"], "observe": self._data["observe"]}
        for key, value in self._data["settings"].items():
            if value is None or isinstance(value, dict):
                continue
            attrs[key] = _np.array(value) if isinstance(value, list) else value
        return xarray.Dataset(variables, coords=coords, attrs=attrs)

    def __repr__(self):
        levels = [level["level"] for level in self._data["levels"]]
        scene = self._data["scene"]
        return f"Transmission(scene={scene!r}, levels={levels}, rows={len(self.table)})"


def _transmission_args(signal, duration, levels, seeds, segment, overlap, confidence, transient):
    """The native call's arguments after the scene, as the command's flags give them."""
    if isinstance(levels, (int, float)):
        levels = [levels]
    return (
        str(signal),
        float(duration),
        None if levels is None else [float(v) for v in levels],
        int(seeds),
        None if segment is None else float(segment),
        float(overlap),
        float(confidence),
        None if transient is None else float(transient),
    )


def transmission(
    scene,
    signal,
    duration,
    levels=None,
    seeds=1,
    segment=None,
    overlap=0.5,
    confidence=0.95,
    transient=None,
    client=None,
    parts=None,
    progress=True,
):
    """The transmissibility from the base to the observed body under random base motion,
    estimated by Welch's method beside the exact linear response with the stops removed, as
    ``rattle transmission SCENE --signal SIGNAL --duration DURATION --levels … --seeds N
    --segment S --overlap F --confidence C --transient T0 --json`` (see
    ``docs/transmission.md``). Returns a :class:`Transmission`, whose :meth:`~Record.to_dict`
    is the command's document bit for bit.

    ``signal``: ``random:band=LO-HI,rms=A,seed=S[,psd=FILE]``; ``duration``: each record's
    ``T`` from rest, s. ``levels``: the levels' RMS base displacement, m (a number or a
    sequence; ``None``: the signal's ``rms``); ``seeds``: records per level, seeds ``S, S + 1,
    …``; ``segment``: the segment length, s, rounded to ``2^m`` samples (``None``: the longest
    cutting a record into 8 segments); ``overlap`` in ``[0, 1)``; ``confidence``: pointwise,
    in ``(0, 1)``; ``transient``: the time cut from each record's start, s (``None``: 10 time
    constants of the least-damped mode, at most ``T/2``). The runs, one per ``(level, seed)``,
    go in parallel on the Rust thread pool (``RAYON_NUM_THREADS``).

    ``client``: a ``dask.distributed.Client``. The runs are cut into ``parts`` contiguous
    blocks (the command's ``--shard K/N``), each a Dask task that returns its runs' raw
    segment sums; they are gathered in order and merged as ``rattle merge`` merges the parts:
    the result equals the single-machine one bit for bit. ``parts=None`` chooses one part per
    ``rattle._grids.TASK_SECONDS`` of estimated work (runs × samples ×
    :data:`TRANSMISSION_SECONDS_PER_SAMPLE`), or one per worker for a smaller estimate, at
    most one per run (:func:`rattle._grids.parts_for`). ``progress`` shows a bar over the parts
    (tqdm, when installed); the tasks show in the Dask dashboard as ``rattle-transmission-…``.
    The request is checked here before any task is sent.

    Bad input is a :class:`ValueError` with the command's message, the option named as the
    parameter here (``overlap = 1 is out of range: must be in [0, 1)``, ``levels[1]``,
    ``seeds``, ``segment``, ``signal`` for a signal that is not ``random:…``, ``duration``).
    """
    args = _transmission_args(
        signal, duration, levels, seeds, segment, overlap, confidence, transient
    )
    if client is None:
        return Transmission(_json.loads(_rattle.transmission(_native_scene(scene), *args)))
    from ._grids import _transmission_on_client

    return Transmission(_json.loads(_transmission_on_client(scene, args, client, parts, progress)))

# Maps and basins, whole, in parts or on a Dask cluster (``_grids``); defined last, since
# ``map`` is this module's name for the command, not the builtin.
from ._grids import (  # noqa: E402
    TRANSMISSION_SECONDS_PER_SAMPLE,
    Basins,
    Map,
    basins,
    map,
    merge,
)
