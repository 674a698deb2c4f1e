//! The registry: algorithm names on the command line → meshers. Every mesher module
//! provides `from_options(&MesherOptions)`; the comparison harness treats all alike.
use crate::error::{Error, Result};
use crate::mesher::Mesher;
use crate::options::MesherOptions;

/// One registered algorithm.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct AlgoInfo {
    /// The `--algo` name.
    pub name: &'static str,
    /// 2 for curves, 3 for surfaces.
    pub dim: usize,
    /// Can its output carry a certificate?
    pub certifying: bool,
    pub summary: &'static str,
}

type Ctor = fn(&MesherOptions) -> Result<Box<dyn Mesher>>;

fn table() -> Vec<(AlgoInfo, Ctor)> {
    vec![]
}

/// Every registered algorithm.
pub fn list() -> Vec<AlgoInfo> {
    table().into_iter().map(|(i, _)| i).collect()
}

/// Build the mesher `name` for functions of dimension `dim` (2 curve, 3 surface).
pub fn build(name: &str, dim: usize, o: &MesherOptions) -> Result<Box<dyn Mesher>> {
    let t = table();
    if let Some((_, ctor)) = t.iter().find(|(i, _)| i.name == name && i.dim == dim) {
        return ctor(o);
    }
    let known: Vec<&str> = t
        .iter()
        .filter(|(i, _)| i.dim == dim)
        .map(|(i, _)| i.name)
        .collect();
    let other = t.iter().any(|(i, _)| i.name == name);
    let kind = if dim == 2 {
        "curve algorithm"
    } else {
        "surface algorithm"
    };
    if other {
        return Err(Error::Param(format!(
            "algorithm '{name}' does not handle {}; use one of: {}",
            if dim == 2 {
                "curves f(x, y)"
            } else {
                "surfaces f(x, y, z)"
            },
            known.join(" ")
        )));
    }
    Err(Error::Unknown {
        kind,
        name: name.to_string(),
        known: known.join(" "),
    })
}
