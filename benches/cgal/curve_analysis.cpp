// CGAL's exact curve analysis (Algebraic_kernel_d_2::Curve_analysis_2, the
// Eigenwillig–Kerber–Wolpert method) on one curve, for the comparison with
// `certmesh curve --algo gvn` (benches/cgal/curve_analysis.sh). Not part of the cargo
// build.
//
// Input (stdin): the shear s, then lines "a i j" for the terms a·x^i·y^j of an integer
// polynomial f. The curve analysed is f(x + s·y, y) (the frame certmesh's sweep chose,
// so that events and arcs are comparable one to one). Arguments: the number of timed
// repetitions (default 5).
//
// Output: one line "events N" and per event line "event x m b1l,b1r b2l,b2r ...",
// bottom to top (branches to the left and right of each point of the fibre), then
// "median_ms T" over the repetitions (a fresh kernel each time, so no cache is shared).
#include <CGAL/Algebraic_kernel_d_2.h>
#include <CGAL/Arithmetic_kernel.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

typedef CGAL::Arithmetic_kernel::Integer Integer;
typedef CGAL::Algebraic_kernel_d_2<Integer> AK;
typedef AK::Polynomial_2 Polynomial_2;
typedef AK::Polynomial_1 Polynomial_1;
typedef AK::Curve_analysis_2 Curve_analysis_2;

struct Term {
  long a;
  int i, j;
};

static Polynomial_2 build(const std::vector<Term> &terms, long s) {
  Polynomial_2 x = CGAL::shift(Polynomial_2(1), 1, 0);
  Polynomial_2 y = CGAL::shift(Polynomial_2(1), 1, 1);
  Polynomial_2 u = x + Polynomial_2(Integer(s)) * y;
  Polynomial_2 f(0);
  for (const Term &t : terms) {
    Polynomial_2 m(Integer(t.a));
    for (int k = 0; k < t.i; ++k) m *= u;
    for (int k = 0; k < t.j; ++k) m *= y;
    f += m;
  }
  return f;
}

// The whole analysis: every event line and every interval line, forced.
static std::string analyse(const Polynomial_2 &f) {
  AK ak;
  Curve_analysis_2 c = ak.construct_curve_2_object()(f);
  std::string out;
  int n = c.number_of_status_lines_with_event();
  out += "events " + std::to_string(n) + "\n";
  for (int i = 0; i < n; ++i) {
    Curve_analysis_2::Status_line_1 sl = c.status_line_at_event(i);
    out += "event " + std::to_string(CGAL::to_double(sl.x())) + " " +
           std::to_string(sl.number_of_events());
    for (int j = 0; j < (int)sl.number_of_events(); ++j) {
      auto b = sl.number_of_incident_branches(j);
      out += " " + std::to_string(b.first) + "," + std::to_string(b.second);
    }
    out += "\n";
  }
  for (int i = 0; i <= n; ++i) {
    Curve_analysis_2::Status_line_1 sl = c.status_line_of_interval(i);
    out += "interval " + std::to_string(sl.number_of_events()) + "\n";
  }
  return out;
}

int main(int argc, char **argv) {
  int reps = argc > 1 ? std::atoi(argv[1]) : 5;
  long s;
  if (!(std::cin >> s)) {
    std::cerr << "expected the shear, then lines 'a i j'\n";
    return 2;
  }
  std::vector<Term> terms;
  Term t;
  while (std::cin >> t.a >> t.i >> t.j) terms.push_back(t);
  Polynomial_2 f = build(terms, s);
  std::string first;
  std::vector<double> ms;
  for (int r = 0; r < std::max(1, reps); ++r) {
    auto t0 = std::chrono::steady_clock::now();
    std::string out = analyse(f);
    auto t1 = std::chrono::steady_clock::now();
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    if (r == 0) first = out;
  }
  std::sort(ms.begin(), ms.end());
  std::cout << first << "median_ms " << ms[ms.size() / 2] << "\n";
  return 0;
}
