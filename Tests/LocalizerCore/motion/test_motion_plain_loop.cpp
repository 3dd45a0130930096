// apply_motion processes particles in blocks with vectorised passes, a wall-clearance fast path and batched
// normal draws. These tests hold it to a plain per-particle loop (the reference below: one particle at a
// time, normals drawn per particle in the order yaw, scale, x, y, the exact wall test for every move, the
// weight sum in float per 1024 particles): the particle states and the returned sum must be bit-identical.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "common/fast_math.hpp"
#include "motion/vio_motion_model.hpp"
#include "support/filter_fixtures.hpp"
#include "support/particle_spread.hpp"

using namespace wf::loc;

namespace {

// The plain loop, for DeltaKind::kMove.
double plain_apply_motion(ParticleSet &p, const VioDelta &delta, const MotionNoise &noise, const LocalizerMap &map,
                          Rng &rng, MotionNoiseAccumulator &a) {
    const size_t n = p.size();
    const float de = delta.d_east, dn = delta.d_north;
    const float dist = std::sqrt(de * de + dn * dn);
    const float turn = std::fabs(delta.d_yaw);
    const float k2 = delta.noise_factor * delta.noise_factor;
    a.add_frame(noise, dist, turn, k2);
    double weight_sum = 0;
    float partial = 0;
    for (size_t i = 0; i < n; ++i) {
        float s, c;
        fast_sincos(p.yaw_offset[i], s, c);
        const float dx = p.scale[i] * (c * de - s * dn);
        const float dy = p.scale[i] * (s * de + c * dn);
        const float x0 = p.x[i], y0 = p.y[i];
        const float x1 = x0 + dx, y1 = y0 + dy;
        float w = p.weight[i];
        if (map.floors[p.floor[i]].walls.crosses(x0, y0, x1, y1)) w *= noise.wall_crossing_weight;
        p.weight[i] = w;
        p.x[i] = x1;
        p.y[i] = y1;
        partial += w;
        if ((i & 1023) == 1023 || i + 1 == n) {
            weight_sum += partial;
            partial = 0;
        }
    }
    if (!a.due()) return weight_sum;
    const float sigma_pos = static_cast<float>(std::sqrt(a.var_position));
    const float sigma_yaw = static_cast<float>(std::sqrt(a.var_yaw));
    const float sigma_scale = static_cast<float>(std::sqrt(a.var_scale));
    a.clear();
    weight_sum = 0;
    float wsum = 0;
    for (size_t i = 0; i < n; ++i) {
        if (sigma_yaw > 0) p.yaw_offset[i] = wrap_angle_f(p.yaw_offset[i] + sigma_yaw * rng.normal());
        if (sigma_scale > 0) {
            p.scale[i] = std::min(noise.scale_max, std::max(noise.scale_min, p.scale[i] + sigma_scale * rng.normal()));
        }
        float w = p.weight[i];
        if (sigma_pos > 0) {
            const float x0 = p.x[i], y0 = p.y[i];
            const float x1 = x0 + sigma_pos * rng.normal(), y1 = y0 + sigma_pos * rng.normal();
            if (map.floors[p.floor[i]].walls.crosses(x0, y0, x1, y1)) w *= noise.wall_crossing_weight;
            p.x[i] = x1;
            p.y[i] = y1;
        }
        p.weight[i] = w;
        wsum += w;
        if ((i & 1023) == 1023) {
            weight_sum += wsum;
            wsum = 0;
        }
    }
    return weight_sum + wsum;
}

// Office floor (rooms, corridor, door gaps); `floors` copies, the second with an extra wall.
wf::test::World office(int floors) {
    wf::test::World w;
    wf::test::FloorSpec f;
    f.box(0, 0, 24, 18);
    for (int i = 0; i < 4; ++i) {
        const float x0 = i * 6.0f, x1 = x0 + 6, d0 = x0 + 2.5f, d1 = d0 + 1;
        f.wall(x0, 8, d0, 8).wall(d1, 8, x1, 8).wall(x0, 10, d0, 10).wall(d1, 10, x1, 10);
        if (i > 0) f.wall(x0, 0, x0, 8).wall(x0, 10, x0, 18);
        f.wall(x0 + 2, 4, x0 + 3.3f, 4.7f);
    }
    for (float x = 1; x < 24; x += 2) f.seed(x, 9).seed(x, 4).seed(x, 14);
    for (int k = 0; k < floors; ++k) {
        wf::test::FloorSpec g = f;
        g.elevation_m = 4.0 * k;
        if (k > 0) g.wall(5, 8.5f, 7, 9.5f);
        w.floors.push_back(g);
    }
    return w;
}

ParticleSet spread(const LocalizerMap &map, size_t n, uint64_t seed) {
    return wf::test::spread_particles(map, n, seed, 97, 0.03f);
}

template <class T>
bool same_bits(const std::vector<T> &a, const std::vector<T> &b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void expect_identical(const ParticleSet &a, const ParticleSet &b, int frame) {
    EXPECT_TRUE(same_bits(a.x, b.x)) << "x, frame " << frame;
    EXPECT_TRUE(same_bits(a.y, b.y)) << "y, frame " << frame;
    EXPECT_TRUE(same_bits(a.yaw_offset, b.yaw_offset)) << "yaw offset, frame " << frame;
    EXPECT_TRUE(same_bits(a.scale, b.scale)) << "scale, frame " << frame;
    EXPECT_TRUE(same_bits(a.weight, b.weight)) << "weight, frame " << frame;
}

void run_against_plain_loop(int floors) {
    auto world = office(floors);
    const auto map = wf::test::build_map(world, wf::test::default_options());
    MotionNoise noise = MotionNoise::from_options(wf::test::default_options());
    ParticleSet fast = spread(map, 5003, 7), plain = fast;  // not a multiple of the block size
    Rng rng_fast(3), rng_plain(3);
    MotionNoiseAccumulator acc_fast, acc_plain;
    for (int frame = 0; frame < 120; ++frame) {
        VioDelta d;
        d.kind = DeltaKind::kMove;
        d.d_east = 0.05f * std::cos(0.07f * frame);
        d.d_north = 0.04f * std::sin(0.05f * frame);
        d.d_yaw = frame % 40 < 20 ? 0.02f : -0.03f;
        if (frame % 11 == 5) d.noise_factor = 3;     // limited tracking
        if (frame % 30 == 17) d.d_east = 0.9f;       // a long step (slow wall test)
        const double s_fast = apply_motion(fast, d, noise, map, rng_fast, &acc_fast);
        const double s_plain = plain_apply_motion(plain, d, noise, map, rng_plain, acc_plain);
        EXPECT_EQ(s_fast, s_plain) << "frame " << frame;
        expect_identical(fast, plain, frame);
        if (::testing::Test::HasFailure()) return;
    }
    EXPECT_EQ(rng_fast.next_u64(), rng_plain.next_u64());
}

}  // namespace

TEST(VioMotionModel, BlockedPassesMatchPlainLoopBitForBitOneFloor) { run_against_plain_loop(1); }

TEST(VioMotionModel, BlockedPassesMatchPlainLoopBitForBitTwoFloors) { run_against_plain_loop(2); }
