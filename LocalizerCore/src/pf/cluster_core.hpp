// The core of a cluster: its particles within a radius of the cluster's weighted median position, and their
// weighted moments. A locked hypothesis is a tight blob; particles that recovery injection scatters along the
// same corridor join it by connectivity (pf/clustering), and a few percent of the weight 10-20 m away moved
// its weighted mean by a meter and its standard deviation past the lock's spread limit: one misread far Exit
// sign broke a 0.95 lock this way (docs/localizer.md, "Estimate"). The median is robust to such a tail (up to
// half the weight), and the moments over the core describe where the hypothesis really is.
//
// Written by hand: a weighted median by histogram (two passes, O(members)) and moment sums; no library does
// this on a member list of a structure-of-arrays particle set.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "pf/particle_set.hpp"

namespace wf::loc {

/// Weighted moments of a cluster's core (weights as stored, not renormalised).
struct ClusterCore {
    /// Total weight of the core's particles (same units as ParticleSet::weight: a share of 1).
    double weight = 0;
    /// Weighted mean position (m, map frame) and position covariance (m^2).
    double x = 0, y = 0, cov_xx = 0, cov_xy = 0, cov_yy = 0;
    /// Weighted sums of cos and sin of the yaw offsets (the heading resultant, not divided by the weight).
    double yaw_cos_sum = 0, yaw_sin_sum = 0;
    /// Particles in the core.
    size_t count = 0;
    /// Centre of the core's disc (the members' weighted median, or the centre given to cluster_core_around), m,
    /// map frame.
    double centre_x = 0, centre_y = 0;
    /// Largest standard deviation of the position (square root of the covariance's largest eigenvalue), m.
    double position_std_m() const;
};

/// Computes the core of the cluster made of `members` (indices into `p`): the particles within `radius_m` of
/// the weighted coordinate-wise median of the members' positions (median per axis, from 5 cm histograms over
/// the members' box, at most 4096 bins per axis), and their moments. Empty members (or zero total weight):
/// a core of weight 0. `scratch` is reused between calls (no allocation once grown).
ClusterCore cluster_core(const ParticleSet &p, const std::vector<uint32_t> &members, double radius_m,
                         std::vector<double> &scratch);

/// The core of `members` around a given centre (centre_x, centre_y, m, map frame) instead of their median: the
/// particles within `radius_m` of it and their moments. Between two full estimates the lock's pose follows the
/// particles of the disc found at the last one; a median taken again over a cluster that recovery injection has
/// merged with particles far along the corridor can fall on the far side (docs/localizer.md "The sighted core").
ClusterCore cluster_core_around(const ParticleSet &p, const std::vector<uint32_t> &members, double centre_x,
                                double centre_y, double radius_m);

/// The members whose history explains at least one sighting, in order, into `out`: the range-bias statistics
/// ParticleSet::bias_s0 > 0 (the sign model adds to them only when a sighting is explained better than by
/// clutter; a particle placed by recovery injection or an init starts at 0). Returns the total weight of every
/// such particle of `p`, members or not.
double sighted_members(const ParticleSet &p, const std::vector<uint32_t> &members, std::vector<uint32_t> &out);

/// Per cluster of a clustering (`cluster_of`: each particle's index into its `cluster_count` clusters, or -1), the
/// weight of its particles whose history explains at least one sighting (bias_s0 > 0, as sighted_members), into
/// `out` (resized to cluster_count). One pass over the particles.
void sighted_weight_per_cluster(const ParticleSet &p, const std::vector<int32_t> &cluster_of, size_t cluster_count,
                                std::vector<double> &out);

}  // namespace wf::loc
