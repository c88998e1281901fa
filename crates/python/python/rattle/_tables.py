"""The command's tables as numpy columns, read from its JSON documents.

The columns and their types are the Rust row types' (``_rattle.table_kinds``): each column
of the command's table, in its order, with its kind, read from its field's Rust type, so that
no column is listed here by hand: ``number`` (``float64``, NaN where the command writes
``null``), ``count`` (``int64``, a count every row has), ``flag`` (``bool``, ``False`` where
the command writes ``null``), ``text`` (``object``: ``str`` or ``None``).
"""

import math as _math

import numpy as _np

from . import _rattle


def column(kind, values):
    """One column of ``kind`` from the rows' JSON values."""
    if kind == "number":
        return _np.array([_math.nan if v is None else v for v in values], dtype=_np.float64)
    if kind == "count":
        return _np.array(values, dtype=_np.int64)
    if kind == "flag":
        return _np.array([bool(v) for v in values], dtype=bool)
    out = _np.empty(len(values), dtype=object)
    out[:] = values
    return out


def columns(table, rows):
    """The columns of ``table`` (``"map"``, ``"basins"``, ``"sweep"``…) from its rows (decoded
    JSON objects), in the command's order, read-only."""
    out = {
        name: column(kind, [r[name] for r in rows])
        for name, kind in _rattle.table_kinds(table)
    }
    for array in out.values():
        array.flags.writeable = False
    return out
