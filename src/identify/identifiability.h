// Identifiability diagnostics of a fit (plumb identify): which parameters the logs barely
// see, which move together, and what log would settle each.

#ifndef PLUMB_SRC_IDENTIFY_IDENTIFIABILITY_H_
#define PLUMB_SRC_IDENTIFY_IDENTIFIABILITY_H_

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "plumb/identify.h"

namespace plumb::internal {

// What log would pin down a parameter of this field ("a log at several speeds ...").
std::string LogThatSettles(const Path& p);

// What would separate two parameters that move together.
std::string PairAdvice(const Path& a, const Path& b);

// Fills result->singular_values (of J's columns normalised, largest = 1) and appends the
// warnings: a parameter whose 100 % change moves the residuals by less than the noise (J is
// in units of the noise per unit of the parameter's scale), a parameter on its bound, pairs
// correlated above 0.95, several that move the fit only together, a rank-deficient Jacobian.
// Needs result->estimates and result->correlation.
void AddIdentifiabilityWarnings(const std::vector<FitParameter>& params, const Eigen::MatrixXd& J,
                                bool singular, IdentifyResult* result);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_IDENTIFY_IDENTIFIABILITY_H_
