// Which cluster is the dominant hypothesis: the heaviest, except while localized when the heaviest is a rival
// away from the locked pose that the evidence refutes against the cluster still holding the locked pose. Weight
// is not evidence: planes and the compass (and recovery injection) move weight between hypotheses that the
// sightings tell apart, and the lock already ignores such a rival while it is second (pf/localized_hysteresis,
// `lock_rival_weight`, `lock_rival_margin_nats`); it must not break the lock by becoming first either (the jump
// test would read the rival's pose). docs/localizer.md "Following the locked hypothesis".
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "pf/clustering.hpp"
#include "pf/localized_hysteresis.hpp"

namespace wf::loc {

/// The pose the lock holds: the locked core's mean position (m, map frame) and floor index.
struct LockedPose {
    double x = 0, y = 0;
    int32_t floor = -1;
};

/// Index into `clusters` (sorted by weight, heaviest first, not empty) of the dominant hypothesis. 0 unless
/// `locked` is given (the filter is localized and p.follow_locked_hypothesis is set), the heaviest cluster is
/// not within p.lock_jump_m of the locked pose, and a cluster holding >= p.lock_rival_weight lies within twice
/// that (its whole-cluster mean may sit beside its core; the hysteresis's jump test reads the core) with
/// evidence more than p.lock_rival_margin_nats better than the heaviest's: then the first such cluster.
size_t dominant_cluster_index(const std::vector<ClusterSummary> &clusters, const LockedPose *locked,
                              const LocalizedHysteresisParams &p);

}  // namespace wf::loc
