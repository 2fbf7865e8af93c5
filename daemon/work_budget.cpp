#include "daemon/work_budget.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace fq::daemon {

double expected_neighbours(double sigma) {
  constexpr double kVerticesPerUnitArea = 2.0 / 1.7320508075688772;  // equilateral sampling
  const double r = 2.0 * sigma;
  return kVerticesPerUnitArea * M_PI * r * r;
}

namespace {

struct Pass {
  const char* name;
  double sigma;
};

template <class F>
void for_each_pass(const Params& p, F&& f) {
  if (p.filter) {
    f(Pass{"sigma_b", p.filtering.effective_sigma_b()});
    f(Pass{"sigma_s", p.filtering.sigma_s});
    if (p.filtering.constrained) f(Pass{"sigma_n", p.filtering.effective_sigma_n()});
  }
  if (p.cluster) {
    f(Pass{"sigma_d", p.clustering.sigma_d});  // score
    f(Pass{"sigma_d", p.clustering.sigma_d});  // link
  }
}

}  // namespace

double expected_neighbour_work(const Params& p, uint32_t vertices) {
  double per_vertex = 0;
  for_each_pass(p, [&](const Pass& s) { per_vertex += expected_neighbours(s.sigma); });
  return per_vertex * vertices;
}

Status check_work_budget(const Params& p, uint32_t vertices, double limit) {
  const double work = expected_neighbour_work(p, vertices);
  if (work <= limit) return {};
  Pass top{"", 0};
  for_each_pass(p, [&](const Pass& s) {
    if (s.sigma > top.sigma) top = s;
  });
  char msg[320];
  std::snprintf(msg, sizeof msg,
                "parameters ask for about %.3g neighbour visits on this frame (%s = %g mean edges: ~%.3g "
                "neighbours per vertex x %u vertices), over caps.max_neighbour_work = %.3g; lower %s or raise the cap",
                work, top.name, top.sigma, expected_neighbours(top.sigma), vertices, limit, top.name);
  return invalid_argument(msg);
}

}  // namespace fq::daemon
