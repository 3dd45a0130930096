// ParticleFilter::update_planes: the vertical-plane measurement update (sensors/plane_measurement_model),
// kept in its own file so the plane evidence stays apart from the rest of the filter. After the likelihood
// step it does what update_signs does: per-particle evidence for the ambiguity guard, adaptive tempering,
// normalisation, resampling when the effective sample size is low (no recovery injection: planes only
// sharpen hypotheses that the signs and walls already support).
#include <algorithm>
#include <cmath>
#include <string>

#include "pf/particle_filter.hpp"
#include "pf/reweighting.hpp"

namespace wf::loc {

int ParticleFilter::update_planes(const wf_plane_observation *obs, size_t count, double t) {
    if (!initialized_) return fail(WF_LOC_ERR_NOT_INITIALIZED, "update_planes before an init");
    if (count > 0 && obs == nullptr) return fail(WF_LOC_ERR_INVALID_ARGUMENT, "planes is NULL with count > 0");
    if (!std::isfinite(t)) return fail(WF_LOC_ERR_NON_FINITE_INPUT, "update_planes time is not finite");
    t_last_ = t;
    planes_.last_applied = 0;
    planes_.last_stats = PlanePrepareStats{};
    if (count == 0 || !tracker_.has_yaw() || p_.size() == 0) return WF_LOC_OK;
    planes_.ensure_fields(map_);
    const std::vector<PreparedPlane> z = prepare_planes(obs, count, tracker_.last_east(), tracker_.last_north(), t,
                                                        planes_.params, &planes_.gate, &planes_.last_stats);
    planes_.last_applied = z.size();
    if (!z.empty()) {
        const size_t n = p_.size();
        log_likelihood_.assign(n, 0.0f);
        const float max_ll = plane_log_likelihood(p_, planes_.fields, planes_.table, planes_.params, z.data(), z.size(),
                                                  log_likelihood_.data());
        // On a symmetric floor, each particle's twin is scored against the same planes (pf/twin_guard).
        accumulate_twin_ratios([&](float *out) {
            plane_log_likelihood(p_, planes_.fields, planes_.table, planes_.params, z.data(), z.size(), out);
        });
        if (std::isfinite(max_ll)) {
            // Evidence for the ambiguity guard, as for signs (relative to the best particle, bounded).
            float *ev = p_.evidence.data();
            const float *ll = log_likelihood_.data();
            for (size_t i = 0; i < n; ++i) ev[i] += std::max(ll[i] - max_ll, -50.0f);
            const double beta = tempering_exponent(max_ll);
            const double s = reweight(p_.weight.data(), ll, n, max_ll, static_cast<float>(beta), nullptr);
            normalize(s);
            maybe_resample(false);
            reseed_twins();
            estimate_dirty_ = true;
        }
    }
    if (planes_.last_stats.non_finite > 0) {
        return fail(WF_LOC_ERR_NON_FINITE_INPUT, std::to_string(planes_.last_stats.non_finite) +
                                                     " plane(s) with a non-finite center, normal or width were ignored");
    }
    return WF_LOC_OK;
}

}  // namespace wf::loc
