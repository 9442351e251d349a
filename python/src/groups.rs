//! Face groups (object, group, material, smoothing) as a Python dict, and back from one.

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use pappus::mesh::groups::{FaceGroups, Group, GroupTable};

/// A mesh's face groups as Python sees them (`Mesh.face_groups`): a dict of `groups` (one
/// dict of `object`, `group`, `material`, `smoothing` per row, each a string or None), `face`
/// (each face's row, uint32, in `faces` order) and `material_libraries`; None without groups.
pub(crate) fn face_groups_dict<'py>(
    py: Python<'py>,
    groups: Option<&FaceGroups>,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(groups) = groups else {
        return Ok(None);
    };
    let rows = PyList::empty(py);
    for g in &groups.table.groups {
        let row = PyDict::new(py);
        row.set_item("object", &g.object)?;
        row.set_item("group", &g.group)?;
        row.set_item("material", &g.material)?;
        row.set_item("smoothing", &g.smoothing)?;
        rows.append(row)?;
    }
    let out = PyDict::new(py);
    out.set_item("groups", rows)?;
    out.set_item("face", PyArray1::from_slice(py, &groups.of_face))?;
    out.set_item("material_libraries", &groups.table.material_libraries)?;
    Ok(Some(out))
}

/// The inverse of [`face_groups_dict`].
pub(crate) fn face_groups_from(value: &Bound<'_, PyAny>) -> PyResult<FaceGroups> {
    let name = |row: &Bound<'_, PyAny>, key: &str| -> PyResult<Option<String>> {
        row.get_item(key)?.extract()
    };
    let mut table = GroupTable {
        material_libraries: value.get_item("material_libraries")?.extract()?,
        groups: Vec::new(),
    };
    for row in value.get_item("groups")?.try_iter()? {
        let row = row?;
        table.groups.push(Group {
            object: name(&row, "object")?,
            group: name(&row, "group")?,
            material: name(&row, "material")?,
            smoothing: name(&row, "smoothing")?,
        });
    }
    let face: PyReadonlyArray1<'_, u32> = value.get_item("face")?.extract()?;
    Ok(FaceGroups {
        table,
        of_face: face.as_array().to_vec(),
    })
}
