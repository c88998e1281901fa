"""Maps and basins, whole or cut into parts, on this machine or on a Dask cluster.

``rattle.map`` and ``rattle.basins`` are the commands ``rattle map`` and ``rattle basins`` on
the same library calls: each returns the command's ``--out F.json`` file as
:attr:`Grid.document` (byte for byte) and its columns as numpy arrays. ``shard=(K, N)``
computes part ``K`` of ``N`` as the command's ``--shard K/N``; :func:`merge` joins parts as
``rattle merge`` does. With ``client=`` (a ``dask.distributed.Client``) the study is cut into
parts that run as Dask tasks, gathered in order and merged: the result is the single-machine
one bit for bit, whatever the number of workers and parts. ``rattle.transmission(...,
client=)`` runs its ``(level, seed)`` runs the same way, in parts merged by their segment
sums (:func:`_transmission_on_client`).
"""

import json as _json
import math as _math
import uuid as _uuid

import numpy as _np

from . import _rattle, _tables
from ._records import Sweep
from ._scene import _native_scene

#: Seconds of one core per map point, as measured on this project's 2-core machine (the
#: performance page, docs/performance.md: 640 000 points of the lightly damped paper unit in 390 s on 2 threads):
#: used only to choose how many parts a study is cut into.
MAP_SECONDS_PER_POINT = 0.0012

#: Seconds of one core per basins start (docs/performance.md: 200 × 200 starts of the paper's unit at
#: ω = 1.9 rad/s in 10.7 s on 2 threads), for the same purpose.
BASINS_SECONDS_PER_START = 0.0005

#: Seconds of one core per sample of one record of ``rattle transmission`` (a run's samples
#: are the document's ``settings.samples``), as measured on this project's 2-core machine
#: (``base-isolated.json``, 8 runs of 3 184 samples at two levels in 3.5 s on one thread):
#: used only to choose how many parts an estimate is cut into.
TRANSMISSION_SECONDS_PER_SAMPLE = 1.4e-4

#: The work a Dask task is given, in seconds of one core: long enough that the per-task
#: overhead of Dask (scheduling, shipping the scene and the part's table) is a small part of
#: it (see the package README for the measurement), short enough that a lost worker costs little.
TASK_SECONDS = 5.0

class Grid:
    """A map's or basins' table: the command's JSON file and its columns.

    ``document`` is the text ``rattle map/basins --out F.json`` writes for the same inputs,
    byte for byte; ``columns`` a dict of read-only numpy arrays named and ordered as the
    command's CSV columns, each also an attribute; every header field of the document
    (``scene``, ``grid``…) is an attribute too. :meth:`to_pandas` and :meth:`to_xarray` when
    those are installed.
    """

    _table = None

    def __init__(self, document):
        """Wraps the command's JSON document (the whole run's, or a part's)."""
        self.document = document
        data = _json.loads(document)
        rows = data.pop("results")
        self.header = data
        self.columns = _tables.columns(self._table, rows)

    def __getattr__(self, name):
        if name in self.__dict__.get("columns", {}):
            return self.__dict__["columns"][name]
        if name in self.__dict__.get("header", {}):
            return self.__dict__["header"][name]
        raise AttributeError(f"{type(self).__name__} has no attribute or column {name!r}")

    def __len__(self):
        return len(next(iter(self.columns.values())))

    def __eq__(self, other):
        """Two results are equal when they are of one type and their documents are equal."""
        return type(other) is type(self) and other.document == self.document

    __hash__ = None

    @property
    def shard(self):
        """``(K, N)`` for a part, ``None`` for the whole run."""
        s = self.header.get("shard")
        return None if s is None else (s["index"], s["count"])

    def to_pandas(self):
        """The columns as a :class:`pandas.DataFrame` (needs pandas: ``pip install pandas``)."""
        try:
            import pandas
        except ImportError as e:
            raise ImportError(f"{type(self).__name__}.to_pandas needs pandas") from e
        return pandas.DataFrame({k: v.copy() for k, v in self.columns.items()})

    def _axes(self):
        raise NotImplementedError

    def to_xarray(self):
        """The columns as an :class:`xarray.Dataset` on the grid's axes (needs xarray, which
        rattle does not require: ``pip install xarray``); a part's table is not a whole grid
        and is refused with a :class:`ValueError`."""
        try:
            import xarray
        except ImportError as e:
            raise ImportError(f"{type(self).__name__}.to_xarray needs xarray") from e
        if self.shard is not None:
            raise ValueError("to_xarray: a part is not a whole grid; merge the parts first")
        axes = self._axes()
        shape = tuple(len(v) for _, v in axes)
        names = [n for n, _ in axes]
        variables = {
            k: (names, v.reshape(shape)) for k, v in self.columns.items() if k not in names
        }
        return xarray.Dataset(variables, coords={n: v for n, v in axes})


class Map(Grid):
    """``rattle map --out F.json``: one row per point, lines x-major (every y of the first
    x, then the next x), frequency ascending along each line.

    Over restitution and gap (the default), the columns are the command's ``restitution``,
    ``gap_over_base_amplitude``, ``omega``, ``simulated_regime``, …, ``lyapunov_regime``.
    Over two parameters (``x=``, ``y=``), the first two are ``x`` and ``y`` whatever the
    parameters, whose JSON paths are :attr:`x_path` and :attr:`y_path` (the header's
    ``grid``); on a structure (:attr:`form` ``"structure"``) ``simulated_body_amplitudes``
    lists every body's amplitude (:meth:`body_amplitudes`) where a unit's map lists every
    cell's (``simulated_cell_outer_amplitudes``). :attr:`axes` are the grid's values by
    column; ``to_xarray()`` puts the columns on them."""

    _table = "map"

    def __init__(self, document):
        """Wraps the command's JSON document (the whole map's, or a part's)."""
        head = _json.loads(document.split("\n", 1)[0] + "]}")
        if "x" in head.get("grid", {}):
            self._table = "map-structure" if head.get("form") == "structure" else "map-parameters"
        super().__init__(document)

    @property
    def form(self):
        """``"cells"`` (a unit or a chain) or ``"structure"``: the scene's form."""
        return self.header.get("form", "cells")

    @property
    def x_path(self):
        """The x axis's parameter as its JSON path (``structure.stops[0].gap_plus``), or
        ``None`` on the map over restitution and gap."""
        return self.header["grid"].get("x", {}).get("path")

    @property
    def y_path(self):
        """The y axis's parameter as its JSON path, or ``None`` on the map over restitution
        and gap."""
        return self.header["grid"].get("y", {}).get("path")

    @property
    def axes(self):
        """The grid's values by column, in the rows' order: ``{"x": …, "y": …, "omega": …}``
        over two parameters, ``{"restitution": …, "gap_over_base_amplitude": …, "omega": …}``
        over restitution and gap; each a ``float64`` array, ascending."""
        grid = self.header["grid"]
        return {
            name: _axis(axis["min"], axis["max"], axis["count"]) for name, axis in grid.items()
        }

    def _axes(self):
        return list(self.axes.items())

    def to_xarray(self):
        """As :meth:`Grid.to_xarray`, on the axes :attr:`axes`; over two parameters the
        Dataset's ``attrs`` hold ``x_path`` and ``y_path``."""
        ds = super().to_xarray()
        if self.x_path is not None:
            ds.attrs.update(x_path=self.x_path, y_path=self.y_path)
        return ds

    def body_amplitudes(self):
        """A structure's ``simulated_body_amplitudes`` as a dict of ``float64`` arrays, one
        per body by name in the scene's order (NaN where the command writes nothing). The map
        of a unit or a chain has no bodies: :class:`ValueError`."""
        if self.form != "structure":
            raise ValueError(
                "Map.body_amplitudes: the map of a unit or a chain has no bodies "
                "(its list column is per cell: simulated_cell_outer_amplitudes)"
            )
        bodies = self.header["bodies"]
        values = _np.full((len(self), len(bodies)), _np.nan)
        for i, cell in enumerate(self.columns["simulated_body_amplitudes"]):
            if cell:
                values[i] = [float(v) if v else _math.nan for v in cell.split(";")]
        return {name: values[:, k].copy() for k, name in enumerate(bodies)}

    def __repr__(self):
        return f"Map(points={len(self)}, shard={self.shard})"


class Basins(Grid):
    """``rattle basins --out F.json``: one row per start, the first coordinate slowest.
    Columns: the two starts' (``outer_start`` and ``inner_start`` on the unit's default
    plane; on a plane of two named coordinates ``NAME_start`` for a displacement and
    ``NAME_velocity_start`` for a velocity, e.g. ``ball_start``, ``ball_velocity_start``),
    ``attractor`` (numbered by first appearance in grid order), ``attractor_words``,
    ``outer_amplitude`` (on a chain the last cell's outer mass's, on a structure the observed
    body's), ``periods_run``, and on a chain or a structure ``body_amplitudes`` (every body's
    amplitude of the motion reached, in body order, a ``;``-separated ``str`` with an empty
    element for a body without one, as the command writes it). ``to_xarray()`` puts them on
    the axes of the two starts. A part's attractors are numbered within the part until
    merged; a part without starts names its start columns as the default plane's."""

    _table = "basins"

    def __init__(self, document):
        """Wraps the command's JSON document (the whole run's, or a part's)."""
        self.document = document
        data = _json.loads(document)
        rows = data.pop("results")
        self.header = data
        self.columns = _basins_columns(rows, data["scene"])

    def _axes(self):
        x, y = list(self.columns)[:2]
        n = round(_math.sqrt(len(self)))
        return [
            (x, self.columns[x][::n].copy()),
            (y, self.columns[y][:n].copy()),
        ]

    def __repr__(self):
        return f"Basins(starts={len(self)}, shard={self.shard})"


def _basins_columns(rows, scene):
    """The columns of a basins table from its rows (decoded JSON objects, in the command's
    column order), read-only: the two starts' (named by their coordinates, numbers), the
    others of the default plane's table with their kinds, and on a chain or a structure
    ``body_amplitudes`` (text). Without rows, the names come from the ``scene`` the document
    holds: the default plane's starts, and ``body_amplitudes`` unless it is a single unit."""
    kinds = dict(_rattle.table_kinds("basins"))
    if rows:
        names = list(rows[0])
    else:
        names = list(kinds)
        chain = (scene.get("cells") or 1) > 1 or len(scene.get("chain") or ()) > 1
        if "structure" in scene or chain:
            names.append("body_amplitudes")
    out = {}
    for k, name in enumerate(names):
        kind = "number" if k < 2 else kinds.get(name, "text")
        out[name] = _tables.column(kind, [r[name] for r in rows])
    for array in out.values():
        array.flags.writeable = False
    return out


def _axis(lo, hi, n):
    if n == 1:
        return _np.array([lo])
    values = _np.array([lo + (hi - lo) * i / (n - 1) for i in range(n)])
    values[-1] = hi
    return values


def merge(parts):
    """Joins the parts of a sharded sweep, map or basins into the whole run, as
    ``rattle merge``: ``parts`` are results (:class:`Map`, :class:`Basins`,
    :class:`~rattle.Sweep` parts) or their documents (``str``), in any order, all JSON or all
    CSV text. Returns the whole run as the type of its parts: a :class:`Map`,
    :class:`Basins` or :class:`~rattle.Sweep` whose ``document`` is byte for byte the one the
    whole run writes, equal to the whole run's result; for documents, the merged document
    (``str``). A part missing, repeated or from another run is a :class:`ValueError` with
    the command's message."""
    parts = list(parts)
    texts = [getattr(p, "document", p) for p in parts]
    if not texts:
        raise ValueError("no parts to merge")
    merged = _rattle.merge([t.decode() if isinstance(t, bytes) else str(t) for t in texts])
    results = {type(p) for p in parts if not isinstance(p, (str, bytes))}
    if len(results) == 1:
        (result,) = results
        if issubclass(result, (Grid, Sweep)):
            return result(merged)
    return merged


def _scene_json(scene):
    return _native_scene(scene).to_json()


def _native(scene_json):
    return _rattle.NativeScene.from_dict_json(scene_json, [])


def _map_part(scene_json, restitution, gap, omega, x, y, accuracy, part):
    """One part of a map, as a Dask task runs it: the part's JSON document."""
    return _rattle.map_document(
        _native(scene_json), restitution, gap, omega, *accuracy, part, x, y
    )


def _basins_part(scene_json, omega, outer, inner, points, axes, part):
    """One part of basins, as a Dask task runs it: the part's JSON document. ``axes`` are
    ``(x, y, x_min, x_max, y_min, y_max)``, as :func:`basins` takes them."""
    return _rattle.basins_document(_native(scene_json), omega, outer, inner, points, part, *axes)


#: The least work a task is given when a study is cut finer than :data:`TASK_SECONDS` to keep
#: every worker busy, seconds of one core.
MIN_TASK_SECONDS = 1.0


def parts_for(seconds, most, workers=1):
    """How many parts a study of ``seconds`` of one core is cut into for Dask: one per
    :data:`TASK_SECONDS`, or, for a study too small to give each of the ``workers`` one,
    one per worker as long as each keeps :data:`MIN_TASK_SECONDS`; at least one, at most
    ``most`` (a map's lines, basins' starts)."""
    parts = max(_math.ceil(seconds / TASK_SECONDS), min(workers, int(seconds / MIN_TASK_SECONDS)))
    return max(1, min(int(most), parts))


def _workers(client):
    """The client's workers now (0 when it cannot tell, e.g. jobs not yet started)."""
    try:
        return len(client.scheduler_info().get("workers", {}))
    except Exception:  # noqa: BLE001 - any client; only a hint for the number of parts
        return 0


def _on_client(client, function, args, count, label, progress, merge=None):
    """``function(*args, (K, count))`` for every K as Dask tasks on ``client``, gathered in
    order and merged (by ``merge``, ``rattle merge``'s join by default). A task that fails raises its error here; a worker lost while running
    one has it rerun by Dask elsewhere."""
    token = _uuid.uuid4().hex[:12]
    futures = [
        client.submit(function, *args, (k, count), key=f"rattle-{label}-{token}-{k}of{count}")
        for k in range(1, count + 1)
    ]
    if progress:
        _progress(futures, label, count)
    return (merge or _rattle.merge)(client.gather(futures))


def _progress(futures, label, count):
    """A notebook or terminal progress bar over the parts (tqdm, when installed)."""
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return
    from distributed import as_completed

    with tqdm(total=count, desc=f"rattle {label} parts") as bar:
        for _ in as_completed(futures):
            bar.update(1)


def _check_axis(name, value, size):
    try:
        items = tuple(value)
    except TypeError:
        items = ()
    if len(items) != size:
        raise ValueError(f"{name} must be a tuple of {size}, not {value!r}")
    return items


def _parameter_axis(name, value):
    """``(path, min, max, count)`` of a parameter axis, checked for its shape."""
    items = _check_axis(name, value, 4)
    if not isinstance(items[0], str):
        raise ValueError(f"{name}[0] must be the parameter's JSON path (a str), not {items[0]!r}")
    return (items[0], float(items[1]), float(items[2]), int(items[3]))


#: The command's default axes: restitution and gap over base amplitude, ``(min, max, count)``.
DEFAULT_RESTITUTION = (0.0, 1.0, 40)
DEFAULT_GAP = (0.05, 1.0, 40)


def map(
    scene,
    restitution=None,
    gap=None,
    omega=(0.1, 4.0, 400),
    max_periods=400,
    tol=None,
    steady_tol=None,
    client=None,
    shard=None,
    parts=None,
    progress=True,
    x=None,
    y=None,
):
    """The map over two scene parameters and frequency, as ``rattle map --out F.json``.

    By default over restitution and gap, as the command without ``--x``/``--y``:
    ``restitution``, ``gap`` (``Δ/u_g``) and ``omega`` (rad/s) are ``(min, max, count)``, the
    command's ``--restitution-min/-max``, ``--restitutions`` and so on, with the same defaults
    (``(0, 1, 40)``, ``(0.05, 1, 40)``, ``(0.1, 4, 400)``); the scene a unit or a chain with
    stops.

    ``x`` and ``y``: two parameters of a scene of any form, each ``(path, min, max, count)``
    with ``path`` the parameter's JSON path (``"structure.stops[0].gap_plus"``,
    ``"unit.inner_mass"``, ``"chain[2].stops.gap"``), the command's ``--x PATH --x-min
    --x-max --x-count`` and the same of ``--y``; each line's scene is the scene with both set.
    They come together, and without ``restitution`` and ``gap``. The columns are then ``x``
    and ``y``, the paths :attr:`Map.x_path` and :attr:`Map.y_path`. On a structure the
    simulator runs the structure, the observed body's amplitude and transmittance are the
    point's, every body's amplitude is listed (:meth:`Map.body_amplitudes`), and the analytic
    prediction is the linear steady state where it keeps every stop clear and the
    structure's free motion decays (none otherwise).

    ``max_periods``, ``tol``, ``steady_tol`` are the command's accuracy options (``None``: the
    command's defaults). Each line goes up in frequency, every point started from the previous
    one's final state; lines run in parallel on the Rust thread pool. Returns a :class:`Map`,
    whose ``document`` is the command's file byte for byte.

    ``shard=(K, N)``: part ``K`` of ``N`` only (a block of whole lines), as ``--shard K/N``;
    join parts with :func:`merge`.

    ``client``: a ``dask.distributed.Client`` (on a ``LocalCluster``, a ``dask-jobqueue``
    cluster, a scheduler's address). The map is cut into ``parts`` tasks of whole lines,
    each run on a worker (the Rust pool there), gathered in order and merged: the result is
    the single-machine one bit for bit. ``parts=None`` chooses one part per
    :data:`TASK_SECONDS` of estimated work (points × :data:`MAP_SECONDS_PER_POINT`), or
    one per worker for a smaller study (each at least :data:`MIN_TASK_SECONDS`), at most
    one per line (:func:`parts_for`). ``progress`` shows a bar over the parts (tqdm, when installed); the
    tasks show in the Dask dashboard as ``rattle-map-…``. A worker lost mid-run has its
    tasks rerun by Dask; an error in a task is raised here.

    A grid out of range is a :class:`ValueError` with the command's message, the field named
    as here (``gap[2]`` for ``--gaps``, ``x[0]`` for ``--x``, ``x[1]`` for ``--x-min``); so
    is a path the scene does not have, a parameter's value out of its range, a scene without
    stops on the default axes, and a structure without ``x`` and ``y``.
    """
    defaults = _rattle.map_defaults()
    accuracy = (
        float(defaults["tol"] if tol is None else tol),
        float(defaults["steady_tol"] if steady_tol is None else steady_tol),
        int(max_periods),
        float(defaults["max_oscillations"]),
    )
    omega = _check_axis("omega", omega, 3)
    omega = (float(omega[0]), float(omega[1]), int(omega[2]))
    if x is None and y is None:
        axes = [
            _check_axis(name, value, 3)
            for name, value in (
                ("restitution", DEFAULT_RESTITUTION if restitution is None else restitution),
                ("gap", DEFAULT_GAP if gap is None else gap),
            )
        ]
        stops = [(float(a), float(b), int(n)) for a, b, n in axes]
        parameters = (None, None)
        lines = stops[0][2] * stops[1][2]
    else:
        if x is None or y is None:
            given, missing = ("x", "y") if y is None else ("y", "x")
            raise ValueError(
                f"{given}[0] is given without {missing}[0]: a map over two parameters takes "
                f"both (x[0] PATH y[0] PATH)"
            )
        for name, value in (("restitution", restitution), ("gap", gap)):
            if value is not None:
                raise ValueError(
                    f"{name} is not taken with x and y: the map's axes are then the two "
                    "parameters"
                )
        parameters = (_parameter_axis("x", x), _parameter_axis("y", y))
        stops = [None, None]
        lines = parameters[0][3] * parameters[1][3]
    scene_json = _scene_json(scene)
    args = (scene_json, *stops, omega, *parameters, accuracy)
    if client is None or shard is not None:
        return Map(_map_part(*args, None if shard is None else tuple(shard)))
    # The checks of the whole map, before any task is sent.
    _map_part(*args, (1, 1 << 62))
    if parts is None:
        parts = parts_for(lines * omega[2] * MAP_SECONDS_PER_POINT, lines, _workers(client))
    document = _on_client(client, _map_part, args, int(parts), "map", progress)
    return Map(document)


def basins(
    scene,
    omega,
    outer=None,
    inner=None,
    points=200,
    client=None,
    shard=None,
    parts=None,
    progress=True,
    x=None,
    y=None,
    x_min=None,
    x_max=None,
    y_min=None,
    y_max=None,
):
    """Basins of attraction, as ``rattle basins --out F.json``: ``points × points`` starts,
    each run to its steady state at ``omega`` and numbered by the attractor it reaches.
    Returns a :class:`Basins`, whose ``document`` is the command's file byte for byte.

    The starts, as the command's flags give them (``None``: the flag left out, its default):

    - on the unit, its default plane: outer displacement over ``outer`` and inner over
      ``inner`` (``(min, max)``, m; ``--outer-min``… ``--inner-max``, default ``(-2, 2)``),
      the rest at rest;
    - on any scene, a plane over two coordinates: ``x`` and ``y`` (``--x``, ``--y``) each
      ``"u:NAME"`` (a body's displacement) or ``"v:NAME"`` (its velocity), over
      ``[x_min, x_max]`` and ``[y_min, y_max]`` (``--x-min``… ``--y-max``, m or m/s, default
      ±2), every other coordinate at rest, at time 0. Bodies are named ``outer`` and
      ``inner`` on the unit, ``outer0``, ``inner0``, ``outer1``… on a chain (cells from 0 at
      the base), by their own names on a structure. ``x`` and ``y`` are required on a chain or
      a structure; on the unit they default to ``"u:outer"`` and ``"u:inner"``, whose table is
      the default plane's. ``outer`` and ``inner`` belong to the unit's default plane: they
      are refused on a chain or a structure and with ``x``, ``y`` or their ranges.

    On a structure a start outside a stop's clearance is not run (its attractor says so); the
    table's columns are named by the coordinates, with every body's amplitude
    (:class:`Basins`).

    ``shard=(K, N)``: part ``K`` of ``N`` only (a block of starts in grid order; its
    attractors numbered within the part), as ``--shard K/N``; join parts with
    :func:`merge`, which numbers the attractors over the whole grid.

    ``client``: a ``dask.distributed.Client``; the grid is cut into ``parts`` tasks, gathered
    in order and merged, bit for bit the single-machine result. ``parts=None`` chooses the
    parts as :func:`map` does, from starts × :data:`BASINS_SECONDS_PER_START`. Every part first runs the grid's coarse reference
    starts (about one in a hundred, to the period cap), as the whole run does, so a part
    costs that much more than its own starts. Progress, faults and errors as :func:`map`.

    A bad ``omega``, ``points``, side or coordinate is a :class:`ValueError` with the
    command's message, the flag named as here (``outer[0]`` for ``--outer-min``, ``x_min``
    for ``--x-min``, ``x`` for ``--x``, listing the scene's coordinates).
    """
    outer = None if outer is None else tuple(float(v) for v in _check_axis("outer", outer, 2))
    inner = None if inner is None else tuple(float(v) for v in _check_axis("inner", inner, 2))
    axes = (
        None if x is None else str(x),
        None if y is None else str(y),
        *(None if v is None else float(v) for v in (x_min, x_max, y_min, y_max)),
    )
    args = (_scene_json(scene), float(omega), outer, inner, int(points), axes)
    if client is None or shard is not None:
        return Basins(_basins_part(*args, None if shard is None else tuple(shard)))
    # The checks of the whole grid, before any task is sent (an empty part computes nothing).
    _basins_part(*args, (1, 1 << 62))
    starts = int(points) ** 2
    if parts is None:
        parts = parts_for(starts * BASINS_SECONDS_PER_START, starts, _workers(client))
    return Basins(_on_client(client, _basins_part, args, int(parts), "basins", progress))


def _transmission_part(scene_json, args, part):
    """One part of a transmission estimate, as a Dask task runs it: the part's JSON text.
    ``args`` are the native call's after the scene (``rattle._transmission_args``)."""
    return _rattle.transmission_part(_native(scene_json), *args, part=part)


def _transmission_on_client(scene, args, client, parts, progress):
    """The document of :func:`rattle.transmission` with ``client=``: the request checked
    here (a part past the runs computes nothing but checks everything), then its runs cut
    into parts run as Dask tasks, gathered in order and merged."""
    scene_json = _scene_json(scene)
    empty = _json.loads(_transmission_part(scene_json, args, (1, 1 << 62)))
    runs = empty["total_runs"]
    if parts is None:
        seconds = runs * empty["settings"]["samples"] * TRANSMISSION_SECONDS_PER_SAMPLE
        parts = parts_for(seconds, runs, _workers(client))
    return _on_client(
        client,
        _transmission_part,
        (scene_json, args),
        int(parts),
        "transmission",
        progress,
        merge=_rattle.merge_transmission_parts,
    )
