#include "common/rng.hpp"

#include <cmath>

namespace wf::loc {

void Rng::reseed(uint64_t seed) {
    // splitmix64 (Steele, Lea, Flood 2014) spreads any seed over the 256-bit state; never all zero.
    uint64_t z = seed;
    for (uint64_t &word : s_) {
        z += 0x9e3779b97f4a7c15ull;
        uint64_t x = z;
        x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
        x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
        word = x ^ (x >> 31);
    }
    have_spare_ = false;
}

// Ziggurat tables for 128 layers of equal area under exp(-x^2/2) (Marsaglia & Tsang 2000, "The Ziggurat
// Method for Generating Random Variables", J. Stat. Software 5(8)): r = 3.442619855899 is the start of the
// tail, v = 9.91256303526217e-3 the common layer area.
Rng::ZigguratTables::ZigguratTables() {
    const double m1 = 2147483648.0;  // 2^31
    double dn = 3.442619855899;
    double tn = dn;
    const double vn = 9.91256303526217e-3;
    const double q = vn / std::exp(-0.5 * dn * dn);
    kn[0] = static_cast<uint32_t>((dn / q) * m1);
    kn[1] = 0;
    wn[0] = static_cast<float>(q / m1);
    wn[127] = static_cast<float>(dn / m1);
    fn[0] = 1.0f;
    fn[127] = static_cast<float>(std::exp(-0.5 * dn * dn));
    for (int i = 126; i >= 1; --i) {
        dn = std::sqrt(-2.0 * std::log(vn / dn + std::exp(-0.5 * dn * dn)));
        kn[i + 1] = static_cast<uint32_t>((dn / tn) * m1);
        tn = dn;
        fn[i] = static_cast<float>(std::exp(-0.5 * dn * dn));
        wn[i] = static_cast<float>(dn / m1);
    }
}

const Rng::ZigguratTables Rng::kTables;

float Rng::normal_slow(int32_t hz, uint32_t iz) {
    constexpr double r = 3.442619855899;
    for (;;) {
        const double x = static_cast<double>(hz) * kTables.wn[iz];
        if (iz == 0) {
            // Tail beyond r: Marsaglia's exponential rejection.
            double xt, yt;
            do {
                xt = -std::log(1.0 - uniform()) / r;
                yt = -std::log(1.0 - uniform());
            } while (yt + yt < xt * xt);
            return static_cast<float>(hz > 0 ? r + xt : -r - xt);
        }
        // Wedge between layers: accept under the density.
        if (kTables.fn[iz] + uniform() * (kTables.fn[iz - 1] - kTables.fn[iz]) < std::exp(-0.5 * x * x)) {
            return static_cast<float>(x);
        }
        hz = static_cast<int32_t>(next_u32());
        iz = static_cast<uint32_t>(hz) & 127u;
        const uint32_t abs_hz = hz < 0 ? 0u - static_cast<uint32_t>(hz) : static_cast<uint32_t>(hz);
        if (abs_hz < kTables.kn[iz]) return static_cast<float>(hz) * kTables.wn[iz];
    }
}

}  // namespace wf::loc
