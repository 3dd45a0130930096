// sign_log_likelihood processes particles in blocks (vectorised sincos and cell lookup, a vectorised
// sign-by-sign "nearly in view" mask on floors of at most 32 signs, a shortcut for particles without
// candidates). These tests hold it to a plain per-particle loop (the reference below, the straightforward
// form of the model in sign_measurement_model.hpp): every log-likelihood and the maximum must be
// bit-identical, on one floor with few signs, one floor with 40 and 80 signs (two visibility words), and
// two floors, with negative information on and off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "common/fast_math.hpp"
#include "common/rng.hpp"
#include "sensors/sign_measurement_model.hpp"
#include "support/filter_fixtures.hpp"
#include "support/particle_spread.hpp"

using namespace wf::loc;

namespace {

float plain_sign_log_likelihood(const ParticleSet &p, float vio_yaw_rad, const LocalizerMap &map,
                                const SignModelParams &m, const std::vector<PreparedSighting> &z, float *out,
                                std::vector<float> *s1_out, std::vector<float> *s0_out) {
    const bool bias_on = m.range_bias_sigma > 0;
    const float prior_precision = bias_on ? 1.0f / (m.range_bias_sigma * m.range_bias_sigma) : 0.0f;
    *s1_out = p.bias_s1;
    *s0_out = p.bias_s0;
    constexpr int kMaxCandidates = 64;
    const float half_fov = m.half_fov_rad, max_r = m.max_range_m;
    const float inv_sb = 1.0f / m.bearing_sigma_rad;
    const float norm_b = 1.0f / (2.0f * kPi * m.bearing_sigma_rad);
    const float u_clutter = 1.0f / (max_r * 2.0f * half_fov);
    const float log_miss = std::log(std::max(1e-6f, m.negative_info_miss_weight));
    const float ra = m.range_sigma_base_m, rb = m.range_sigma_per_meter;
    float max_ll = -INFINITY;
    for (size_t i = 0; i < p.size(); ++i) {
        const FloorData &fd = map.floors[p.floor[i]];
        const uint64_t *vis = fd.visibility_at(p.x[i], p.y[i]);
        float cand_r[kMaxCandidates], cand_b[kMaxCandidates];
        int32_t cand_kind[kMaxCandidates];
        int nc = 0;
        float s, c;
        fast_sincos(vio_yaw_rad + p.yaw_offset[i], s, c);
        for (size_t j = 0; vis && j < fd.signs.size() && nc < kMaxCandidates; ++j) {
            if (!((vis[j / 64] >> (j % 64)) & 1u)) continue;
            bool relevant = m.negative_information;
            for (const PreparedSighting &o : z) relevant = relevant || o.kind == fd.signs.kind[j];
            if (!relevant) continue;
            const float dx = fd.signs.x[j] - p.x[i], dy = fd.signs.y[j] - p.y[i];
            const float fwd = c * dx + s * dy;
            const float left = -s * dx + c * dy;
            if (fwd <= 0.0f) continue;
            const float bearing = fast_atan2(left, fwd);
            if (bearing > half_fov || bearing < -half_fov) continue;
            const float r = std::sqrt(dx * dx + dy * dy);
            if (r > max_r) continue;
            cand_r[nc] = r;
            cand_b[nc] = bearing;
            cand_kind[nc] = fd.signs.kind[j];
            ++nc;
        }
        // Range bias: the particle's posterior N(s1 / P, 1 / P), P = 1 / sigma_b^2 + s0.
        float factor = 1.0f, var = 0.0f, s1 = p.bias_s1[i], s0 = p.bias_s0[i];
        if (bias_on) {
            factor = std::exp(s1 / (prior_precision + s0));
            var = 1.0f / (prior_precision + s0);
        }
        float ll = 0.0f;
        for (const PreparedSighting &o : z) {
            float mix = 0.0f, best_term = 0.0f;
            int nvis = 0, best = -1;
            for (int k = 0; k < nc; ++k) {
                if (cand_kind[k] != o.kind) continue;
                ++nvis;
                const float rp = bias_on ? cand_r[k] * factor : cand_r[k];
                const float sr0 = ra + rb * rp;
                const float sr = bias_on ? std::sqrt(sr0 * sr0 + rp * rp * var) : sr0;
                const float er = (o.range_m - rp) / sr;
                const float eb = wrap_angle_f(o.bearing_rad - cand_b[k]) * inv_sb;
                const float term = std::exp(-0.5f * (er * er + eb * eb)) / sr;
                mix += term;
                if (term > best_term) { best_term = term; best = k; }
            }
            const float clutter = o.clutter_probability * u_clutter;
            const float per_sign = (1.0f - o.clutter_probability) * norm_b / static_cast<float>(std::max(1, nvis));
            ll += nvis > 0 ? std::log(clutter + per_sign * mix) : std::log(clutter);
            if (bias_on && best >= 0 && per_sign * best_term > clutter) {
                const float rel = (ra + rb * cand_r[best]) / cand_r[best];
                const float w = 1.0f / (rel * rel);
                s1 += w * std::log(o.range_m / cand_r[best]);
                s0 += w;
            }
        }
        if (bias_on) {
            const float keep = s0 > m.range_bias_max_precision ? m.range_bias_max_precision / s0 : 1.0f;
            (*s1_out)[i] = s1 * keep;
            (*s0_out)[i] = s0 * keep;
        }
        if (m.negative_information) {
            for (int k = 0; k < nc; ++k) {
                const float neg_b = m.negative_info_fov_fraction * half_fov;
                if (cand_r[k] > m.negative_info_max_range_m || cand_r[k] < m.negative_info_min_range_m ||
                    std::fabs(cand_b[k]) > neg_b)
                    continue;
                const float rp = bias_on ? cand_r[k] * factor : cand_r[k];
                const float sr3 = 3.0f * (ra + rb * rp);
                const float sb3 = 3.0f * m.bearing_sigma_rad;
                bool matched = false;
                for (size_t o = 0; o < z.size() && !matched; ++o) {
                    matched = z[o].kind == cand_kind[k] && std::fabs(z[o].range_m - rp) < sr3 &&
                              std::fabs(wrap_angle_f(z[o].bearing_rad - cand_b[k])) < sb3;
                }
                if (!matched) ll += log_miss;
            }
        }
        out[i] = ll;
        max_ll = std::max(max_ll, ll);
    }
    return p.size() ? max_ll : 0.0f;
}

// A floor of rooms around a corridor with `extra_signs` signs along the corridor walls besides 10 on the
// outer and corridor walls; `floors` copies.
wf::test::World signed_office(int extra_signs, int floors) {
    wf::test::World w;
    wf::test::FloorSpec f;
    f.box(0, 0, 30, 20);
    for (int i = 0; i < 5; ++i) {
        const float x0 = i * 6.0f, x1 = x0 + 6, d0 = x0 + 2.5f, d1 = d0 + 1;
        f.wall(x0, 8, d0, 8).wall(d1, 8, x1, 8).wall(x0, 12, d0, 12).wall(d1, 12, x1, 12);
        if (i > 0) f.wall(x0, 0, x0, 8).wall(x0, 12, x0, 20);
    }
    using wf::test::kExit;
    using wf::test::kRestroom;
    f.sign(kExit, 0, 10, 1, 0).sign(kExit, 30, 10, -1, 0).sign(kRestroom, 9, 12, 0, -1);
    f.sign(kExit, 15, 8, 0, 1).sign(kExit, 21, 12, 0, -1, true).sign(kRestroom, 3, 20, 0, -1);
    f.sign(kExit, 27, 0, 0, 1).sign(kExit, 14, 20, 0, -1).sign(kRestroom, 20, 0, 0, 1);
    f.sign(kExit, 6, 4, 1, 0);
    for (int k = 0; k < extra_signs; ++k) {
        const bool north = k % 2 == 0;
        f.sign(k % 3 == 0 ? kRestroom : kExit, 0.5f + static_cast<float>((k * 7) % 29),
               north ? 12.0f : 8.0f, 0, north ? -1.0f : 1.0f, k % 5 == 0);
    }
    for (float x = 1; x < 30; x += 2) f.seed(x, 10).seed(x, 4).seed(x, 16);
    for (int k = 0; k < floors; ++k) {
        wf::test::FloorSpec g = f;
        g.elevation_m = 4.0 * k;
        w.floors.push_back(g);
    }
    return w;
}

ParticleSet spread(const LocalizerMap &map, size_t n, uint64_t seed) {
    return wf::test::spread_particles(map, n, seed, 101, 0);
}

void run_against_plain_loop(int extra_signs, int floors) {
    auto world = signed_office(extra_signs, floors);
    const auto map = wf::test::build_map(world, wf::test::default_options());
    ParticleSet p = spread(map, 20011, 9);
    // Range-bias statistics of every kind: none yet, a few sightings, a long history (up to the cap the filter
    // keeps), biased both ways.
    for (size_t i = 0; i < p.size(); ++i) {
        p.bias_s0[i] = static_cast<float>((i * 37) % 1001);
        p.bias_s1[i] = p.bias_s0[i] * (0.004f * static_cast<float>(static_cast<int>(i % 101) - 50));
    }
    using wf::test::kExit;
    using wf::test::kRestroom;
    const std::vector<std::vector<PreparedSighting>> frames = {
        {},
        {{kExit, 6.0f, 0.1f, 0.1f}},
        {{kExit, 6.0f, 0.1f, 0.1f}, {kRestroom, 3.5f, -0.2f, 0.4f}},
        {{kRestroom, 9.5f, 0.3f, 0.1f}, {kExit, 2.0f, -0.35f, 0.1f}, {kExit, 4.0f, 0.0f, 0.9f}},
    };
    for (int variant = 0; variant < 4; ++variant) {
        const int negative = variant % 2;
        SignModelParams m = SignModelParams::from_options(wf::test::default_options());
        m.negative_information = negative != 0;
        if (variant >= 2) m.range_bias_sigma = 0;  // the model without the bias term
        for (size_t k = 0; k < frames.size(); ++k) {
            std::vector<float> fast(p.size()), plain(p.size()), s1_plain, s0_plain;
            const float yaw = 0.3f + 0.7f * static_cast<float>(k);
            ParticleSet q = p;  // updated in place
            const float max_fast = sign_log_likelihood(q, yaw, map, m, frames[k].data(), frames[k].size(), fast.data(),
                                                       q.bias_s1.data(), q.bias_s0.data());
            const float max_plain = plain_sign_log_likelihood(p, yaw, map, m, frames[k], plain.data(), &s1_plain, &s0_plain);
            EXPECT_EQ(std::memcmp(q.bias_s1.data(), s1_plain.data(), p.size() * sizeof(float)), 0) << "frame " << k;
            EXPECT_EQ(std::memcmp(q.bias_s0.data(), s0_plain.data(), p.size() * sizeof(float)), 0) << "frame " << k;
            size_t updated = 0;
            for (size_t i = 0; i < p.size(); ++i) updated += q.bias_s0[i] != p.bias_s0[i];
            if (variant >= 2 || frames[k].empty()) EXPECT_EQ(updated, 0u) << "frame " << k;
            else EXPECT_GT(updated, 0u) << "frame " << k << ": some particle explains a sighting";
            EXPECT_EQ(std::memcmp(&max_fast, &max_plain, sizeof(float)), 0)
                << "frame " << k << " variant " << variant;
            EXPECT_EQ(std::memcmp(fast.data(), plain.data(), fast.size() * sizeof(float)), 0)
                << "frame " << k << " variant " << variant;
            size_t informative = 0;
            for (float v : plain) informative += v != plain[0];
            if (!frames[k].empty()) EXPECT_GT(informative, p.size() / 50) << "the frame should tell particles apart";
        }
    }
}

}  // namespace

TEST(SignMeasurementModel, MatchesPlainLoopBitForBitFewSigns) { run_against_plain_loop(0, 1); }

TEST(SignMeasurementModel, MatchesPlainLoopBitForBitManySigns) {
    run_against_plain_loop(30, 1);  // 40 signs: one visibility word, no sign-by-sign pass
    run_against_plain_loop(70, 1);  // 80 signs: two words per cell
}

TEST(SignMeasurementModel, MatchesPlainLoopBitForBitTwoFloors) { run_against_plain_loop(0, 2); }
