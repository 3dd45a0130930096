// Sums over per-particle float arrays, accumulated in double in kSumLanes independent lanes (element i goes to
// lane i % kSumLanes; the lanes are added pairwise at the end). A plain `double s; for (...) s += v[i];` is a
// chain of dependent additions, one per particle (4 cycles each: 0.15 ms for 100k particles), that the
// compiler may not reorder; eight lanes let it keep several additions in flight and vectorise the loop (two
// AVX2 registers of four doubles). The result differs from the sequential sum only in the last bits
// (reassociation; the inputs are rounded to float anyway, each lane in double). The same function gives the
// same value for the same input, so every caller that needs "the" sum of an array (e.g. the ESS test and the
// systematic draws' total) gets one value.
#pragma once

#include <cstddef>

namespace wf::loc {

/// Number of independent double accumulators of the lane sums.
inline constexpr size_t kSumLanes = 8;

/// Adds the lanes pairwise: (l0 + l4) + (l2 + l6) + ((l1 + l5) + (l3 + l7)) in a fixed order.
inline double fold_lanes(const double (&lane)[kSumLanes]) {
    const double a = lane[0] + lane[4], b = lane[1] + lane[5], c = lane[2] + lane[6], d = lane[3] + lane[7];
    return (a + c) + (b + d);
}

/// Sum of v[0..n) in double, in kSumLanes lanes.
inline double lane_sum(const float *v, size_t n) {
    double lane[kSumLanes] = {};
    size_t i = 0;
    for (; i + kSumLanes <= n; i += kSumLanes) {
        for (size_t k = 0; k < kSumLanes; ++k) lane[k] += static_cast<double>(v[i + k]);
    }
    for (size_t k = 0; i < n; ++i, ++k) lane[k] += static_cast<double>(v[i]);
    return fold_lanes(lane);
}

/// Sum and sum of squares of v[0..n) in double (each square of the float value formed in double), in
/// kSumLanes lanes each; `sum` is lane_sum(v, n) exactly.
inline void lane_sum_and_squares(const float *v, size_t n, double &sum, double &sum_squares) {
    double s[kSumLanes] = {}, s2[kSumLanes] = {};
    size_t i = 0;
    for (; i + kSumLanes <= n; i += kSumLanes) {
        for (size_t k = 0; k < kSumLanes; ++k) {
            const double x = v[i + k];
            s[k] += x;
            s2[k] += x * x;
        }
    }
    for (size_t k = 0; i < n; ++i, ++k) {
        const double x = v[i];
        s[k] += x;
        s2[k] += x * x;
    }
    sum = fold_lanes(s);
    sum_squares = fold_lanes(s2);
}

}  // namespace wf::loc
