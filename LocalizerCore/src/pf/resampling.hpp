// Resampling building blocks (Probabilistic Robotics = PR):
//  - effective sample size ESS = 1 / sum w_i^2 (Kong, Liu & Wong 1994; PR section 4.3.4): resample only
//    when it falls below a fraction of N, which limits particle depletion;
//  - low-variance (systematic) resampling, PR Table 4.4: one random offset, N evenly spaced pointers;
//  - KLD-sampling (Fox 2003, "Adapting the sample size in particle filters through KLD-sampling", IJRR
//    22(12)): the number of particles needed so that, with probability 1 - delta, the KL divergence between
//    the sample-based and the true posterior (discretised on k occupied bins) stays below epsilon.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "pf/particle_set.hpp"

namespace wf::loc {

/// 1 / sum(w^2) for weights summing to 1. When `weight_sum` is not null it receives sum(w) as lane_sum forms it
/// (common/lane_sums): the total that systematic_resample forms, for systematic_resample_with_total.
double effective_sample_size(const float *weights, size_t n, double *weight_sum = nullptr);

/// Systematic resampling: writes `n_out` source indices into `out` (sorted, proportional to the weights,
/// each particle i drawn floor or ceil of n_out * w_i times). `u0` in [0, 1) is the single random offset.
/// Weights need not be normalised; all-zero or non-finite sums fall back to uniform.
/// With `first` < n_out only the first `first` of the n_out draws are written (`out` holds that many): the
/// same values as the full draw's first entries, at a fraction of the cost.
void systematic_resample(const float *weights, size_t n, size_t n_out, double u0, std::vector<uint32_t> &out,
                         size_t first = SIZE_MAX);

/// systematic_resample(weights, n, n_out, u0, out, first) for a caller that already holds `total`, the weights'
/// sum formed as systematic_resample forms it (lane_sum of the weights): the same draws without the
/// summing pass.
void systematic_resample_with_total(const float *weights, size_t n, size_t n_out, double u0, double total,
                                    std::vector<uint32_t> &out, size_t first = SIZE_MAX);

/// Fox 2003 eq. (12): n = (k-1)/(2 eps) * (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) z)^3, for k occupied bins.
/// Returns 1 for k <= 1.
size_t kld_sample_count(size_t k, double epsilon, double z);

/// The least number of occupied bins k from which kld_sample_count(k', epsilon, z) >= `count` for every
/// k' >= k (the bound is non-decreasing in k once k - 1 >= z^2 / 18, where this search starts), or SIZE_MAX
/// when no k up to 64 * count + 64 reaches it. KLD-sampling uses it to stop counting bins once the count is
/// certain to be clamped to max_particles.
size_t kld_bins_reaching(size_t count, double epsilon, double z);

/// Histogram bins over (floor, x, y, heading) for KLD-sampling and clustering: a flat open-addressing set
/// of 64-bit keys, reused between calls.
class BinCounter {
public:
    /// Key of a state: floor, x / bin_m, y / bin_m, heading / bin_yaw (heading wrapped to [-pi, pi)).
    static uint64_t key(int16_t floor, float x, float y, float heading_rad, float inv_bin_m, float inv_bin_yaw,
                        int32_t yaw_bins);
    void clear(size_t expected);
    /// Inserts a key; returns its dense id (0, 1, 2, ... in order of first insertion).
    uint32_t insert(uint64_t key);
    /// Dense id of a key, or UINT32_MAX when absent.
    uint32_t find(uint64_t key) const;
    size_t size() const { return count_; }

private:
    std::vector<uint64_t> keys_;
    std::vector<uint32_t> ids_;
    size_t mask_ = 0, count_ = 0;
};

/// Dense numbering of the bins of BinCounter::key (the same bins: floor, floor(x / bin_m), floor(y / bin_m),
/// heading bin) over the box of bins the particles occupy, so that per-particle binning is a vectorised index
/// computation and one array read instead of a hash probe (the hash table of a spread-out cloud is larger
/// than the cache). Used by the clustering and by KLD-sampling; when the box would be too large (particles
/// far apart) or a coordinate is non-finite or beyond the key's range, `assign` refuses and the caller keeps
/// the hash table.
class DenseBins {
public:
    /// Computes the box bin of particles idx[0..m) (of 0..m-1 when idx is null), with heading
    /// vio_yaw + yaw offset. Returns false when a particle is non-finite or beyond the key range, or when the
    /// box holds more than max_box bins.
    bool assign(const ParticleSet &p, const uint32_t *idx, size_t m, float vio_yaw, float inv_bin_m,
                float inv_bin_yaw, int32_t yaw_bins, size_t max_box);
    /// Sizes the per-item work arrays for `m` items, so that an assign of up to m items neither allocates nor
    /// zero-fills them.
    void reserve(size_t m);
    /// Box bin of item k of the last assign, in [0, box_size()).
    const std::vector<uint32_t> &box_bin() const { return box_; }
    size_t box_size() const { return static_cast<size_t>(nf_) * ny_ * nx_ * nh_; }
    /// Box coordinates of box bin b: column, row, heading bin, floor (relative to the box).
    void decode(uint32_t b, int32_t &ix, int32_t &iy, int32_t &ih, int32_t &f) const {
        ih = static_cast<int32_t>(b % static_cast<uint32_t>(nh_));
        uint32_t r = b / static_cast<uint32_t>(nh_);
        ix = static_cast<int32_t>(r % static_cast<uint32_t>(nx_));
        r /= static_cast<uint32_t>(nx_);
        iy = static_cast<int32_t>(r % static_cast<uint32_t>(ny_));
        f = static_cast<int32_t>(r / static_cast<uint32_t>(ny_));
    }
    int32_t nx() const { return nx_; }
    int32_t ny() const { return ny_; }
    int32_t nh() const { return nh_; }

private:
    std::vector<int32_t> ix_, iy_, ih_;
    std::vector<uint32_t> box_;
    int32_t nx_ = 0, ny_ = 0, nh_ = 1, nf_ = 0, yaw_bins_ = 1;
};

/// Number of KLD bins occupied by the particles listed in `indices` (heading = vio_yaw + yaw offset).
size_t count_occupied_bins(const ParticleSet &p, const std::vector<uint32_t> &indices, float vio_yaw, float bin_m,
                           float bin_yaw_rad, BinCounter &bins);

/// The same count with dense bins when the box of occupied bins is small (at most 16 bins per listed
/// particle), else with the hash table; `dense` and `seen` are reused between calls.
size_t count_occupied_bins(const ParticleSet &p, const std::vector<uint32_t> &indices, float vio_yaw, float bin_m,
                           float bin_yaw_rad, BinCounter &bins, DenseBins &dense, std::vector<uint8_t> &seen);

}  // namespace wf::loc
