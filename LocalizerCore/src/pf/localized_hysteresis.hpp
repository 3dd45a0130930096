// The `localized` flag: when the filter is sure enough to guide. A state machine over the cluster summary
// of each estimate (pf/clustering), kept apart from the filter so its rules can be read and tested alone.
//
// Becoming localized (unchanged since options version 1): the dominant cluster holds > localize_weight, its
// position std is < localize_std_m, and no rival holding >= rival_min_weight is unrefuted (its recent evidence,
// nats, is less than rival_refute_nats below the dominant's), all for localize_hold_s. A thin rival (from
// thin_rival_min_weight up to rival_min_weight) counts too while its evidence is less than thin_rival_refute_nats
// below the dominant's and most of its weight has explained a sighting (rival_unrefuted; thirty-first stop).
//
// Staying localized ("a steady lock"): once on, the flag drops only when the evidence refutes the estimate,
// not when Monte Carlo noise or recovery injection shuffles the weights. The tests below read the dominant
// cluster's core (its particles within lock_core_radius_m of its weighted median, pf/cluster_core) when the
// filter supplies it: injected particles that join the cluster by connectivity far along the corridor are not
// the locked pose, neither for its spread nor for its weight.
//  - the dominant cluster spreads beyond unlocalize_std_m (e.g. a long tracking loss);
//  - the dominant cluster is no longer the locked hypothesis (the estimate jumped more than `lock_jump_m`
//    between two estimates: a rival overtook it);
// The two weight tests below break it once they have failed for lock_break_hold_s on end; the others at once.
//  - the dominant cluster's weight fell below unlocalize_weight, unless that weight went to a rival holding
//    >= `lock_rival_weight` whose evidence is more than `lock_rival_margin_nats` worse than the dominant's (a
//    rival revived by injection starts with the worst evidence present: it does not break the lock until the
//    sightings favour it); weight diffused over the floor (the sightings refuted the lock) breaks it, but weight
//    handed to fresh particles by recovery injection that have not yet explained a sighting does not, when the
//    lock's core has explained sightings (`discount_unsighted`: the sighted core must also fall below the share);
//  - the spread test likewise, when the core's sighted particles stay within unlocalize_std_m;
//  - the dominant cluster's weight fell below `lock_min_weight`, whatever the rivals;
//  - on a symmetric floor, its twin explains the evidence better by more than `lock_rival_margin_nats`.
// On a symmetric floor, becoming localized also needs the evidence against the dominant hypothesis's twins to
// reach rival_refute_nats (pf/twin_guard).
// Becoming localized also needs the dominant hypothesis to account for the sightings of the last
// explain_window_s (4 s; the hold period's 1 s until the thirty-fourth stop): the
// sighting frames it explains only as false positives (pf/particle_filter.cpp, note_unexplained_sightings)
// must not be less likely under the detector's false-positive model than e^-rival_refute_nats. Such sightings
// were made by some sign, so some pose the cloud does not hold explains them (a rival no particle
// represents); a lock meanwhile is a lock on the best of the wrong places (docs/localizer.md "Thirteenth
// stop").
// Becoming localized also needs ARKit's tracking to be normal for the whole hold period (no_lock_while_limited),
// unless a limited spell has lasted longer than limited_spell_max_s.
#pragma once

#include <cstdint>

namespace wf::loc {

/// Thresholds of the localized flag (the localize_* / unlocalize_* / rival_* options, plus internal lock
/// parameters that are not part of the C ABI).
struct LocalizedHysteresisParams {
    double localize_weight = 0.8, localize_std_m = 1.0, localize_hold_s = 1.0;
    double unlocalize_weight = 0.5, unlocalize_std_m = 2.0;
    double rival_min_weight = 0.001, rival_refute_nats = 4.0;
    /// A rival lighter than rival_min_weight but holding at least this much keeps the flag off while its evidence
    /// is less than thin_rival_refute_nats below the dominant's. Weight is not evidence: a hypothesis that recovery
    /// injection re-created a moment ago, or that KLD-sampling thinned to a few hundred particles, holds little
    /// weight however well it explains the sightings (behind the unrefined cascade's -25 % range bias the true pose
    /// came back at 0.1-0.3 % of the weight with its evidence 0.8-2.7 nats short of the dominant's, fell below 0.1 %
    /// and was ignored; a parallel corridor 13 m off locked for 4.2 m walked: docs/benchmarks.md "Thirty-first
    /// stop"). Its margin is smaller than rival_refute_nats because its weight already counts against it. 0 (or
    /// >= rival_min_weight) turns the rule off. "lock.thin_rival_weight", "lock.thin_rival_refute_nats".
    double thin_rival_min_weight = 1e-4, thin_rival_refute_nats = 3.0;
    /// ... and only while at least this share of its weight is on particles whose history explains a sighting
    /// (pf/cluster_core, sighted_weight_per_cluster; rival_unrefuted): particles that recovery injection
    /// has just placed carry the worst evidence present, which can be less than thin_rival_refute_nats below the
    /// dominant's when the recent sightings refute little, and scattered over the floor they made dozens of thin
    /// "rivals" that explain nothing (a study walk behind detector-rough: the lock 7 m later).
    /// "lock.thin_rival_sighted_share".
    double thin_rival_min_sighted_share = 0.5;
    /// Rival weight that can break a lock, and how close its evidence must come to the dominant's, nats.
    double lock_rival_weight = 0.2, lock_rival_margin_nats = 1.0;
    /// Below this dominant weight the lock always breaks (after lock_break_hold_s).
    double lock_min_weight = 0.25;
    /// The weight tests (unlocalize_weight, lock_min_weight) break the lock only once they have failed for this
    /// long without a break, seconds (0: at once); the spread, the jump and the twin break it at once. One misread
    /// sighting can move the weight off a right lock for a tenth of a second (docs/localizer.md "Localized
    /// flag"). "lock.break_hold_s".
    double lock_break_hold_s = 0.3;
    /// A jump of the estimate larger than this between two reads means another hypothesis took over, meters.
    double lock_jump_m = 3.0;
    /// Radius of the locked cluster's core around its weighted median (pf/cluster_core), meters. While
    /// localized, the spread and the weight tests look at the core: particles that recovery injection scatters
    /// along the same corridor join the cluster but are not the locked pose. 3 x unlocalize_std_m, so a
    /// cluster that really spreads still breaks the lock (a 2-D Gaussian of std 2.1 m keeps 97 % of its
    /// weight and a core std above 2 m: test_cluster_core).
    double lock_core_radius_m = 6.0;
    /// Nonzero: becoming localized needs the dominant hypothesis to explain the recent sightings
    /// (HysteresisInput::unexplained_sighting_nats); 0 turns the rule off (for studies).
    bool explain_sightings = true;
    /// How far back that rule looks, seconds: the sighting frames of the last explain_window_s that the dominant
    /// hypothesis explains only as false positives (HysteresisInput::unexplained_sighting_nats). 4 s, not the 1 s
    /// hold period: a hypothesis that left a sign seen for ten seconds unexplained locked in the first second
    /// without a sighting (a pause in the detections, a sign passed): behind all-rough and behind look-alikes,
    /// office-long-many-turns locked 15 m off, outside the building, after its every sighting for 10 s had been
    /// unexplained (docs/benchmarks.md "Thirty-fourth stop"). "lock.explain_window_s".
    double explain_window_s = 4.0;
    /// While VIO tracking is lost the traveler may walk on unobserved: once this speed times the time lost
    /// exceeds unlocalize_std_m they may be that far from the locked pose, and the lock is void (the flag
    /// drops and must be earned again). m/s; default 1.4, a brisk preferred walking speed (Bohannon 1997:
    /// 1.3-1.5 m/s for adults under 60); 0 keeps the lock through any loss. "lock.lost_walk_speed_mps".
    double lost_walk_speed_mps = 1.4;
    /// Nonzero: while localized on a core that has explained sightings, the weight and spread tests break the
    /// lock only when the particles whose history explains a sighting show it too (HysteresisInput::
    /// sighted_core_weight against contested_weight, sighted_core_std_m): the weight recovery injection hands to
    /// fresh particles, which have no sighting behind them, neither dilutes nor spreads the lock until one of
    /// them explains a sighting (what `lock_rival_weight` does for a heavy rival, here for particles scattered
    /// over the floor and along the locked corridor). The rule only relaxes those two tests; lock_min_weight
    /// still reads the whole core. 0 turns the rule off (for studies). "lock.discount_unsighted".
    bool discount_unsighted = true;
    /// Nonzero: while localized, when the heaviest cluster is a rival away from the locked pose whose evidence is
    /// more than lock_rival_margin_nats worse than that of a cluster (holding >= lock_rival_weight) still at the
    /// locked pose, the filter keeps reporting and testing the locked cluster (pf/particle_filter.cpp,
    /// compute_estimate): weight is not evidence, and such a rival breaks no lock while it is second either. 0
    /// turns the rule off (for studies). "lock.follow_locked".
    bool follow_locked_hypothesis = true;
    /// Nonzero: no lock is earned while ARKit reports limited tracking (HysteresisInput::tracking_limited_s): the
    /// hold period restarts, and starts again once tracking is normal. In a dark spell, a featureless corridor
    /// or fast motion, the VIO displacement the hypotheses were weighed over is the least trustworthy, and the
    /// sightings of such a spell are the fewest (docs/benchmarks.md, "Twenty-eighth stop"). A lock held is kept
    /// (limited tracking is not evidence against it). 0 turns the rule off (for studies).
    /// "lock.none_while_limited".
    bool no_lock_while_limited = true;
    /// The rule above holds for spells up to this long, seconds: ARKit's passing troubles (initializing, a dark
    /// stretch or a blank wall, a fast turn, relocalizing until the phone restarts tracking at 6 s) last seconds;
    /// a spell longer than this is the place's normal (a dim building), where the motion model's limited-tracking
    /// noise already widens the cloud and a lock is earned as anywhere, not withheld for good.
    /// "lock.limited_spell_max_s".
    double limited_spell_max_s = 10.0;
};

/// Whether a rival cluster holding `rival_weight` (0..1) whose recent evidence is `evidence_gap_nats` below the
/// dominant cluster's keeps the flag from turning on: from rival_min_weight up, while the gap is less than
/// rival_refute_nats; from thin_rival_min_weight up to rival_min_weight, while it is less than
/// thin_rival_refute_nats and the weight of its particles whose history explains a sighting,
/// `sighted_weight()` (same units as rival_weight; called at most once, only then, since it costs a pass over
/// the particles: pf/cluster_core, sighted_weight_per_cluster), is at least thin_rival_min_sighted_share of
/// rival_weight; never below both. (The dominant's own symmetric twins are judged by the twin ratio instead,
/// pf/twin_guard.)
template <class SightedWeight>
bool rival_unrefuted(const LocalizedHysteresisParams &p, double rival_weight, double evidence_gap_nats,
                     SightedWeight &&sighted_weight) {
    if (rival_weight >= p.rival_min_weight) return evidence_gap_nats < p.rival_refute_nats;
    if (p.thin_rival_min_weight > 0 && rival_weight >= p.thin_rival_min_weight &&
        evidence_gap_nats < p.thin_rival_refute_nats) {
        return sighted_weight() >= p.thin_rival_min_sighted_share * rival_weight;
    }
    return false;
}

/// The lightest rival weight rival_unrefuted can count (the lower of rival_min_weight and an active
/// thin_rival_min_weight): clusters lighter than this need no summary.
double lightest_counted_rival_weight(const LocalizedHysteresisParams &p);

/// What the flag looks at, from one clustering of the particles.
struct HysteresisInput {
    /// Time of the estimate, seconds.
    double t = 0;
    /// Dominant cluster: weight (0..1), position std (m), mean position (m, map frame), floor index.
    double dominant_weight = 0, std_m = 0, x = 0, y = 0;
    int32_t floor = -1;
    /// Heaviest rival that rival_unrefuted counts (0 when none).
    double unrefuted_rival_weight = 0;
    /// Largest (rival evidence - dominant evidence), nats, over rivals holding >= lock_rival_weight
    /// (-infinity when there is none).
    double strongest_rival_evidence_margin = -1e300;
    /// The dominant cluster's core (pf/cluster_core, radius lock_core_radius_m): weight (0..1) and position
    /// std (m). Read only while localized; negative: not computed (the whole cluster's figures are used).
    double core_weight = -1, core_std_m = -1;
    /// The lock's figures among the particles whose history explains at least one sighting (pf/cluster_core,
    /// sighted_members): the core of the dominant cluster's sighted particles, its weight (0..1 of the whole
    /// cloud) and position std (m), and the sighted weight held outside it, which could belong to a rival.
    /// Read only while localized; a negative contested_weight: not computed (the weight and spread tests then
    /// read core_weight and core_std_m).
    double sighted_core_weight = -1, sighted_core_std_m = -1, contested_weight = -1;
    /// Evidence for the dominant hypothesis against its symmetric twins (pf/twin_guard), nats: the lowest over
    /// the floor's symmetries; +infinity on a floor without any. Becoming localized needs it to reach
    /// rival_refute_nats (the twin is a rival that no particle may happen to represent); a lock drops when it
    /// falls below -lock_rival_margin_nats (the twin explains the evidence better).
    double twin_log_ratio = 1e300;
    /// Sighting frames of the last explain_window_s that the dominant hypothesis explains only as false
    /// positives: the sum of -log(false-positive probability) over their sightings, nats (0 when it explains
    /// every one). Becoming localized needs it below rival_refute_nats.
    double unexplained_sighting_nats = 0;
    /// Seconds VIO tracking has been lost (0 while it is available). Once lost_walk_speed_mps times this exceeds
    /// unlocalize_std_m, the flag is off, whatever else holds.
    double tracking_lost_s = 0;
    /// Seconds ARKit has reported limited tracking without a break (VioDeltaTracker::tracking_limited_s); negative
    /// while tracking is normal or lost.
    double tracking_limited_s = -1;
};

/// The flag's state machine. Value type; reset() on every init of the filter.
class LocalizedHysteresis {
public:
    explicit LocalizedHysteresis(const LocalizedHysteresisParams &p = {}) : p_(p) {}
    const LocalizedHysteresisParams &params() const { return p_; }
    LocalizedHysteresisParams &mutable_params() { return p_; }

    /// Advances the state with one estimate and returns the flag (off, with no candidate, while tracking has been
    /// lost too long: HysteresisInput::tracking_lost_s).
    bool update(const HysteresisInput &in);
    /// Not localized, no candidate, no locked pose.
    void reset();
    bool localized() const { return localized_; }
    /// The pose of the last estimate (the locked core's while localized): position (m, map frame) and floor
    /// index. False before the first estimate after a reset.
    bool last_pose(double &x, double &y, int32_t &floor) const {
        x = last_x_;
        y = last_y_;
        floor = last_floor_;
        return has_last_;
    }
    /// Forces the flag off (a non-finite estimate).
    void drop() { localized_ = false; has_candidate_ = false; has_break_ = false; }

private:
    /// The flag's rules on the estimate alone (update() adds the tracking-lost rule).
    void advance(const HysteresisInput &in);

    LocalizedHysteresisParams p_;
    bool localized_ = false;
    bool has_candidate_ = false;
    double candidate_since_t_ = 0;
    /// While localized: a weight test has failed at every estimate since break_since_t_ (lock_break_hold_s).
    bool has_break_ = false;
    double break_since_t_ = 0;
    bool has_last_ = false;
    double last_x_ = 0, last_y_ = 0;
    int32_t last_floor_ = -1;
};

}  // namespace wf::loc
