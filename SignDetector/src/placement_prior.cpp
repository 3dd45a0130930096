#include "placement_prior.hpp"

#include <algorithm>
#include <cmath>

namespace wf::sign {

std::pair<int, int> placementRowBand(const PlacementPrior& prior, double windowWidthPx, double windowHeightPx,
                                     double pitchRad, const Intrinsics& unrolled) {
    const double cosP = std::cos(pitchRad), sinP = std::sin(pitchRad);
    // Camera depth of the sign for the smallest and largest physical window width.
    const double zNear = unrolled.fx * prior.windowWidthMinMeters / windowWidthPx;
    const double zFar = unrolled.fx * prior.windowWidthMaxMeters / windowWidthPx;
    const double dhHigh = prior.centreAboveCameraMaxMeters, dhLow = prior.centreAboveCameraMinMeters;
    const double eHigh = std::atan2(dhHigh * cosP, zNear - dhHigh * sinP) + prior.elevationMarginRad;
    const double eLow = std::atan2(dhLow * cosP, zFar - dhLow * sinP) - prior.elevationMarginRad;
    // Rows grow downwards: the highest elevation is the top of the band.
    const double top = unrolledRowAtElevation(unrolled, eHigh, pitchRad) - 0.5 * windowHeightPx;
    const double bottom = unrolledRowAtElevation(unrolled, eLow, pitchRad) + 0.5 * windowHeightPx;
    const double limit = 1e6;
    const int first = static_cast<int>(std::floor(std::clamp(top, -limit, limit)));
    const int last = static_cast<int>(std::ceil(std::clamp(bottom, -limit, limit))) + 1;
    return {first, std::max(first, last)};
}

}  // namespace wf::sign
