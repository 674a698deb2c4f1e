//! The PLY reader on arbitrary bytes: a valid mesh or a `Format` error, never a panic.
#![no_main]
use certmesh::Error;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| match certmesh::io::ply::parse(data) {
    Ok(m) => {
        assert!(m.vertices.iter().flatten().all(|c| c.is_finite()));
        let n = m.vertices.len();
        assert!(m.triangles.iter().flatten().all(|&i| (i as usize) < n));
    }
    Err(Error::Format { .. }) => {}
    Err(e) => panic!("unexpected error kind: {e:?}"),
});
