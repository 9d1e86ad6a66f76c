#include "encoder/track/powell.h"

#include <cmath>
#include <vector>

namespace fvv {

PowellResult MinimisePowell(const std::function<double(const Eigen::VectorXd&)>& f,
                            Eigen::VectorXd* x, const Eigen::VectorXd& step,
                            const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                            const PowellOptions& o) {
  const int n = static_cast<int>(x->size());
  PowellResult r;
  auto clamp = [&](Eigen::VectorXd v) { return v.cwiseMax(lo).cwiseMin(hi); };
  auto eval = [&](const Eigen::VectorXd& v) {
    ++r.evaluations;
    return f(v);
  };
  *x = clamp(*x);
  double best = eval(*x);
  double shrink = 1;  // how far the steps have been refined
  // Directions start as the scaled axes.
  std::vector<Eigen::VectorXd> dirs;
  for (int i = 0; i < n; ++i) dirs.push_back(Eigen::VectorXd::Unit(n, i) * step[i]);

  // Minimises along x + t d; returns the new value (x and best updated).
  auto line = [&](const Eigen::VectorXd& d) {
    if (d.norm() == 0) return;
    // Bracket: try +-1, expanding by 2 while it improves.
    double t_best = 0, f_best = best;
    for (double sign : {1.0, -1.0}) {
      for (double t = sign; std::abs(t) <= 8 && r.evaluations < o.max_evaluations; t *= 2) {
        const double v = eval(clamp(*x + t * d));
        if (v < f_best) {
          f_best = v, t_best = t;
        } else {
          break;
        }
      }
      if (t_best != 0) break;  // improved going this way: no need to try the other
    }
    // Golden section in [t_best - h, t_best + h], h = half the last step.
    double a = t_best - (t_best == 0 ? 1.0 : std::abs(t_best) / 2),
           b = t_best + (t_best == 0 ? 1.0 : std::abs(t_best) / 2);
    const double g = 0.6180339887498949;
    for (int k = 0; k < o.golden_steps && r.evaluations < o.max_evaluations; ++k) {
      const double c = b - g * (b - a), e = a + g * (b - a);
      const double fc = eval(clamp(*x + c * d)), fe = eval(clamp(*x + e * d));
      if (fc < f_best) f_best = fc, t_best = c;
      if (fe < f_best) f_best = fe, t_best = e;
      if (fc < fe) {
        b = e;
      } else {
        a = c;
      }
    }
    if (f_best < best) {
      *x = clamp(*x + t_best * d);
      best = f_best;
    }
  };

  for (int it = 0; it < o.max_iterations && r.evaluations < o.max_evaluations; ++it) {
    const Eigen::VectorXd start = *x;
    const double start_value = best;
    int biggest = 0;
    double biggest_drop = 0;
    for (int i = 0; i < n && r.evaluations < o.max_evaluations; ++i) {
      const double before = best;
      line(dirs[i]);
      if (before - best > biggest_drop) biggest_drop = before - best, biggest = i;
    }
    // Powell's update: the net move of this pass becomes a direction, replacing
    // the one that helped most (keeps the set from collapsing).
    const Eigen::VectorXd moved = *x - start;
    if (moved.norm() > 0 && r.evaluations < o.max_evaluations) {
      line(moved);
      dirs.erase(dirs.begin() + biggest);
      dirs.push_back(moved);
    }
    if (best < start_value) {
      if (start_value - best <= o.relative_tolerance * std::abs(start_value)) break;  // converged
      continue;
    }
    // No progress at this scale: search finer (a narrow valley or a plateau
    // edge), until the steps are a thousandth of the initial ones.
    for (Eigen::VectorXd& d : dirs) d *= 0.25;
    shrink *= 0.25;
    if (shrink < 1e-3) break;
  }
  r.value = best;
  return r;
}

}  // namespace fvv
