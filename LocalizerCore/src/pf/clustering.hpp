// Clustering of the particle cloud into pose hypotheses, for the estimate. Particles are binned on a coarse
// (floor, x, y, heading) grid; occupied bins holding at least `min_cell_weight` are joined with their 26
// neighbours (heading wraps around) by union-find, so each connected blob of probability mass is one
// hypothesis. The estimate is the weighted mean of the heaviest cluster (circular mean for angles), never the
// mean of the whole cloud, which for two mirrored hypotheses would lie in a wall between them.
#pragma once

#include <cstdint>
#include <vector>

#include "pf/particle_set.hpp"
#include "pf/resampling.hpp"

namespace wf::loc {

struct ClusterSummary {
    /// Total normalised weight of the cluster.
    double weight = 0;
    int16_t floor = 0;
    /// Weighted mean position (m) and position covariance (m^2).
    double x = 0, y = 0, cov_xx = 0, cov_xy = 0, cov_yy = 0;
    /// Circular mean and circular std (sqrt(-2 ln R)) of the map heading, radians.
    double heading = 0, heading_std = 0;
    /// Circular mean of the yaw offset, radians; weighted mean scale.
    double yaw_offset = 0, scale = 1;
    size_t particle_count = 0;
    /// Weighted mean of the particles' recent sign evidence plus their capped compass log-weight (nats, relative;
    /// 0 when the set carries none).
    double evidence = 0;
};

struct ClusterParams {
    float cell_m = 1.0f;
    float yaw_bin_rad = 0.7853982f;
    /// Bins lighter than this do not join clusters (a thin trail of near-dead particles must not merge two
    /// hypotheses).
    float min_cell_weight = 1e-4f;
    /// Bin with DenseBins when the cloud's box of bins is small (same clusters as the hash table, faster);
    /// false forces the hash table (tests compare the two).
    bool dense_bins = true;
    /// Only the clusters whose (cell) weight is at least this get their moments (position, covariance,
    /// heading, yaw offset, scale, evidence); lighter ones get only weight, floor and particle count, with the
    /// moments left at their defaults. The heaviest cluster is always summarised. 0 (default): every cluster.
    /// The weights, the partition and the order are the same whatever this is, and so are the summaries that
    /// are computed (same particle order, same arithmetic): callers that read only the heavy clusters save the
    /// per-particle sums of the light ones.
    double summary_min_weight = 0;
    /// True: no cluster gets its moments (the partition, the weights and the order only, e.g. for the
    /// hypothesis-preserving resampling); the sines and cosines of the headings are skipped too.
    bool weights_only = false;
    /// True: when the particles are the copies announced by carry_bins (nothing moved since), the clusters are
    /// those of the run before the copy (each copy in its source's cluster; copies of light-bin particles in
    /// none), weighed and summarised with the current weights, instead of being found again (binning, light-bin
    /// threshold, union of neighbouring bins). The estimate after a resampling uses it: the partition is the
    /// one the resampling grouped by, a moment earlier. False: the bins are carried, the clusters found again.
    bool reuse_carried_partition = false;
};

class ParticleClusterer {
public:
    /// Clusters `p` (weights normalised) with headings vio_yaw + yaw_offset. Result sorted by weight,
    /// heaviest first; empty only for an empty set.
    const std::vector<ClusterSummary> &run(const ParticleSet &p, float vio_yaw, const ClusterParams &params);

    /// For each particle of the last run: index into the sorted clusters, or -1 (bin too light to join).
    /// Before the first run (after reserve) its size is unspecified.
    const std::vector<int32_t> &particle_clusters() const { return particle_cluster_; }

    /// Sizes the per-particle work arrays for runs of up to `n` particles (and carry_bins of up to n copies),
    /// so that such runs neither allocate nor zero-fill them on first use.
    void reserve(size_t n);

    /// After a resampling of the last run's particle set: particle k of the new set (k < count) is an
    /// unchanged copy of particle src[k] of that set. The next run, when it gets `count` particles, the same
    /// VIO yaw and the same bin parameters, takes each particle's bin from its source instead of binning it
    /// again: the same bins, numbered in the same order (first occurrence), so the same clusters and sums; or,
    /// with ClusterParams::reuse_carried_partition, each particle's cluster from its source.
    /// The caller must call forget_carried_bins() as soon as any particle moves (motion, floor change, a new
    /// VIO yaw, injection, init); the next run consumes the carried bins either way.
    void carry_bins(const uint32_t *src, size_t count);
    void forget_carried_bins() { carried_valid_ = false; }
    /// Whether the last run took its bins from carry_bins (tests, diagnostics).
    bool last_run_used_carried_bins() const { return last_used_carried_; }
    /// Whether the last run took its clusters from carry_bins (ClusterParams::reuse_carried_partition).
    bool last_run_used_carried_partition() const { return last_used_partition_; }

private:
    /// Weighted moment sums over the particles of one cluster (its weight and count come from its cells).
    struct MomentSums {
        double w = 0, wx = 0, wy = 0, wxx = 0, wxy = 0, wyy = 0, oc = 0, os = 0, sc = 0, ev = 0;
    };
    int32_t find(int32_t a);
    /// The carried partition (reuse_carried_partition): clusters' weights, counts and ranks from the current
    /// weights, particle_cluster_ from each copy's carried cluster.
    void rank_carried_partition(const ParticleSet &p);
    /// Adds to `out` the moment sums of particles block + [begin, end) (one run of one cluster within a block),
    /// with their yaw offsets' sines sn[k] and cosines cs[k] and their evidence e[k] (k relative to the block).
    static void add_moments(const ParticleSet &p, size_t block, size_t begin, size_t end, const float *sn,
                            const float *cs, const float *e, MomentSums &out);
    /// Fills clusters_ from the ranked clusters' weights, counts and floors (ranked_*), and the moments of
    /// those chosen by `params` from one pass over the particles of particle_cluster_.
    void summarise(const ParticleSet &p, float vio_yaw, const ClusterParams &params);
    BinCounter bins_;
    DenseBins dense_;
    /// Dense path: cell id of each box bin (-1: empty).
    std::vector<int32_t> box_cell_;
    /// Per cell: its hash key, or its box bin on the dense path.
    std::vector<uint64_t> keys_;
    std::vector<uint32_t> cell_of_;
    std::vector<double> cell_weight_;
    /// Per cell: particles in it, and its floor.
    std::vector<uint32_t> cell_count_;
    std::vector<int16_t> cell_floor_;
    /// Per ranked cluster (heaviest first): weight (sum of its cells' or particles' weights), particle count,
    /// floor.
    std::vector<double> ranked_weight_;
    std::vector<size_t> ranked_count_;
    std::vector<int16_t> ranked_floor_;
    std::vector<MomentSums> acc_;
    std::vector<int32_t> order_, rank_;
    std::vector<double> cluster_weight_;
    std::vector<int32_t> parent_;
    std::vector<int32_t> cluster_of_cell_;
    /// carry_bins: each new particle's cell in the last run's numbering, and what that run was binned with.
    std::vector<uint32_t> carried_cell_;
    /// carry_bins: each new particle's cluster in the last run's ranking (-1: none), those clusters' floors,
    /// and the carried partition's weight and count per cluster (index cluster + 1; slot 0 collects the
    /// particles of no cluster).
    std::vector<int32_t> carried_cluster_;
    std::vector<int16_t> carried_floor_;
    std::vector<double> carried_weight_;
    std::vector<uint32_t> carried_count_;
    std::vector<int32_t> remap_;
    std::vector<uint64_t> old_keys_;
    bool carried_valid_ = false, last_used_carried_ = false, last_used_partition_ = false;
    bool last_dense_ = false;
    float last_vio_yaw_ = 0, last_cell_m_ = 0, last_yaw_bin_rad_ = 0;
    bool last_dense_param_ = true;
    /// Per ranked cluster: 1 when its moments are summed (ClusterParams::summary_min_weight).
    std::vector<uint8_t> summarised_;
    std::vector<ClusterSummary> clusters_;
    std::vector<int32_t> particle_cluster_;
};

}  // namespace wf::loc
