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

/// 1 / sum(w^2) for weights summing to 1.
double effective_sample_size(const float *weights, size_t n);

/// Systematic resampling: writes `n_out` source indices into `out` (sorted, proportional to the weights,
/// each particle i drawn floor or ceil of n_out * w_i times). `u0` in [0, 1) is the single random offset.
/// Weights need not be normalised; all-zero or non-finite sums fall back to uniform.
void systematic_resample(const float *weights, size_t n, size_t n_out, double u0, std::vector<uint32_t> &out);

/// Fox 2003 eq. (12): n = (k-1)/(2 eps) * (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) z)^3, for k occupied bins.
/// Returns 1 for k <= 1.
size_t kld_sample_count(size_t k, double epsilon, double z);

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

/// Number of KLD bins occupied by the particles listed in `indices` (heading = vio_yaw + yaw offset).
size_t count_occupied_bins(const ParticleSet &p, const std::vector<uint32_t> &indices, float vio_yaw, float bin_m,
                           float bin_yaw_rad, BinCounter &bins);

}  // namespace wf::loc
