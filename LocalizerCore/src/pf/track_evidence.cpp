#include "pf/track_evidence.hpp"

#include <algorithm>
#include <cmath>

#include "common/fast_math.hpp"

namespace wf::loc {

namespace {
/// Stored ratios are kept within this many nats, so they stay finite however long an object is watched: below,
/// far beyond where f(A) saturates at log c (e^-30 of the look-alike share); above, f(A) = A + log(1 - c) to float
/// precision, so a pose at the clamp has no more to gain from the object's latent state. The increment of the
/// weights is computed from the unclamped new ratio: clamped, every pose at the upper clamp scored log q alike, and
/// a lock's core was no longer told apart from its fringe by a sign watched for more than about 25 frames
/// (docs/benchmarks.md "Twenty-ninth stop").
constexpr float kRatioClamp = 30.0f;
}  // namespace

void TrackEvidence::reset() { slots_ = {}; }

float TrackEvidence::lookalike_log_density(const SignModelParams &m, const PreparedSighting &z, float variance_factor) {
    // The sign model's own mixture, with the object's earlier position in place of a map sign: the same detector
    // noise (whatever it really is, both explanations see it), the earlier positions' own error added
    // (variance_factor), and the same clutter share.
    const float u = m.clutter_density();
    const float pc = z.clutter_probability;
    const float inflate = std::sqrt(std::max(1.0f, variance_factor));
    if (!(z.track_range_m > 0)) {
        // Unknown: the expected density of a re-sighting under the model (a 2-D Gaussian's log is its peak's - 1).
        const float sr = (m.range_sigma_base_m + m.range_sigma_per_meter * z.range_m) * inflate;
        const float peak = 1.0f / ((2.0f * kPi) * m.bearing_sigma_rad * inflate * sr);
        return std::log((1.0f - pc) * peak * std::exp(-1.0f) + pc * u);
    }
    const float sr = (m.range_sigma_base_m + m.range_sigma_per_meter * z.track_range_m) * inflate;
    const float sb = m.bearing_sigma_rad * inflate;
    const float er = (z.range_m - z.track_range_m) / sr;
    const float eb = wrap_angle_f(z.bearing_rad - z.track_bearing_rad) / sb;
    const float density = std::exp(-0.5f * (er * er + eb * eb)) / ((2.0f * kPi) * sb * sr);
    return std::log((1.0f - pc) * density + pc * u);
}

float TrackEvidence::mixture_log(float a, float c) {
    // log((1 - c) e^a + c): for a > 0 factor e^a out, so nothing overflows.
    if (a > 0) return a + std::log((1.0f - c) + c * std::exp(-a));
    return std::log(c + (1.0f - c) * std::exp(a));
}

void TrackEvidence::assign(ParticleSet &p, const std::vector<PreparedSighting> &z, double t, std::vector<int> &slot_of,
                           std::vector<uint8_t> &first) {
    slot_of.assign(z.size(), -1);
    first.assign(z.size(), 0);
    if (!p_.enabled || p.track_arrays < slots_.size()) return;  // off, or a set without the ratio arrays
    for (Slot &s : slots_) {
        if (s.track_id != 0 && !(t - s.last_t <= p_.forget_s)) s = Slot{};
    }
    for (size_t o = 0; o < z.size(); ++o) {
        const uint32_t id = z[o].track_id;
        if (id == 0) continue;
        bool repeated = false;
        for (size_t q = 0; q < o; ++q) repeated |= z[q].track_id == id && slot_of[q] >= 0;
        if (repeated) continue;
        int slot = -1;
        for (size_t k = 0; k < slots_.size(); ++k) {
            if (slots_[k].track_id == id) slot = static_cast<int>(k);
        }
        if (slot < 0) {
            // A free slot, else the one seen longest ago (not one of this frame's).
            double oldest = INFINITY;
            for (size_t k = 0; k < slots_.size(); ++k) {
                bool used_now = false;
                for (size_t q = 0; q < o; ++q) used_now |= slot_of[q] == static_cast<int>(k);
                if (used_now) continue;
                const double age_key = slots_[k].track_id == 0 ? -INFINITY : slots_[k].last_t;
                if (age_key < oldest) {
                    oldest = age_key;
                    slot = static_cast<int>(k);
                }
            }
            if (slot < 0) continue;  // more tracked sightings in one frame than slots: the rest count on their own
            slots_[static_cast<size_t>(slot)].track_id = id;
            std::fill(p.track_llr[static_cast<size_t>(slot)].begin(), p.track_llr[static_cast<size_t>(slot)].end(), 0.0f);
            first[o] = 1;
        }
        slots_[static_cast<size_t>(slot)].last_t = t;
        slot_of[o] = slot;
    }
}

float TrackEvidence::apply(ParticleSet &p, const SignModelParams &m, const std::vector<PreparedSighting> &z,
                           const std::vector<int> &slot_of, const std::vector<uint8_t> &first, const float *const *per_ll,
                           float *ll) const {
    const size_t n = p.size();
    const float c = static_cast<float>(std::clamp(p_.lookalike_share, 1e-6, 1.0 - 1e-6));
    const float u = m.clutter_density();
    const float log_u = std::log(u);
    for (size_t o = 0; o < z.size(); ++o) {
        if (slot_of[o] < 0 || per_ll[o] == nullptr) continue;
        float *a = p.track_llr[static_cast<size_t>(slot_of[o])].data();
        const float *l = per_ll[o];
        if (first[o]) {
            // The first sighting counts as the per-frame model has it; it starts the ratio.
            for (size_t i = 0; i < n; ++i) a[i] = std::clamp(l[i] - log_u, -kRatioClamp, kRatioClamp);
            continue;
        }
        const float log_q = lookalike_log_density(m, z[o], static_cast<float>(p_.variance_factor));
        // Runs of equal (l, A) pairs (resampled copies sit together; particles that see no sign share l) reuse
        // the previous particle's two logarithms.
        float prev_l = NAN, prev_a = NAN, prev_new = 0, prev_delta = 0;
        for (size_t i = 0; i < n; ++i) {
            if (l[i] != prev_l || a[i] != prev_a) {
                prev_l = l[i];
                prev_a = a[i];
                const float a_new = a[i] + l[i] - log_q;
                prev_new = std::clamp(a_new, -kRatioClamp, kRatioClamp);
                // + log_q: the look-alike's density is a factor of every pose's likelihood of this sighting, so the
                // frame's likelihoods keep their level (the recovery averages read it); as c -> 0 this is l itself.
                prev_delta = mixture_log(a_new, c) - mixture_log(a[i], c) + log_q - l[i];
            }
            ll[i] += prev_delta;
            a[i] = prev_new;
        }
    }
    float max_ll = -INFINITY;
    for (size_t i = 0; i < n; ++i) max_ll = std::max(max_ll, ll[i]);
    return n ? max_ll : 0.0f;
}

}  // namespace wf::loc
