// CGAL Mesh_3 on the unit sphere x^2 + y^2 + z^2 - 1 < 0: the anchor of issue 20's
// stuffing row (scripts/bench.py). CGAL from Debian's libcgal-dev, never a dependency
// of the cargo build. Prints one JSON line: tetrahedra in the complex, vertices, the
// seconds of make_mesh_3 (its default perturb and exude included, no output), and the dihedral angle range.
//
// usage: mesh3_sphere CELL_SIZE [FACET_SIZE FACET_DISTANCE]   (seeded RNG: runs repeat)
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Random.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/number_utils.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::FT FT;
typedef K::Point_3 Point;
typedef CGAL::Labeled_mesh_domain_3<K> Domain;
typedef CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type Tr;
typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr> C3t3;
typedef CGAL::Mesh_criteria_3<Tr> Criteria;

static FT sphere(const Point& p) { return p.x() * p.x() + p.y() * p.y() + p.z() * p.z() - 1; }

static double dihedral(const Point& a, const Point& b, const Point& c, const Point& d) {
    // angle at edge ab between faces abc and abd
    K::Vector_3 e = b - a, u = c - a, v = d - a;
    K::Vector_3 n1 = CGAL::cross_product(e, u), n2 = CGAL::cross_product(e, v);
    double cs = CGAL::to_double(n1 * n2) / std::sqrt(CGAL::to_double(n1 * n1) * CGAL::to_double(n2 * n2));
    return std::acos(std::max(-1.0, std::min(1.0, cs))) * 180.0 / M_PI;
}

int main(int argc, char** argv) {
    if (argc != 2 && argc != 4) {
        std::fprintf(stderr, "usage: %s CELL_SIZE [FACET_SIZE FACET_DISTANCE]\n", argv[0]);
        return 2;
    }
    double cell = std::atof(argv[1]);
    double fsize = argc == 4 ? std::atof(argv[2]) : cell;
    double fdist = argc == 4 ? std::atof(argv[3]) : cell / 10.0;
    CGAL::get_default_random() = CGAL::Random(0);
    namespace p = CGAL::parameters;
    Domain domain = Domain::create_implicit_mesh_domain(
        sphere, K::Sphere_3(CGAL::ORIGIN, K::FT(4)), p::relative_error_bound = 1e-6);
    Criteria criteria(p::facet_angle = 25, p::facet_size = fsize, p::facet_distance = fdist,
                      p::cell_radius_edge_ratio = 2, p::cell_size = cell);
    auto t0 = std::chrono::steady_clock::now();
    // CGAL's defaults: Delaunay refinement, then sliver perturbation and exudation (their
    // time is part of the run: they are what lifts the dihedral angles off 0 and 180).
    C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria);
    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double lo = 180, hi = 0;
    for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
        const Point* q[4];
        for (int i = 0; i < 4; ++i) q[i] = &c->vertex(i)->point().point();
        static const int E[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                    {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
        for (auto& e : E) {
            double a = dihedral(*q[e[0]], *q[e[1]], *q[e[2]], *q[e[3]]);
            lo = std::min(lo, a);
            hi = std::max(hi, a);
        }
    }
    std::printf("{\"tetrahedra\": %zu, \"vertices\": %zu, \"seconds\": %.6f, "
                "\"min_dihedral_deg\": %.4f, \"max_dihedral_deg\": %.4f, \"cell_size\": %g}\n",
                (size_t)c3t3.number_of_cells_in_complex(),
                (size_t)c3t3.triangulation().number_of_vertices(), secs, lo, hi, cell);
    return 0;
}
