#include "pf/reweighting.hpp"

#include "common/fast_math.hpp"
#include "common/lane_sums.hpp"
#include "common/simd_clones.hpp"

namespace wf::loc {

WF_SIMD_CLONES double reweight(float *w, const float *ll, size_t n, float max_ll, float beta, double *untempered_sum) {
    double s[kSumLanes] = {}, full[kSumLanes] = {};
    const bool separate_full = untempered_sum != nullptr && beta != 1.0f;
    // Elements in groups of kSumLanes (element i in lane i % kSumLanes, as lane_sum), then the tail.
    const size_t body = n - n % kSumLanes;
    if (separate_full) {
        for (size_t i = 0; i < body; i += kSumLanes) {
            for (size_t k = 0; k < kSumLanes; ++k) {
                const float d = ll[i + k] - max_ll;
                full[k] += static_cast<double>(w[i + k] * fast_exp(d));
                w[i + k] *= fast_exp(beta * d);
                s[k] += static_cast<double>(w[i + k]);
            }
        }
        for (size_t i = body, k = 0; i < n; ++i, ++k) {
            const float d = ll[i] - max_ll;
            full[k] += static_cast<double>(w[i] * fast_exp(d));
            w[i] *= fast_exp(beta * d);
            s[k] += static_cast<double>(w[i]);
        }
    } else {
        for (size_t i = 0; i < body; i += kSumLanes) {
            for (size_t k = 0; k < kSumLanes; ++k) {
                w[i + k] *= fast_exp(beta * (ll[i + k] - max_ll));
                s[k] += static_cast<double>(w[i + k]);
            }
        }
        for (size_t i = body, k = 0; i < n; ++i, ++k) {
            w[i] *= fast_exp(beta * (ll[i] - max_ll));
            s[k] += static_cast<double>(w[i]);
        }
    }
    const double sum = fold_lanes(s);
    if (untempered_sum) *untempered_sum = separate_full ? fold_lanes(full) : sum;
    return sum;
}

WF_SIMD_CLONES double tempered_ess_fraction(const float *w, const float *d, size_t m, float beta) {
    double s[kSumLanes] = {}, s2[kSumLanes] = {};
    const size_t body = m - m % kSumLanes;
    for (size_t i = 0; i < body; i += kSumLanes) {
        for (size_t k = 0; k < kSumLanes; ++k) {
            const double v = w[i + k] * fast_exp(beta * d[i + k]);
            s[k] += v;
            s2[k] += v * v;
        }
    }
    for (size_t i = body, k = 0; i < m; ++i, ++k) {
        const double v = w[i] * fast_exp(beta * d[i]);
        s[k] += v;
        s2[k] += v * v;
    }
    const double sum = fold_lanes(s), sum2 = fold_lanes(s2);
    return sum2 > 0 ? (sum * sum / sum2) / static_cast<double>(m) : 1.0;
}

}  // namespace wf::loc
