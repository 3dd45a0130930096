// Tests for pf/resampling.hpp: ESS, systematic resampling proportions (and with a given total), KLD sample
// counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "common/lane_sums.hpp"
#include "common/rng.hpp"
#include "pf/resampling.hpp"

using namespace wf::loc;

TEST(Resampling, EffectiveSampleSize) {
    std::vector<float> uniform(100, 0.01f);
    EXPECT_NEAR(effective_sample_size(uniform.data(), uniform.size()), 100.0, 1e-3);
    std::vector<float> one_hot(100, 0.0f);
    one_hot[7] = 1;
    EXPECT_NEAR(effective_sample_size(one_hot.data(), one_hot.size()), 1.0, 1e-9);
    std::vector<float> half(100, 0.0f);
    for (int i = 0; i < 50; ++i) half[i] = 0.02f;
    EXPECT_NEAR(effective_sample_size(half.data(), half.size()), 50.0, 1e-3);
}

// Systematic resampling draws particle i floor(N w_i) or ceil(N w_i) times, whatever the offset.
TEST(Resampling, SystematicKeepsProportions) {
    const std::vector<float> w = {0.5f, 0.25f, 0.125f, 0.125f, 0.0f};
    std::vector<uint32_t> idx;
    // Offsets away from exact ties with the cumulative sums.
    for (double u0 : {0.1, 0.5, 0.9}) {
        systematic_resample(w.data(), w.size(), 80, u0, idx);
        std::map<uint32_t, int> count;
        for (uint32_t i : idx) ++count[i];
        EXPECT_EQ(count[0], 40);
        EXPECT_EQ(count[1], 20);
        EXPECT_EQ(count[2], 10);
        EXPECT_EQ(count[3], 10);
        EXPECT_EQ(count[4], 0);
        EXPECT_TRUE(std::is_sorted(idx.begin(), idx.end()));
    }
    // Random weights: each count within 1 of N w_i.
    Rng rng(3);
    std::vector<float> r(1000);
    double total = 0;
    for (float &v : r) total += (v = rng.uniform_float());
    systematic_resample(r.data(), r.size(), 5000, rng.uniform(), idx);
    std::vector<int> c(r.size(), 0);
    for (uint32_t i : idx) ++c[i];
    for (size_t i = 0; i < r.size(); ++i) EXPECT_NEAR(c[i], 5000 * r[i] / total, 1.0 + 1e-6);
}

TEST(Resampling, SystematicWithZeroWeightsFallsBackToUniform) {
    const std::vector<float> w(10, 0.0f);
    std::vector<uint32_t> idx;
    systematic_resample(w.data(), w.size(), 20, 0.5, idx);
    ASSERT_EQ(idx.size(), 20u);
    EXPECT_EQ(idx.front(), 0u);
    EXPECT_EQ(idx.back(), 9u);
}

// Fox 2003 bound: grows about linearly in k; e.g. k = 100, epsilon 0.05, z 2.326 gives ~1,300 particles.
// The caller's total (the sum systematic_resample and effective_sample_size form: lane_sum) gives
// the same draws.
TEST(Resampling, SystematicWithTotalIsTheSameDraw) {
    Rng rng(11);
    std::vector<float> w(3000);
    for (float &v : w) v = rng.uniform_float() * rng.uniform_float();
    const double total = lane_sum(w.data(), w.size());
    double ess_sum = -1;
    effective_sample_size(w.data(), w.size(), &ess_sum);
    EXPECT_EQ(ess_sum, total);  // the ESS's sum is the draws' total
    std::vector<uint32_t> plain, given;
    for (size_t n_out : {1, 7, 3000, 10000}) {
        const double u0 = rng.uniform();
        systematic_resample(w.data(), w.size(), n_out, u0, plain);
        systematic_resample_with_total(w.data(), w.size(), n_out, u0, total, given);
        EXPECT_EQ(plain, given) << n_out;
        systematic_resample(w.data(), w.size(), n_out, u0, plain, n_out / 3);
        systematic_resample_with_total(w.data(), w.size(), n_out, u0, total, given, n_out / 3);
        EXPECT_EQ(plain, given) << n_out << " first " << n_out / 3;
    }
    const std::vector<float> zero(10, 0.0f);
    systematic_resample(zero.data(), zero.size(), 20, 0.5, plain);
    systematic_resample_with_total(zero.data(), zero.size(), 20, 0.5, 0.0, given);
    EXPECT_EQ(plain, given);
    systematic_resample_with_total(w.data(), 0, 20, 0.5, 0.0, given);
    EXPECT_TRUE(given.empty());
}

namespace {

/// The plain systematic walk (PR Table 4.4): pointer k at (u0 + k) * total / n_out, accumulated, goes to the
/// first particle whose cumulative weight reaches it (the last one when a rounding leaves it beyond).
std::vector<uint32_t> walked_draws(const std::vector<float> &w, size_t n_out, double u0, size_t m) {
    double total = lane_sum(w.data(), w.size());
    std::vector<uint32_t> out(m);
    const double step = total / static_cast<double>(n_out);
    double target = u0 * step, cumulative = w[0];
    size_t i = 0;
    for (size_t k = 0; k < m; ++k) {
        while (target > cumulative && i + 1 < w.size()) cumulative += w[++i];
        out[k] = static_cast<uint32_t>(i);
        target += step;
    }
    return out;
}

}  // namespace

// The per-particle count of the draws (systematic_resample) against the plain pointer walk: the same draws
// on random weights (a pointer exactly on a cumulative weight is where they may differ, by one position),
// with light, heavy (many copies of one particle, beyond the copy block) and zero weights, full and prefix.
TEST(Resampling, CountedDrawsAreThePointerWalk) {
    Rng rng(47);
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<float> w(1 + rng.below(5000));
        for (float &v : w) {
            const double u = rng.uniform();
            v = u < 0.2 ? 0.0f : u < 0.21 ? 50.0f * rng.uniform_float() : rng.uniform_float() * rng.uniform_float();
        }
        w[rng.below(static_cast<uint32_t>(w.size()))] = 100.0f;  // at least one heavy particle
        for (size_t n_out : {size_t{1}, size_t{13}, w.size(), 3 * w.size() + 7}) {
            const double u0 = rng.uniform();
            std::vector<uint32_t> drawn;
            systematic_resample(w.data(), w.size(), n_out, u0, drawn);
            const std::vector<uint32_t> walked = walked_draws(w, n_out, u0, n_out);
            ASSERT_EQ(drawn.size(), walked.size());
            size_t differ = 0;
            for (size_t k = 0; k < drawn.size(); ++k) differ += drawn[k] != walked[k] ? 1 : 0;
            EXPECT_EQ(differ, 0u) << "trial " << trial << " n_out " << n_out;
            systematic_resample(w.data(), w.size(), n_out, u0, drawn, n_out / 2 + 1);
            EXPECT_EQ(drawn, walked_draws(w, n_out, u0, std::min(n_out, n_out / 2 + 1)));
        }
    }
}

TEST(Resampling, KldCountGrowsWithBins) {
    EXPECT_EQ(kld_sample_count(1, 0.05, 2.326), 1u);
    size_t prev = 1;
    for (size_t k : {2, 10, 100, 1000, 10000}) {
        const size_t n = kld_sample_count(k, 0.05, 2.326);
        EXPECT_GT(n, prev);
        prev = n;
    }
    const double k = 100, a = 2.0 / (9 * (k - 1));
    const double expected = (k - 1) / 0.1 * std::pow(1 - a + std::sqrt(a) * 2.326, 3);
    EXPECT_NEAR(double(kld_sample_count(100, 0.05, 2.326)), expected, 1.0);
    EXPECT_GT(kld_sample_count(100, 0.05, 2.326), 1200u);
    EXPECT_LT(kld_sample_count(100, 0.05, 2.326), 1400u);
}

// A spread-out cloud occupies more bins than a concentrated one, so KLD asks for more particles.
TEST(Resampling, KldCountGrowsWithSpread) {
    Rng rng(8);
    BinCounter bins;
    size_t previous = 0;
    for (float spread : {0.2f, 2.0f, 20.0f}) {
        ParticleSet p;
        p.resize(5000);
        std::vector<uint32_t> idx(5000);
        for (size_t i = 0; i < 5000; ++i) {
            p.x[i] = spread * rng.normal();
            p.y[i] = spread * rng.normal();
            p.yaw_offset[i] = 0.1f * spread * rng.normal();
            p.floor[i] = 0;
            idx[i] = static_cast<uint32_t>(i);
        }
        const size_t k = count_occupied_bins(p, idx, 0.0f, 0.5f, 0.1745f, bins);
        const size_t n = kld_sample_count(k, 0.05, 2.326);
        EXPECT_GT(n, previous) << "spread " << spread;
        previous = n;
    }
}

TEST(Resampling, BinCounterDenseIds) {
    BinCounter b;
    b.clear(4);
    EXPECT_EQ(b.insert(10), 0u);
    EXPECT_EQ(b.insert(20), 1u);
    EXPECT_EQ(b.insert(10), 0u);
    for (uint64_t k = 100; k < 1100; ++k) b.insert(k);  // forces growth
    EXPECT_EQ(b.size(), 1002u);
    EXPECT_EQ(b.find(20), 1u);
    EXPECT_EQ(b.find(555), 457u);
    EXPECT_EQ(b.find(99999), UINT32_MAX);
}

// The dense count of occupied KLD bins equals the hash table's, for clouds of growing spread (negative
// coordinates, headings across +-pi, duplicate indices as systematic resampling leaves them), and a cloud
// too spread out for the dense box falls back to the hash count.
TEST(Resampling, DenseOccupiedBinsMatchHashTable) {
    Rng rng(9);
    BinCounter bins;
    DenseBins dense;
    std::vector<uint8_t> seen;
    for (float spread : {0.2f, 2.0f, 20.0f, 5000.0f}) {
        ParticleSet p;
        p.resize(4000);
        std::vector<uint32_t> idx;
        for (size_t i = 0; i < p.size(); ++i) {
            p.x[i] = spread * rng.normal() - 3.0f;
            p.y[i] = spread * rng.normal() + 1.0f;
            p.yaw_offset[i] = static_cast<float>(rng.uniform(-3.2, 3.2));
            p.floor[i] = static_cast<int16_t>(i % 3 == 0 ? 1 : 0);
            idx.push_back(static_cast<uint32_t>(i));
            if (i % 5 == 0) idx.push_back(static_cast<uint32_t>(i));
        }
        const size_t expected = count_occupied_bins(p, idx, 0.4f, 0.5f, 0.1745f, bins);
        EXPECT_EQ(count_occupied_bins(p, idx, 0.4f, 0.5f, 0.1745f, bins, dense, seen), expected) << "spread " << spread;
        EXPECT_GT(expected, 10u);
    }
}

// The first draws of a systematic resampling (used by the KLD count's early stop) are exactly the first
// entries of the full draw, for random and for all-zero weights.
TEST(Resampling, SystematicPrefixIsTheFullDrawsStart) {
    Rng rng(31);
    std::vector<float> w(5000);
    for (float &v : w) v = rng.uniform_float() * rng.uniform_float();
    std::vector<uint32_t> full, prefix;
    for (double u0 : {0.05, 0.5, 0.95}) {
        systematic_resample(w.data(), w.size(), 7000, u0, full);
        systematic_resample(w.data(), w.size(), 7000, u0, prefix, 1234);
        ASSERT_EQ(prefix.size(), 1234u);
        EXPECT_TRUE(std::equal(prefix.begin(), prefix.end(), full.begin()));
    }
    systematic_resample(w.data(), w.size(), 70, 0.5, prefix, 1000);  // first > n_out: the whole draw
    EXPECT_EQ(prefix.size(), 70u);
    const std::vector<float> zero(10, 0.0f);
    systematic_resample(zero.data(), zero.size(), 20, 0.5, full);
    systematic_resample(zero.data(), zero.size(), 20, 0.5, prefix, 7);
    EXPECT_TRUE(std::equal(prefix.begin(), prefix.end(), full.begin()));
}

// kld_bins_reaching(count) is the least k whose KLD bound reaches `count`, and the bound stays there for
// every larger k (checked up to 4x), for the shipped epsilon / z and for extreme ones.
TEST(Resampling, KldBinsReachingIsTheThreshold) {
    for (const auto &[eps, z] : {std::pair{0.05, 2.326}, std::pair{0.01, 0.0}, std::pair{0.5, 10.0}, std::pair{1.0, 3.0}}) {
        for (size_t count : {size_t{2000}, size_t{100000}, size_t{1000000}}) {
            const size_t k = kld_bins_reaching(count, eps, z);
            ASSERT_NE(k, SIZE_MAX) << eps << " " << z;
            EXPECT_GE(kld_sample_count(k, eps, z), count);
            if (k > 2) EXPECT_LT(kld_sample_count(k - 1, eps, z), count) << eps << " " << z << " " << count;
            for (size_t j = k; j < 4 * k; j += 1 + j / 97) {
                ASSERT_GE(kld_sample_count(j, eps, z), count) << "k " << j << " eps " << eps << " z " << z;
            }
        }
    }
    // Shipped defaults: about 10^4 bins reach 100k particles (far fewer than a spread-out cloud occupies).
    const size_t k = kld_bins_reaching(100000, 0.05, 2.326);
    EXPECT_GT(k, 9000u);
    EXPECT_LT(k, 11000u);
}
