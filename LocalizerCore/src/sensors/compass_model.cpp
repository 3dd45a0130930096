#include "sensors/compass_model.hpp"

#include <algorithm>
#include <cmath>

#include "common/fast_math.hpp"

namespace wf::loc {

namespace {

/// log I0(k), the von Mises normaliser: the power series for small k, the asymptotic expansion for large k
/// (Abramowitz & Stegun 9.8.1-9.8.2 ranges; the relative error of either is < 1e-7 where it is used).
double log_bessel_i0(double k) {
    if (k < 15.0) {
        double term = 1, sum = 1;
        const double q = 0.25 * k * k;
        for (int m = 1; m < 60; ++m) {
            term *= q / (static_cast<double>(m) * static_cast<double>(m));
            sum += term;
            if (term < 1e-16 * sum) break;
        }
        return std::log(sum);
    }
    const double inv = 1.0 / k;
    return k - 0.5 * std::log(2.0 * kPiD * k) + std::log1p(inv / 8.0 + 9.0 * inv * inv / 128.0);
}

}  // namespace

double CompassModel::log_density(double error_rad, double kappa, double outlier_share) {
    const double u = std::clamp(outlier_share, 0.0, 1.0);
    // VM(e) = exp(kappa (cos e - 1)) * exp(kappa) / (2 pi I0(kappa)), computed without overflow.
    const double log_peak = kappa - std::log(2.0 * kPiD) - log_bessel_i0(kappa);
    const double core = (1.0 - u) * std::exp(kappa * (std::cos(error_rad) - 1.0) + log_peak);
    return std::log(core + u / (2.0 * kPiD));
}

void CompassModel::log_likelihood(const ParticleSet &p, float vio_yaw, double heading_in_map_rad,
                                  double accuracy_rad, float *out_ll) const {
    const size_t n = p.size();
    double kappa = params_.kappa;
    // A reported accuracy only widens the core (sigma = max(model sigma, accuracy)): the model already holds
    // the typical error, and Core Location's figure is a rough bound, not a calibrated spread.
    if (std::isfinite(accuracy_rad) && accuracy_rad > 0) kappa = std::min(kappa, 1.0 / (accuracy_rad * accuracy_rad));
    const double u = std::clamp(params_.outlier_share, 1e-6, 1.0);
    // Relative to the peak: log(core(e) + floor) - log(core(0) + floor), with core(e) = a exp(kappa (cos e - 1)).
    const double log_peak = kappa - std::log(2.0 * kPiD) - log_bessel_i0(kappa);
    const float a = static_cast<float>((1.0 - u) * std::exp(log_peak));
    const float floor_density = static_cast<float>(u / (2.0 * kPiD));
    const float log_best = std::log(a + floor_density);
    const float cap = static_cast<float>(-std::max(0.0, params_.max_nats));
    const float k = static_cast<float>(kappa);
    const float z = static_cast<float>(wrap_angle(heading_in_map_rad));
    const float *yaw = p.yaw_offset.data();
    for (size_t i = 0; i < n; ++i) {
        // cos(vio_yaw + yaw_offset - z): no wrap needed for a cosine.
        const float c = std::cos(vio_yaw + yaw[i] - z);
        const float ll = std::log(a * std::exp(k * (c - 1.0f)) + floor_density) - log_best;
        out_ll[i] = std::max(ll, cap);
    }
}

}  // namespace wf::loc
