#include "pf/clustering.hpp"

#include <algorithm>
#include <cmath>

#include "common/fast_math.hpp"
#include "common/lane_sums.hpp"
#include "common/simd_clones.hpp"

namespace wf::loc {

namespace {

/// (h + bins) % bins for h in [-1, bins] (a heading bin and its neighbours, wrapped around): a compare and an
/// add instead of an integer division, 13 times per active bin.
inline int32_t wrap_bin(int32_t h, int32_t bins) {
    if (h < 0) return h + bins;
    return h >= bins ? h - bins : h;
}

}  // namespace

int32_t ParticleClusterer::find(int32_t a) {
    while (parent_[a] != a) {
        parent_[a] = parent_[parent_[a]];  // path halving
        a = parent_[a];
    }
    return a;
}

void ParticleClusterer::reserve(size_t n) {
    if (cell_of_.size() < n) cell_of_.resize(n);
    if (particle_cluster_.size() < n) particle_cluster_.resize(n);
    if (carried_cell_.size() < n) carried_cell_.resize(n);
    if (carried_cluster_.size() < n) carried_cluster_.resize(n);
    dense_.reserve(n);
}

void ParticleClusterer::carry_bins(const uint32_t *src, size_t count) {
    carried_cell_.resize(count);
    carried_cluster_.resize(count);
    const size_t m = cell_of_.size();
    if (particle_cluster_.size() != m) {
        carried_valid_ = false;
        return;
    }
    for (size_t k = 0; k < count; ++k) {
        if (src[k] >= m) {  // not a particle of the last run: bin afresh
            carried_valid_ = false;
            return;
        }
        carried_cell_[k] = cell_of_[src[k]];
        carried_cluster_[k] = particle_cluster_[src[k]];
    }
    carried_floor_.resize(clusters_.size());
    for (size_t c = 0; c < clusters_.size(); ++c) carried_floor_[c] = clusters_[c].floor;
    carried_valid_ = true;
}

void ParticleClusterer::rank_carried_partition(const ParticleSet &p) {
    const size_t n = p.size();
    const size_t clusters = carried_floor_.size();
    // Weight and count per carried cluster, slot 0 for the particles of none, summed along runs of copies in
    // one cluster (the resampling writes each group's copies together: long runs).
    carried_weight_.assign(clusters + 1, 0.0);
    carried_count_.assign(clusters + 1, 0);
    const float *wp = p.weight.data();
    const int32_t *cc = carried_cluster_.data();
    for (size_t i = 0; i < n;) {
        const int32_t c = cc[i];
        size_t end = i + 1;
        while (end < n && cc[end] == c) ++end;
        const size_t slot = static_cast<size_t>(c + 1);
        carried_weight_[slot] += lane_sum(wp + i, end - i);
        carried_count_[slot] += static_cast<uint32_t>(end - i);
        i = end;
    }
    // Ranked heaviest first (ties: the carried order); clusters left without a particle are dropped.
    order_.clear();
    for (size_t c = 0; c < clusters; ++c) {
        if (carried_count_[c + 1] > 0) order_.push_back(static_cast<int32_t>(c));
    }
    std::sort(order_.begin(), order_.end(), [&](int32_t a, int32_t b) {
        const double wa = carried_weight_[static_cast<size_t>(a) + 1], wb = carried_weight_[static_cast<size_t>(b) + 1];
        return wa != wb ? wa > wb : a < b;
    });
    // rank_[c + 1]: the new rank of carried cluster c (-1 for none and for dropped clusters).
    rank_.assign(clusters + 1, -1);
    ranked_weight_.resize(order_.size());
    ranked_count_.resize(order_.size());
    ranked_floor_.resize(order_.size());
    for (size_t k = 0; k < order_.size(); ++k) {
        const size_t c = static_cast<size_t>(order_[k]);
        rank_[c + 1] = static_cast<int32_t>(k);
        ranked_weight_[k] = carried_weight_[c + 1];
        ranked_count_[k] = carried_count_[c + 1];
        ranked_floor_[k] = carried_floor_[c];
    }
    particle_cluster_.resize(n);
    int32_t *pc = particle_cluster_.data();
    const int32_t *rank = rank_.data();
    for (size_t i = 0; i < n; ++i) pc[i] = rank[cc[i] + 1];
    // The cells stay those of the run before the copy (keys_ unchanged): a further carry_bins, before anything
    // moves, can carry them again.
    cell_of_.swap(carried_cell_);
}

WF_SIMD_CLONES const std::vector<ClusterSummary> &ParticleClusterer::run(const ParticleSet &p, float vio_yaw,
                                                          const ClusterParams &params) {
    clusters_.clear();
    const size_t n = p.size();
    // particle_cluster_ is resized to n (within its capacity: no fill) and written in full below.
    if (n == 0) {
        particle_cluster_.clear();
        return clusters_;
    }
    const int32_t yaw_bins = std::max<int32_t>(1, static_cast<int32_t>(std::lround(2.0 * kPiD / params.yaw_bin_rad)));
    const float inv_m = 1.0f / params.cell_m;
    const float inv_yaw = static_cast<float>(yaw_bins) / (2.0f * kPi);
    cell_weight_.clear();
    cell_count_.clear();
    cell_floor_.clear();
    cell_of_.resize(n);
    // Bins carried over from the last run through a resampling (carry_bins): the sources' cells, renumbered
    // in order of first occurrence in the new set, exactly as binning the (unchanged) copies again would.
    const bool reuse = carried_valid_ && carried_cell_.size() == n && last_vio_yaw_ == vio_yaw &&
                       last_cell_m_ == params.cell_m && last_yaw_bin_rad_ == params.yaw_bin_rad &&
                       last_dense_param_ == params.dense_bins;
    carried_valid_ = false;
    last_used_carried_ = reuse;
    last_used_partition_ = reuse && params.reuse_carried_partition;
    if (last_used_partition_) {
        rank_carried_partition(p);
        summarise(p, vio_yaw, params);
        return clusters_;
    }
    const float *wp = p.weight.data();
    bool dense = last_dense_;
    if (reuse) {
        old_keys_.swap(keys_);
        keys_.clear();
        remap_.assign(old_keys_.size(), -1);
        for (size_t i = 0; i < n; ++i) {
            int32_t &slot = remap_[carried_cell_[i]];
            if (slot < 0) {
                slot = static_cast<int32_t>(keys_.size());
                keys_.push_back(old_keys_[carried_cell_[i]]);
                cell_weight_.push_back(0.0);
                cell_count_.push_back(0);
                cell_floor_.push_back(p.floor[i]);
            }
            cell_of_[i] = static_cast<uint32_t>(slot);
            cell_weight_[slot] += wp[i];
            ++cell_count_[slot];
        }
        if (dense) {
            box_cell_.assign(dense_.box_size(), -1);
            for (size_t c = 0; c < keys_.size(); ++c) box_cell_[keys_[c]] = static_cast<int32_t>(c);
        } else {
            bins_.clear(std::min<size_t>(n, 1 << 15));
            for (uint64_t k : keys_) bins_.insert(k);
        }
    } else {
        keys_.clear();
        // Dense bins over the occupied box when it is small (the usual case: one building, at most 8 bins per
        // particle), else the hash table. Both number the cells in order of first occurrence, so the clusters are
        // the same either way.
        dense = params.dense_bins && dense_.assign(p, nullptr, n, vio_yaw, inv_m, inv_yaw, yaw_bins, 8 * n + 4096);
        if (dense) {
            box_cell_.assign(dense_.box_size(), -1);
        } else {
            bins_.clear(std::min<size_t>(n, 1 << 15));
        }
        // First pass: the cell of each particle and the cells' weights (small arrays, cache-resident).
        uint64_t last_key = ~uint64_t{0};
        uint32_t last_id = 0;
        if (dense) {
            const uint32_t *box = dense_.box_bin().data();
            // The arrays' data pointers in locals, refreshed when a new cell grows them (otherwise every store
            // through one of them makes the compiler load the others' again).
            int32_t *box_cell = box_cell_.data();
            uint32_t *cell_of = cell_of_.data();
            double *cell_weight = cell_weight_.data();
            uint32_t *cell_count = cell_count_.data();
            for (size_t i = 0; i < n; ++i) {
                int32_t slot = box_cell[box[i]];
                if (slot < 0) {
                    slot = static_cast<int32_t>(keys_.size());
                    box_cell[box[i]] = slot;
                    keys_.push_back(box[i]);
                    cell_weight_.push_back(0.0);
                    cell_count_.push_back(0);
                    cell_floor_.push_back(p.floor[i]);
                    cell_weight = cell_weight_.data();
                    cell_count = cell_count_.data();
                }
                cell_of[i] = static_cast<uint32_t>(slot);
                cell_weight[slot] += wp[i];
                ++cell_count[slot];
            }
        } else {
            for (size_t i = 0; i < n; ++i) {
                // Resampling leaves copies of a particle next to each other, and a moved copy is usually still in
                // the same bin: the last key is checked before the hash table.
                const uint64_t key =
                    BinCounter::key(p.floor[i], p.x[i], p.y[i], vio_yaw + p.yaw_offset[i], inv_m, inv_yaw, yaw_bins);
                const uint32_t id = key == last_key ? last_id : bins_.insert(key);
                last_key = key;
                last_id = id;
                if (id == keys_.size()) {
                    keys_.push_back(key);
                    cell_weight_.push_back(0.0);
                    cell_count_.push_back(0);
                    cell_floor_.push_back(p.floor[i]);
                }
                cell_of_[i] = id;
                cell_weight_[id] += wp[i];
                ++cell_count_[id];
            }
        }
    }
    last_dense_ = dense;
    last_vio_yaw_ = vio_yaw;
    last_cell_m_ = params.cell_m;
    last_yaw_bin_rad_ = params.yaw_bin_rad;
    last_dense_param_ = params.dense_bins;
    const size_t cells = keys_.size();
    double max_cell = 0;
    for (double w : cell_weight_) max_cell = std::max(max_cell, w);
    // With a cloud spread thinner than the threshold everywhere, cluster all bins instead.
    const double threshold = max_cell >= params.min_cell_weight ? params.min_cell_weight : 0.0;
    parent_.resize(cells);
    for (size_t c = 0; c < cells; ++c) parent_[c] = static_cast<int32_t>(c);
    // Dense path: bins too light to join are removed from the box, so a neighbour test is one array read.
    if (dense) {
        for (size_t c = 0; c < cells; ++c) {
            if (cell_weight_[c] < threshold) box_cell_[keys_[c]] = -1;
        }
    }
    // Union of cell c (whose root `root` is kept up to date) with an active neighbour nid (smaller root wins).
    auto join = [&](int32_t &root, uint32_t nid) {
        const int32_t rb = find(static_cast<int32_t>(nid));
        if (root == rb) return;
        parent_[std::max(root, rb)] = std::min(root, rb);
        root = std::min(root, rb);
    };
    // Each pair of neighbouring bins is visited once, from the bin whose offset to the other is "forward"
    // (dx, dy, dh lexicographically after 0, 0, 0): the partition is the same as visiting all 26.
    if (dense) {
        const int32_t nx = dense_.nx(), ny = dense_.ny(), nh = dense_.nh();
        for (size_t c = 0; c < cells; ++c) {
            if (cell_weight_[c] < threshold) continue;
            int32_t ix, iy, ih, f;
            dense_.decode(static_cast<uint32_t>(keys_[c]), ix, iy, ih, f);
            int32_t root = find(static_cast<int32_t>(c));
            const int64_t plane = static_cast<int64_t>(f) * ny;
            for (int dx = 0; dx <= 1; ++dx) {
                for (int dy = -1; dy <= 1; ++dy) {
                    if (dx == 0 && dy < 0) continue;
                    const int32_t jx = ix + dx, jy = iy + dy;
                    if (jx >= nx || jy < 0 || jy >= ny) continue;
                    const int64_t base = ((plane + jy) * nx + jx) * nh;
                    for (int dh = -1; dh <= 1; ++dh) {
                        if (dx == 0 && dy == 0 && dh <= 0) continue;
                        const int32_t h = wrap_bin(ih + dh, yaw_bins);
                        const int32_t id = box_cell_[static_cast<size_t>(base + h)];
                        if (id >= 0) join(root, static_cast<uint32_t>(id));
                    }
                }
            }
        }
    } else {
        const uint64_t mask22 = (uint64_t{1} << 22) - 1;
        for (size_t c = 0; c < cells; ++c) {
            if (cell_weight_[c] < threshold) continue;
            const uint64_t k = keys_[c];
            const uint64_t fl = k >> 52, ux = (k >> 30) & mask22, uy = (k >> 8) & mask22, ih = k & 0xff;
            int32_t root = find(static_cast<int32_t>(c));
            for (int dx = 0; dx <= 1; ++dx) {
                for (int dy = -1; dy <= 1; ++dy) {
                    if (dx == 0 && dy < 0) continue;
                    for (int dh = -1; dh <= 1; ++dh) {
                        if (dx == 0 && dy == 0 && dh <= 0) continue;
                        const int64_t h = wrap_bin(static_cast<int32_t>(ih) + dh, yaw_bins);
                        const uint64_t nk = (fl << 52) | ((ux + dx) << 30) | ((uy + dy) << 8) | static_cast<uint64_t>(h);
                        const uint32_t nid = bins_.find(nk);
                        if (nid != UINT32_MAX && cell_weight_[nid] >= threshold) join(root, nid);
                    }
                }
            }
        }
    }
    // Clusters numbered in order of their first cell, with their weights (sums of their cells'), then
    // ranked heaviest first (ties: first cell first).
    cluster_of_cell_.assign(cells, -1);
    cluster_weight_.clear();
    int32_t cluster_count = 0;
    for (size_t c = 0; c < cells; ++c) {
        if (cell_weight_[c] < threshold) continue;
        const int32_t r = find(static_cast<int32_t>(c));
        if (cluster_of_cell_[r] < 0) {
            cluster_of_cell_[r] = cluster_count++;
            cluster_weight_.push_back(0.0);
        }
        cluster_of_cell_[c] = cluster_of_cell_[r];
        cluster_weight_[cluster_of_cell_[c]] += cell_weight_[c];
    }
    order_.resize(static_cast<size_t>(cluster_count));
    for (size_t k = 0; k < order_.size(); ++k) order_[k] = static_cast<int32_t>(k);
    std::sort(order_.begin(), order_.end(), [&](int32_t a, int32_t b) {
        return cluster_weight_[a] != cluster_weight_[b] ? cluster_weight_[a] > cluster_weight_[b] : a < b;
    });
    rank_.resize(order_.size());
    for (size_t k = 0; k < order_.size(); ++k) rank_[order_[k]] = static_cast<int32_t>(k);
    // Each ranked cluster's weight, count and floor from its cells (a cluster lies on one floor: bins join
    // only on their own floor), and each cell's ranked cluster.
    ranked_weight_.resize(order_.size());
    ranked_count_.assign(order_.size(), 0);
    ranked_floor_.resize(order_.size());
    for (size_t k = 0; k < order_.size(); ++k) ranked_weight_[k] = cluster_weight_[order_[k]];
    for (size_t c = 0; c < cells; ++c) {
        if (cluster_of_cell_[c] < 0) continue;
        const int32_t k = rank_[cluster_of_cell_[c]];
        cluster_of_cell_[c] = k;
        ranked_count_[k] += cell_count_[c];
        ranked_floor_[k] = cell_floor_[c];
    }
    // Each particle's cluster: one gather per particle.
    particle_cluster_.resize(n);
    int32_t *pc = particle_cluster_.data();
    const int32_t *cluster_of_cell = cluster_of_cell_.data();
    const uint32_t *cell_of = cell_of_.data();
    for (size_t i = 0; i < n; ++i) pc[i] = cluster_of_cell[cell_of[i]];
    summarise(p, vio_yaw, params);
    return clusters_;
}

namespace {

/// Per-particle inputs of the moment sums for one block of particles: sine and cosine of the yaw offset,
/// evidence plus compass log-weight.
struct MomentInputs {
    static constexpr size_t kBlock = 256;
    alignas(64) float sn[kBlock], cs[kBlock], e[kBlock];
};

}  // namespace

inline void ParticleClusterer::add_moments(const ParticleSet &p, size_t block, size_t begin, size_t end,
                                    const float *sn, const float *cs, const float *e, MomentSums &out) {
    const float *pw = p.weight.data() + block, *px = p.x.data() + block, *py = p.y.data() + block,
                *ps = p.scale.data() + block;
    // Headings are the offsets turned by the common VIO yaw: their resultant is the offsets' resultant rotated
    // by it (summarise), so one sincos per particle serves both means.
    constexpr size_t kLanes = 4;
    if (end - begin < 4 * kLanes) {
        // A short run (a cloud in particle order, the light clusters): one particle at a time.
        for (size_t k = begin; k < end; ++k) {
            const double wk = pw[k], x = px[k], y = py[k];
            const double wxk = wk * x, wyk = wk * y;
            out.w += wk;
            out.wx += wxk;
            out.wy += wyk;
            out.wxx += wxk * x;
            out.wxy += wxk * y;
            out.wyy += wyk * y;
            out.oc += wk * cs[k];
            out.os += wk * sn[k];
            out.sc += wk * ps[k];
            out.ev += wk * e[k];
        }
        return;
    }
    // A long run: kLanes lanes per sum (element k in lane (k - begin) % kLanes), so that the loop vectorises.
    double w[kLanes] = {}, wx[kLanes] = {}, wy[kLanes] = {}, wxx[kLanes] = {}, wxy[kLanes] = {}, wyy[kLanes] = {},
           oc[kLanes] = {}, os[kLanes] = {}, sc[kLanes] = {}, ev[kLanes] = {};
    auto add = [&](size_t k, size_t l) {
        const double wk = pw[k], x = px[k], y = py[k];
        const double wxk = wk * x, wyk = wk * y;
        w[l] += wk;
        wx[l] += wxk;
        wy[l] += wyk;
        wxx[l] += wxk * x;
        wxy[l] += wxk * y;
        wyy[l] += wyk * y;
        oc[l] += wk * cs[k];
        os[l] += wk * sn[k];
        sc[l] += wk * ps[k];
        ev[l] += wk * e[k];
    };
    const size_t body = begin + (end - begin) - (end - begin) % kLanes;
    for (size_t k = begin; k < body; k += kLanes) {
        for (size_t l = 0; l < kLanes; ++l) add(k + l, l);
    }
    for (size_t k = body; k < end; ++k) add(k, k - body);
    auto fold = [](const double (&v)[kLanes]) { return (v[0] + v[2]) + (v[1] + v[3]); };
    out.w += fold(w);
    out.wx += fold(wx);
    out.wy += fold(wy);
    out.wxx += fold(wxx);
    out.wxy += fold(wxy);
    out.wyy += fold(wyy);
    out.oc += fold(oc);
    out.os += fold(os);
    out.sc += fold(sc);
    out.ev += fold(ev);
}

WF_SIMD_CLONES void ParticleClusterer::summarise(const ParticleSet &p, float vio_yaw, const ClusterParams &params) {
    const size_t n = p.size();
    const size_t cluster_count = ranked_weight_.size();
    // Which clusters get their moments: none (weights_only), else the heaviest and those holding at least
    // summary_min_weight.
    summarised_.assign(cluster_count, 0);
    bool any_summary = false;
    if (!params.weights_only) {
        for (size_t k = 0; k < cluster_count; ++k) {
            summarised_[k] = k == 0 || ranked_weight_[k] >= params.summary_min_weight;
            any_summary |= summarised_[k] != 0;
        }
    }
    // The summarised clusters' moment sums, along runs of consecutive particles in one cluster (the
    // resampling writes each group's copies together; the whole cloud is one run once it has converged).
    acc_.assign(cluster_count, MomentSums{});
    const uint8_t *full = summarised_.data();
    if (any_summary) {
        const int32_t *pc = particle_cluster_.data();
        const bool has_evidence = p.evidence.size() == n;
        const bool has_compass = p.compass_ll.size() == n;
        MomentInputs in;
        constexpr size_t kBlock = MomentInputs::kBlock;
        MomentSums run;
        int32_t run_cluster = -1;
        auto flush = [&] {
            if (run_cluster >= 0) {
                MomentSums &a = acc_[static_cast<size_t>(run_cluster)];
                a.w += run.w;
                a.wx += run.wx;
                a.wy += run.wy;
                a.wxx += run.wxx;
                a.wxy += run.wxy;
                a.wyy += run.wyy;
                a.oc += run.oc;
                a.os += run.os;
                a.sc += run.sc;
                a.ev += run.ev;
            }
            run = MomentSums{};
        };
        for (size_t b = 0; b < n; b += kBlock) {
            const size_t nb = std::min(kBlock, n - b);
            // The block's sines and cosines and evidence (vectorised), computed when its first run of a summarised
            // cluster comes (a block of only light or unclustered particles, most of a spread-out cloud after a
            // resampling, needs none), then its runs.
            bool inputs_ready = false;
            auto prepare_inputs = [&] {
                const float *yo = p.yaw_offset.data() + b;
                for (size_t k = 0; k < nb; ++k) fast_sincos(wrap_angle_f(yo[k]), in.sn[k], in.cs[k]);
                for (size_t k = 0; k < nb; ++k) in.e[k] = 0.0f;
                if (has_evidence) {
                    for (size_t k = 0; k < nb; ++k) in.e[k] = p.evidence[b + k];
                }
                if (has_compass) {
                    for (size_t k = 0; k < nb; ++k) in.e[k] += p.compass_ll[b + k];
                }
                inputs_ready = true;
            };
            for (size_t k = 0; k < nb;) {
                const int32_t cl = pc[b + k];
                size_t end = k + 1;
                while (end < nb && pc[b + end] == cl) ++end;
                // Sums of consecutive runs of one cluster (across blocks) are kept in `run` (registers) and added
                // to the cluster's at a change of cluster, summarised or not, so that a cluster's sums do not
                // depend on which others are summarised.
                if (cl != run_cluster) {
                    flush();
                    run_cluster = cl;
                }
                if (cl >= 0 && full[cl]) {
                    if (!inputs_ready) prepare_inputs();
                    add_moments(p, b, k, end, in.sn, in.cs, in.e, run);
                }
                k = end;
            }
        }
        flush();
    }
    clusters_.resize(cluster_count);
    const double cv = std::cos(static_cast<double>(vio_yaw)), sv = std::sin(static_cast<double>(vio_yaw));
    for (size_t k = 0; k < cluster_count; ++k) {
        const MomentSums &a = acc_[k];
        ClusterSummary &s = clusters_[k];
        s = ClusterSummary{};
        s.weight = ranked_weight_[k];
        s.floor = ranked_floor_[k];
        s.particle_count = ranked_count_[k];
        if (!full[k]) {
            s.heading_std = kPiD;  // not summarised: weight, floor and count only
        } else if (a.w > 0) {
            // The moments are normalised by the weight their own pass summed (the same particles and weights
            // as the cluster's weight, added in another order).
            const double hc = cv * a.oc - sv * a.os, hs = sv * a.oc + cv * a.os;
            s.x = a.wx / a.w;
            s.y = a.wy / a.w;
            // Covariance from the moments about the origin (double sums: for positions within 10 km and a
            // spread of 1 mm the cancellation leaves more than 6 significant digits).
            s.cov_xx = std::max(0.0, a.wxx / a.w - s.x * s.x);
            s.cov_yy = std::max(0.0, a.wyy / a.w - s.y * s.y);
            s.cov_xy = a.wxy / a.w - s.x * s.y;
            s.heading = std::atan2(hs, hc);
            const double rlen = std::min(1.0, std::sqrt(hc * hc + hs * hs) / a.w);
            s.heading_std = rlen > 1e-12 ? std::sqrt(std::max(0.0, -2.0 * std::log(rlen))) : kPiD;
            s.yaw_offset = std::atan2(a.os, a.oc);
            s.scale = a.sc / a.w;
            s.evidence = a.ev / a.w;
        } else {
            // Weightless cluster (all weights zero).
            s.heading_std = kPiD;
        }
    }
}

}  // namespace wf::loc
