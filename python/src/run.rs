//! Long runs from Python: the work runs on its own thread with the GIL released; the
//! calling thread polls every 50 ms for Ctrl-C (`Python::check_signals`) and forwards
//! progress to a Python callback. Interrupting sets a flag that every evaluation of f
//! (and every progress step) checks; the worker then unwinds with [`Interrupted`]
//! (`resume_unwind`: no panic message) and the call raises `KeyboardInterrupt`.
use certmesh::implicit::{Dual, Hyper, IBox, Implicit, Regularity};
use certmesh::mesher::Progress;
use inari::Interval;
use pyo3::prelude::*;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// The payload of the unwinding that stops an interrupted run.
pub struct Interrupted;

/// Shared between the worker and the polling thread.
#[derive(Default)]
pub struct Control {
    stop: AtomicBool,
    phase: Mutex<String>,
    done: AtomicU64,
    total: AtomicU64,
    /// Called once when the run is interrupted (e.g. to exhaust a proof's budget, for
    /// work that does not evaluate f through [`Guarded`]).
    hooks: Mutex<Vec<Box<dyn Fn() + Send>>>,
}

impl Control {
    /// Run `f` when the run is interrupted.
    pub fn on_stop(&self, f: impl Fn() + Send + 'static) {
        if let Ok(mut h) = self.hooks.lock() {
            h.push(Box::new(f));
        }
    }
    fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Ok(h) = self.hooks.lock() {
            h.iter().for_each(|f| f());
        }
    }
    /// Unwind the worker if the run was interrupted.
    #[inline]
    pub fn check(&self) {
        if self.stop.load(Ordering::Relaxed) {
            resume_unwind(Box::new(Interrupted));
        }
    }
}

impl Progress for Control {
    fn start(&self, phase: &str, total: u64) {
        self.check();
        if let Ok(mut p) = self.phase.lock() {
            *p = phase.to_string();
        }
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }
    fn inc(&self, n: u64) {
        self.check();
        self.done.fetch_add(n, Ordering::Relaxed);
    }
}

/// f, checking for an interrupt at every evaluation (one relaxed atomic load).
pub struct Guarded<'a> {
    pub f: &'a dyn Implicit,
    pub control: &'a Control,
}

impl Implicit for Guarded<'_> {
    fn dim(&self) -> usize {
        self.f.dim()
    }
    fn eval(&self, p: [f64; 3]) -> f64 {
        self.control.check();
        self.f.eval(p)
    }
    fn eval_interval(&self, b: &IBox) -> Interval {
        self.control.check();
        self.f.eval_interval(b)
    }
    fn eval_batch(&self, p: [&[f64]; 3], out: &mut [f64]) {
        self.control.check();
        self.f.eval_batch(p, out)
    }
    fn eval_interval_batch(&self, b: &[IBox], out: &mut [Interval]) {
        self.control.check();
        self.f.eval_interval_batch(b, out)
    }
    fn grad(&self, p: [f64; 3]) -> Dual<f64> {
        self.control.check();
        self.f.grad(p)
    }
    fn grad_batch(&self, p: &[[f64; 3]], out: &mut [Dual<f64>]) {
        self.control.check();
        self.f.grad_batch(p, out)
    }
    fn grad_interval(&self, b: &IBox) -> Dual<Interval> {
        self.control.check();
        self.f.grad_interval(b)
    }
    fn hessian(&self, p: [f64; 3]) -> Hyper<f64> {
        self.control.check();
        self.f.hessian(p)
    }
    fn hessian_interval(&self, b: &IBox) -> Hyper<Interval> {
        self.control.check();
        self.f.hessian_interval(b)
    }
    fn is_rigorous(&self) -> bool {
        self.f.is_rigorous()
    }
    fn regularity(&self, b: &IBox) -> Regularity {
        self.f.regularity(b)
    }
    fn describe(&self) -> String {
        self.f.describe()
    }
    fn expression(&self) -> Option<&certmesh::implicit::Expr> {
        self.f.expression()
    }
}

/// Run `work` with the GIL released, Ctrl-C honoured and progress forwarded to
/// `progress(phase, done, total)` (a Python callable, or None).
pub fn interruptible<T: Send>(
    py: Python<'_>,
    progress: Option<&Py<PyAny>>,
    work: impl FnOnce(&Control) -> Result<T, String> + Send,
) -> PyResult<T> {
    let control = Control::default();
    let progress = progress.map(|p| p.clone_ref(py));
    py.detach(|| {
        std::thread::scope(|s| {
            let c = &control;
            let (done_tx, done_rx) = std::sync::mpsc::channel::<()>();
            let h = s.spawn(move || {
                let r = catch_unwind(AssertUnwindSafe(|| work(c)));
                let _ = done_tx.send(());
                r
            });
            let mut interrupt: Option<PyErr> = None;
            let mut last = (String::new(), u64::MAX);
            // Wake at once when the work ends, else every 50 ms for Ctrl-C and progress.
            while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) =
                done_rx.recv_timeout(Duration::from_millis(50))
            {
                if interrupt.is_some() {
                    continue;
                }
                Python::attach(|py| {
                    if let Err(e) = py.check_signals() {
                        control.stop();
                        interrupt = Some(e);
                        return;
                    }
                    if let Some(cb) = &progress {
                        let phase = control.phase.lock().map(|p| p.clone()).unwrap_or_default();
                        let done = control.done.load(Ordering::Relaxed);
                        if (phase.clone(), done) != last {
                            let total = control.total.load(Ordering::Relaxed);
                            if let Err(e) = cb.call1(py, (phase.clone(), done, total)) {
                                control.stop();
                                interrupt = Some(e);
                            }
                            last = (phase, done);
                        }
                    }
                });
            }
            let outcome = h.join();
            if let Some(e) = interrupt {
                return Err(e);
            }
            match outcome {
                Ok(Ok(Ok(v))) => Ok(v),
                Ok(Ok(Err(msg))) => Err(crate::CertmeshError::new_err(msg)),
                Ok(Err(payload)) | Err(payload)
                    if payload.is::<crate::callback::CallbackFailed>() =>
                {
                    match payload.downcast::<crate::callback::CallbackFailed>() {
                        Ok(c) => Err(c.0),
                        Err(_) => unreachable!("checked by is()"),
                    }
                }
                Ok(Err(payload)) | Err(payload) => Err(crate::CertmeshError::new_err(
                    if payload.is::<Interrupted>() {
                        "interrupted".to_string()
                    } else {
                        format!(
                            "internal error (a bug in certmesh, please report it): {}",
                            payload
                                .downcast_ref::<String>()
                                .cloned()
                                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                                .unwrap_or_default()
                        )
                    },
                )),
            }
        })
    })
}
