//! The curve CSV reader on arbitrary bytes: a valid curve or a `Format` error.
#![no_main]
use certmesh::Error;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| match certmesh::io::csv::parse(data) {
    Ok(c) => {
        assert!(c.vertices.iter().flatten().all(|x| x.is_finite()));
        let n = c.vertices.len();
        assert!(c.segments.iter().flatten().all(|&i| (i as usize) < n));
    }
    Err(Error::Format { .. }) => {}
    Err(e) => panic!("unexpected error kind: {e:?}"),
});
