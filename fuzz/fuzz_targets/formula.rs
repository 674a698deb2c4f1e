//! The formula parser on arbitrary UTF-8, for curves (dim 2) and surfaces (dim 3):
//! it must return an expression or a located error, never panic; a formula that parses
//! must compile and evaluate (f64, interval, gradient) without panicking.
#![no_main]
use certmesh::{Aabb, Error, Formula, Implicit};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(s) = std::str::from_utf8(data) else {
        return;
    };
    for dim in [2, 3] {
        match certmesh::implicit::parse(s, dim) {
            Ok(_) => {
                if let Ok(f) = Formula::with_dim(s, dim) {
                    let _ = f.eval([0.5, -0.25, 0.125]);
                    let _ = f.eval_interval(&Aabb::cube(1.0).intervals());
                    let _ = f.grad([0.5, -0.25, 0.125]);
                }
            }
            Err(Error::Parse { column, .. }) | Err(Error::NeedsFeature { column, .. }) => {
                assert!(column >= 1 && column <= s.chars().count() + 1);
            }
            Err(e) => panic!("unexpected error kind: {e:?}"),
        }
    }
});
