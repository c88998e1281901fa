//! `rattle.merge`'s native half: the parts of a sharded sweep, map or basins joined as
//! `rattle merge` joins them.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rattle_compare::runs::shard::merge as merge_parts;

/// `rattle merge`: the parts of a sharded sweep, map or basins (documents as text, all JSON
/// or all CSV, any order) joined into exactly the document of the whole run.
#[pyfunction]
fn merge(py: Python<'_>, parts: Vec<String>) -> PyResult<String> {
    py.detach(|| merge_parts(&parts))
        .map_err(PyValueError::new_err)
}

/// Registers `merge`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(merge, m)?)
}
