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

void Rng::fill_normal(float *out, size_t count) {
    size_t i = 0;
    while (i < count) {
        if (have_spare_) {
            out[i++] = normal();  // consumes the spare half first, as normal() would
            continue;
        }
        // Fast loop on a local copy of the state (kept in registers): each xoshiro256++ step gives two
        // 32-bit words, the low one first (next_u32 returns it and keeps the high one as the spare). It
        // stops at the first word that needs the Ziggurat slow path, which then runs on the member state.
        uint64_t s0 = s_[0], s1 = s_[1], s2 = s_[2], s3 = s_[3];
        int32_t slow_hz = 0;
        bool slow = false, slow_has_spare = false;
        uint32_t slow_spare = 0;
        while (i < count) {
            const uint64_t v = rotl(s0 + s3, 23) + s0;
            const uint64_t t = s1 << 17;
            s2 ^= s0;
            s3 ^= s1;
            s1 ^= s2;
            s0 ^= s3;
            s2 ^= t;
            s3 = rotl(s3, 45);
            const int32_t lo = static_cast<int32_t>(static_cast<uint32_t>(v));
            const int32_t hi = static_cast<int32_t>(static_cast<uint32_t>(v >> 32));
            const uint32_t ilo = static_cast<uint32_t>(lo) & 127u;
            const uint32_t alo = lo < 0 ? 0u - static_cast<uint32_t>(lo) : static_cast<uint32_t>(lo);
            if (alo >= kTables.kn[ilo]) {
                slow = true;
                slow_hz = lo;
                slow_has_spare = true;  // the high half is the next 32-bit word
                slow_spare = static_cast<uint32_t>(hi);
                break;
            }
            out[i++] = static_cast<float>(lo) * kTables.wn[ilo];
            if (i == count) {
                slow_has_spare = true;  // unused high half, kept as next_u32 would
                slow_spare = static_cast<uint32_t>(hi);
                break;
            }
            const uint32_t ihi = static_cast<uint32_t>(hi) & 127u;
            const uint32_t ahi = hi < 0 ? 0u - static_cast<uint32_t>(hi) : static_cast<uint32_t>(hi);
            if (ahi >= kTables.kn[ihi]) {
                slow = true;
                slow_hz = hi;
                break;
            }
            out[i++] = static_cast<float>(hi) * kTables.wn[ihi];
        }
        s_[0] = s0;
        s_[1] = s1;
        s_[2] = s2;
        s_[3] = s3;
        if (slow_has_spare) {
            spare_ = slow_spare;
            have_spare_ = true;
        }
        if (slow) out[i++] = normal_slow(slow_hz, static_cast<uint32_t>(slow_hz) & 127u);
    }
}

}  // namespace wf::loc
