// Tests for pf/clustering.hpp: separate blobs become separate hypotheses, means and covariances are right,
// headings average circularly across +-pi.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "common/rng.hpp"
#include "pf/clustering.hpp"

using namespace wf::loc;

namespace {
void add_blob(ParticleSet &p, Rng &rng, size_t n, float x, float y, float heading, float sigma, float weight_each) {
    const size_t s = p.size();
    p.resize(s + n);
    for (size_t i = s; i < s + n; ++i) {
        p.x[i] = x + sigma * rng.normal();
        p.y[i] = y + sigma * rng.normal();
        p.yaw_offset[i] = heading + 0.05f * rng.normal();
        p.scale[i] = 1;
        p.floor[i] = 0;
        p.weight[i] = weight_each;
    }
}
}  // namespace

TEST(Clustering, TwoBlobsTwoHypotheses) {
    Rng rng(4);
    ParticleSet p;
    add_blob(p, rng, 3000, 5, 1, 0.0f, 0.3f, 0.7f / 3000);
    add_blob(p, rng, 2000, 25, 1, 3.14159f, 0.3f, 0.3f / 2000);
    ParticleClusterer c;
    const auto &cl = c.run(p, 0.0f, ClusterParams{});
    ASSERT_GE(cl.size(), 2u);
    EXPECT_NEAR(cl[0].weight, 0.7, 0.01);
    EXPECT_NEAR(cl[1].weight, 0.3, 0.01);
    EXPECT_NEAR(cl[0].x, 5, 0.03);    // 3 standard errors of 0.3/sqrt(3000)
    EXPECT_NEAR(cl[1].x, 25, 0.03);
    EXPECT_NEAR(std::sqrt(cl[0].cov_xx), 0.3, 0.02);
    EXPECT_NEAR(std::sqrt(cl[0].cov_yy), 0.3, 0.02);
    EXPECT_NEAR(cl[0].cov_xy, 0.0, 0.01);
    EXPECT_NEAR(std::fabs(cl[1].heading), 3.14159, 0.01);
}

TEST(Clustering, CircularMeanAcrossPi) {
    Rng rng(5);
    ParticleSet p;
    add_blob(p, rng, 1000, 0, 0, 3.1f, 0.2f, 0.5f / 1000);
    add_blob(p, rng, 1000, 0, 0, -3.1f, 0.2f, 0.5f / 1000);
    ParticleClusterer c;
    const auto &cl = c.run(p, 0.0f, ClusterParams{});
    ASSERT_EQ(cl.size(), 1u);  // adjacent heading bins wrap around
    EXPECT_NEAR(std::fabs(cl[0].heading), 3.14159, 0.01);
    EXPECT_LT(cl[0].heading_std, 0.1);
}

TEST(Clustering, HeadingUsesVioYawPlusOffset) {
    Rng rng(6);
    ParticleSet p;
    add_blob(p, rng, 500, 0, 0, 0.5f, 0.1f, 1.0f / 500);
    ParticleClusterer c;
    const auto &cl = c.run(p, 1.0f, ClusterParams{});
    ASSERT_EQ(cl.size(), 1u);
    EXPECT_NEAR(cl[0].heading, 1.5, 0.01);
    EXPECT_NEAR(cl[0].yaw_offset, 0.5, 0.01);
}

namespace {
// Runs the clustering with dense bins and with the hash table and expects the very same result (the dense
// path numbers cells and clusters in the same order and sums in the same order).
void expect_same_clusters(const ParticleSet &p, float vio_yaw) {
    ClusterParams dense_params, hash_params;
    hash_params.dense_bins = false;
    ParticleClusterer dense, hash;
    const std::vector<ClusterSummary> a = dense.run(p, vio_yaw, dense_params);
    const std::vector<ClusterSummary> b = hash.run(p, vio_yaw, hash_params);
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].weight, b[k].weight) << "cluster " << k;
        EXPECT_EQ(a[k].x, b[k].x) << "cluster " << k;
        EXPECT_EQ(a[k].y, b[k].y) << "cluster " << k;
        EXPECT_EQ(a[k].cov_xx, b[k].cov_xx) << "cluster " << k;
        EXPECT_EQ(a[k].cov_xy, b[k].cov_xy) << "cluster " << k;
        EXPECT_EQ(a[k].heading, b[k].heading) << "cluster " << k;
        EXPECT_EQ(a[k].floor, b[k].floor) << "cluster " << k;
        EXPECT_EQ(a[k].particle_count, b[k].particle_count) << "cluster " << k;
    }
    EXPECT_EQ(dense.particle_clusters(), hash.particle_clusters());
}
}  // namespace

// Dense bins (the fast path) and the hash table give identical clusters: a spread-out cloud over a floor
// (the costly case: thousands of bins near the weight threshold), blobs on two floors at negative
// coordinates, headings across +-pi.
TEST(Clustering, DenseBinsMatchHashTable) {
    Rng rng(11);
    ParticleSet spread;
    spread.resize(20000);
    for (size_t i = 0; i < spread.size(); ++i) {
        spread.x[i] = 40 * rng.uniform_float();
        spread.y[i] = 30 * rng.uniform_float();
        spread.yaw_offset[i] = static_cast<float>(rng.uniform(-3.14159, 3.14159));
        spread.scale[i] = 1;
        spread.floor[i] = 0;
        spread.weight[i] = (0.5f + rng.uniform_float()) / 20000.0f;
    }
    expect_same_clusters(spread, 0.7f);

    ParticleSet blobs;
    add_blob(blobs, rng, 3000, -12.5f, -3.2f, 3.1f, 0.4f, 0.5f / 3000);
    add_blob(blobs, rng, 2000, 7.0f, -20.0f, -3.1f, 0.6f, 0.3f / 2000);
    const size_t first_upper = blobs.size();
    add_blob(blobs, rng, 2000, -12.5f, -3.2f, 0.0f, 0.4f, 0.2f / 2000);
    for (size_t i = first_upper; i < blobs.size(); ++i) blobs.floor[i] = 2;
    expect_same_clusters(blobs, -2.0f);
}

// Particles too far apart for a small box of bins (two hypotheses 3 km apart) take the hash table path and
// still give both clusters.
TEST(Clustering, FarApartFallsBackToHashTable) {
    Rng rng(12);
    ParticleSet p;
    add_blob(p, rng, 500, 0, 0, 0.0f, 0.2f, 0.6f / 500);
    add_blob(p, rng, 500, 3000, 2000, 1.0f, 0.2f, 0.4f / 500);
    expect_same_clusters(p, 0.0f);
    ParticleClusterer c;
    const auto &cl = c.run(p, 0.0f, ClusterParams{});
    ASSERT_EQ(cl.size(), 2u);
    EXPECT_NEAR(cl[1].x, 3000, 0.05);
}

// The covariance comes from moments about the origin: a tight blob far from the origin (5 km, 5 cm spread)
// keeps its covariance.
TEST(Clustering, CovarianceFarFromOrigin) {
    Rng rng(13);
    ParticleSet p;
    add_blob(p, rng, 4000, 5000, -4000, 0.3f, 0.05f, 1.0f / 4000);
    ParticleClusterer c;
    const auto &cl = c.run(p, 0.0f, ClusterParams{});
    ASSERT_EQ(cl.size(), 1u);
    EXPECT_NEAR(std::sqrt(cl[0].cov_xx), 0.05, 0.004);
    EXPECT_NEAR(std::sqrt(cl[0].cov_yy), 0.05, 0.004);
    EXPECT_NEAR(cl[0].cov_xy, 0.0, 2e-4);
}

namespace {
// A cloud of blobs of very different weights (0.4 down to 0.0005) over a spread-out background of light
// particles, with evidence, weights normalised to 1 (seed `seed`): many clusters, heavy and light.
ParticleSet mixed_cloud(uint64_t seed) {
    Rng rng(seed);
    ParticleSet p;
    const float blob_w[] = {0.4f, 0.2f, 0.1f, 0.05f, 0.01f, 0.003f, 0.0015f, 0.0005f};
    for (int b = 0; b < 8; ++b) {
        add_blob(p, rng, 1500, 3.0f + 5.0f * b, (b % 2) ? 4.0f : 24.0f, 0.7f * b, 0.3f, blob_w[b] / 1500);
    }
    const size_t first_spread = p.size();
    p.resize(first_spread + 20000);
    for (size_t i = first_spread; i < p.size(); ++i) {
        p.x[i] = 40 * rng.uniform_float();
        p.y[i] = 30 * rng.uniform_float();
        p.yaw_offset[i] = static_cast<float>(rng.uniform(-3.14159, 3.14159));
        p.scale[i] = 1.0f + 0.03f * rng.normal();
        p.floor[i] = 0;
        p.weight[i] = 0.2f * rng.uniform_float() / 20000;
    }
    double total = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        p.evidence[i] = -rng.uniform_float();
        p.compass_ll[i] = -0.1f * rng.uniform_float();
        total += p.weight[i];
    }
    for (float &w : p.weight) w = static_cast<float>(w / total);
    return p;
}

void expect_same_summary(const ClusterSummary &a, const ClusterSummary &b, size_t k) {
    EXPECT_EQ(a.weight, b.weight) << "cluster " << k;
    EXPECT_EQ(a.particle_count, b.particle_count) << "cluster " << k;
    EXPECT_EQ(a.floor, b.floor) << "cluster " << k;
    EXPECT_EQ(a.x, b.x) << "cluster " << k;
    EXPECT_EQ(a.y, b.y) << "cluster " << k;
    EXPECT_EQ(a.cov_xx, b.cov_xx) << "cluster " << k;
    EXPECT_EQ(a.cov_xy, b.cov_xy) << "cluster " << k;
    EXPECT_EQ(a.cov_yy, b.cov_yy) << "cluster " << k;
    EXPECT_EQ(a.heading, b.heading) << "cluster " << k;
    EXPECT_EQ(a.heading_std, b.heading_std) << "cluster " << k;
    EXPECT_EQ(a.yaw_offset, b.yaw_offset) << "cluster " << k;
    EXPECT_EQ(a.scale, b.scale) << "cluster " << k;
    EXPECT_EQ(a.evidence, b.evidence) << "cluster " << k;
}
/// A resampling-like copy of `p`: each particle 0, 1 or 2 times (its indices in *src), each copy's weight its
/// source's times a uniform factor in [lo, lo + span), then normalised (a later reweighting).
ParticleSet resampled_copies(const ParticleSet &p, Rng &rng, float lo, float span, std::vector<uint32_t> *src) {
    src->clear();
    for (uint32_t i = 0; i < p.size(); ++i) {
        const uint32_t copies = rng.below(3);
        for (uint32_t c = 0; c < copies; ++c) src->push_back(i);
    }
    ParticleSet q;
    q.resize(src->size());
    double total = 0;
    for (size_t k = 0; k < src->size(); ++k) {
        const uint32_t i = (*src)[k];
        q.x[k] = p.x[i];
        q.y[k] = p.y[i];
        q.yaw_offset[k] = p.yaw_offset[i];
        q.scale[k] = p.scale[i];
        q.floor[k] = p.floor[i];
        q.evidence[k] = p.evidence[i];
        q.compass_ll[k] = p.compass_ll[i];
        q.weight[k] = p.weight[i] * (lo + span * rng.uniform_float());
        total += q.weight[k];
    }
    for (float &w : q.weight) w = static_cast<float>(w / total);
    return q;
}

}  // namespace

// Summarising only the clusters that are read (summary_min_weight) or none (weights_only, the resampling's
// use) leaves the partition, the order and the weights exactly as a full run, and the summarised clusters'
// moments exactly the same; the heaviest cluster is always summarised.
TEST(Clustering, PartialSummariesMatchFullRun) {
    const ParticleSet p = mixed_cloud(21);
    ClusterParams full_params, partial_params, weights_params;
    partial_params.summary_min_weight = 0.002;
    weights_params.weights_only = true;
    ParticleClusterer full, partial, weights;
    const std::vector<ClusterSummary> a = full.run(p, 0.4f, full_params);
    const std::vector<ClusterSummary> b = partial.run(p, 0.4f, partial_params);
    const std::vector<ClusterSummary> c = weights.run(p, 0.4f, weights_params);
    ASSERT_GT(a.size(), 3u);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_EQ(a.size(), c.size());
    EXPECT_EQ(full.particle_clusters(), partial.particle_clusters());
    EXPECT_EQ(full.particle_clusters(), weights.particle_clusters());
    size_t summarised = 0, skipped = 0;
    for (size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].weight, b[k].weight) << "cluster " << k;
        EXPECT_EQ(a[k].weight, c[k].weight) << "cluster " << k;
        EXPECT_EQ(a[k].particle_count, c[k].particle_count) << "cluster " << k;
        if (k == 0 || a[k].weight >= 0.002) {
            expect_same_summary(a[k], b[k], k);
            ++summarised;
        } else if (a[k].weight < 0.001) {
            EXPECT_EQ(b[k].x, 0.0) << "cluster " << k << " should not be summarised";
            ++skipped;
        }
    }
    EXPECT_GT(summarised, 0u);
    EXPECT_GT(skipped, 0u);  // the threshold really skips some clusters in this cloud
    EXPECT_EQ(c[0].x, 0.0);  // weights only: not even the heaviest
}

// carry_bins: after a resampling-like copy (sources repeated, some dropped, in sorted order), the next run
// takes each copy's bin from its source and gives exactly the clusters of a fresh clusterer on the new set;
// a new VIO yaw (particles' headings changed) or forget_carried_bins makes it bin afresh.
TEST(Clustering, CarriedBinsMatchFreshRun) {
    const ParticleSet p = mixed_cloud(22);
    Rng rng(23);
    for (const bool dense : {true, false}) {
        ClusterParams params;
        params.dense_bins = dense;
        ParticleClusterer carried;
        carried.run(p, 0.4f, params);
        // Copies: each source 0, 1 or 2 times, then new weights (a later reweighting), normalised.
        std::vector<uint32_t> src;
        const ParticleSet q = resampled_copies(p, rng, 0.5f, 1.0f, &src);
        carried.carry_bins(src.data(), src.size());
        const std::vector<ClusterSummary> a = carried.run(q, 0.4f, params);
        EXPECT_TRUE(carried.last_run_used_carried_bins());
        ParticleClusterer fresh;
        const std::vector<ClusterSummary> b = fresh.run(q, 0.4f, params);
        EXPECT_FALSE(fresh.last_run_used_carried_bins());
        ASSERT_EQ(a.size(), b.size()) << (dense ? "dense" : "hash");
        for (size_t k = 0; k < a.size(); ++k) expect_same_summary(a[k], b[k], k);
        EXPECT_EQ(carried.particle_clusters(), fresh.particle_clusters());
        // Consumed by that run: the next one bins afresh.
        carried.run(q, 0.4f, params);
        EXPECT_FALSE(carried.last_run_used_carried_bins());
        // Another VIO yaw: the carried bins are stale and not used.
        carried.run(p, 0.4f, params);
        carried.carry_bins(src.data(), src.size());
        carried.run(q, 0.9f, params);
        EXPECT_FALSE(carried.last_run_used_carried_bins());
        carried.run(p, 0.4f, params);
        carried.carry_bins(src.data(), src.size());
        carried.forget_carried_bins();
        carried.run(q, 0.4f, params);
        EXPECT_FALSE(carried.last_run_used_carried_bins());
    }
}

// reuse_carried_partition: after a resampling-like copy, each copy is in its source's cluster (copies of
// particles in no cluster in none), the clusters are ranked by their current weight, and each one's weight,
// count, floor and moments are the plain sums over its copies under the current weights; a cluster left
// without copies is dropped. Without the flag (or after forget_carried_bins) the clusters are found again.
TEST(Clustering, CarriedPartitionSummarisesTheSourcesClusters) {
    const ParticleSet p = mixed_cloud(24);
    Rng rng(25);
    ParticleClusterer carried;
    carried.run(p, 0.4f, ClusterParams{});
    const std::vector<int32_t> source_cluster = carried.particle_clusters();
    std::vector<uint32_t> src;
    const ParticleSet q = resampled_copies(p, rng, 0.2f, 2.0f, &src);  // copies, then a later reweighting
    ClusterParams reuse;
    reuse.reuse_carried_partition = true;
    carried.carry_bins(src.data(), src.size());
    const std::vector<ClusterSummary> a = carried.run(q, 0.4f, reuse);
    EXPECT_TRUE(carried.last_run_used_carried_partition());
    ASSERT_GT(a.size(), 3u);
    // Same partition: copies of one source cluster share a new cluster, and distinct ones do not.
    const std::vector<int32_t> &pc = carried.particle_clusters();
    ASSERT_EQ(pc.size(), q.size());
    std::map<int32_t, int32_t> new_of_old;
    for (size_t k = 0; k < src.size(); ++k) {
        const int32_t old_c = source_cluster[src[k]];
        if (old_c < 0) {
            EXPECT_EQ(pc[k], -1) << k;
            continue;
        }
        const auto it = new_of_old.emplace(old_c, pc[k]).first;
        EXPECT_EQ(it->second, pc[k]) << k;
    }
    EXPECT_EQ(new_of_old.size(), a.size());
    // Plain sums per new cluster.
    std::vector<double> w(a.size()), wx(a.size()), wy(a.size()), wxx(a.size()), ws(a.size());
    std::vector<size_t> count(a.size());
    for (size_t k = 0; k < q.size(); ++k) {
        if (pc[k] < 0) continue;
        const double wk = q.weight[k];
        w[pc[k]] += wk;
        wx[pc[k]] += wk * q.x[k];
        wy[pc[k]] += wk * q.y[k];
        wxx[pc[k]] += wk * q.x[k] * q.x[k];
        ws[pc[k]] += wk * q.scale[k];
        ++count[pc[k]];
    }
    for (size_t c = 0; c < a.size(); ++c) {
        if (c > 0) EXPECT_GE(a[c - 1].weight, a[c].weight) << c;  // ranked by current weight
        EXPECT_NEAR(a[c].weight, w[c], 1e-12) << c;
        EXPECT_EQ(a[c].particle_count, count[c]) << c;
        if (c > 0) continue;  // only the heaviest is surely summarised (default summary_min_weight: all are)
        EXPECT_NEAR(a[c].x, wx[c] / w[c], 1e-9) << c;
        EXPECT_NEAR(a[c].y, wy[c] / w[c], 1e-9) << c;
        EXPECT_NEAR(a[c].cov_xx, wxx[c] / w[c] - (wx[c] / w[c]) * (wx[c] / w[c]), 1e-7) << c;
        EXPECT_NEAR(a[c].scale, ws[c] / w[c], 1e-9) << c;
    }
    // Without the flag: the bins are carried, the clusters found again (as a fresh clusterer finds them).
    carried.run(p, 0.4f, ClusterParams{});
    carried.carry_bins(src.data(), src.size());
    const std::vector<ClusterSummary> b = carried.run(q, 0.4f, ClusterParams{});
    EXPECT_TRUE(carried.last_run_used_carried_bins());
    EXPECT_FALSE(carried.last_run_used_carried_partition());
    ParticleClusterer fresh;
    EXPECT_EQ(fresh.run(q, 0.4f, ClusterParams{}).size(), b.size());
    EXPECT_EQ(fresh.particle_clusters(), carried.particle_clusters());
    // Forgotten: nothing carried.
    carried.run(p, 0.4f, ClusterParams{});
    carried.carry_bins(src.data(), src.size());
    carried.forget_carried_bins();
    carried.run(q, 0.4f, reuse);
    EXPECT_FALSE(carried.last_run_used_carried_partition());
}
