#include "sensors/sign_measurement_model.hpp"

#include <algorithm>
#include <cmath>

#include "common/fast_math.hpp"

namespace wf::loc {

SignModelParams SignModelParams::from_options(const wf_localizer_options &o) {
    SignModelParams m;
    m.half_fov_rad = static_cast<float>(0.5 * o.horizontal_fov_rad);
    m.max_range_m = static_cast<float>(o.max_sign_range_m);
    m.range_sigma_base_m = static_cast<float>(o.range_sigma_base_m);
    m.range_sigma_per_meter = static_cast<float>(o.range_sigma_per_meter);
    m.bearing_sigma_rad = static_cast<float>(o.bearing_sigma_rad);
    m.clutter_probability = static_cast<float>(o.clutter_probability);
    m.negative_information = o.negative_information != 0;
    m.negative_info_max_range_m = static_cast<float>(o.negative_info_max_range_m);
    m.negative_info_fov_fraction = static_cast<float>(o.negative_info_fov_fraction);
    m.negative_info_miss_weight = static_cast<float>(o.negative_info_miss_weight);
    return m;
}

std::vector<PreparedSighting> prepare_sightings(const wf_sign_observation *obs, size_t count, const SignModelParams &m,
                                                int32_t kind_count, size_t *non_finite) {
    std::vector<PreparedSighting> out;
    size_t bad = 0;
    for (size_t i = 0; i < count; ++i) {
        const wf_sign_observation &o = obs[i];
        if (!std::isfinite(o.range_m) || !std::isfinite(o.bearing_rad) || !std::isfinite(o.score) || o.range_m < 0) {
            ++bad;
            continue;
        }
        if (o.kind < 0 || o.kind >= kind_count) continue;
        const float score = std::clamp(static_cast<float>(o.score), 0.0f, 1.0f);
        const float pc = std::clamp(1.0f - (1.0f - m.clutter_probability) * score, m.clutter_probability, 0.999f);
        out.push_back({o.kind, static_cast<float>(o.range_m), static_cast<float>(wrap_angle(o.bearing_rad)), pc});
    }
    if (non_finite) *non_finite = bad;
    return out;
}

namespace {
constexpr int kMaxCandidates = 64;
}

float sign_log_likelihood(const ParticleSet &p, float vio_yaw_rad, const LocalizerMap &map, const SignModelParams &m,
                          const PreparedSighting *sightings, size_t count, float *log_likelihood) {
    const size_t n = p.size();
    if (count == 0 && !m.negative_information) {
        std::fill(log_likelihood, log_likelihood + n, 0.0f);
        return 0.0f;
    }
    // Which sign bits matter, per floor: the observed kinds, or all signs when negative information is on.
    std::vector<std::vector<uint64_t>> relevant(map.floors.size());
    for (size_t f = 0; f < map.floors.size(); ++f) {
        const FloorData &fd = map.floors[f];
        relevant[f].assign(fd.words_per_cell, m.negative_information ? ~uint64_t{0} : 0);
        if (!m.negative_information) {
            for (size_t o = 0; o < count; ++o) {
                for (int32_t w = 0; w < fd.words_per_cell; ++w) {
                    relevant[f][w] |= fd.kind_masks[static_cast<size_t>(sightings[o].kind) * fd.words_per_cell + w];
                }
            }
        }
    }
    const float half_fov = m.half_fov_rad;
    const float max_r = m.max_range_m;
    const float inv_sb = 1.0f / m.bearing_sigma_rad;
    const float norm_b = 1.0f / (2.0f * kPi * m.bearing_sigma_rad);  // 1/sqrt(2pi) of range and of bearing
    const float u_clutter = 1.0f / (max_r * 2.0f * half_fov);
    const float neg_r = m.negative_info_max_range_m;
    const float neg_b = m.negative_info_fov_fraction * half_fov;
    const float log_miss = std::log(std::max(1e-6f, m.negative_info_miss_weight));
    const float ra = m.range_sigma_base_m, rb = m.range_sigma_per_meter;
    const float max_r2_margin = (max_r * 1.001f) * (max_r * 1.001f) + 1e-4f;
    const float tan_half_fov_margin = half_fov < 1.5f ? std::tan(half_fov) * 1.001f + 1e-4f : INFINITY;

    float cand_r[kMaxCandidates], cand_b[kMaxCandidates];
    int32_t cand_kind[kMaxCandidates];
    float max_ll = -INFINITY;
    for (size_t i = 0; i < n; ++i) {
        const float px = p.x[i], py = p.y[i];
        const int16_t f = p.floor[i];
        const FloorData &fd = map.floors[f];
        const uint64_t *vis = fd.visibility_at(px, py);
        int nc = 0;
        if (vis) {
            float s, c;
            fast_sincos(vio_yaw_rad + p.yaw_offset[i], s, c);
            const uint64_t *rel = relevant[f].data();
            for (int32_t w = 0; w < fd.words_per_cell && nc < kMaxCandidates; ++w) {
                uint64_t bits = vis[w] & rel[w];
                while (bits && nc < kMaxCandidates) {
                    const int b = __builtin_ctzll(bits);
                    bits &= bits - 1;
                    const size_t j = static_cast<size_t>(w) * 64 + b;
                    const float dx = fd.signs.x[j] - px, dy = fd.signs.y[j] - py;
                    const float fwd = c * dx + s * dy;     // along camera forward
                    if (fwd <= 0.0f) continue;
                    const float left = -s * dx + c * dy;   // to the camera's left
                    // Cheap rejections first (most candidate signs are out of view or range); they keep a
                    // margin so the exact tests below still decide every borderline case.
                    const float r2 = dx * dx + dy * dy;
                    if (r2 > max_r2_margin || std::fabs(left) > tan_half_fov_margin * fwd) continue;
                    const float bearing = fast_atan2(left, fwd);
                    if (bearing > half_fov || bearing < -half_fov) continue;
                    const float r = std::sqrt(r2);
                    if (r > max_r) continue;
                    cand_r[nc] = r;
                    cand_b[nc] = bearing;
                    cand_kind[nc] = fd.signs.kind[j];
                    ++nc;
                }
            }
        }
        float ll = 0.0f;
        for (size_t o = 0; o < count; ++o) {
            const PreparedSighting &z = sightings[o];
            float mix = 0.0f;
            int nvis = 0;
            for (int k = 0; k < nc; ++k) {
                if (cand_kind[k] != z.kind) continue;
                ++nvis;
                const float sr = ra + rb * cand_r[k];
                const float er = (z.range_m - cand_r[k]) / sr;
                const float eb = wrap_angle_f(z.bearing_rad - cand_b[k]) * inv_sb;
                mix += std::exp(-0.5f * (er * er + eb * eb)) / sr;
            }
            float like = z.clutter_probability * u_clutter;
            if (nvis > 0) like += (1.0f - z.clutter_probability) * mix * norm_b / static_cast<float>(nvis);
            ll += std::log(like);
        }
        if (m.negative_information) {
            for (int k = 0; k < nc; ++k) {
                if (cand_r[k] > neg_r || std::fabs(cand_b[k]) > neg_b) continue;
                const float sr3 = 3.0f * (ra + rb * cand_r[k]);
                const float sb3 = 3.0f * m.bearing_sigma_rad;
                bool matched = false;
                for (size_t o = 0; o < count && !matched; ++o) {
                    const PreparedSighting &z = sightings[o];
                    matched = z.kind == cand_kind[k] && std::fabs(z.range_m - cand_r[k]) < sr3 &&
                              std::fabs(wrap_angle_f(z.bearing_rad - cand_b[k])) < sb3;
                }
                if (!matched) ll += log_miss;
            }
        }
        log_likelihood[i] = ll;
        max_ll = std::max(max_ll, ll);
    }
    return n ? max_ll : 0.0f;
}

}  // namespace wf::loc
