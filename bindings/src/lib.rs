//! Python bindings: `slipstep._engine.solve(model: dict, progress=None) -> dict`.
//! Only translation between numpy/dict and the engine's records lives here; the event loop
//! runs in Rust with the GIL released (it re-attaches every `report_interval` seconds to call
//! the progress callback, and at the next increment after a Ctrl-C).

use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use slipstep_core::dim::{Dim, Planar, PlaneSection, Spatial};
use slipstep_core::error::ErrorKind;
use slipstep_core::material::{Material, Plane, PLANAR};
use slipstep_core::mesh::Mesh;
use slipstep_core::model::*;
use slipstep_core::options;
use std::sync::{Arc, Mutex};
use std::time::Instant;

mod interrupt;

fn get<'py>(d: &Bound<'py, PyDict>, key: &str) -> PyResult<Bound<'py, PyAny>> {
    d.get_item(key)?.ok_or_else(|| input_error(format!("engine model: missing key '{key}'")))
}

/// Rows of a float64 (n, cols) array, each padded with zeros to three components.
fn f64_2d(d: &Bound<'_, PyDict>, key: &str, cols: usize) -> PyResult<Vec<[f64; 3]>> {
    let arr: PyReadonlyArray2<f64> = get(d, key)?.extract().map_err(|_| {
        input_error(format!("engine model: '{key}' must be a float64 array of shape (n, {cols})"))
    })?;
    let a = arr.as_array();
    if a.ncols() != cols {
        return Err(input_error(format!("engine model: '{key}' must have {cols} columns")));
    }
    Ok(a.rows()
        .into_iter()
        .map(|r| std::array::from_fn(|k| if k < cols { r[k] } else { 0.0 }))
        .collect())
}

/// Rows of an int64 (m, cols) array of node indices.
fn index_rows<const C: usize>(d: &Bound<'_, PyDict>, key: &str) -> PyResult<Vec<[usize; C]>> {
    let arr: PyReadonlyArray2<i64> = get(d, key)?.extract().map_err(|_| {
        input_error(format!("engine model: '{key}' must be an int64 array of shape (m, {C})"))
    })?;
    let a = arr.as_array();
    if a.ncols() != C {
        return Err(input_error(format!("engine model: '{key}' must have {C} columns")));
    }
    a.rows()
        .into_iter()
        .map(|r| {
            let mut row = [0usize; C];
            for k in 0..C {
                row[k] = to_index(r[k], key)?;
            }
            Ok(row)
        })
        .collect()
}

/// A model of the dimension the dict gives (`dimension`: 2 when absent), read once here: every
/// later step is generic over it (`slipstep_core::dim`).
enum Scene {
    Plane(Model<Planar>),
    Space(Model<Spatial>),
}

/// The model of the dict's dimension: nodes (N, 2), triangles (M, 3), `plane` and `thickness`;
/// or nodes (N, 3) and tetrahedra (M, 4). A key of the other dimension is refused by name.
fn read_scene(d: &Bound<'_, PyDict>) -> PyResult<Scene> {
    let dimension: i64 = match d.get_item("dimension")? {
        Some(v) => v
            .extract()
            .map_err(|_| input_error("engine model: 'dimension' must be an int, 2 or 3"))?,
        None => 2,
    };
    let refuse = |keys: &[&str], what: &str| -> PyResult<()> {
        match keys.iter().find(|k| d.contains(**k).unwrap_or(false)) {
            Some(k) => {
                Err(input_error(format!("engine model: '{k}' is a key of {what}; remove it")))
            }
            None => Ok(()),
        }
    };
    match dimension {
        2 => {
            refuse(&["tetrahedra"], "3D models (dimension = 3), not of this 2D one")?;
            let nodes = f64_2d(d, "nodes", 2)?.into_iter().map(|p| [p[0], p[1]]).collect();
            let mesh = Mesh::new(nodes, index_rows::<3>(d, "triangles")?);
            let section = || -> PyResult<PlaneSection> {
                Ok(PlaneSection {
                    plane: read_plane(d)?,
                    thickness: get(d, "thickness")?.extract()?,
                })
            };
            Ok(Scene::Plane(read_model(d, mesh, section)?))
        }
        3 => {
            refuse(
                &["triangles", "plane", "thickness"],
                "2D models, not of a 3D one (dimension = 3)",
            )?;
            let mesh = Mesh::new(f64_2d(d, "nodes", 3)?, index_rows::<4>(d, "tetrahedra")?);
            Ok(Scene::Space(read_model(d, mesh, || Ok(()))?))
        }
        other => Err(input_error(format!("engine model: dimension = {other}: use 2 or 3"))),
    }
}

fn i64_1d(d: &Bound<'_, PyDict>, key: &str) -> PyResult<Vec<i64>> {
    let arr: PyReadonlyArray1<i64> = get(d, key)?
        .extract()
        .map_err(|_| input_error(format!("engine model: '{key}' must be an int64 array")))?;
    Ok(arr.as_array().to_vec())
}

fn f64_1d(d: &Bound<'_, PyDict>, key: &str) -> PyResult<Vec<f64>> {
    let arr: PyReadonlyArray1<f64> = get(d, key)?
        .extract()
        .map_err(|_| input_error(format!("engine model: '{key}' must be a float64 array")))?;
    Ok(arr.as_array().to_vec())
}

fn to_index(v: i64, what: &str) -> PyResult<usize> {
    usize::try_from(v)
        .map_err(|_| input_error(format!("engine model: negative index {v} in {what}")))
}

/// The materials E, nu and, when plastic, Sy and H.
fn read_materials(d: &Bound<'_, PyDict>) -> PyResult<Vec<Material>> {
    let mut materials = Vec::new();
    for m in get(d, "materials")?.cast::<PyList>()?.iter() {
        let m = m.cast::<PyDict>()?;
        let young: f64 = get(m, "E")?.extract()?;
        let poisson: f64 = get(m, "nu")?.extract()?;
        let mut mat = Material::elastic(young, poisson);
        if let Some(sy) = m.get_item("Sy")? {
            if !sy.is_none() {
                mat.yield_stress = sy.extract()?;
            }
        }
        if let Some(h) = m.get_item("H")? {
            if !h.is_none() {
                mat.hardening = h.extract()?;
            }
        }
        materials.push(mat);
    }
    Ok(materials)
}

/// The model of `mesh`, with the `section` its dimension reads (after the materials): everything
/// else a dict gives, the same in both dimensions.
fn read_model<D: Dim>(
    d: &Bound<'_, PyDict>,
    mesh: Mesh<D>,
    section: impl FnOnce() -> PyResult<D::Section>,
) -> PyResult<Model<D>> {
    let dim = D::N;
    let element_material = i64_1d(d, "element_material")?
        .into_iter()
        .map(|v| to_index(v, "element_material"))
        .collect::<PyResult<_>>()?;
    let materials = read_materials(d)?;
    let section = section()?;
    let fixed_dofs = i64_1d(d, "fixed_dofs")?
        .into_iter()
        .map(|v| to_index(v, "fixed_dofs"))
        .collect::<PyResult<_>>()?;
    let load = f64_1d(d, "load")?;
    let mut pairs = Vec::new();
    if let Some(p) = d.get_item("pairs")? {
        let p = p.cast::<PyDict>()?;
        let a = i64_1d(p, "node_a")?;
        let b = i64_1d(p, "node_b")?;
        let normal = f64_2d(p, "normal", dim)?;
        let tangents = read_tangents(p, dim, a.len())?;
        let gap = f64_1d(p, "gap")?;
        let mu = f64_1d(p, "mu")?;
        let n = a.len();
        let contact = match p.get_item("contact")? {
            Some(_) => Some(
                i64_1d(p, "contact")?
                    .into_iter()
                    .map(|v| to_index(v, "pairs.contact"))
                    .collect::<PyResult<Vec<_>>>()?,
            ),
            None => None,
        };
        if [b.len(), normal.len(), gap.len(), mu.len()].iter().any(|&l| l != n)
            || contact.as_ref().map_or(false, |c| c.len() != n)
        {
            return Err(input_error(
                "engine model: the pair arrays node_a, node_b, normal, gap, mu differ in length",
            ));
        }
        let weights = read_pair_weights(p, n)?;
        for k in 0..n {
            pairs.push(PairInput {
                node_a: to_index(a[k], "pairs.node_a")?,
                node_b: if b[k] < 0 { None } else { Some(b[k] as usize) },
                normal: normal[k],
                tangents: tangents.as_ref().map(|t| t[k]),
                gap: gap[k],
                mu: mu[k],
                contact: contact.as_ref().map_or(0, |c| c[k]),
                weights: weights[k].clone(),
            });
        }
    }
    let options = read_options(d)?;
    let names = read_names(d)?;
    let (patterns, stages) = read_path(d, dim)?;
    Ok(Model {
        mesh,
        element_material,
        materials,
        section,
        fixed_dofs,
        load,
        patterns,
        stages,
        pairs,
        names,
        options,
    })
}

fn read_plane(d: &Bound<'_, PyDict>) -> PyResult<Plane> {
    match get(d, "plane")?.extract::<String>()?.as_str() {
        "strain" => Ok(Plane::Strain),
        "stress" => Ok(Plane::Stress),
        "axisymmetric" => Ok(Plane::Axisymmetric),
        other => Err(input_error(format!(
            "engine model: plane = '{other}': use 'strain', 'stress' or 'axisymmetric'"
        ))),
    }
}

/// The optional `pairs.tangent` (P, 2, 3) of a 3D model (a 2D model's is refused by name).
fn read_tangents(
    p: &Bound<'_, PyDict>,
    dim: usize,
    n: usize,
) -> PyResult<Option<Vec<[[f64; 3]; 2]>>> {
    let Some(t) = p.get_item("tangent")? else { return Ok(None) };
    if dim != 3 {
        return Err(input_error(
            "engine model: 'pairs.tangent' is a key of 3D models (dimension = 3); remove it",
        ));
    }
    let arr: numpy::PyReadonlyArray3<f64> = t.extract().map_err(|_| {
        input_error("engine model: 'pairs.tangent' must be a float64 array of shape (P, 2, 3)")
    })?;
    let a = arr.as_array();
    if a.shape() != [n, 2, 3] {
        return Err(input_error(format!(
            "engine model: 'pairs.tangent' has shape {:?}, not (P, 2, 3) = ({n}, 2, 3)",
            a.shape()
        )));
    }
    Ok(Some(
        (0..n).map(|k| std::array::from_fn(|i| std::array::from_fn(|c| a[[k, i, c]]))).collect(),
    ))
}

/// Node-to-segment pairs' weights, in compressed rows (optional keys `weight_ptr` (P+1),
/// `weight_node`, `weight_value`); pairs without weights get an empty list.
fn read_pair_weights(p: &Bound<'_, PyDict>, n: usize) -> PyResult<Vec<Vec<(usize, f64)>>> {
    if p.get_item("weight_ptr")?.is_none() {
        return Ok(vec![vec![]; n]);
    }
    let ptr = i64_1d(p, "weight_ptr")?;
    let nodes = i64_1d(p, "weight_node")?;
    let values = f64_1d(p, "weight_value")?;
    let bad = ptr.len() != n + 1
        || nodes.len() != values.len()
        || ptr.windows(2).any(|w| w[0] > w[1])
        || ptr.first() != Some(&0)
        || ptr.last().map_or(true, |&e| e as usize != nodes.len());
    if bad {
        return Err(input_error("engine model: pairs.weight_ptr must have P+1 non-decreasing entries from 0 to len(weight_node) = len(weight_value)"));
    }
    (0..n)
        .map(|k| {
            (ptr[k] as usize..ptr[k + 1] as usize)
                .map(|i| Ok((to_index(nodes[i], "pairs.weight_node")?, values[i])))
                .collect()
        })
        .collect()
}

/// The load path: optional `patterns` (list of dict) and `stages` (list of dict), see
/// docs/engine_api.md.
fn read_path(d: &Bound<'_, PyDict>, dim: usize) -> PyResult<(Vec<LoadPattern>, Vec<Stage>)> {
    let list = |key: &str| -> PyResult<Vec<Bound<'_, PyDict>>> {
        match d.get_item(key)? {
            None => Ok(vec![]),
            Some(v) => v
                .cast::<PyList>()
                .map_err(|_| input_error(format!("engine model: '{key}' must be a list of dict")))?
                .iter()
                .map(|x| {
                    x.cast_into::<PyDict>().map_err(|_| {
                        input_error(format!("engine model: '{key}' must be a list of dict"))
                    })
                })
                .collect(),
        }
    };
    let optional =
        |p: &Bound<'_, PyDict>, key: &str| -> PyResult<bool> { Ok(p.get_item(key)?.is_some()) };
    let mut patterns = Vec::new();
    for p in list("patterns")? {
        let name: String = get(&p, "name")?.extract()?;
        let force = if optional(&p, "force")? { f64_1d(&p, "force")? } else { vec![] };
        let mut displacement = Vec::new();
        if optional(&p, "displacement_dofs")? {
            let dofs = i64_1d(&p, "displacement_dofs")?;
            let values = f64_1d(&p, "displacement_values")?;
            if dofs.len() != values.len() {
                return Err(input_error(format!("engine model: pattern '{name}': displacement_dofs and displacement_values differ in length")));
            }
            for (dof, v) in dofs.into_iter().zip(values) {
                displacement.push((to_index(dof, "displacement_dofs")?, v));
            }
        }
        let mut motion = Vec::new();
        if optional(&p, "motion_contacts")? {
            let contacts = i64_1d(&p, "motion_contacts")?;
            let m = f64_2d(&p, "motion", dim)?;
            if contacts.len() != m.len() {
                return Err(input_error(format!(
                    "engine model: pattern '{name}': motion_contacts and motion differ in length"
                )));
            }
            for (c, v) in contacts.into_iter().zip(m) {
                motion.push((to_index(c, "motion_contacts")?, v));
            }
        }
        patterns.push(LoadPattern { name, force, displacement, motion });
    }
    let mut stages = Vec::new();
    for s in list("stages")? {
        let name = match s.get_item("name")? {
            Some(v) if !v.is_none() => v.extract()?,
            _ => String::new(),
        };
        stages.push(Stage { name, factors: f64_1d(&s, "factors")? });
    }
    Ok((patterns, stages))
}

/// The solver options (key "options"): each key of `slipstep_core::options::SPECS`, read as its
/// kind and checked by `Options::set` (absent keys keep their defaults, an unknown key is an
/// input error), and the snapshot request (`output`, with `times` or `fractions`).
fn read_options(d: &Bound<'_, PyDict>) -> PyResult<Options> {
    let mut options = Options::default();
    let Some(o) = d.get_item("options")? else { return Ok(options) };
    let o = o.cast::<PyDict>()?;
    for (key, v) in o.iter() {
        let key: String = key.extract()?;
        let value = match options::spec(&key).map(|s| s.kind) {
            _ if matches!(key.as_str(), "output" | "times" | "fractions") => continue,
            Some(options::Kind::Real) => options::Value::Real(v.extract()?),
            Some(options::Kind::Count) => options::Value::Count(v.extract()?),
            Some(options::Kind::Flag) => options::Value::Flag(v.extract()?),
            Some(options::Kind::Choice(_)) => options::Value::Choice(v.extract()?),
            None => options::Value::Real(f64::NAN), // `set` names the unknown key
        };
        options.set(&key, value).map_err(|e| python_error(d.py(), &e))?;
    }
    if let Some(v) = o.get_item("output")? {
        options.snapshots = match v.extract::<String>()?.as_str() {
            "events" => SnapshotRequest::EveryEvent,
            "times" => SnapshotRequest::Times(f64_1d(o, "times")?),
            "fractions" => SnapshotRequest::Times(f64_1d(o, "fractions")?),
            other => {
                return Err(input_error(format!(
                    "engine model: options.output = '{other}': use 'events' or 'times'"
                )))
            }
        };
    }
    Ok(options)
}

/// The declaration of every solver option (`slipstep_core::options::SPECS`), for the case
/// schema's `[solver]` table: a list of dicts with key, kind ("real", "count", "flag"),
/// default, min and max (None or (value, inclusive)) and doc.
#[pyfunction]
fn option_specs(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for s in options::SPECS {
        let d = PyDict::new(py);
        d.set_item("key", s.key)?;
        let kind = match s.kind {
            options::Kind::Real => "real",
            options::Kind::Count => "count",
            options::Kind::Flag => "flag",
            options::Kind::Choice(_) => "choice",
        };
        d.set_item("kind", kind)?;
        match s.kind {
            options::Kind::Real => d.set_item("default", s.default)?,
            options::Kind::Count => d.set_item("default", s.default as i64)?,
            options::Kind::Flag => d.set_item("default", s.default != 0.0)?,
            options::Kind::Choice(names) => {
                d.set_item("default", names[s.default as usize])?;
                d.set_item("choices", names.to_vec())?;
            }
        }
        d.set_item("min", s.min.map(|e| (e.value, e.inclusive)))?;
        d.set_item("max", s.max.map(|e| (e.value, e.inclusive)))?;
        d.set_item("doc", s.doc)?;
        list.append(d)?;
    }
    Ok(list)
}

/// The case's names for messages (optional keys body_names, element_body, contact_names).
fn read_names(d: &Bound<'_, PyDict>) -> PyResult<Names> {
    let strings = |key: &str| -> PyResult<Vec<String>> {
        match d.get_item(key)? {
            Some(v) => v
                .extract()
                .map_err(|_| input_error(format!("engine model: '{key}' must be a list of str"))),
            None => Ok(vec![]),
        }
    };
    let element_body = match d.get_item("element_body")? {
        Some(_) => i64_1d(d, "element_body")?
            .into_iter()
            .map(|v| to_index(v, "element_body"))
            .collect::<PyResult<_>>()?,
        None => vec![],
    };
    let supports = match d.get_item("support_dofs")? {
        None => vec![],
        Some(v) => {
            let names = strings("support_names")?;
            let groups: Vec<PyReadonlyArray1<i64>> = v.extract().map_err(|_| {
                input_error("engine model: 'support_dofs' must be a list of int64 arrays")
            })?;
            if groups.len() != names.len() {
                return Err(input_error(format!(
                    "engine model: 'support_dofs' has {} groups for {} support_names",
                    groups.len(),
                    names.len()
                )));
            }
            let dofs = groups.iter().map(|g| {
                g.as_array()
                    .iter()
                    .map(|&v| to_index(v, "support_dofs"))
                    .collect::<PyResult<Vec<_>>>()
            });
            names.into_iter().zip(dofs).map(|(n, d)| Ok((n, d?))).collect::<PyResult<_>>()?
        }
    };
    Ok(Names {
        bodies: strings("body_names")?,
        element_body,
        contacts: strings("contact_names")?,
        supports,
    })
}

fn result_to_dict<'py>(py: Python<'py>, r: RunResult) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let ev = PyDict::new(py);
    ev.set_item(
        "step",
        r.events.iter().map(|e| e.step as i64).collect::<Vec<_>>().into_pyarray(py),
    )?;
    ev.set_item(
        "load_fraction",
        r.events.iter().map(|e| e.load_fraction).collect::<Vec<_>>().into_pyarray(py),
    )?;
    ev.set_item("t", r.events.iter().map(|e| e.time).collect::<Vec<_>>().into_pyarray(py))?;
    ev.set_item(
        "stage",
        r.events.iter().map(|e| e.stage as i64).collect::<Vec<_>>().into_pyarray(py),
    )?;
    ev.set_item("kind", r.events.iter().map(|e| e.kind.name()).collect::<Vec<_>>())?;
    ev.set_item(
        "entity",
        r.events.iter().map(|e| e.entity as i64).collect::<Vec<_>>().into_pyarray(py),
    )?;
    out.set_item("events", ev)?;
    let st = PyDict::new(py);
    st.set_item(
        "load_fraction",
        r.steps.iter().map(|s| s.load_fraction).collect::<Vec<_>>().into_pyarray(py),
    )?;
    st.set_item("t", r.steps.iter().map(|s| s.time).collect::<Vec<_>>().into_pyarray(py))?;
    st.set_item(
        "stage",
        r.steps.iter().map(|s| s.stage as i64).collect::<Vec<_>>().into_pyarray(py),
    )?;
    st.set_item("scale", r.steps.iter().map(|s| s.scale).collect::<Vec<_>>().into_pyarray(py))?;
    st.set_item(
        "residual",
        r.steps.iter().map(|s| s.residual).collect::<Vec<_>>().into_pyarray(py),
    )?;
    st.set_item(
        "n_closed",
        r.steps.iter().map(|s| s.n_closed as i64).collect::<Vec<_>>().into_pyarray(py),
    )?;
    st.set_item(
        "n_stick",
        r.steps.iter().map(|s| s.n_stick as i64).collect::<Vec<_>>().into_pyarray(py),
    )?;
    st.set_item(
        "n_slip",
        r.steps.iter().map(|s| s.n_slip as i64).collect::<Vec<_>>().into_pyarray(py),
    )?;
    st.set_item(
        "normal_force",
        r.steps.iter().map(|s| s.normal_force).collect::<Vec<_>>().into_pyarray(py),
    )?;
    st.set_item(
        "n_plastic",
        r.steps.iter().map(|s| s.n_plastic as i64).collect::<Vec<_>>().into_pyarray(py),
    )?;
    st.set_item("drift", r.steps.iter().map(|s| s.drift).collect::<Vec<_>>().into_pyarray(py))?;
    // the resultants (issue 38): (S, C, dim) forces, moments (S, C, 3) in 3D and M_z (S, C) in
    // 2D, reactions (S, G, dim) per support group, works (S, 1 + patterns)
    let dim = r.dim;
    let rows = |per: fn(&StepRecord) -> &Vec<[f64; 3]>, width: usize, cols: &[usize]| {
        let data: Vec<f64> = r
            .steps
            .iter()
            .flat_map(|s| per(s).iter().flat_map(|v| cols.iter().map(|&k| v[k])))
            .collect();
        numpy::ndarray::Array3::from_shape_vec((r.steps.len(), width, cols.len()), data).unwrap()
    };
    let n_contacts = r.steps.first().map_or(0, |s| s.contact_force.len());
    let n_supports = r.steps.first().map_or(0, |s| s.reaction.len());
    let n_loads = r.steps.first().map_or(0, |s| s.load_work.len());
    let components: &[usize] = if dim == 3 { &[0, 1, 2] } else { &[0, 1] };
    st.set_item(
        "contact_force",
        rows(|s| &s.contact_force, n_contacts, components).into_pyarray(py),
    )?;
    if dim == 3 {
        st.set_item(
            "contact_moment",
            rows(|s| &s.contact_moment, n_contacts, &[0, 1, 2]).into_pyarray(py),
        )?;
    } else {
        let mz = rows(|s| &s.contact_moment, n_contacts, &[2])
            .into_shape_with_order((r.steps.len(), n_contacts))
            .unwrap();
        st.set_item("contact_moment", mz.into_pyarray(py))?;
    }
    st.set_item("reaction", rows(|s| &s.reaction, n_supports, components).into_pyarray(py))?;
    let work: Vec<f64> = r.steps.iter().flat_map(|s| s.load_work.iter().copied()).collect();
    st.set_item(
        "load_work",
        Array2::from_shape_vec((r.steps.len(), n_loads), work).unwrap().into_pyarray(py),
    )?;
    out.set_item("steps", st)?;
    let snaps = PyList::empty(py);
    for s in r.snapshots {
        let d = PyDict::new(py);
        d.set_item("load_fraction", s.load_fraction)?;
        d.set_item("t", s.time)?;
        d.set_item("stage", s.stage)?;
        let (dim, n) = (s.dim, s.u.len() / s.dim);
        d.set_item(
            "reaction",
            Array2::from_shape_vec((n, dim), s.reaction).unwrap().into_pyarray(py),
        )?;
        d.set_item("u", Array2::from_shape_vec((n, dim), s.u).unwrap().into_pyarray(py))?;
        let m = s.stress.len();
        // 2D: (σx, σy, σz, τxy) of the six; 3D: all six in Voigt order
        let columns: &[usize] = if dim == 3 { &[0, 1, 2, 3, 4, 5] } else { &PLANAR };
        let stress: Vec<f64> =
            s.stress.iter().flat_map(|row| columns.iter().map(move |&k| row[k])).collect();
        d.set_item(
            "stress",
            Array2::from_shape_vec((m, columns.len()), stress).unwrap().into_pyarray(py),
        )?;
        d.set_item("plastic_strain", s.plastic_strain.into_pyarray(py))?;
        d.set_item("plastic", Array1::from(s.plastic).into_pyarray(py))?;
        d.set_item("lambda_n", s.lambda_n.into_pyarray(py))?;
        d.set_item("status", Array1::from(s.status).into_pyarray(py))?;
        d.set_item("gap", s.gap.into_pyarray(py))?;
        if dim == 3 {
            // (P, 2) in each pair's (t1, t2)
            let two = |a: Vec<f64>, b: Vec<f64>| {
                Array2::from_shape_vec(
                    (a.len(), 2),
                    a.into_iter().zip(b).flat_map(|(x, y)| [x, y]).collect(),
                )
                .unwrap()
            };
            d.set_item("lambda_t", two(s.lambda_t, s.lambda_t2).into_pyarray(py))?;
            d.set_item("rtd", two(s.rtd, s.rtd2).into_pyarray(py))?;
        } else {
            d.set_item("lambda_t", s.lambda_t.into_pyarray(py))?;
            d.set_item("rtd", s.rtd.into_pyarray(py))?;
        }
        snaps.append(d)?;
    }
    out.set_item("snapshots", snaps)?;
    out.set_item("closure_fraction", r.closure_fraction.into_pyarray(py))?;
    out.set_item("predicted_closure", r.predicted_closure.into_pyarray(py))?;
    out.set_item("max_equilibrium_residual", r.max_equilibrium_residual)?;
    out.set_item("max_drift", r.max_drift)?;
    out.set_item("n_factorizations", r.n_factorizations)?;
    out.set_item("n_factor_builds", r.n_factor_builds)?;
    out.set_item("n_solves", r.n_solves)?;
    out.set_item("n_low_rank_updates", r.n_low_rank_updates)?;
    out.set_item("n_contact_substeps", r.n_contact_substeps)?;
    out.set_item("n_retaken_windows", r.n_retaken_windows)?;
    let stop = PyDict::new(py);
    stop.set_item("kind", r.stop.name())?;
    stop.set_item("message", r.stop.message())?;
    stop.set_item("load_fraction", r.steps.last().map_or(0.0, |s| s.load_fraction))?;
    stop.set_item("t", r.steps.last().map_or(0.0, |s| s.time))?;
    out.set_item("n_stages", r.stage_names.len())?;
    out.set_item("stage_names", r.stage_names.clone())?;
    out.set_item("interrupted", matches!(r.stop, StopReason::Interrupted { .. }))?;
    out.set_item(
        "stop_reason",
        match r.stop {
            StopReason::LimitLoad { .. }
            | StopReason::EventBound { .. }
            | StopReason::SupportLost { .. } => r.stop.message(),
            _ => None,
        },
    )?;
    out.set_item("stop", stop)?;
    out.set_item("n_rate_problems", r.n_rate_problems)?;
    let t = PyDict::new(py);
    t.set_item("assembly", r.timings.assembly)?;
    t.set_item("factorization", r.timings.factorization)?;
    t.set_item("solves", r.timings.solves)?;
    t.set_item("events", r.timings.events)?;
    t.set_item("flexibility", r.timings.flexibility)?;
    t.set_item("dense", r.timings.dense)?;
    t.set_item("low_rank", r.timings.low_rank)?;
    t.set_item("integration", r.timings.integration)?;
    t.set_item("corrections", r.timings.corrections)?;
    t.set_item("solve_pair", r.timings.solve_pair)?;
    out.set_item("timings", t)?;
    Ok(out)
}

/// Run the adaptive incremental procedure on `model` (see docs/engine_api.md).
///
/// `progress`: None or False (no reports), or a callable `progress(events, steps, t)`, called
/// between increments at most every `report_interval` seconds (0: after every increment but
/// the last), with the GIL held; the event loop runs with it released. Returning False stops
/// the run like Ctrl-C does (`stop.kind == "interrupted"`, the partial result is returned).
/// Ctrl-C (SIGINT, also a KeyboardInterrupt the callback raises) stops the run the same way at
/// the next increment; one that arrives during the last increment, when nothing is left to
/// stop, is reported as `stop.late_interrupt` with the complete result. Any other exception the
/// callback raises stops the run and is re-raised. Inside an increment that takes long (a
/// rate problem, say) the callback is called with the last increment's progress at most every
/// `max(report_interval, PULSE_S)` seconds, and Ctrl-C stops the run there too.
///
/// A run that fails inside its loop raises its error (`slipstep.errors`) with the results up to
/// its last completed increment as the exception's `result` (the same dict); a panic (an
/// engine bug) is an `InternalError`, never a Rust panic.
#[pyfunction]
#[pyo3(signature = (model, progress = None, report_interval = 0.1))]
fn solve<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyDict>,
    progress: Option<Bound<'py, PyAny>>,
    report_interval: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let reporting = Arc::new(Reporting {
        callback: progress_callback(progress)?,
        last: Mutex::new(None),
        failure: Mutex::new(None),
    });
    let scene = read_scene(model).map_err(|e| malformed(py, e))?;
    slipstep_core::interrupt::clear();
    let watch = interrupt::Watch::start(py);
    let mut trigger = interrupt::TestTrigger::from_env();
    let pulsing = reporting.clone();
    slipstep_core::interrupt::pulse(Some((
        Box::new(move || pulsing.pulse()),
        report_interval.max(PULSE_S),
    )));
    let result = py.detach(|| {
        let mut last_report = Instant::now();
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let mut progress = |p: Progress| {
                trigger.after_increment(p.events);
                *lock(&reporting.last) = Some(p);
                slipstep_core::interrupt::touch();
                if !watch.take() && last_report.elapsed().as_secs_f64() < report_interval {
                    return true;
                }
                last_report = Instant::now();
                reporting.report(&p)
            };
            match &scene {
                Scene::Plane(model) => slipstep_core::run(model, &mut progress),
                Scene::Space(model) => slipstep_core::run(model, &mut progress),
            }
        }))
    });
    slipstep_core::interrupt::pulse(None);
    slipstep_core::interrupt::arm(None);
    slipstep_core::interrupt::clear();
    trigger.at_end();
    drop(watch);
    let result = result.map_err(|panic| python_error(py, &engine_bug(panic.as_ref())))?;
    if let Some(e) = lock(&reporting.failure).take() {
        if !e.is_instance_of::<PyKeyboardInterrupt>(py) {
            return Err(e);
        }
    }
    let r = result.map_err(|e| python_error(py, &e))?;
    match &r.stop {
        StopReason::Interrupted { .. } => {
            pending_interrupt(py)?; // taken where a checkpoint inside an increment saw it first
        }
        StopReason::Failed { error, .. } => {
            let raised = python_error(py, error);
            raised.value(py).setattr("result", result_to_dict(py, r.clone())?)?;
            return Err(raised);
        }
        _ => {}
    }
    let late = r.stop == StopReason::Completed && pending_interrupt(py)?;
    let out = result_to_dict(py, r)?;
    if late {
        out.get_item("stop")?
            .expect("result_to_dict writes stop")
            .set_item("late_interrupt", true)?;
    }
    Ok(out)
}

/// Progress inside an increment is reported at most this often (s), whatever `report_interval`.
const PULSE_S: f64 = 0.25;

/// The progress callback and what it has seen, shared by the event loop's reports and the
/// engine's pulse inside long increments.
struct Reporting {
    callback: Option<Py<PyAny>>,
    /// The last increment's progress (None before the first).
    last: Mutex<Option<Progress>>,
    /// An exception the callback raised (the run stops).
    failure: Mutex<Option<PyErr>>,
}

impl Reporting {
    /// Report `p` with the GIL; false (stop the run) when the callback asks or raised.
    fn report(&self, p: &Progress) -> bool {
        Python::attach(|py| report(py, self.callback.as_ref(), p)).unwrap_or_else(|e| {
            *lock(&self.failure) = Some(e);
            false
        })
    }

    /// Inside a long increment: report the last progress; a stop asked then stops the engine at
    /// its next checkpoint.
    fn pulse(&self) {
        let p = lock(&self.last).unwrap_or(Progress { steps: 0, events: 0, t: 0.0 });
        if !self.report(&p) {
            slipstep_core::interrupt::request();
        }
    }
}

/// A mutex's value, also after a panic poisoned it.
fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// A panic outside the event loop (which turns its own into a failed stop) as the bug it is.
fn engine_bug(payload: &(dyn std::any::Any + Send)) -> slipstep_core::Error {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown".into());
    slipstep_core::Error::new(ErrorKind::Internal, format!("an engine bug stopped the run before it began ({what}); please report it with the case"))
}

/// A Ctrl-C that arrived during the last increment, when nothing was left to stop: taken here
/// (so Python does not raise it over the complete result) and reported as
/// `stop.late_interrupt`. Another exception a signal handler raises is raised.
fn pending_interrupt(py: Python<'_>) -> PyResult<bool> {
    match py.check_signals() {
        Ok(()) => Ok(false),
        Err(e) if e.is_instance_of::<PyKeyboardInterrupt>(py) => Ok(true),
        Err(e) => Err(e),
    }
}

/// The progress argument: None/False = no callback; a callable; anything else is an input error.
fn progress_callback(progress: Option<Bound<'_, PyAny>>) -> PyResult<Option<Py<PyAny>>> {
    match progress {
        None => Ok(None),
        Some(p) if p.is_none() || p.extract::<bool>().ok() == Some(false) => Ok(None),
        Some(p) if p.is_callable() => Ok(Some(p.unbind())),
        Some(p) => Err(input_error(format!(
            "progress = {}: give None or a callable progress(events, steps, t)",
            p.repr().map(|r| r.to_string()).unwrap_or_default()
        ))),
    }
}

/// One report between increments: Ctrl-C first, then the callback. Ok(false) = stop the run.
fn report(py: Python<'_>, callback: Option<&Py<PyAny>>, p: &Progress) -> PyResult<bool> {
    py.check_signals()?;
    let Some(callback) = callback else { return Ok(true) };
    let answer = callback.call1(py, (p.events, p.steps, p.t))?;
    Ok(answer.is_none(py) || answer.is_truthy(py)?)
}

/// Any failure while reading the model dict (a wrong type pyo3 could not extract, say) is an
/// input error of the model, not a bug of the caller's Python.
fn malformed(py: Python<'_>, e: PyErr) -> PyErr {
    let already = py
        .import("slipstep.errors")
        .and_then(|m| m.getattr("InputError"))
        .map(|c| e.is_instance(py, &c))
        .unwrap_or(false);
    if already {
        e
    } else {
        input_error(format!("engine model: {}", e.value(py)))
    }
}

/// A malformed model dict: `slipstep.errors.InputError` (ValueError if that cannot be imported).
fn input_error(message: impl Into<String>) -> PyErr {
    let message = message.into();
    Python::attach(|py| python_error(py, &slipstep_core::Error::new(ErrorKind::Input, message)))
}

/// The engine's error as the exception class of `slipstep.errors` for its kind (ValueError, or
/// RuntimeError for an internal error, when that module cannot be imported).
fn python_error(py: Python<'_>, e: &slipstep_core::Error) -> PyErr {
    let class = match e.kind {
        ErrorKind::Input => "InputError",
        ErrorKind::FreeBody => "FreeBodyError",
        ErrorKind::GrossSliding => "GrossSlidingError",
        ErrorKind::Singular => "SingularSystemError",
        ErrorKind::Equilibrium => "EquilibriumError",
        ErrorKind::IllPosed => "IllPosedError",
        ErrorKind::Internal => "InternalError",
        ErrorKind::Interrupted => "InternalError", // never raised: an interrupted run returns
    };
    let raised = py
        .import("slipstep.errors")
        .and_then(|m| m.getattr(class))
        .and_then(|c| c.call1((e.message.clone(),)));
    match raised {
        Ok(exc) => PyErr::from_value(exc),
        Err(_) if e.kind == ErrorKind::Internal => {
            pyo3::exceptions::PyRuntimeError::new_err(e.message.clone())
        }
        Err(_) => PyValueError::new_err(e.message.clone()),
    }
}

#[pymodule]
fn _engine(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // A panic is caught and raised as an InternalError naming it; Rust's own report on stderr
    // (two lines and a backtrace hint) only with SLIPSTEP_TRACE, for diagnosis.
    let rust_report = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if slipstep_core::error::tracing() {
            rust_report(info);
        }
    }));
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    m.add_function(wrap_pyfunction!(option_specs, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
