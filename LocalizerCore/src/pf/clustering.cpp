#include "pf/clustering.hpp"

#include <algorithm>
#include <cmath>

#include "common/fast_math.hpp"

namespace wf::loc {

int32_t ParticleClusterer::find(int32_t a) {
    while (parent_[a] != a) {
        parent_[a] = parent_[parent_[a]];  // path halving
        a = parent_[a];
    }
    return a;
}

const std::vector<ClusterSummary> &ParticleClusterer::run(const ParticleSet &p, float vio_yaw,
                                                          const ClusterParams &params) {
    clusters_.clear();
    particle_cluster_.clear();
    const size_t n = p.size();
    if (n == 0) return clusters_;
    const int32_t yaw_bins = std::max<int32_t>(1, static_cast<int32_t>(std::lround(2.0 * kPiD / params.yaw_bin_rad)));
    const float inv_m = 1.0f / params.cell_m;
    const float inv_yaw = static_cast<float>(yaw_bins) / (2.0f * kPi);
    bins_.clear(std::min<size_t>(n, 1 << 15));
    keys_.clear();
    cell_weight_.clear();
    cell_of_.resize(n);
    // Resampling leaves copies of a particle next to each other, and a moved copy is usually still in the
    // same bin: the last key is checked before the hash table.
    uint64_t last_key = ~uint64_t{0};
    uint32_t last_id = 0;
    for (size_t i = 0; i < n; ++i) {
        const uint64_t k = BinCounter::key(p.floor[i], p.x[i], p.y[i], vio_yaw + p.yaw_offset[i], inv_m, inv_yaw, yaw_bins);
        const uint32_t id = k == last_key ? last_id : bins_.insert(k);
        last_key = k;
        last_id = id;
        if (id == keys_.size()) {
            keys_.push_back(k);
            cell_weight_.push_back(0.0);
        }
        cell_of_[i] = id;
        cell_weight_[id] += p.weight[i];
    }
    const size_t cells = keys_.size();
    double max_cell = 0;
    for (double w : cell_weight_) max_cell = std::max(max_cell, w);
    // With a cloud spread thinner than the threshold everywhere, cluster all bins instead.
    const double threshold = max_cell >= params.min_cell_weight ? params.min_cell_weight : 0.0;
    parent_.resize(cells);
    for (size_t c = 0; c < cells; ++c) parent_[c] = static_cast<int32_t>(c);
    const uint64_t mask22 = (uint64_t{1} << 22) - 1;
    for (size_t c = 0; c < cells; ++c) {
        if (cell_weight_[c] < threshold) continue;
        const uint64_t k = keys_[c];
        const uint64_t fl = k >> 52, ux = (k >> 30) & mask22, uy = (k >> 8) & mask22, ih = k & 0xff;
        for (int dx = -1; dx <= 1; ++dx) {
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dh = -1; dh <= 1; ++dh) {
                    if (dx == 0 && dy == 0 && dh == 0) continue;
                    const int64_t h = (static_cast<int64_t>(ih) + dh + yaw_bins) % yaw_bins;
                    const uint64_t nk = (fl << 52) | ((ux + dx) << 30) | ((uy + dy) << 8) | static_cast<uint64_t>(h);
                    const uint32_t nid = bins_.find(nk);
                    if (nid == UINT32_MAX || cell_weight_[nid] < threshold) continue;
                    const int32_t ra = find(static_cast<int32_t>(c)), rb = find(static_cast<int32_t>(nid));
                    if (ra != rb) parent_[std::max(ra, rb)] = std::min(ra, rb);
                }
            }
        }
    }
    cluster_of_cell_.assign(cells, -1);
    struct Acc {
        double w = 0, wx = 0, wy = 0, oc = 0, os = 0, sc = 0, ev = 0;
        int16_t floor = 0;
        size_t count = 0;
    };
    std::vector<Acc> acc;
    for (size_t c = 0; c < cells; ++c) {
        if (cell_weight_[c] < threshold) continue;
        const int32_t r = find(static_cast<int32_t>(c));
        if (cluster_of_cell_[r] < 0) {
            cluster_of_cell_[r] = static_cast<int32_t>(acc.size());
            acc.emplace_back();
        }
        cluster_of_cell_[c] = cluster_of_cell_[r];
    }
    const bool has_evidence = p.evidence.size() == n;
    const bool has_compass = p.compass_ll.size() == n;
    for (size_t i = 0; i < n; ++i) {
        const int32_t cl = cluster_of_cell_[cell_of_[i]];
        if (cl < 0) continue;
        Acc &a = acc[cl];
        const double w = p.weight[i];
        float so, co;
        fast_sincos(wrap_angle_f(p.yaw_offset[i]), so, co);
        a.w += w;
        a.wx += w * p.x[i];
        a.wy += w * p.y[i];
        // Headings are the offsets turned by the common VIO yaw: their resultant is the offsets' resultant
        // rotated by it (below), so one sincos per particle serves both means.
        a.oc += w * co;
        a.os += w * so;
        a.sc += w * p.scale[i];
        if (has_evidence) a.ev += w * p.evidence[i];
        if (has_compass) a.ev += w * p.compass_ll[i];
        a.floor = p.floor[i];
        ++a.count;
    }
    clusters_.resize(acc.size());
    for (size_t k = 0; k < acc.size(); ++k) {
        const Acc &a = acc[k];
        ClusterSummary &s = clusters_[k];
        s.weight = a.w;
        s.floor = a.floor;
        s.particle_count = a.count;
        if (a.w > 0) {
            const double cv = std::cos(static_cast<double>(vio_yaw)), sv = std::sin(static_cast<double>(vio_yaw));
            const double hc = cv * a.oc - sv * a.os, hs = sv * a.oc + cv * a.os;
            s.x = a.wx / a.w;
            s.y = a.wy / a.w;
            s.heading = std::atan2(hs, hc);
            const double rlen = std::min(1.0, std::sqrt(hc * hc + hs * hs) / a.w);
            s.heading_std = rlen > 1e-12 ? std::sqrt(std::max(0.0, -2.0 * std::log(rlen))) : kPiD;
            s.yaw_offset = std::atan2(a.os, a.oc);
            s.scale = a.sc / a.w;
            s.evidence = a.ev / a.w;
        } else {
            // Weightless cluster (all weights zero): plain means.
            s.heading_std = kPiD;
        }
    }
    for (size_t i = 0; i < n; ++i) {
        const int32_t cl = cluster_of_cell_[cell_of_[i]];
        if (cl < 0) continue;
        ClusterSummary &s = clusters_[cl];
        if (!(s.weight > 0)) continue;
        const double w = p.weight[i] / s.weight;
        const double dx = p.x[i] - s.x, dy = p.y[i] - s.y;
        s.cov_xx += w * dx * dx;
        s.cov_xy += w * dx * dy;
        s.cov_yy += w * dy * dy;
    }
    // Sort heaviest first and remap the per-particle cluster ids to the sorted order.
    std::vector<int32_t> order(clusters_.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int32_t>(k);
    std::sort(order.begin(), order.end(), [&](int32_t a, int32_t b) {
        return clusters_[a].weight != clusters_[b].weight ? clusters_[a].weight > clusters_[b].weight : a < b;
    });
    std::vector<int32_t> rank(order.size());
    std::vector<ClusterSummary> sorted(order.size());
    for (size_t k = 0; k < order.size(); ++k) {
        rank[order[k]] = static_cast<int32_t>(k);
        sorted[k] = clusters_[order[k]];
    }
    clusters_.swap(sorted);
    particle_cluster_.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const int32_t cl = cluster_of_cell_[cell_of_[i]];
        particle_cluster_[i] = cl < 0 ? -1 : rank[cl];
    }
    return clusters_;
}

}  // namespace wf::loc
