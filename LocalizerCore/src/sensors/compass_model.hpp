// Compass measurement model: the camera heading that Core Location reports (magnetic, converted to the map
// frame with the map's recorded north) as evidence on each particle's implied heading (VIO yaw + yaw offset).
//
// Likelihood (a robust mixture, as PR section 6.3 mixes a hit model with a uniform random share):
//   p(z | h) = (1 - u) * VonMises(z; h, kappa_eff) + u / (2 pi)
// with kappa_eff = min(kappa, 1 / accuracy^2) when Core Location's heading accuracy is known (a reported
// accuracy only widens the core: sigma = max(model sigma, accuracy)). Indoor magnetic disturbance is spatially correlated (steel, wiring: docs/compass.md
// measures it on 31 real mall walks), so consecutive readings are not independent: the model applies a reading
// at most once per `min_distance_m` walked, caps the log-likelihood ratio one application can give
// (`max_nats`) and the total a particle's history can receive (`max_total_nats`, applied by the filter), so a
// persistent bias near steel cannot build false certainty by repetition. Readings taken
// while standing still add nothing new and are never applied twice.
#pragma once

#include <cstddef>

#include "pf/particle_set.hpp"

namespace wf::loc {

/// Tuning of the compass model (internal parameters, not part of the C ABI options struct; set by name
/// through wf_localizer_set_parameter, "compass.*").
struct CompassModelParams {
    /// Nonzero: compass readings are evidence. "compass.enabled".
    bool enabled = true;
    /// Von Mises concentration of the core (1/rad^2 for small errors: sigma ~ 1/sqrt(kappa)). Default 10
    /// (sigma ~ 18 deg): 31 real mall walks gave kappa 12.1 (sigma 16.4 deg, docs/compass.md), widened a little
    /// for other phones and buildings. "compass.kappa".
    double kappa = 10.0;
    /// Share of readings that are outliers (uniform over all headings). Default 0.05: the real walks had none
    /// beyond 72 deg in 1.2 km (1.8 % once each walk's own offset is removed); the rest is a margin for steel.
    /// "compass.outlier_share".
    double outlier_share = 0.05;
    /// A reading is applied at most once per this distance walked, meters. Default 5 m: the real error's
    /// correlation falls to 1/e after 4.0 m and below 0.2 after 5.5 m. "compass.min_distance_m".
    double min_distance_m = 5.0;
    /// Cap on the log-likelihood ratio between the best and the worst particle of one application, nats.
    /// Default 2.5. "compass.max_nats".
    double max_nats = 2.5;
    /// Cap on the total compass log-weight a particle's history can receive, nats (per particle, carried
    /// through resampling): floor and walk offsets of 15-22 deg persist over a whole walk, so repeated
    /// applications must not build more than ln 100 of certainty by themselves. Default 4.6.
    /// "compass.max_total_nats".
    double max_total_nats = 4.6;
};

/// Decides when a compass reading is due and scores the particles against it. Owns no particle data.
class CompassModel {
public:
    explicit CompassModel(const CompassModelParams &params = {}) : params_(params) {}

    const CompassModelParams &params() const { return params_; }
    CompassModelParams &mutable_params() { return params_; }

    /// Adds horizontal distance walked, meters (from the VIO deltas, before scale).
    void add_distance(double walked_m) { walked_since_m_ += walked_m; }
    /// Forgets the distance walked (after an init): the next reading is due at once.
    void reset() { walked_since_m_ = 0; applied_once_ = false; }
    /// True when a reading given now would be applied.
    bool due() const { return params_.enabled && (!applied_once_ || walked_since_m_ >= params_.min_distance_m); }
    /// Marks a reading applied now.
    void mark_applied() { walked_since_m_ = 0; applied_once_ = true; }

    /// Writes into `out_ll[i]` the capped log-likelihood of particle i relative to the most likely heading,
    /// in [-max_nats, 0], for a reading `heading_in_map_rad` (CCW from map +x) with heading accuracy
    /// `accuracy_rad` (<= 0 or non-finite: unknown). `vio_yaw` is the current VIO yaw (radians).
    void log_likelihood(const ParticleSet &p, float vio_yaw, double heading_in_map_rad, double accuracy_rad,
                        float *out_ll) const;

    /// The model's log density (not capped, not relative) of a heading error `error_rad` with concentration
    /// `kappa`: log((1 - u) VM(error; 0, kappa) + u / (2 pi)). For tests and docs.
    static double log_density(double error_rad, double kappa, double outlier_share);

private:
    CompassModelParams params_;
    double walked_since_m_ = 0;
    bool applied_once_ = false;
};

}  // namespace wf::loc
