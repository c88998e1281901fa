"""Non-periodic excitation: the response to a signal and the transmissibility under random base motion."""

import json as _json

import numpy as _np

from . import _rattle, _tables
from ._records import Record, Table
from ._scene import _native_scene


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
