// Which cluster is the dominant hypothesis (pf/locked_hypothesis): the heaviest, unless a locked filter's heaviest
// cluster is a rival away from the locked pose that the evidence refutes against the cluster still holding it.
#include <gtest/gtest.h>

#include <vector>

#include "pf/locked_hypothesis.hpp"

using wf::loc::ClusterSummary;
using wf::loc::dominant_cluster_index;
using wf::loc::LocalizedHysteresisParams;
using wf::loc::LockedPose;

namespace {

ClusterSummary cluster(double weight, double x, double y, double evidence, int16_t floor = 0) {
    ClusterSummary c;
    c.weight = weight;
    c.x = x;
    c.y = y;
    c.evidence = evidence;
    c.floor = floor;
    return c;
}

}  // namespace

TEST(LockedHypothesis, ARefutedRivalThatOutweighsTheLockDoesNotTakeIt) {
    // Locked at (17, 16); the planes moved weight to a rival 7 m away, now the heaviest (0.48 against 0.40),
    // whose sign evidence is 12.9 nats worse: the lock stays on its cluster.
    const LocalizedHysteresisParams p;
    const LockedPose locked{17.2, 16.1, 0};
    const std::vector<ClusterSummary> clusters = {cluster(0.48, 20, 10, -12.9), cluster(0.40, 17, 16, 0),
                                                  cluster(0.05, 30, 4, -20)};
    EXPECT_EQ(dominant_cluster_index(clusters, &locked, p), 1u);
    // Not localized (no locked pose): the heaviest.
    EXPECT_EQ(dominant_cluster_index(clusters, nullptr, p), 0u);
    // The rule off: the heaviest.
    LocalizedHysteresisParams off;
    off.follow_locked_hypothesis = false;
    EXPECT_EQ(dominant_cluster_index(clusters, &locked, off), 0u);
}

TEST(LockedHypothesis, TheHeaviestStaysDominantUnlessTheEvidenceRefutesItAgainstTheLock) {
    const LocalizedHysteresisParams p;  // margin 1 nat, rival weight 0.2, jump 3 m
    const LockedPose locked{17, 16, 0};
    // The heaviest is the locked cluster itself (within 3 m): 0.
    EXPECT_EQ(dominant_cluster_index({cluster(0.6, 18, 15, 0), cluster(0.3, 25, 10, 2)}, &locked, p), 0u);
    // A rival that explains the evidence as well (within 1 nat) takes over: 0 (the jump then breaks the lock).
    EXPECT_EQ(dominant_cluster_index({cluster(0.5, 25, 10, -0.5), cluster(0.4, 17, 16, 0)}, &locked, p), 0u);
    // The cluster at the locked pose is too light to hold a lock (< lock_rival_weight): 0.
    EXPECT_EQ(dominant_cluster_index({cluster(0.85, 25, 10, -9), cluster(0.1, 17, 16, 0)}, &locked, p), 0u);
    // Nothing left at the locked pose (the second cluster is elsewhere): 0.
    EXPECT_EQ(dominant_cluster_index({cluster(0.5, 25, 10, -9), cluster(0.4, 40, 16, 0)}, &locked, p), 0u);
    // The locked cluster on another floor than the lock's: 0.
    EXPECT_EQ(dominant_cluster_index({cluster(0.5, 25, 10, -9), cluster(0.4, 17, 16, 0, 1)}, &locked, p), 0u);
    // Its whole-cluster mean 5 m from the locked core (a tail along the corridor): still the locked cluster.
    EXPECT_EQ(dominant_cluster_index({cluster(0.5, 25, 10, -9), cluster(0.4, 22, 16, 0)}, &locked, p), 1u);
}
