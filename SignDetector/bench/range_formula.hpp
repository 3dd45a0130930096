// The paper's range formula (Fusco et al. 2020, eq. 3), for the benchmark table and tests only: the
// product computes range in LocalizerCore (RangeEstimator.apparentHeight), never in the detector.
#pragma once

#include <cmath>

namespace wf::sign {

/// Horizontal range (meters) to a sign of face height `signHeightMeters` whose bottom edge is at unrolled
/// row `bottomEdgePx` and which spans `heightPx` rows, seen by an unrolled camera with focal length `fyPx`
/// and principal row `cyPx`, pitched up by `pitchRad`:
///   Z = h0 / (tan(p + alpha + delta) - tan(p + alpha)),
///   alpha = atan((cy - v_bottom) / fy),  alpha + delta = atan((cy - v_top) / fy),  v_top = v_bottom - height.
/// Returns NaN when the sign spans no angle or reaches past the zenith/nadir.
inline double rangeFromApparentHeight(double signHeightMeters, double bottomEdgePx, double heightPx, double fyPx,
                                      double cyPx, double pitchRad) {
    const double alpha = std::atan((cyPx - bottomEdgePx) / fyPx);
    const double alphaDelta = std::atan((cyPx - (bottomEdgePx - heightPx)) / fyPx);
    const double lo = pitchRad + alpha, hi = pitchRad + alphaDelta;
    const double halfPi = 1.5707963267948966;
    if (!(hi > lo) || std::abs(lo) >= halfPi || std::abs(hi) >= halfPi) return std::nan("");
    return signHeightMeters / (std::tan(hi) - std::tan(lo));
}

}  // namespace wf::sign
