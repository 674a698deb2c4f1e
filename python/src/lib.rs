//! `certmesh._certmesh`: the Rust side of the Python package. It hands the library's
//! typed results to Python as numpy arrays (moved, not copied, where the layout allows)
//! and JSON texts (the same documents the command line prints with `--json`); the
//! Python package (`python/certmesh/`) wraps them in objects. Nothing is judged here:
//! certificates come from the meshers, reports from `certmesh::harness`.
use certmesh::harness::{compare, report, target};
use certmesh::implicit::{Formula, Implicit};
use certmesh::mesh::{Curve2, TetMesh, TriMesh};
use certmesh::mesher::{self, registry, Mesh};
use numpy::{IntoPyArray, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

mod callback;
mod options;
mod proofs_api;
mod run;

create_exception!(
    certmesh,
    CertmeshError,
    PyValueError,
    "A certmesh error: bad input (formula, domain, options, file) or a run that failed. The message is the command line's."
);

pub(crate) fn err(e: certmesh::error::Error) -> PyErr {
    CertmeshError::new_err(e.to_string())
}

fn json<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_string(v).expect("reports serialise to JSON")
}

/// (N, 3) float64 from the mesh's vertices, moving the buffer into numpy (no copy).
fn points3<'py>(py: Python<'py>, v: Vec<[f64; 3]>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = v.len();
    v.into_flattened().into_pyarray(py).reshape([n, 3])
}

fn points2<'py>(py: Python<'py>, v: Vec<[f64; 2]>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = v.len();
    v.into_flattened().into_pyarray(py).reshape([n, 2])
}

/// (M, K) int64 from u32 index tuples (a widening copy: numpy's default index type).
fn cells<'py, const K: usize>(
    py: Python<'py>,
    v: &[[u32; K]],
) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let flat: Vec<i64> = v.iter().flatten().map(|&i| i as i64).collect();
    flat.into_pyarray(py).reshape([v.len(), K])
}

/// Index tuples from an (M, K) integer array, each checked against `n` vertices.
fn read_cells<const K: usize>(a: PyReadonlyArray2<'_, i64>, n: usize) -> PyResult<Vec<[u32; K]>> {
    let s = a.shape();
    if s[1] != K {
        return Err(CertmeshError::new_err(format!(
            "expected an (M, {K}) index array, got shape {s:?}"
        )));
    }
    let a = a.as_array();
    let mut out = Vec::with_capacity(s[0]);
    for (r, row) in a.outer_iter().enumerate() {
        let mut c = [0u32; K];
        for (k, &i) in row.iter().enumerate() {
            if i < 0 || i as usize >= n {
                return Err(CertmeshError::new_err(format!(
                    "row {r}: vertex index {i} out of range (there are {n} vertices)"
                )));
            }
            c[k] = i as u32;
        }
        out.push(c);
    }
    Ok(out)
}

fn read_points<const D: usize>(a: PyReadonlyArray2<'_, f64>) -> PyResult<Vec<[f64; D]>> {
    let s = a.shape();
    if s[1] != D {
        return Err(CertmeshError::new_err(format!(
            "expected an (N, {D}) float array of points, got shape {s:?}"
        )));
    }
    let mut out = Vec::with_capacity(s[0]);
    for (r, row) in a.as_array().outer_iter().enumerate() {
        let mut p = [0.0; D];
        for (k, &x) in row.iter().enumerate() {
            if !x.is_finite() {
                return Err(CertmeshError::new_err(format!(
                    "point {r}: coordinate {k} is {x}, not a finite number"
                )));
            }
            p[k] = x;
        }
        out.push(p);
    }
    Ok(out)
}

/// The target of a run: a catalog name, a formula, or a Python callable, on `domain`
/// (empty: the catalog's box or the default box).
fn resolve(
    surface: Option<String>,
    formula: Option<String>,
    function: Option<Py<PyAny>>,
    domain: Option<Vec<f64>>,
    dim: usize,
) -> PyResult<target::Target> {
    let domain = domain.unwrap_or_default();
    let source =
        match (&surface, formula, function) {
            (Some(n), None, None) => target::Source::Catalog(n),
            (None, Some(t), None) => target::Source::Function {
                name: "formula".into(),
                f: Box::new(Formula::with_dim(&t, dim).map_err(err)?),
            },
            (None, None, Some(c)) => target::Source::Function {
                name: "python".into(),
                f: Box::new(callback::PyFunction::new(c, dim)),
            },
            (None, None, None) => return Err(CertmeshError::new_err(
                "give a catalog surface (see certmesh.surfaces()), formula=, or a Python function",
            )),
            _ => {
                return Err(CertmeshError::new_err(
                    "give one of: a catalog surface, formula=, or a Python function",
                ))
            }
        };
    target::resolve(source, &domain, dim).map_err(err)
}

/// One mesher run. Returns a dict: `kind` ("surface", "volume", "curve"), the arrays,
/// and `report` (the JSON of `certmesh mesh --json`, or of the run alone when
/// `report=False`).
#[pyfunction]
#[pyo3(signature = (dim, algo, surface=None, formula=None, function=None, domain=None, options="{}", report=true, metrics="fast", progress=None))]
#[allow(clippy::too_many_arguments)]
fn mesh<'py>(
    py: Python<'py>,
    dim: usize,
    algo: &str,
    surface: Option<String>,
    formula: Option<String>,
    function: Option<Py<PyAny>>,
    domain: Option<Vec<f64>>,
    options: &str,
    report: bool,
    metrics: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = options::parse(options)?;
    let metrics = compare::Metrics::parse(metrics).map_err(err)?;
    let m = registry::build(algo, dim, &opts).map_err(err)?;
    let t = resolve(surface, formula, function, domain, dim)?;
    let (run, doc) = run::interruptible(py, progress.as_ref(), |c| {
        let f = run::Guarded {
            f: t.f.as_ref(),
            control: c,
        };
        let run = mesher::run(m.as_ref(), &f, &t.domain, c).map_err(|e| e.to_string())?;
        let doc = if report {
            let r = report::mesh_report(
                &t.name,
                &f,
                &t.domain,
                t.domain_source,
                t.entry.as_ref().and_then(|e| e.topology.as_ref()),
                &run,
                metrics,
            )
            .map_err(|e| e.to_string())?;
            json(&r)
        } else {
            json(&serde_json::json!({
                "surface": t.name,
                "algo": run.algo,
                "dim": dim,
                "seconds": run.seconds,
                "evaluations": run.evaluations.total(),
                "evaluation_counts": run.evaluations,
                "certified": run.output.certificate.is_certified(),
                "certificate": run.output.certificate,
                "stats": run.output.stats,
                "domain": t.domain,
                "domain_source": t.domain_source,
            }))
        };
        Ok((run, doc))
    })?;
    let d = PyDict::new(py);
    d.set_item("report", doc)?;
    match run.output.mesh {
        Mesh::Surface(m) => {
            d.set_item("kind", "surface")?;
            d.set_item("faces", cells(py, &m.triangles)?)?;
            d.set_item("points", points3(py, m.vertices)?)?;
        }
        Mesh::Volume { tets, boundary } => {
            d.set_item("kind", "volume")?;
            d.set_item("tets", cells(py, &tets.tets)?)?;
            d.set_item("points", points3(py, tets.vertices)?)?;
            d.set_item("boundary_faces", cells(py, &boundary.triangles)?)?;
            d.set_item("boundary_points", points3(py, boundary.vertices)?)?;
        }
        Mesh::Curve(c) => {
            d.set_item("kind", "curve")?;
            d.set_item("segments", cells(py, &c.segments)?)?;
            d.set_item("points", points2(py, c.vertices)?)?;
        }
    }
    Ok(d)
}

/// Write a mesh with the project's writers (the format from the extension). `cells`
/// is (M, 3) triangles, (M, 4) tetrahedra or (M, 2) curve segments.
#[pyfunction]
#[pyo3(signature = (path, points, cells, boundary_points=None, boundary_faces=None))]
fn write_mesh(
    path: std::path::PathBuf,
    points: PyReadonlyArray2<'_, f64>,
    cells: PyReadonlyArray2<'_, i64>,
    boundary_points: Option<PyReadonlyArray2<'_, f64>>,
    boundary_faces: Option<PyReadonlyArray2<'_, i64>>,
) -> PyResult<()> {
    let k = cells.shape()[1];
    let mesh = match k {
        2 => {
            let vertices = read_points::<2>(points)?;
            let n = vertices.len();
            Mesh::Curve(Curve2 {
                vertices,
                segments: read_cells::<2>(cells, n)?,
            })
        }
        3 => {
            let vertices = read_points::<3>(points)?;
            let n = vertices.len();
            Mesh::Surface(TriMesh::new(vertices, read_cells::<3>(cells, n)?))
        }
        4 => {
            let vertices = read_points::<3>(points)?;
            let n = vertices.len();
            let tets = TetMesh {
                vertices,
                tets: read_cells::<4>(cells, n)?,
            };
            let boundary = match (boundary_points, boundary_faces) {
                (Some(p), Some(f)) => {
                    let v = read_points::<3>(p)?;
                    let n = v.len();
                    TriMesh::new(v, read_cells::<3>(f, n)?)
                }
                _ => TriMesh::new(Vec::new(), Vec::new()),
            };
            Mesh::Volume { tets, boundary }
        }
        _ => {
            return Err(CertmeshError::new_err(format!(
                "cells must have 2 (segments), 3 (triangles) or 4 (tetrahedra) columns, got {k}"
            )))
        }
    };
    certmesh::io::write_mesh(&path, &mesh).map_err(err)
}

/// The statistics of a triangle mesh (`certmesh stats --json`), judged against a
/// catalog surface or a formula when one is given.
#[pyfunction]
#[pyo3(signature = (points, faces, surface=None, formula=None))]
fn stats(
    py: Python<'_>,
    points: PyReadonlyArray2<'_, f64>,
    faces: PyReadonlyArray2<'_, i64>,
    surface: Option<String>,
    formula: Option<String>,
) -> PyResult<String> {
    let vertices = read_points::<3>(points)?;
    let n = vertices.len();
    let m = TriMesh::new(vertices, read_cells::<3>(faces, n)?);
    let entry = surface
        .as_deref()
        .map(certmesh::catalog::get)
        .transpose()
        .map_err(err)?;
    let f: Option<Box<dyn Implicit>> = match (&entry, formula) {
        (Some(_), Some(_)) => {
            return Err(CertmeshError::new_err(
                "give surface= or formula=, not both",
            ))
        }
        (Some(e), None) => Some(Box::new(e.function())),
        (None, Some(t)) => Some(Box::new(Formula::with_dim(&t, 3).map_err(err)?)),
        (None, None) => None,
    };
    let mut params = certmesh::metrics::FidelityParams::default();
    if let Some(e) = &entry {
        params = params.domain(e.domain);
    }
    run::interruptible(py, None, |c| {
        let g = f.as_deref().map(|f| run::Guarded { f, control: c });
        let s = certmesh::metrics::stats_with(&m, g.as_ref().map(|g| g as &dyn Implicit), &params)
            .map_err(|e| e.to_string())?;
        let verdict = match &entry {
            Some(e) => match (&e.topology, certmesh::metrics::analyze(&m)) {
                (Some(t), Ok(r)) => Some(certmesh::metrics::verdict(&r, t)),
                _ => None,
            },
            None => None,
        };
        Ok(json(&report::StatsReport::new(s, verdict)))
    })
}

/// The comparison matrix (`certmesh compare --json`): one record per (surface, algo).
#[pyfunction]
#[pyo3(signature = (surfaces, algos, options="{}", progress=None))]
fn compare_runs(
    py: Python<'_>,
    surfaces: Vec<String>,
    algos: Vec<String>,
    options: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    let opts = options::parse(options)?;
    let entries = surfaces
        .iter()
        .map(|n| certmesh::catalog::get(n))
        .collect::<Result<Vec<_>, _>>()
        .map_err(err)?;
    for a in &algos {
        if !registry::list().iter().any(|i| i.name == a.as_str()) {
            return Err(CertmeshError::new_err(format!(
                "unknown algorithm '{a}' (see certmesh.algorithms())"
            )));
        }
    }
    run::interruptible(py, progress.as_ref(), |c| {
        Ok(json(&compare::compare(&entries, &algos, &opts, c)))
    })
}

/// The certified Morse census of a surface (`certmesh morse --json`).
#[pyfunction]
#[pyo3(signature = (surface=None, formula=None, domain=None, height=None, max_boxes=None))]
fn morse(
    py: Python<'_>,
    surface: Option<String>,
    formula: Option<String>,
    domain: Option<Vec<f64>>,
    height: Option<[f64; 3]>,
    max_boxes: Option<usize>,
) -> PyResult<String> {
    let t = resolve(surface, formula, None, domain, 3)?;
    let mut opts = certmesh::morse::MorseOptions::default();
    if let Some(n) = max_boxes {
        if n == 0 {
            return Err(CertmeshError::new_err("max_boxes must be at least 1"));
        }
        opts = opts.with_max_boxes(n);
    }
    if let Some(h) = height {
        let norm = h.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(CertmeshError::new_err(format!(
                "height needs a non-zero direction, got {h:?}"
            )));
        }
        opts.direction = Some(h);
    }
    run::interruptible(py, None, |c| {
        let f = run::Guarded {
            f: t.f.as_ref(),
            control: c,
        };
        let domain = certmesh::implicit::critical::Bx::from(t.domain);
        let r = certmesh::morse::analyze(&f, domain, &opts);
        let mut v = serde_json::to_value(&r).map_err(|e| e.to_string())?;
        if let Some(o) = v.as_object_mut() {
            o.insert("surface".into(), t.name.clone().into());
            o.insert("formula".into(), t.f.describe().into());
            o.insert(
                "expected_chi".into(),
                serde_json::json!(t.entry.as_ref().and_then(|e| e.euler_characteristic())),
            );
        }
        Ok(json(&v))
    })
}

/// The topological-ball-property certificate of any triangle mesh against f = 0
/// (`certmesh certify --json`): the report, and the certified restricted Delaunay
/// triangulation of the mesh's vertices as arrays.
#[pyfunction]
#[pyo3(signature = (points, faces, surface=None, formula=None, domain=None, max_boxes=None))]
fn certify<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'_, f64>,
    faces: PyReadonlyArray2<'_, i64>,
    surface: Option<String>,
    formula: Option<String>,
    domain: Option<Vec<f64>>,
    max_boxes: Option<u32>,
) -> PyResult<Bound<'py, PyDict>> {
    use certmesh::restricted_delaunay::certify::{certify_mesh, CertifyOptions};
    let vertices = read_points::<3>(points)?;
    let n = vertices.len();
    let m = TriMesh::new(vertices, read_cells::<3>(faces, n)?);
    let t = resolve(surface, formula, None, domain, 3)?;
    let mut o = CertifyOptions::default();
    if let Some(b) = max_boxes {
        if b == 0 {
            return Err(CertmeshError::new_err("max_boxes must be at least 1"));
        }
        o.tbp.cover.max_boxes = b;
    }
    let (doc, rdt) = run::interruptible(py, None, |c| {
        let f = run::Guarded {
            f: t.f.as_ref(),
            control: c,
        };
        let (r, rdt) = certify_mesh(&m, &f, &t.domain, &o).map_err(|e| e.to_string())?;
        let mut v = serde_json::to_value(&r).map_err(|e| e.to_string())?;
        if let Some(obj) = v.as_object_mut() {
            obj.insert("surface".into(), t.name.clone().into());
            obj.insert("domain".into(), serde_json::json!(t.domain));
        }
        Ok((json(&v), rdt))
    })?;
    let d = PyDict::new(py);
    d.set_item("report", doc)?;
    d.set_item("faces", cells(py, &rdt.triangles)?)?;
    d.set_item("points", points3(py, rdt.vertices)?)?;
    Ok(d)
}

/// The catalog (`certmesh surfaces` and `certmesh curves`) as JSON.
#[pyfunction]
fn catalog() -> String {
    json(&certmesh::catalog::entries())
}

/// The registered algorithms as JSON (name, dim, certifying, summary, options read).
#[pyfunction]
fn algorithms() -> String {
    json(&registry::list())
}

/// The names of the options `mesh(..., **params)` accepts.
#[pyfunction]
fn option_names() -> Vec<String> {
    options::names()
}

#[pymodule]
fn _certmesh(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("CertmeshError", m.py().get_type::<CertmeshError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(mesh, m)?)?;
    m.add_function(wrap_pyfunction!(write_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(stats, m)?)?;
    m.add_function(wrap_pyfunction!(compare_runs, m)?)?;
    m.add_function(wrap_pyfunction!(morse, m)?)?;
    m.add_function(wrap_pyfunction!(certify, m)?)?;
    m.add_function(wrap_pyfunction!(catalog, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms, m)?)?;
    m.add_function(wrap_pyfunction!(option_names, m)?)?;
    proofs_api::register(m)?;
    Ok(())
}
