// Powell's direction-set method (no derivatives) with bounded parameters: what
// the tracker minimises silhouette XOR with. The objective is piecewise
// constant at pixel scale, so line searches bracket with expanding steps of a
// given scale and refine by golden section, rather than fitting parabolas.
#ifndef FVV_ENCODER_TRACK_POWELL_H_
#define FVV_ENCODER_TRACK_POWELL_H_

#include <Eigen/Core>
#include <functional>

namespace fvv {

struct PowellOptions {
  int max_evaluations = 300;
  int max_iterations = 3;            // passes over the direction set
  double relative_tolerance = 1e-3;  // stop when a pass improves less than this share
  int golden_steps = 5;
};

struct PowellResult {
  double value = 0;
  int evaluations = 0;
};

// Minimises f over x within [lo, hi] (clamped); `step` is each parameter's
// initial search scale. x holds the start and receives the best point found.
PowellResult MinimisePowell(const std::function<double(const Eigen::VectorXd&)>& f,
                            Eigen::VectorXd* x, const Eigen::VectorXd& step,
                            const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                            const PowellOptions& options = PowellOptions());

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_POWELL_H_
