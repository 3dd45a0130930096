// Symmetric twins (docs/localizer.md, "Symmetric twins"). On a floor that a rotation maps onto itself
// (map/floor_symmetry), every hypothesis has a twin: each particle rotated about the fixed point, its heading
// turned by the same angle. Walls, planes and symmetrically placed signs give both the same likelihood, so only
// Monte Carlo noise decides which one a particle filter keeps. Measured on the bundled office (a half-turn
// symmetric plan): five of eight filter seeds locked on the twin of the truth, 180 degrees off, after about 9 m
// of a walk whose evidence could not tell the two apart until room numbers were read some 20 m later.
// KLD-sampling makes it worse (the cloud shrinks to 2,000 particles among a dozen early hypotheses), but a fixed
// 100,000 does not cure it: the twins' early particles are not equally well placed, and the better placed survive.
//
// The guard makes the twin's case explicit instead of leaving it to the sampling:
//  - Each particle carries, per symmetry of its floor, the log-likelihood ratio of its history against its
//    twin's history (`ParticleSet::twin_llr`, inherited through resampling like the other states): at each sign,
//    plane and compass update the filter scores the whole cloud's twins with the same model and adds the
//    difference (the walls that the symmetry does not map onto walls, a few percent of the plan, are real
//    evidence: without the planes a walk in the office's south corridor settled after 24 s instead of 12-16 s).
//    This doubles the measurement cost on a symmetric floor; an asymmetric map pays nothing.
//  - Lock: a cluster's Bayes factor against its twin is log(sum w) - log(sum w exp(-llr)) over its particles;
//    the localized flag needs it to reach the rival-refuting margin for every symmetry, and a lock drops when
//    the twin is ahead by the lock's rival margin (pf/localized_hysteresis).
//  - Reseeding: the dominant hypothesis and its twin share their mass as the ratios say (twin : dominant =
//    sum w exp(-llr) : sum w over the dominant's particles). When the twin region holds less than half its share,
//    particles of the dominant hypothesis are moved onto their twin poses (their ratio negated, their evidence
//    lowered by it) until it holds its share: the pair's mass is split, never created, so the other hypotheses
//    keep their weight. The filter then holds both until the evidence tells them apart, and the twin is there
//    when it does. Twins refuted by more than `refuted_nats` are left alone.
// Written here: no library keeps a particle filter's symmetric hypotheses apart. The twin ratio is the exact
// likelihood ratio of two deterministic trajectories (the twin is a rigid transform of the particle's).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "map/localizer_map.hpp"
#include "pf/particle_set.hpp"

namespace wf::loc {

/// Internal parameters of the twin guard (not part of the C ABI; `twin.enabled` by name).
struct TwinGuardParams {
    /// Off: no twin scoring, no reseeding, no twin condition on the lock.
    bool enabled = true;
    /// Particles within clamp(region_std_factor * std, region_min_radius_m, region_max_radius_m) of the dominant
    /// mean, meters, and within region_yaw_rad of its yaw offset stand for the dominant hypothesis (reseeding).
    double region_min_radius_m = 1.5, region_max_radius_m = 4.0, region_std_factor = 2.0;
    double region_yaw_rad = 0.6;
    /// Reseed when the twin region holds less than this share of the weight the ratios give it.
    double reseed_fraction = 0.5;
    /// A twin refuted by more than this (nats, the dominant's Bayes factor) is not reseeded.
    double refuted_nats = 8.0;
    /// Largest change of a particle's ratio by one update, nats (one wild sighting cannot settle it).
    double max_step_nats = 20.0;
};

/// Twin scoring helpers and the reseeding state; reset() on every init of the filter. Value type.
class TwinGuard {
public:
    explicit TwinGuard(const TwinGuardParams &p = {}) : p_(p) {}
    const TwinGuardParams &params() const { return p_; }
    TwinGuardParams &mutable_params() { return p_; }

    /// Number of twin ratio arrays the map needs: the most symmetries of one floor, at most
    /// ParticleSet::kMaxTwins (0 on a map without symmetric floor).
    static size_t twin_arrays_for(const LocalizerMap &map);

    /// Forgets the dominant hypothesis (reseeding region).
    void reset() { has_dominant_ = false; }
    /// After each estimate: the dominant cluster's floor, mean position (meters, map frame), yaw offset
    /// (radians) and position std (meters), the region reseed() works on.
    void observe_dominant(int32_t floor, double x, double y, double yaw_offset_rad, double std_m);

    /// True when a cluster at (floor, x, y) with mean yaw offset `yaw_offset_rad` lies in the region of a twin
    /// of the dominant hypothesis last observed (its mean rotated by a symmetry of the floor, the yaw offset turned
    /// by the same angle).
    bool is_twin_of_dominant(const LocalizerMap &map, int32_t floor, double x, double y, double yaw_offset_rad) const;
    /// Fills x, y and yaw_offset (resized to p.size()) with the pose of every particle's twin under symmetry k
    /// of its floor (position turned about the fixed point, yaw offset by the angle); particles on floors with
    /// fewer symmetries keep their own pose (their ratio is then not updated). Every other state of a twin is
    /// its particle's. False when the guard is off or no floor has a k-th symmetry.
    bool twin_poses(const ParticleSet &p, const LocalizerMap &map, size_t k, std::vector<float> &x,
                    std::vector<float> &y, std::vector<float> &yaw_offset) const;
    /// Sets every particle's ratios to the prior's: log_prior(floor, x, y) at the particle minus at its twin
    /// (clamped to max_step_nats). A named start makes the start's twin unlikely before any evidence: with the
    /// ratios left at 0 the guard would hold the twin as equally likely and block the lock.
    template <class LogPrior>
    void set_prior_ratios(ParticleSet &p, const LocalizerMap &map, LogPrior &&log_prior) const {
        for (size_t k = 0; k < p.twin_arrays; ++k) {
            for (size_t i = 0; i < p.size(); ++i) {
                const FloorSymmetry *sym = symmetry_of(map, p.floor[i], k);
                if (!sym || !p_.enabled) {
                    p.twin_llr[k][i] = 0;
                    continue;
                }
                float tx, ty;
                sym->apply(p.x[i], p.y[i], tx, ty);
                const double r = log_prior(p.floor[i], p.x[i], p.y[i]) - log_prior(p.floor[i], tx, ty);
                p.twin_llr[k][i] = static_cast<float>(std::clamp(r, -p_.max_step_nats, p_.max_step_nats));
            }
        }
    }
    /// Symmetry k of floor f of `map`, or nullptr.
    static const FloorSymmetry *symmetry_of(const LocalizerMap &map, int32_t f, size_t k) {
        if (f < 0 || static_cast<size_t>(f) >= map.floors.size()) return nullptr;
        const std::vector<FloorSymmetry> &s = map.floors[static_cast<size_t>(f)].symmetries;
        return k < s.size() ? &s[k] : nullptr;
    }
    /// p.twin_llr[k][i] += ll[i] - twin_ll[i] (clamped to max_step_nats) for the particles whose floor has a k-th
    /// symmetry; non-finite values count as the clamp.
    void accumulate(ParticleSet &p, const LocalizerMap &map, size_t k, const float *ll, const float *twin_ll) const;
    /// Bayes factor of the particles `members` (a cluster, all on one floor) against their twins, nats: the
    /// lowest over the symmetries of their floor of log(sum w) - log(sum w exp(-twin_llr)). +infinity when there is none (no
    /// symmetric floor, guard off, no weight).
    double log_ratio(const ParticleSet &p, const LocalizerMap &map, const uint32_t *members, size_t count) const;
    /// Moves particles of the dominant hypothesis onto their twin poses where the twin region holds less than
    /// reseed_fraction of the pair's mass share its ratios give it. Weights are kept (mass moves). Returns the number moved (then the caller's clusters and estimate are stale).
    size_t reseed(ParticleSet &p, const LocalizerMap &map);

private:
    /// Within radius_m_ of (cx, cy) and within region_yaw_rad of the yaw offset cyaw (the dominant's or a twin's
    /// region).
    bool near_pose(double x, double y, double yaw_offset_rad, double cx, double cy, double cyaw) const;
    /// Particle i on the guard's floor and near_pose of (cx, cy, yaw).
    bool in_region(const ParticleSet &p, size_t i, double cx, double cy, double yaw) const;

    TwinGuardParams p_;
    bool has_dominant_ = false;
    int32_t floor_ = -1;
    double x_ = 0, y_ = 0, yaw_offset_ = 0, radius_m_ = 0;
    std::vector<uint32_t> region_;  // reseed scratch
};

}  // namespace wf::loc
