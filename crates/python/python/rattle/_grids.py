"""Maps and basins, whole or cut into parts, on this machine or on a Dask cluster.

``rattle.map`` and ``rattle.basins`` are the commands ``rattle map`` and ``rattle basins`` on
the same library calls: each returns the command's ``--out F.json`` file as
:attr:`Grid.document` (byte for byte) and its columns as numpy arrays. ``shard=(K, N)``
computes part ``K`` of ``N`` as the command's ``--shard K/N``; :func:`merge` joins parts as
``rattle merge`` does. With ``client=`` (a ``dask.distributed.Client``) the study is cut into
parts that run as Dask tasks, gathered in order and merged: the result is the single-machine
one bit for bit, whatever the number of workers and parts.
"""

import json as _json
import math as _math
import uuid as _uuid

import numpy as _np

from . import _rattle, _tables

#: Seconds of one core per map point, as measured on this project's 2-core machine (the
#: performance page, docs/performance.md: 640 000 points of the lightly damped paper unit in 390 s on 2 threads):
#: used only to choose how many parts a study is cut into.
MAP_SECONDS_PER_POINT = 0.0012

#: Seconds of one core per basins start (docs/performance.md: 200 × 200 starts of the paper's unit at
#: ω = 1.9 rad/s in 10.7 s on 2 threads), for the same purpose.
BASINS_SECONDS_PER_START = 0.0005

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
    """``rattle map --out F.json``: one row per point, lines restitution-major, frequency
    ascending along each line. Columns as the command's (``restitution``,
    ``gap_over_base_amplitude``, ``omega``, ``simulated_regime``, …,
    ``lyapunov_regime``); ``to_xarray()`` puts them on the axes ``restitution``,
    ``gap_over_base_amplitude`` and ``omega``."""

    _table = "map"

    def _axes(self):
        grid = self.header["grid"]
        return [
            (name, _axis(grid[name]["min"], grid[name]["max"], grid[name]["count"]))
            for name in ("restitution", "gap_over_base_amplitude", "omega")
        ]

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
        from . import Sweep

        (result,) = results
        if issubclass(result, (Grid, Sweep)):
            return result(merged)
    return merged


def _scene_json(scene):
    from . import _native_scene

    return _native_scene(scene).to_json()


def _native(scene_json):
    return _rattle.NativeScene.from_dict_json(scene_json, [])


def _map_part(scene_json, restitution, gap, omega, accuracy, part):
    """One part of a map, as a Dask task runs it: the part's JSON document."""
    return _rattle.map_document(_native(scene_json), restitution, gap, omega, *accuracy, part)


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


def _on_client(client, function, args, count, label, progress):
    """``function(*args, (K, count))`` for every K as Dask tasks on ``client``, gathered in
    order and merged. A task that fails raises its error here; a worker lost while running
    one has it rerun by Dask elsewhere."""
    token = _uuid.uuid4().hex[:12]
    futures = [
        client.submit(function, *args, (k, count), key=f"rattle-{label}-{token}-{k}of{count}")
        for k in range(1, count + 1)
    ]
    if progress:
        _progress(futures, label, count)
    return _rattle.merge(client.gather(futures))


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


def map(
    scene,
    restitution=(0.0, 1.0, 40),
    gap=(0.05, 1.0, 40),
    omega=(0.1, 4.0, 400),
    max_periods=400,
    tol=None,
    steady_tol=None,
    client=None,
    shard=None,
    parts=None,
    progress=True,
):
    """The map over restitution, gap and frequency, as ``rattle map --out F.json``.

    ``restitution``, ``gap`` (``Δ/u_g``) and ``omega`` (rad/s) are ``(min, max, count)``,
    the command's ``--restitution-min/-max``, ``--restitutions`` and so on, with the same
    defaults; ``max_periods``, ``tol``, ``steady_tol`` its accuracy options (``None``: the
    command's defaults). Each ``(restitution, gap)`` line goes up in frequency, every point
    started from the previous one's final state; lines run in parallel on the Rust thread
    pool. Returns a :class:`Map`, whose ``document`` is the command's file byte for byte.

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
    as here (``gap[2]`` for ``--gaps``); a scene without stops too, and a scene in the
    structure form (the map's axes are a unit's restitution and gap), naming ``rattle.map``.
    """
    defaults = _rattle.map_defaults()
    accuracy = (
        float(defaults["tol"] if tol is None else tol),
        float(defaults["steady_tol"] if steady_tol is None else steady_tol),
        int(max_periods),
        float(defaults["max_oscillations"]),
    )
    axes = [
        _check_axis(name, value, 3)
        for name, value in (("restitution", restitution), ("gap", gap), ("omega", omega))
    ]
    axes = [(float(a), float(b), int(n)) for a, b, n in axes]
    scene_json = _scene_json(scene)
    if client is None or shard is not None:
        return Map(_map_part(scene_json, *axes, accuracy, None if shard is None else tuple(shard)))
    # The checks of the whole map, before any task is sent.
    _rattle.map_document(_native(scene_json), *axes, *accuracy, (1, 1 << 62))
    lines = axes[0][2] * axes[1][2]
    if parts is None:
        parts = parts_for(lines * axes[2][2] * MAP_SECONDS_PER_POINT, lines, _workers(client))
    document = _on_client(
        client, _map_part, (scene_json, *axes, accuracy), int(parts), "map", progress
    )
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
