// What the residuals at the end of a fit (plumb identify) say about the model: structure over
// time that noise does not have (lag-1 autocorrelation, a runs test of the signs), a fit worse
// than nominal, and standard errors that hold when the model is wrong (a Newey–West sandwich).

#ifndef PLUMB_SRC_IDENTIFY_IDENTIFY_RESIDUALS_H_
#define PLUMB_SRC_IDENTIFY_IDENTIFY_RESIDUALS_H_

#include <Eigen/Dense>
#include <vector>

#include "plumb/identify.h"

namespace plumb::internal {

// The lag-1 autocorrelation of `e` about its mean: sum (e_k - m)(e_k+1 - m) / sum (e_k - m)^2.
// About N(0, 1/n) for n samples of white noise. NaN for fewer than 3 samples or a constant.
double LagOneAutocorrelation(const std::vector<double>& e);

// The Wald–Wolfowitz runs test of the signs of `e` (zeros skipped): (runs - mean) / sd under
// independent signs with the counts seen. Negative: fewer runs than chance (slow structure);
// positive: more (alternation). About N(0, 1) for white noise. NaN when one sign has fewer
// than 2 samples.
double RunsTestZ(const std::vector<double>& e);

// Newey and West's (1994) rule for the Bartlett kernel's bandwidth: floor(4 (n/100)^(2/9)),
// at most n - 1; 0 for n < 2.
int NeweyWestBandwidth(long samples);

// Andrews's (1991) bandwidth for the Bartlett kernel from an AR(1) fitted to each column of
// `scores` (one row per time): 1.1447 (alpha n)^(1/3), alpha = sum 4 rho^2 s^4 / ((1 - rho)^6
// (1 + rho)^2) / sum s^4 / (1 - rho)^4 over the columns (rho, s^2: each AR(1)'s coefficient and
// innovation variance). It grows with how long the scores stay correlated, where Newey and
// West's rule depends on n alone. Infinite when a column's rho is 1 or more.
double AndrewsBandwidth(const Eigen::MatrixXd& scores);

// The long-run covariance of a series of score vectors (`scores`: one row per time, in time
// order): sum over |l| <= bandwidth of (1 - |l| / (bandwidth + 1)) * sum_t s_t s_t+l'.
// Positive semi-definite (the Bartlett kernel's property).
Eigen::MatrixXd NeweyWestLongRun(const Eigen::MatrixXd& scores, int bandwidth);

// The inverse of the standard normal's upper tail: z with P(Z > z) = p, for 0 < p < 1.
double NormalUpperQuantile(double p);

// The |z| beyond which one signal's autocorrelation or runs z counts as structure, for
// `signals` signals: the family-wise false-alarm rate on white noise, two tests per signal,
// two-sided, Bonferroni, is kStructureFalseAlarm; never below 4.
constexpr double kStructureFalseAlarm = 1e-3;
double StructureThreshold(std::size_t signals);

// Judges each signal's series of `residuals` (the fit's residual vector: every measured
// sample of every signal of every log, in order, over its weight `weights` [log][signal]) and
// fills result->misspecification's signals, threshold and `structured`; a signal matched to
// rounding is not judged. The verdict comes from JudgeMisspecification.
void DiagnoseResiduals(const std::vector<RobotLog>& logs, const std::vector<double>& residuals,
                       const std::vector<std::vector<double>>& weights, IdentifyResult* result);

// Half the sum of squared residuals of `replay` against `log`, each signal over its weight
// (`weights`, [signal]); a divergence counts as the fit's large residual (1e6 per sample).
double WeightedCost(const RobotLog& log, const ReplayResult& replay,
                    const std::vector<double>& weights);

// Sets misspecification.before_cost / after_cost from result->before / after on `weights`
// ([log][signal]), whether the fit is worse than nominal (by 10 %, and beyond what `unknowns`
// fitted values can lose by chance), and the verdict and its reason.
void JudgeMisspecification(const std::vector<RobotLog>& logs,
                           const std::vector<std::vector<double>>& weights, std::size_t unknowns,
                           IdentifyResult* result);

// (J'J)^+ of `jacobian` and its rank, with the columns scaled to unit length first: unknowns in
// very different units (a damping, a start velocity) and sensitivities (1e-1 to 1e7 on a Go2)
// would otherwise pass for a rank deficiency at double precision. A column that is all zero,
// or a combination of others, still lowers the rank.
struct NormalInverse {
  Eigen::MatrixXd inverse;
  long rank = 0;
};
NormalInverse InvertNormal(const Eigen::MatrixXd& jacobian);

// The Newey–West sandwich covariance of everything fitted: bread (J'J)^+ around the long-run
// covariance of the scores J_k' r_k, summed over each log's series (signals sampled at the
// same times are one series, their scores added per time), scaled by m / (m - unknowns).
// `jacobian` is m x unknowns in the residuals' units, its first `parameters` columns the
// model parameters. Each series' bandwidth is the larger of Newey and West's rule and
// Andrews's for the parameters' scores. Returns false (and says why) when it cannot be had: a
// rank-deficient Jacobian, residuals correlated over more than a quarter of a series, or a
// covariance that is not finite. *bandwidth: the largest series' bandwidth used.
bool NeweyWestCovariance(const std::vector<RobotLog>& logs, const Eigen::MatrixXd& jacobian,
                         const std::vector<double>& residuals, long parameters,
                         Eigen::MatrixXd* covariance, int* bandwidth, std::string* why);

// After the fit: diagnoses the residuals at the optimum (`residuals`, with the `jacobian` of
// everything fitted, both in units of the noise), compares result->before and after on
// `weights` ([log][signal]), and when the model is misspecified replaces each estimate's
// standard error by Newey–West's, or withholds it; fills result->misspecification and
// result->std_errors.
void JudgeFit(const std::vector<RobotLog>& logs, const std::vector<FitParameter>& params,
              const Eigen::MatrixXd& jacobian, const std::vector<double>& residuals,
              const std::vector<std::vector<double>>& weights, IdentifyResult* result);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_IDENTIFY_IDENTIFY_RESIDUALS_H_
