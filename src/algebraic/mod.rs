//! Exact algebraic methods: integer polynomials, subresultants, real root isolation,
//! real algebraic numbers, and the González-Vega–Necula sweep that computes the exact
//! topology of a real algebraic curve f(x, y) = 0, singular points included (the
//! chapter "Meshing of Surfaces", §1.4–§1.4.1). Every decision is exact integer or
//! rational arithmetic, or outward-rounded f64 interval arithmetic used as a filter
//! (a sign it proves holds exactly; otherwise the exact path decides); floating point
//! is otherwise only in the output coordinates.
pub mod algnum;
pub mod bipoly;
pub mod check;
pub mod fint;
pub mod modgcd;
pub mod subres;
pub mod sweep;
pub mod tolerance;
pub mod upoly;

pub use bipoly::{from_expr, from_formula, BiPoly};
pub use check::{check_curve, CurveCert};
pub use sweep::{analyse, Sweep, SweepParams};
pub use upoly::UPoly;
