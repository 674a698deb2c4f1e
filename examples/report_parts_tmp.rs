use certmesh::catalog;
use certmesh::harness::compare::fidelity_params;
use certmesh::mesher::options::MesherOptions;
use certmesh::mesher::{self, registry, NoProgress};
use certmesh::metrics::{fidelity, nearest::CentroidGrid};
use rayon::prelude::*;
use std::time::Instant;

fn t<R>(name: &str, reps: usize, mut f: impl FnMut() -> R) -> R {
    let reps = std::env::var("REPS").ok().and_then(|r| r.parse().ok()).unwrap_or(reps);
    let mut best = f64::INFINITY;
    let mut r = None;
    for _ in 0..reps {
        let t0 = Instant::now();
        r = Some(f());
        best = best.min(t0.elapsed().as_secs_f64());
    }
    eprintln!("{name}: {:.2} ms", best * 1e3);
    r.unwrap()
}

fn main() {
    let e = catalog::get("torus").unwrap();
    let f = e.function();
    let o = MesherOptions { resolution: Some(256), prune: true, ..Default::default() };
    let m = registry::build("mc", 3, &o).unwrap();
    let run = mesher::run(m.as_ref(), &f, &e.domain, &NoProgress).unwrap();
    let surf = run.output.mesh.surface().unwrap().clone();
    let dom: certmesh::Aabb = e.domain.into();
    let tol = 1e-10 * dom.diagonal();
    let (spts, _) = t("surface points 40", 10, || fidelity::surface_points_counted(&f, &dom, 40, 16, tol));
    eprintln!("{} surface points", spts.len());
    let g = t("centroid grid build", 10, || CentroidGrid::new(&surf));
    t("centroid grid queries", 10, || spts.par_iter().filter_map(|&p| g.closest_dist2(p)).count());
    let tg = t("trigrid build", 5, || certmesh::kernel::cellgrid::TriGrid::new(&surf).unwrap());
    t("trigrid queries", 5, || spts.par_iter().filter_map(|&p| tg.closest_dist2(p)).count());
    let p = fidelity_params(&dom, 3).hausdorff_only(true).project_vertices(false);
    t("fidelity fast", 10, || fidelity::surface_fidelity(&surf, &f, &p).unwrap());
    let p0 = p.clone().mesh_samples(0);
    t("fidelity fast, 0 mesh samples", 10, || fidelity::surface_fidelity(&surf, &f, &p0).unwrap());
    let p1 = p.clone().seed_grid(2);
    t("fidelity fast, seed grid 2", 10, || fidelity::surface_fidelity(&surf, &f, &p1).unwrap());
    t("check", 10, || certmesh::metrics::check_trimesh(&surf).unwrap());
}
