//! The function, domain and expected topology one run works on, resolved the same way
//! for every front end (the command line's `NAME | --formula F [--domain ...]`, the
//! Python package's `surface=`, `formula=`, `domain=`).
use crate::catalog::{self, Entry};
use crate::error::{Error, Result};
use crate::harness::report::DomainSource;
use crate::implicit::Implicit;
use crate::kernel::geom::Aabb;

/// Half-width of the default domain of a formula: [-2, 2]³ for surfaces, [-2, 2]² for
/// curves (the catalog's unit-scale shapes fit in it).
pub const DEFAULT_HALF_WIDTH: f64 = 2.0;

/// What a run meshes: the function, the domain and where it came from, and the catalog
/// entry when there is one (its expected topology judges the output).
pub struct Target {
    /// The catalog name, or `"formula"` (a front end may name it otherwise).
    pub name: String,
    pub f: Box<dyn Implicit>,
    pub domain: Aabb,
    pub domain_source: DomainSource,
    pub entry: Option<Entry>,
}

/// Where the function comes from.
pub enum Source<'a> {
    /// A catalog entry by name (`certmesh surfaces`, `certmesh curves`).
    Catalog(&'a str),
    /// A parsed formula or any other function, under a display name.
    Function { name: String, f: Box<dyn Implicit> },
}

/// The domain given as numbers: `x0,y0,z0,x1,y1,z1` for surfaces, `x0,y0,x1,y1` for
/// curves.
pub fn domain_from(v: &[f64], dim: usize) -> Result<Aabb> {
    let b = match (v.len(), dim) {
        (6, 3) => Aabb::new([v[0], v[1], v[2]], [v[3], v[4], v[5]]),
        (4, 2) => Aabb::new([v[0], v[1], 0.0], [v[2], v[3], 0.0]),
        (n, _) => Err(Error::Domain(format!(
            "--domain needs {} numbers ({}), got {n}",
            if dim == 3 { 6 } else { 4 },
            if dim == 3 {
                "x0,y0,z0,x1,y1,z1"
            } else {
                "x0,y0,x1,y1"
            }
        ))),
    }?;
    // Finite corners can still give an infinite width or diagonal (±1e308), and then
    // every cell size, grid coordinate and distance is infinite or NaN.
    if !b.diagonal().is_finite() {
        return Err(Error::Domain(format!(
            "--domain {:?}..{:?}: its width or diagonal overflows to infinity; give a \
             smaller box",
            b.min, b.max
        )));
    }
    Ok(b)
}

/// The default domain of a formula: [-2, 2]³, or [-2, 2]² for a curve.
pub fn default_domain(dim: usize) -> Aabb {
    let h = DEFAULT_HALF_WIDTH;
    let z = if dim == 3 { h } else { 0.0 };
    Aabb::new([-h, -h, -z], [h, h, z]).expect("a valid box")
}

/// Resolve a run's target: the function of `source` on `domain` (empty: the catalog
/// entry's box, else the default box), checked to have `dim` variables and a domain
/// with positive extent along each axis.
pub fn resolve(source: Source<'_>, domain: &[f64], dim: usize) -> Result<Target> {
    let (name, f, entry): (String, Box<dyn Implicit>, Option<Entry>) = match source {
        Source::Catalog(n) => {
            let e = catalog::get(n)?;
            if e.dim != dim {
                return Err(Error::Param(format!(
                    "'{n}' is a {}; use `certmesh {}`",
                    if e.dim == 2 { "curve" } else { "surface" },
                    if e.dim == 2 { "curve" } else { "mesh" }
                )));
            }
            (n.to_string(), Box::new(e.function()), Some(e))
        }
        Source::Function { name, f } => {
            if f.dim() != dim {
                return Err(Error::Param(format!(
                    "the function has {} variables; a {} needs {dim}",
                    f.dim(),
                    if dim == 2 { "curve" } else { "surface" }
                )));
            }
            (name, f, None)
        }
    };
    let (domain, domain_source) = match (&entry, domain.is_empty()) {
        (_, false) => (domain_from(domain, dim)?, DomainSource::Given),
        (Some(e), true) => (e.domain, DomainSource::Catalog),
        (None, true) => (default_domain(dim), DomainSource::Default),
    };
    let s = domain.size();
    if (0..dim).any(|k| s[k] <= 0.0) {
        return Err(Error::Domain(format!(
            "the domain {:?}..{:?} is empty along some axis",
            domain.min, domain.max
        )));
    }
    Ok(Target {
        name,
        f,
        domain,
        domain_source,
        entry,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::implicit::Formula;

    #[test]
    fn catalog_domain_default_domain_and_given_domain() {
        let t = resolve(Source::Catalog("torus"), &[], 3).unwrap();
        assert_eq!(t.domain_source, DomainSource::Catalog);
        assert!(t.entry.is_some());
        let f = Formula::with_dim("x^2 + y^2 - 1", 2).unwrap();
        let t = resolve(
            Source::Function {
                name: "formula".into(),
                f: Box::new(f),
            },
            &[],
            2,
        )
        .unwrap();
        assert_eq!(t.domain_source, DomainSource::Default);
        assert_eq!(t.domain.max[0], DEFAULT_HALF_WIDTH);
        let t = resolve(Source::Catalog("sphere"), &[0., 0., 0., 1., 1., 1.], 3).unwrap();
        assert_eq!(t.domain_source, DomainSource::Given);
        assert_eq!(t.domain.max, [1.0; 3]);
    }

    #[test]
    fn wrong_dimension_and_empty_domain_are_errors() {
        assert!(resolve(Source::Catalog("torus"), &[], 2).is_err());
        let e = resolve(Source::Catalog("sphere"), &[0., 0., 0., 1., 0., 1.], 3);
        assert!(e.err().unwrap().to_string().contains("empty"));
        let f = Formula::with_dim("x^2 + y^2 - 1", 2).unwrap();
        let e = resolve(
            Source::Function {
                name: "f".into(),
                f: Box::new(f),
            },
            &[],
            3,
        );
        assert!(e.is_err());
        assert!(domain_from(&[1.0, 2.0], 3).is_err());
    }
}
