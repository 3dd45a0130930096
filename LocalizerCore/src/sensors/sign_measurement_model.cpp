#include "sensors/sign_measurement_model.hpp"

#include <algorithm>
#include <cmath>

#include "common/fast_math.hpp"
#include "common/simd_clones.hpp"

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
        const bool track_known = o.track_id != 0 && std::isfinite(o.track_range_m) && std::isfinite(o.track_bearing_rad) &&
                                 o.track_range_m > 0;
        out.push_back({o.kind, static_cast<float>(o.range_m), static_cast<float>(wrap_angle(o.bearing_rad)), pc,
                       o.track_id, track_known ? static_cast<float>(o.track_range_m) : 0.0f,
                       track_known ? static_cast<float>(wrap_angle(o.track_bearing_rad)) : 0.0f});
    }
    if (non_finite) *non_finite = bad;
    return out;
}

namespace {
constexpr int kMaxCandidates = 64;
}

float clutter_only_log_likelihood(const SignModelParams &m, const PreparedSighting *sightings, size_t count) {
    const float u_clutter = m.clutter_density();
    float ll = 0.0f;
    for (size_t o = 0; o < count; ++o) ll += std::log(sightings[o].clutter_probability * u_clutter);
    return ll;
}

WF_SIMD_CLONES float sign_log_likelihood(const ParticleSet &p, float vio_yaw_rad, const LocalizerMap &map, const SignModelParams &m,
                          const PreparedSighting *sightings, size_t count, float *log_likelihood,
                          float *bias_s1_out, float *bias_s0_out, const uint8_t *unsearched_kind,
                          float *const *per_sighting_ll) {
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
        } else if (unsearched_kind != nullptr) {
            // A kind not looked for on this frame (and not sighted): its signs are no candidates, so their
            // absence costs nothing.
            for (int32_t k = 0; k < map.kind_count; ++k) {
                if (!unsearched_kind[k]) continue;
                bool sighted = false;
                for (size_t o = 0; o < count && !sighted; ++o) sighted = sightings[o].kind == k;
                if (sighted) continue;
                for (int32_t w = 0; w < fd.words_per_cell; ++w) {
                    relevant[f][w] &= ~fd.kind_masks[static_cast<size_t>(k) * fd.words_per_cell + w];
                }
            }
        }
    }
    const float half_fov = m.half_fov_rad;
    const float max_r = m.max_range_m;
    const float inv_sb = 1.0f / m.bearing_sigma_rad;
    const float norm_b = 1.0f / (2.0f * kPi * m.bearing_sigma_rad);  // 1/sqrt(2pi) of range and of bearing
    const float u_clutter = m.clutter_density();
    const float neg_r = m.negative_info_max_range_m, neg_r_min = m.negative_info_min_range_m;
    const float neg_b = m.negative_info_fov_fraction * half_fov;
    const float log_miss = std::log(std::max(1e-6f, m.negative_info_miss_weight));
    const float ra = m.range_sigma_base_m, rb = m.range_sigma_per_meter;
    const float max_r2_margin = (max_r * 1.001f) * (max_r * 1.001f) + 1e-4f;
    const float tan_half_fov_margin = half_fov < 1.5f ? std::tan(half_fov) * 1.001f + 1e-4f : INFINITY;

    // Range bias (see the header): prior precision, and whether the statistics are read and written.
    const bool bias_on = m.range_bias_sigma > 0 && p.bias_s1.size() == n && p.bias_s0.size() == n;
    const bool bias_update = bias_on && bias_s1_out != nullptr && bias_s0_out != nullptr;
    const float bias_prior_precision = bias_on ? 1.0f / (m.range_bias_sigma * m.range_bias_sigma) : 0.0f;
    float cand_r[kMaxCandidates], cand_b[kMaxCandidates];
    int32_t cand_kind[kMaxCandidates];
    float max_ll = -INFINITY;
    bool any_no_candidate = false;
    // log of the clutter term alone, per sighting: the likelihood of a particle that sees no sign of the
    // sighted kind (most particles of a spread-out cloud). Same float expressions as in the loop below, so a
    // particle without candidates gets exactly the value the loop would compute.
    std::vector<float> log_clutter_only(count);
    for (size_t o = 0; o < count; ++o) log_clutter_only[o] = std::log(sightings[o].clutter_probability * u_clutter);
    const float ll_no_candidate = clutter_only_log_likelihood(m, sightings, count);

    // Geometry of sign j seen from a particle at (px, py) with heading (c, s) = (cos, sin): the cheap test
    // `near` (in front, within range and the field of view, with margins), then the exact bearing and range
    // tests. One definition for both code paths below, so they agree bit for bit.
    struct SignView {
        float dx, dy, fwd, left, r2;
        bool near;
    };
    auto view_of = [&](const SignTable &st, size_t j, float px, float py, float c, float s) {
        SignView v;
        v.dx = st.x[j] - px;
        v.dy = st.y[j] - py;
        v.fwd = c * v.dx + s * v.dy;     // along camera forward
        v.left = -s * v.dx + c * v.dy;   // to the camera's left
        v.r2 = v.dx * v.dx + v.dy * v.dy;
        v.near = (v.fwd > 0.0f) & (v.r2 <= max_r2_margin) & (std::fabs(v.left) <= tan_half_fov_margin * v.fwd);
        return v;
    };
    // Exact tests on a near sign; appends it to the candidates when it is in view (branch-free: written
    // always, kept by advancing nc).
    auto add_if_in_view = [&](const SignView &v, int32_t kind, int &nc) {
        const float bearing = fast_atan2(v.left, v.fwd);
        const float r = std::sqrt(v.r2);
        const bool in_view = (bearing <= half_fov) & (bearing >= -half_fov) & (r <= max_r);
        cand_r[nc] = r;
        cand_b[nc] = bearing;
        cand_kind[nc] = kind;
        nc += in_view ? 1 : 0;
    };

    // Blocks of particles: branch-free passes the compiler vectorises (heading sincos, visibility cell),
    // then the per-particle candidate and likelihood loop. With one floor of at most 32 signs, the cheap
    // `near` test is also done in a vectorised pass, sign by sign over the block, into a bit mask per
    // particle: the per-particle loop then only visits signs that are nearly in view (usually none), and
    // the unpredictable branches of the visibility and near tests are gone. Candidates are found in the same
    // order (ascending sign index) with the same arithmetic as a plain per-particle loop.
    constexpr size_t kBlock = 512;
    float sin_b[kBlock], cos_b[kBlock];
    int32_t cell_b[kBlock];
    uint32_t near_b[kBlock], seeing_b[kBlock];
    const bool one_floor = map.floors.size() == 1;
    const bool sign_major = one_floor && map.floors[0].words_per_cell == 1 && map.floors[0].signs.size() <= 32;
    const float *const yaw_offsets = p.yaw_offset.data();
    const float *const xs = p.x.data();
    const float *const ys = p.y.data();
    for (size_t b = 0; b < n; b += kBlock) {
        const size_t nb = std::min(kBlock, n - b);
        for (size_t j = 0; j < nb; ++j) fast_sincos(vio_yaw_rad + yaw_offsets[b + j], sin_b[j], cos_b[j]);
        if (one_floor) {
            const FloorGrid &g = map.floors[0].grid;
            for (size_t j = 0; j < nb; ++j) cell_b[j] = g.index_branch_free(xs[b + j], ys[b + j]);
        } else {
            for (size_t j = 0; j < nb; ++j) {
                cell_b[j] = map.floors[p.floor[b + j]].grid.index_branch_free(xs[b + j], ys[b + j]);
            }
        }
        if (sign_major) {
            const FloorData &fd = map.floors[0];
            const uint64_t *const vis0 = fd.visibility.data();
            const uint32_t rel0 = static_cast<uint32_t>(relevant[0][0]);
            for (size_t j = 0; j < nb; ++j) {
                const int32_t c = cell_b[j];
                near_b[j] = static_cast<uint32_t>(vis0[c < 0 ? 0 : c]) & (c < 0 ? 0u : rel0);
            }
            for (size_t sj = 0; sj < fd.signs.size(); ++sj) {
                const uint32_t bit = uint32_t{1} << sj;
                if (!(rel0 & bit)) continue;
                for (size_t j = 0; j < nb; ++j) {
                    const SignView v = view_of(fd.signs, sj, xs[b + j], ys[b + j], cos_b[j], sin_b[j]);
                    near_b[j] &= v.near ? ~uint32_t{0} : ~bit;
                }
            }
        }
        // Sign-major: a particle with no sign nearly in view gets the clutter-only value, with no negative
        // information (as the loops below would give it); the value joins the maximum once, after the loop (a
        // repeated value: the same maximum, with no dependency chain through every particle). The others are
        // listed by a branch-free compaction (whether a particle sees a sign is unpredictable) and scored below.
        size_t scored = nb;
        if (sign_major) {
            scored = 0;
            for (size_t j = 0; j < nb; ++j) {
                log_likelihood[b + j] = ll_no_candidate;
                seeing_b[scored] = static_cast<uint32_t>(j);
                scored += near_b[j] != 0 ? 1 : 0;
            }
            any_no_candidate |= scored < nb;
            if (per_sighting_ll != nullptr) {
                for (size_t o = 0; o < count; ++o) {
                    if (per_sighting_ll[o] != nullptr) std::fill_n(per_sighting_ll[o] + b, nb, log_clutter_only[o]);
                }
            }
        }
        for (size_t t = 0; t < scored; ++t) {
            const size_t j = sign_major ? seeing_b[t] : t;
            const size_t i = b + j;
            const float px = xs[i], py = ys[i];
            const int16_t f = p.floor[i];
            const FloorData &fd = map.floors[f];
            const float s = sin_b[j], c = cos_b[j];
            int nc = 0;
            if (sign_major) {
                uint32_t bits = near_b[j];
                while (bits) {
                    const int sj = __builtin_ctz(bits);
                    bits &= bits - 1;
                    add_if_in_view(view_of(fd.signs, static_cast<size_t>(sj), px, py, c, s), fd.signs.kind[sj], nc);
                }
            } else {
                const int32_t words = cell_b[j] < 0 ? 0 : fd.words_per_cell;
                for (int32_t w = 0; w < words && nc < kMaxCandidates; ++w) {
                    const size_t word = static_cast<size_t>(cell_b[j]) * fd.words_per_cell + w;
                    uint64_t bits = fd.visibility[word] & relevant[f][w];
                    while (bits && nc < kMaxCandidates) {
                        const int bit = __builtin_ctzll(bits);
                        bits &= bits - 1;
                        const size_t sj = static_cast<size_t>(w) * 64 + bit;
                        const SignView v = view_of(fd.signs, sj, px, py, c, s);
                        if (!v.near) continue;  // most visible signs are out of view or range
                        add_if_in_view(v, fd.signs.kind[sj], nc);
                    }
                }
            }
            // The particle's range-bias posterior: predicted ranges times bias_factor, variance grown by bias_var
            // (relative, per squared meter of range). Without the bias term: factor 1, no growth.
            float bias_factor = 1.0f, bias_var = 0.0f, s1 = 0.0f, s0 = 0.0f;
            if (bias_on) {
                s1 = p.bias_s1[i];
                s0 = p.bias_s0[i];
                const float precision = bias_prior_precision + s0;
                bias_factor = std::exp(s1 / precision);
                bias_var = 1.0f / precision;
            }
            float ll = 0.0f;
            for (size_t o = 0; o < count; ++o) {
                const PreparedSighting &z = sightings[o];
                float mix = 0.0f, best_term = 0.0f;
                int nvis = 0, best = -1;
                for (int k = 0; k < nc; ++k) {
                    if (cand_kind[k] != z.kind) continue;
                    ++nvis;
                    // Without the bias term rp is the distance and sr the plain range std (x 1.0f is exact).
                    const float rp = cand_r[k] * bias_factor;
                    const float sr0 = ra + rb * rp;
                    const float sr = bias_on ? std::sqrt(sr0 * sr0 + rp * rp * bias_var) : sr0;
                    const float er = (z.range_m - rp) / sr;
                    const float eb = wrap_angle_f(z.bearing_rad - cand_b[k]) * inv_sb;
                    const float term = std::exp(-0.5f * (er * er + eb * eb)) / sr;
                    mix += term;
                    if (term > best_term) {
                        best_term = term;
                        best = k;
                    }
                }
                float *const own = per_sighting_ll != nullptr ? per_sighting_ll[o] : nullptr;
                if (nvis == 0) {
                    ll += log_clutter_only[o];
                    if (own != nullptr) own[i] = log_clutter_only[o];
                    continue;
                }
                const float clutter_like = z.clutter_probability * u_clutter;
                const float scale_sign = (1.0f - z.clutter_probability) * norm_b / static_cast<float>(nvis);
                const float term_ll = std::log(clutter_like + scale_sign * mix);
                ll += term_ll;
                if (own != nullptr) own[i] = term_ll;
                // The best candidate explains the sighting better than clutter does: its log range ratio joins
                // the statistics, with the precision of the range model at that distance.
                if (bias_update && best >= 0 && scale_sign * best_term > clutter_like && z.range_m > 0) {
                    const float r = cand_r[best];
                    const float rel_sigma = (ra + rb * r) / std::max(r, 1e-3f);
                    const float w = 1.0f / (rel_sigma * rel_sigma);
                    s1 += w * std::log(z.range_m / std::max(r, 1e-3f));
                    s0 += w;
                }
            }
            if (bias_update) {
                // Above the cap the statistics shrink together (the mean kept): old sightings weigh less.
                const float keep = s0 > m.range_bias_max_precision ? m.range_bias_max_precision / s0 : 1.0f;
                bias_s1_out[i] = s1 * keep;
                bias_s0_out[i] = s0 * keep;
            }
            if (m.negative_information) {
                for (int k = 0; k < nc; ++k) {
                    if (cand_r[k] > neg_r || cand_r[k] < neg_r_min || std::fabs(cand_b[k]) > neg_b) continue;
                    const float rp = cand_r[k] * bias_factor;
                    const float sr3 = 3.0f * (ra + rb * rp);
                    const float sb3 = 3.0f * m.bearing_sigma_rad;
                    bool matched = false;
                    for (size_t o = 0; o < count && !matched; ++o) {
                        const PreparedSighting &z = sightings[o];
                        matched = z.kind == cand_kind[k] && std::fabs(z.range_m - rp) < sr3 &&
                                  std::fabs(wrap_angle_f(z.bearing_rad - cand_b[k])) < sb3;
                    }
                    if (!matched) ll += log_miss;
                }
            }
            log_likelihood[i] = ll;
            max_ll = std::max(max_ll, ll);
        }
    }
    // Order-free: no log-likelihood here is NaN-sensitive (std::max keeps its first argument against a NaN, and
    // max_ll never is one) or a negative zero (every sum starts at +0 and adds logs of positive values).
    if (any_no_candidate) max_ll = std::max(max_ll, ll_no_candidate);
    return n ? max_ll : 0.0f;
}

}  // namespace wf::loc
