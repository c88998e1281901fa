"""Results: the command's JSON documents with attribute access, and their tables as numpy columns."""

import json as _json
import math as _math

import numpy as _np

from . import _tables


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
