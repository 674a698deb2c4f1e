// CGAL anchor for the certmesh Delaunay kernel: triangulate the same binary point file
// (u64 count, then x y z little-endian doubles) with CGAL's Delaunay_triangulation_3
// (exact predicates, inexact constructions; range insertion, which spatially sorts)
// and print the same one-line summary as `examples/delaunay.rs run`.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Delaunay_triangulation_3<K> DT;
typedef K::Point_3 Point;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: delaunay3 POINTS.bin\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  std::uint64_t n = 0;
  in.read(reinterpret_cast<char*>(&n), 8);
  std::vector<double> xyz(3 * n);
  in.read(reinterpret_cast<char*>(xyz.data()), 24 * n);
  if (!in) {
    std::fprintf(stderr, "cannot read %s\n", argv[1]);
    return 1;
  }
  std::vector<Point> pts;
  pts.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) pts.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  auto t0 = std::chrono::steady_clock::now();
  DT dt(pts.begin(), pts.end());
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("cgal points %llu vertices %zu cells %zu seconds %.4f points/s %.0f valid %d\n",
              (unsigned long long)n, (size_t)dt.number_of_vertices(), (size_t)dt.number_of_finite_cells(), s,
              n / s, argc > 2 ? (int)dt.is_valid() : -1);
  return 0;
}
