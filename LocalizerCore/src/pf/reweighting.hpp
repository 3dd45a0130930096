// The weight update of a measurement, tempered (likelihood raised to an exponent beta in (0, 1], as in
// annealed importance sampling, Neal 2001, and the adaptive tempering of progressive correction, Oudjane &
// Musso 2000), in the log domain relative to the best particle so that nothing underflows:
//
//   w_i <- w_i * exp(beta * (ll_i - max_ll))          (then normalised by the caller)
//
// and the ESS fraction such an update would leave, which the filter's tempering bisection evaluates. Both are
// single vectorised passes: the exponential is fast_exp (common/fast_math.hpp) and the sums are lane sums
// (common/lane_sums.hpp).
#pragma once

#include <cstddef>

namespace wf::loc {

/// w[i] *= exp(beta * (ll[i] - max_ll)) for i < n; returns the sum of the new weights (double, lane sum).
/// When `untempered_sum` is not null it receives sum_i w_i * exp(ll_i - max_ll) over the old weights (the
/// untempered likelihood ratio that feeds the augmented-MCL averages, PR Table 8.3); with beta = 1 it is the
/// returned sum.
double reweight(float *w, const float *ll, size_t n, float max_ll, float beta, double *untempered_sum);

/// Effective sample size fraction ESS / m = (sum v)^2 / (m sum v^2) of v_k = w[k] * exp(beta * d[k]), k < m
/// (d: log-likelihoods relative to their maximum, <= 0); 1 when every v is 0.
double tempered_ess_fraction(const float *w, const float *d, size_t m, float beta);

}  // namespace wf::loc
