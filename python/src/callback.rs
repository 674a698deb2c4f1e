//! A Python function as the surface: `f(x, y, z)` (or `f(x, y)` for curves) called on
//! numpy arrays of coordinates, so it can be evaluated on whole batches. It has no
//! interval extension: intervals are the whole line (no pruning, nothing proven), the
//! gradient is a central difference, `is_rigorous` is false, and `certmesh::mesher::run`
//! therefore never lets a mesher certify anything computed from it.
use certmesh::implicit::{Dual, Hyper, IBox, Implicit, Regularity};
use inari::Interval;
use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;
use std::panic::resume_unwind;

/// The payload of the unwinding that stops a run when the Python function raised:
/// the exception itself, re-raised by the caller.
pub struct CallbackFailed(pub PyErr);

pub struct PyFunction {
    f: Py<PyAny>,
    dim: usize,
}

impl PyFunction {
    pub fn new(f: Py<PyAny>, dim: usize) -> Self {
        PyFunction { f, dim }
    }

    /// f at every point (coordinate slices `p[0][i], p[1][i], p[2][i]`), in one call
    /// of the Python function.
    fn call(&self, p: [&[f64]; 3], out: &mut [f64]) {
        let n = out.len();
        let r = Python::attach(|py| -> PyResult<()> {
            let coords: Vec<_> = (0..self.dim)
                .map(|k| p[k].to_vec().into_pyarray(py))
                .collect();
            let v = self.f.call1(py, pyo3::types::PyTuple::new(py, coords)?)?;
            let np = py.import("numpy")?;
            let a = np.call_method1("asarray", (v.bind(py), "float64"))?;
            if a.getattr("ndim")?.extract::<usize>()? > 1 {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "the function must return one value per point (a 1-D array), got shape {}",
                    a.getattr("shape")?.str()?
                )));
            }
            let a = np.call_method1("broadcast_to", (a, (n,)))?;
            let a: Bound<'_, numpy::PyArray1<f64>> = np
                .call_method1("ascontiguousarray", (a,))?
                .cast_into()
                .map_err(PyErr::from)?;
            out.copy_from_slice(a.readonly().as_slice()?);
            Ok(())
        });
        if let Err(e) = r {
            resume_unwind(Box::new(CallbackFailed(e)));
        }
    }

    fn one(&self, p: [f64; 3]) -> f64 {
        let mut v = [0.0];
        self.call([&[p[0]], &[p[1]], &[p[2]]], &mut v);
        v[0]
    }

    /// Central differences: the values at p ± h e_k in one batch.
    fn gradient(&self, p: [f64; 3]) -> Dual<f64> {
        let mut out = [Dual { v: 0.0, g: [0.0; 3] }];
        self.gradients(&[p], &mut out);
        out[0]
    }

    /// Central differences at every point: one call of the Python function for the
    /// values at all points and at p ± h e_k (1 + 2·dim per point).
    fn gradients(&self, pts: &[[f64; 3]], out: &mut [Dual<f64>]) {
        let per = 1 + 2 * self.dim;
        let mut c: [Vec<f64>; 3] = Default::default();
        let mut hs = Vec::with_capacity(pts.len());
        for &p in pts {
            let h: [f64; 3] = [0, 1, 2].map(|k| 1e-6 * p[k].abs().max(1.0));
            let mut push = |q: [f64; 3]| (0..3).for_each(|k| c[k].push(q[k]));
            push(p);
            for k in 0..self.dim {
                for s in [1.0, -1.0] {
                    let mut q = p;
                    q[k] += s * h[k];
                    push(q);
                }
            }
            hs.push(h);
        }
        let mut v = vec![0.0; c[0].len()];
        self.call([&c[0], &c[1], &c[2]], &mut v);
        for (i, (o, h)) in out.iter_mut().zip(&hs).enumerate() {
            let w = &v[i * per..(i + 1) * per];
            let mut g = [0.0; 3];
            for k in 0..self.dim {
                g[k] = (w[1 + 2 * k] - w[2 + 2 * k]) / (2.0 * h[k]);
            }
            *o = Dual { v: w[0], g };
        }
    }
}

impl Implicit for PyFunction {
    fn dim(&self) -> usize {
        self.dim
    }
    fn eval(&self, p: [f64; 3]) -> f64 {
        self.one(p)
    }
    /// One call of the Python function for the whole batch.
    fn eval_batch(&self, p: [&[f64]; 3], out: &mut [f64]) {
        self.call(p, out)
    }
    /// Nothing is known: the whole line (so no box is ever pruned or certified).
    fn eval_interval(&self, _b: &IBox) -> Interval {
        Interval::ENTIRE
    }
    fn grad(&self, p: [f64; 3]) -> Dual<f64> {
        self.gradient(p)
    }
    /// One call of the Python function for the whole batch (central differences).
    fn grad_batch(&self, p: &[[f64; 3]], out: &mut [Dual<f64>]) {
        assert!(p.len() == out.len(), "batch slices of different lengths");
        self.gradients(p, out)
    }
    fn grad_interval(&self, _b: &IBox) -> Dual<Interval> {
        Dual {
            v: Interval::ENTIRE,
            g: [Interval::ENTIRE; 3],
        }
    }
    fn hessian(&self, p: [f64; 3]) -> Hyper<f64> {
        let d = self.gradient(p);
        Hyper {
            v: d.v,
            g: d.g,
            h: [f64::NAN; 6],
        }
    }
    fn hessian_interval(&self, _b: &IBox) -> Hyper<Interval> {
        Hyper {
            v: Interval::ENTIRE,
            g: [Interval::ENTIRE; 3],
            h: [Interval::ENTIRE; 6],
        }
    }
    fn is_rigorous(&self) -> bool {
        false
    }
    /// Nothing is proven about a Python function.
    fn regularity(&self, _b: &IBox) -> Regularity {
        Regularity::Undefined
    }
    fn describe(&self) -> String {
        Python::attach(|py| {
            self.f
                .bind(py)
                .getattr("__name__")
                .and_then(|n| n.extract::<String>())
                .map(|n| format!("<python function {n}>"))
                .unwrap_or_else(|_| "<python function>".into())
        })
    }
}
