//! The MEDIT `.mesh` reader on arbitrary bytes: a valid mesh or a `Format` error.
#![no_main]
use certmesh::Error;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| match certmesh::io::medit::parse(data) {
    Ok(m) => {
        assert!(m.mesh.vertices.iter().flatten().all(|c| c.is_finite()));
        let n = m.mesh.vertices.len();
        assert!(m.mesh.tets.iter().flatten().all(|&i| (i as usize) < n));
        assert!(m.triangles.iter().flatten().all(|&i| (i as usize) < n));
    }
    Err(Error::Format { .. }) => {}
    Err(e) => panic!("unexpected error kind: {e:?}"),
});
