// CGAL side of the Boissonnat-Oudot comparison (issue 14): CGAL's Surface_mesher
// (make_surface_mesh, Implicit_surface_3, Surface_mesh_default_criteria_3,
// Manifold_tag) on the catalog formulas of certmesh, error bound 1e-6, the default
// random generator seeded. Prints: surface angle radius distance seed vertices facets
// seconds f-evaluations; with a 6th argument, writes the mesh as OFF there.
// Build: g++ -O3 -DNDEBUG -std=c++17 surface_mesher.cpp -lgmp -lmpfr
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Random.h>
#include <CGAL/IO/Complex_2_in_triangulation_3_file_writer.h>
#include <fstream>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

typedef CGAL::Surface_mesh_default_triangulation_3 Tr;
typedef CGAL::Complex_2_in_triangulation_3<Tr> C2t3;
typedef Tr::Geom_traits GT;
typedef GT::Sphere_3 Sphere_3;
typedef GT::Point_3 Point_3;
typedef GT::FT FT;
typedef FT (*Function)(Point_3);
typedef CGAL::Implicit_surface_3<GT, Function> Surface_3;

static long evals = 0;
static inline double sq(double x) { return x * x; }

// The same formulas as certmesh's catalog (src/catalog.rs).
static FT sphere(Point_3 p) { ++evals; double x = p.x(), y = p.y(), z = p.z(); return x*x + y*y + z*z - 1; }
static FT torus(Point_3 p) { ++evals; double x = p.x(), y = p.y(), z = p.z();
  return sq(x*x + y*y + z*z + 0.36 - 0.0625) - 4*0.36*(x*x + y*y); }
static FT genus2(Point_3 p) { ++evals; double x = p.x(), y = p.y(), z = p.z();
  return z*z + 0.5*(x*x/1.44 + y*y/0.64 - 1)*(sq(x - 0.55) + y*y - 0.09)*(sq(x + 0.55) + y*y - 0.09); }
static FT tanglecube(Point_3 p) { ++evals; double x = p.x(), y = p.y(), z = p.z();
  return x*x*x*x - 5*x*x + y*y*y*y - 5*y*y + z*z*z*z - 5*z*z + 11.8; }
static FT two_spheres(Point_3 p) { ++evals; double x = p.x(), y = p.y(), z = p.z();
  return (sq(x - 0.51) + y*y + z*z - 0.25)*(sq(x + 0.51) + y*y + z*z - 0.25); }
static FT thin_torus(Point_3 p) { ++evals; double x = p.x(), y = p.y(), z = p.z();
  return sq(x*x + y*y + z*z + 0.36 - 0.0025) - 4*0.36*(x*x + y*y); }

int main(int argc, char** argv) {
  if (argc < 5) { std::fprintf(stderr, "usage: %s SURFACE ANGLE RADIUS DISTANCE [SEED [OUT.off]]\n", argv[0]); return 2; }
  std::string s = argv[1];
  double angle = std::atof(argv[2]), radius = std::atof(argv[3]), distance = std::atof(argv[4]);
  int seed = argc > 5 ? std::atoi(argv[5]) : 0;
  CGAL::get_default_random() = CGAL::Random(seed);
  Function f; Point_3 c(0, 0, 0); double r2;
  // Bounding sphere centre must have f < 0; radius covers the catalog box.
  if (s == "sphere") { f = sphere; r2 = 3 * 1.5 * 1.5; }
  else if (s == "torus") { f = torus; c = Point_3(0.6, 0, 0); r2 = sq(0.6 + std::sqrt(3.0)); }
  else if (s == "genus2") { f = genus2; r2 = 3 * 1.5 * 1.5; }
  else if (s == "tanglecube") { f = tanglecube; r2 = 3 * 9.0; }
  else if (s == "two-spheres") { f = two_spheres; c = Point_3(0.51, 0, 0); r2 = sq(0.51 + 1.2 * std::sqrt(3.0)); }
  else if (s == "thin-torus") { f = thin_torus; c = Point_3(0.6, 0, 0); r2 = sq(0.6 + std::sqrt(3.0)); }
  else { std::fprintf(stderr, "unknown surface %s\n", s.c_str()); return 2; }
  Tr tr; C2t3 c2t3(tr);
  Surface_3 surface(f, Sphere_3(c, r2), 1e-6);
  CGAL::Surface_mesh_default_criteria_3<Tr> criteria(angle, radius, distance);
  auto t0 = std::chrono::steady_clock::now();
  CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_tag());
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("cgal %s %g %g %g seed %d vertices %zu facets %zu seconds %.3f evals %ld\n", s.c_str(), angle, radius,
              distance, seed, (size_t)tr.number_of_vertices(), (size_t)c2t3.number_of_facets(), secs, evals);
  if (argc > 6) {
    std::ofstream o(argv[6]);
    CGAL::output_surface_facets_to_off(o, c2t3);
  }
  return 0;
}
