#include "pf/resampling.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/fast_math.hpp"
#include "common/lane_sums.hpp"
#include "common/simd_clones.hpp"

namespace wf::loc {

WF_SIMD_CLONES double effective_sample_size(const float *weights, size_t n, double *weight_sum) {
    double s = 0, s2 = 0;
    lane_sum_and_squares(weights, n, s, s2);
    if (weight_sum) *weight_sum = s;
    if (!(s2 > 0) || !std::isfinite(s2)) return 0;
    return s * s / s2;  // = 1 / sum w^2 when the weights sum to 1
}

namespace {

/// Slack past the last draw of systematic_draws' output: each particle's copies are written as one block of
/// kCopyBlock stores whatever their number (up to kCopyBlock), so that the walk has no branch per copy.
constexpr size_t kCopyBlock = 8;

/// The draws of systematic_resample once the weights' sum is known. Pointer k (k = 0 .. n_out - 1) lies at
/// (u0 + k) * step along the cumulative weights, step = total / n_out, and falls to the first particle whose
/// cumulative weight reaches it (PR Table 4.4). Counted per particle instead of walked per pointer: the
/// pointers at or below the cumulative weight c_i are N_i = floor(c_i / step - u0) + 1 (clamped to [0, m]), so
/// particle i gets N_i - N_{i-1} copies, written as one block of stores; the pointers a rounding leaves beyond
/// the last cumulative weight go to the last particle, as in the walk. The same draws as the walk up to the
/// rounding of a pointer that lies on a cumulative weight (Tests/LocalizerCore/pf/test_resampling.cpp compares
/// both).
void systematic_draws(const float *weights, size_t n, size_t n_out, double u0, double total, size_t m,
                      std::vector<uint32_t> &out) {
    if (!(total > 0) || !std::isfinite(total)) {
        out.resize(m);
        for (size_t k = 0; k < m; ++k) out[k] = static_cast<uint32_t>((k * n) / n_out);
        return;
    }
    out.resize(m + kCopyBlock);
    uint32_t *o = out.data();
    const double inv_step = static_cast<double>(n_out) / total;
    const auto limit = static_cast<int64_t>(m);
    double cumulative = 0;
    int64_t written = 0;
    for (size_t i = 0; i < n && written < limit; ++i) {
        cumulative += weights[i];
        // Pointers at or below the cumulative weight: floor(x) + 1 = trunc(x + 1) for x = c / step - u0 > -1
        // (c >= 0, u0 < 1), clamped to m as an integer (no floor call, no branch).
        const int64_t upto = std::min(static_cast<int64_t>(cumulative * inv_step - u0 + 1.0), limit);
        const auto id = static_cast<uint32_t>(i);
        for (size_t c = 0; c < kCopyBlock; ++c) o[written + static_cast<int64_t>(c)] = id;
        for (int64_t k = written + static_cast<int64_t>(kCopyBlock); k < upto; ++k) o[k] = id;  // rare
        written = std::max(written, upto);
    }
    for (auto k = static_cast<size_t>(written); k < m; ++k) o[k] = static_cast<uint32_t>(n - 1);
    out.resize(m);
}

}  // namespace

void systematic_resample(const float *weights, size_t n, size_t n_out, double u0, std::vector<uint32_t> &out,
                         size_t first) {
    const size_t m = std::min(n_out, first);
    if (n == 0 || n_out == 0) {
        out.clear();
        return;
    }
    const double total = lane_sum(weights, n);
    systematic_draws(weights, n, n_out, u0, total, m, out);
}

void systematic_resample_with_total(const float *weights, size_t n, size_t n_out, double u0, double total,
                                    std::vector<uint32_t> &out, size_t first) {
    if (n == 0 || n_out == 0) {
        out.clear();
        return;
    }
    systematic_draws(weights, n, n_out, u0, total, std::min(n_out, first), out);
}

size_t kld_sample_count(size_t k, double epsilon, double z) {
    if (k <= 1) return 1;
    const double km1 = static_cast<double>(k - 1);
    const double a = 2.0 / (9.0 * km1);
    const double t = 1.0 - a + std::sqrt(a) * z;
    const double n = km1 / (2.0 * epsilon) * t * t * t;
    if (!(n < 1e12)) return static_cast<size_t>(1e12);
    return static_cast<size_t>(std::ceil(n));
}

size_t kld_bins_reaching(size_t count, double epsilon, double z) {
    // Binary search on the non-decreasing part of the bound: k - 1 >= z^2 / 18 (derivative of
    // (k-1)^(1/3) (1 - a + sqrt(a) z) in k - 1 is positive there; ceil and the cap keep it non-decreasing).
    size_t lo = std::max<size_t>(2, static_cast<size_t>(std::ceil(z * z / 18.0)) + 1);
    size_t hi = 64 * count + 64;
    if (kld_sample_count(hi, epsilon, z) < count) return SIZE_MAX;
    if (kld_sample_count(lo, epsilon, z) >= count) return lo;
    while (hi - lo > 1) {  // invariant: f(lo) < count <= f(hi)
        const size_t mid = lo + (hi - lo) / 2;
        (kld_sample_count(mid, epsilon, z) >= count ? hi : lo) = mid;
    }
    return hi;
}

uint64_t BinCounter::key(int16_t floor, float x, float y, float heading_rad, float inv_bin_m, float inv_bin_yaw,
                         int32_t yaw_bins) {
    // 22 bits per axis (offset by 2^21 bins), 8 bits of heading, 12 bits of floor.
    const int64_t ix = static_cast<int64_t>(std::floor(x * inv_bin_m)) + (int64_t{1} << 21);
    const int64_t iy = static_cast<int64_t>(std::floor(y * inv_bin_m)) + (int64_t{1} << 21);
    const float h = wrap_angle_f(heading_rad) + kPi;  // [0, 2pi]
    int64_t ih = static_cast<int64_t>(h * inv_bin_yaw);
    if (ih >= yaw_bins) ih -= yaw_bins;
    if (ih < 0) ih = 0;
    const uint64_t ux = static_cast<uint64_t>(std::clamp<int64_t>(ix, 0, (int64_t{1} << 22) - 1));
    const uint64_t uy = static_cast<uint64_t>(std::clamp<int64_t>(iy, 0, (int64_t{1} << 22) - 1));
    return (static_cast<uint64_t>(static_cast<uint16_t>(floor) & 0xfff) << 52) | (ux << 30) | (uy << 8) |
           static_cast<uint64_t>(ih & 0xff);
}

void BinCounter::clear(size_t expected) {
    size_t cap = 64;
    while (cap < 2 * expected) cap <<= 1;
    keys_.assign(cap, ~uint64_t{0});
    ids_.assign(cap, 0);
    mask_ = cap - 1;
    count_ = 0;
}

namespace {
inline size_t hash64(uint64_t k) {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    return static_cast<size_t>(k);
}
}  // namespace

uint32_t BinCounter::insert(uint64_t key) {
    if (2 * (count_ + 1) > keys_.size()) {
        // Grow and rehash (keeps ids).
        std::vector<uint64_t> old_keys;
        std::vector<uint32_t> old_ids;
        old_keys.swap(keys_);
        old_ids.swap(ids_);
        const size_t cap = std::max<size_t>(64, old_keys.size() * 2);
        keys_.assign(cap, ~uint64_t{0});
        ids_.assign(cap, 0);
        mask_ = cap - 1;
        for (size_t i = 0; i < old_keys.size(); ++i) {
            if (old_keys[i] == ~uint64_t{0}) continue;
            size_t h = hash64(old_keys[i]) & mask_;
            while (keys_[h] != ~uint64_t{0}) h = (h + 1) & mask_;
            keys_[h] = old_keys[i];
            ids_[h] = old_ids[i];
        }
    }
    size_t h = hash64(key) & mask_;
    while (keys_[h] != ~uint64_t{0}) {
        if (keys_[h] == key) return ids_[h];
        h = (h + 1) & mask_;
    }
    keys_[h] = key;
    ids_[h] = static_cast<uint32_t>(count_);
    return static_cast<uint32_t>(count_++);
}

uint32_t BinCounter::find(uint64_t key) const {
    if (keys_.empty()) return UINT32_MAX;
    size_t h = hash64(key) & mask_;
    while (keys_[h] != ~uint64_t{0}) {
        if (keys_[h] == key) return ids_[h];
        h = (h + 1) & mask_;
    }
    return UINT32_MAX;
}

void DenseBins::reserve(size_t m) {
    if (ix_.size() < m) ix_.resize(m);
    if (iy_.size() < m) iy_.resize(m);
    if (ih_.size() < m) ih_.resize(m);
    if (box_.size() < m) box_.resize(m);
}

WF_SIMD_CLONES bool DenseBins::assign(const ParticleSet &p, const uint32_t *idx, size_t m, float vio_yaw, float inv_bin_m,
                       float inv_bin_yaw, int32_t yaw_bins, size_t max_box) {
    ix_.resize(m);
    iy_.resize(m);
    ih_.resize(m);
    box_.resize(m);
    yaw_bins_ = yaw_bins;
    nx_ = ny_ = nf_ = 0;
    nh_ = yaw_bins;
    if (m == 0) return true;
    // BinCounter::key's arithmetic, branch-free so that it vectorises: floor(v) = trunc(v) - (trunc(v) > v),
    // exact for |v| < 2^31. The key's range is |bin| < 2^21; beyond 2^20 bins, or for a non-finite value
    // (the comparisons reject NaN), the caller falls back to the hash table.
    // The range tests compare the magnitude bits (|v| < 2^20 bins, |heading| < 1e4 rad), and a value outside
    // is zeroed by a mask before its conversion: integer operations only, so both GCC and Clang vectorise.
    constexpr uint32_t kBinLimitBits = 0x49800000u;  // 2^20 as a float
    constexpr uint32_t kYawLimitBits = 0x461c4000u;  // 1e4 as a float (wrap_angle_f's documented range)
    uint32_t bad = 0;
    int32_t xmin = INT32_MAX, xmax = INT32_MIN, ymin = INT32_MAX, ymax = INT32_MIN;
    int32_t fmin = INT32_MAX, fmax = INT32_MIN;
    constexpr size_t kBlock = 256;
    alignas(64) float vx[kBlock], vy[kBlock], hd[kBlock];
    alignas(64) int32_t fl[kBlock];
    auto bits_of = [](float v) {
        uint32_t u;
        std::memcpy(&u, &v, sizeof(u));
        return u;
    };
    auto float_of = [](uint32_t u) {
        float v;
        std::memcpy(&v, &u, sizeof(v));
        return v;
    };
    for (size_t b = 0; b < m; b += kBlock) {
        const size_t nb = std::min(kBlock, m - b);
        if (idx) {
            for (size_t k = 0; k < nb; ++k) {
                const size_t i = idx[b + k];
                vx[k] = p.x[i];
                vy[k] = p.y[i];
                hd[k] = p.yaw_offset[i];
                fl[k] = p.floor[i];
            }
        } else {
            for (size_t k = 0; k < nb; ++k) {
                vx[k] = p.x[b + k];
                vy[k] = p.y[b + k];
                hd[k] = p.yaw_offset[b + k];
                fl[k] = p.floor[b + k];
            }
        }
        int32_t *__restrict ox = ix_.data() + b, *__restrict oy = iy_.data() + b, *__restrict oh = ih_.data() + b;
        for (size_t k = 0; k < nb; ++k) {
            const uint32_t bx = bits_of(vx[k] * inv_bin_m), by = bits_of(vy[k] * inv_bin_m), ba = bits_of(vio_yaw + hd[k]);
            const uint32_t in = static_cast<uint32_t>((bx & 0x7fffffffu) < kBinLimitBits) &
                                static_cast<uint32_t>((by & 0x7fffffffu) < kBinLimitBits) &
                                static_cast<uint32_t>((ba & 0x7fffffffu) < kYawLimitBits);
            bad += in ^ 1u;
            const uint32_t mask = 0u - in;
            const float sx = float_of(bx & mask), sy = float_of(by & mask), sa = float_of(ba & mask);
            const int32_t tx = static_cast<int32_t>(sx), ty = static_cast<int32_t>(sy);
            ox[k] = tx - static_cast<int32_t>(static_cast<float>(tx) > sx);
            oy[k] = ty - static_cast<int32_t>(static_cast<float>(ty) > sy);
            // wrap_angle_f(sa), with the rounding's sign select written as copysign (the same value).
            const float t = sa * (1.0f / kTwoPi);
            const float wrapped = sa - kTwoPi * static_cast<float>(static_cast<int32_t>(t + std::copysign(0.5f, t)));
            int32_t ih = static_cast<int32_t>((wrapped + kPi) * inv_bin_yaw);
            ih -= yaw_bins & -static_cast<int32_t>(ih >= yaw_bins);
            oh[k] = ih & -static_cast<int32_t>(ih >= 0);
        }
        for (size_t k = 0; k < nb; ++k) {
            xmin = std::min(xmin, ox[k]);
            xmax = std::max(xmax, ox[k]);
            ymin = std::min(ymin, oy[k]);
            ymax = std::max(ymax, oy[k]);
            fmin = std::min(fmin, fl[k]);
            fmax = std::max(fmax, fl[k]);
        }
    }
    if (bad != 0) return false;
    const int64_t nx = int64_t{xmax} - xmin + 1, ny = int64_t{ymax} - ymin + 1, nf = int64_t{fmax} - fmin + 1;
    const int64_t nh = yaw_bins;
    if (nx * ny > static_cast<int64_t>(max_box) || nx * ny * nf > static_cast<int64_t>(max_box) ||
        nx * ny * nf * nh > static_cast<int64_t>(max_box)) {
        return false;
    }
    nx_ = static_cast<int32_t>(nx);
    ny_ = static_cast<int32_t>(ny);
    nf_ = static_cast<int32_t>(nf);
    const uint32_t ux = static_cast<uint32_t>(nx_), uy = static_cast<uint32_t>(ny_), uh = static_cast<uint32_t>(nh_);
    for (size_t k = 0; k < m; ++k) {
        const uint32_t f = static_cast<uint32_t>((idx ? p.floor[idx[k]] : p.floor[k]) - fmin);
        box_[k] = ((f * uy + static_cast<uint32_t>(iy_[k] - ymin)) * ux + static_cast<uint32_t>(ix_[k] - xmin)) * uh +
                  static_cast<uint32_t>(ih_[k]);
    }
    return true;
}

size_t count_occupied_bins(const ParticleSet &p, const std::vector<uint32_t> &indices, float vio_yaw, float bin_m,
                           float bin_yaw_rad, BinCounter &bins, DenseBins &dense, std::vector<uint8_t> &seen) {
    const int32_t yaw_bins = std::max<int32_t>(1, static_cast<int32_t>(std::ceil(2.0f * kPi / bin_yaw_rad)));
    const float inv_m = 1.0f / bin_m, inv_yaw = static_cast<float>(yaw_bins) / (2.0f * kPi);
    if (!dense.assign(p, indices.data(), indices.size(), vio_yaw, inv_m, inv_yaw, yaw_bins, 16 * indices.size() + 4096)) {
        return count_occupied_bins(p, indices, vio_yaw, bin_m, bin_yaw_rad, bins);
    }
    seen.assign(dense.box_size(), 0);
    size_t count = 0;
    for (uint32_t b : dense.box_bin()) {
        count += seen[b] ^ 1u;
        seen[b] = 1;
    }
    return count;
}

size_t count_occupied_bins(const ParticleSet &p, const std::vector<uint32_t> &indices, float vio_yaw, float bin_m,
                           float bin_yaw_rad, BinCounter &bins) {
    const int32_t yaw_bins = std::max<int32_t>(1, static_cast<int32_t>(std::ceil(2.0f * kPi / bin_yaw_rad)));
    const float inv_m = 1.0f / bin_m, inv_yaw = static_cast<float>(yaw_bins) / (2.0f * kPi);
    bins.clear(std::min<size_t>(indices.size(), 1 << 16));
    uint32_t last = UINT32_MAX;
    for (uint32_t i : indices) {
        if (i == last) continue;  // systematic indices are sorted: duplicates are adjacent
        last = i;
        bins.insert(BinCounter::key(p.floor[i], p.x[i], p.y[i], vio_yaw + p.yaw_offset[i], inv_m, inv_yaw, yaw_bins));
    }
    return bins.size();
}

}  // namespace wf::loc
