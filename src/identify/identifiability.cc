// Identifiability diagnostics (identifiability.h).

#include "identify/identifiability.h"

#include <fmt/format.h>

#include <cmath>
#include <set>

namespace plumb::internal {

std::string LogThatSettles(const Path& p) {
  const std::string& f = p.field;
  if (f == "dof_damping") {
    return "a log at several speeds (steps or a chirp of several amplitudes): viscous damping "
           "grows with speed";
  }
  if (f == "dof_frictionloss") {
    return "a log with slow motions that reverse often (small steps, a slow sine): friction "
           "loss dominates near zero speed";
  }
  if (f == "dof_armature" || f == "body_mass" || f == "body_inertia" || f == "body_ipos") {
    return "a log with large accelerations (fast steps, a chirp up to high frequency) that moves "
           "this body or joint";
  }
  if (f == "jnt_stiffness" || f == "qpos_spring") {
    return "a log with large displacements from the spring's rest position";
  }
  if (f == "geom_friction") return "a log in which this geom slides on its contacts";
  if (f.rfind("actuator_", 0) == 0) {
    return "a log with large, varied commands to this actuator (steps of several sizes)";
  }
  return "a log whose motion depends on it more strongly (richer excitation)";
}

std::string PairAdvice(const Path& a, const Path& b) {
  std::set<std::string> fields = {a.field, b.field};
  if (fields == std::set<std::string>{"dof_damping", "dof_frictionloss"}) {
    return "both take energy out of the motion, and one free decay cannot tell viscous from dry "
           "friction apart: add free decays from several amplitudes, or a chirp (damping grows "
           "with speed, friction loss does not)";
  }
  return "add " + LogThatSettles(a) + "; or " + LogThatSettles(b);
}

void AddIdentifiabilityWarnings(const std::vector<FitParameter>& params, const Eigen::MatrixXd& J,
                                bool singular, IdentifyResult* result) {
  std::size_t n = params.size();
  Eigen::MatrixXd normalised = J;
  for (long j = 0; j < normalised.cols(); ++j) {
    double norm = normalised.col(j).norm();
    if (norm > 0) normalised.col(j) /= norm;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(normalised, Eigen::ComputeThinV);
  Eigen::VectorXd sv = svd.singularValues();
  for (long k = 0; k < sv.size(); ++k) {
    result->singular_values.push_back(sv(0) > 0 ? sv(k) / sv(0) : 0);
  }
  // warnings: a parameter the logs barely see, pairs that move together, bounds
  for (std::size_t i = 0; i < n; ++i) {
    const Estimate& e = result->estimates[i];
    if (e.sensitivity < 1) {
      result->warnings.push_back(
          fmt::format("{} barely changes the fit: doubling it moves the residuals by {:.2g} noise "
                      "standard deviations in all. To settle it, add {}",
                      e.path, e.sensitivity, LogThatSettles(params[i].path)));
    }
    if (e.at_bound) {
      result->warnings.push_back(fmt::format(
          "{} ended on its bound ({:g}): the logs push it further than the bounds allow, and "
          "its standard error does not hold there",
          e.path, e.value));
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      double c = result->correlation[i][j];
      if (std::fabs(c) > 0.95) {
        result->warnings.push_back(
            fmt::format("{} and {} are correlated at {:.3f}: these logs cannot tell them apart; {}",
                        params[i].path.text, params[j].path.text, c,
                        PairAdvice(params[i].path, params[j].path)));
      }
    }
  }
  if (n > 2 && result->singular_values.back() < 1e-3) {
    Eigen::VectorXd weak = svd.matrixV().col(static_cast<long>(n) - 1);
    std::string names;
    for (std::size_t i = 0; i < n; ++i) {
      if (std::fabs(weak(static_cast<long>(i))) > 0.3) {
        names += (names.empty() ? "" : ", ") + params[i].path.text;
      }
    }
    result->warnings.push_back(fmt::format(
        "the parameters {} move the fit only together (smallest singular value {:.2g} of the "
        "largest): fix one of them, or add logs that excite each on its own",
        names, result->singular_values.back()));
  }
  if (singular) {
    result->warnings.push_back(
        "the Jacobian is rank deficient: some parameters do not change the fit at all, and no "
        "standard errors can be given");
  }
}

}  // namespace plumb::internal
