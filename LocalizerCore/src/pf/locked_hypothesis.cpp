#include "pf/locked_hypothesis.hpp"

#include <cmath>

namespace wf::loc {

size_t dominant_cluster_index(const std::vector<ClusterSummary> &clusters, const LockedPose *locked,
                              const LocalizedHysteresisParams &p) {
    if (locked == nullptr || !p.follow_locked_hypothesis || clusters.empty()) return 0;
    const auto near_lock = [&](const ClusterSummary &c, double radius_m) {
        return c.floor == locked->floor && std::hypot(c.x - locked->x, c.y - locked->y) <= radius_m;
    };
    const ClusterSummary &top = clusters.front();
    if (near_lock(top, p.lock_jump_m)) return 0;
    for (size_t k = 1; k < clusters.size() && clusters[k].weight >= p.lock_rival_weight; ++k) {
        if (near_lock(clusters[k], 2.0 * p.lock_jump_m) && clusters[k].evidence - top.evidence > p.lock_rival_margin_nats) {
            return k;
        }
    }
    return 0;
}

}  // namespace wf::loc
