// Tests for pf/reweighting.hpp: the vectorised weight update and tempered ESS fraction against a plain
// reference (std::exp in double, one particle at a time, sequential sums).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/rng.hpp"
#include "pf/reweighting.hpp"

using namespace wf::loc;

namespace {

/// Log-likelihoods like a sign update's: most particles share one value, some differ, one is the maximum.
std::vector<float> sample_log_likelihoods(size_t n, Rng &rng) {
    std::vector<float> ll(n, -12.5f);
    for (size_t i = 0; i < n; ++i) {
        if (rng.uniform_float() < 0.3f) ll[i] = -30.0f * rng.uniform_float() - 2.0f;
    }
    if (n > 0) ll[n / 2] = -1.0f;
    return ll;
}

}  // namespace

TEST(Reweighting, MatchesThePlainUpdate) {
    Rng rng(17);
    for (size_t n : {1, 5, 8, 13, 4096, 100'001}) {
        const std::vector<float> ll = sample_log_likelihoods(n, rng);
        std::vector<float> w0(n);
        for (float &x : w0) x = rng.uniform_float() / static_cast<float>(n);
        for (float beta : {1.0f, 0.37f}) {
            std::vector<float> w = w0;
            double full = -1;
            const double s = reweight(w.data(), ll.data(), n, -1.0f, beta, &full);
            double ref_s = 0, ref_full = 0;
            for (size_t i = 0; i < n; ++i) {
                // The exponent is formed in float (as the filter always did), then exponentiated in double.
                const float d = ll[i] - -1.0f;
                const double wi = w0[i] * std::exp(static_cast<double>(beta * d));
                EXPECT_NEAR(w[i], wi, 4e-7 * wi) << n << " " << i;
                ref_s += wi;
                ref_full += w0[i] * std::exp(static_cast<double>(d));
            }
            EXPECT_NEAR(s, ref_s, 1e-6 * ref_s) << n;
            EXPECT_NEAR(full, ref_full, 1e-6 * ref_full) << n;
            EXPECT_EQ(w[n / 2], w0[n / 2]);  // the best particle: exp(0) = 1 exactly
            std::vector<float> w2 = w0;
            EXPECT_EQ(reweight(w2.data(), ll.data(), n, -1.0f, beta, nullptr), s);
            EXPECT_EQ(w2, w);
        }
    }
}

TEST(Reweighting, TemperedEssFractionMatchesThePlainFormula) {
    Rng rng(5);
    const size_t m = 8193;
    std::vector<float> w(m), d(m);
    for (size_t k = 0; k < m; ++k) {
        w[k] = rng.uniform_float();
        d[k] = -20.0f * rng.uniform_float();
    }
    for (float beta : {0.0f, 0.1f, 0.5f, 1.0f}) {
        double s = 0, s2 = 0;
        for (size_t k = 0; k < m; ++k) {
            const double v = w[k] * std::exp(static_cast<double>(beta * d[k]));
            s += v;
            s2 += v * v;
        }
        EXPECT_NEAR(tempered_ess_fraction(w.data(), d.data(), m, beta), s * s / s2 / m, 1e-6) << beta;
    }
    const std::vector<float> zero(10, 0.0f);
    EXPECT_EQ(tempered_ess_fraction(zero.data(), d.data(), zero.size(), 1.0f), 1.0);
}
