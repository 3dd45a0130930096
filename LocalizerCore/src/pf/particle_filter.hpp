// The Monte Carlo localizer (Probabilistic Robotics Table 8.2 MCL, with the augmented-MCL recovery of
// Table 8.3 and KLD-sampling of Fox 2003): particles over (map x, y, VIO->map yaw offset, VIO scale, floor),
// moved by VIO deltas (motion/vio_motion_model), weighted by sign sightings (sensors/sign_measurement_model)
// and by walls, resampled with the low-variance sampler, summarised by clustering (pf/clustering). All
// methods return a wf_localizer_status; the C ABI (capi/wf_localizer.cpp) is a thin shell around this class.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "common/rng.hpp"
#include "map/localizer_map.hpp"
#include "motion/vio_motion_model.hpp"
#include "pf/cluster_core.hpp"
#include "pf/clustering.hpp"
#include "pf/particle_set.hpp"
#include "pf/localized_hysteresis.hpp"
#include "pf/track_evidence.hpp"
#include "pf/twin_guard.hpp"
#include "pf/resampling.hpp"
#include "sensors/barometric_floor_model.hpp"
#include "sensors/compass_model.hpp"
#include "sensors/plane_measurement_model.hpp"
#include "sensors/sign_measurement_model.hpp"
#include "wf_localizer.h"

namespace wf::loc {

/// Share of the compass prior kept uniform over all headings (indoor magnetic disturbance can exceed any
/// Gaussian spread): yaw offsets drawn after wf_localizer_set_compass_prior come from the reading with
/// probability 1 - this, uniform otherwise, and a prior set after the init reweights with the same mixture.
inline constexpr double kCompassUniformShare = 0.2;

/// Checks every option against its documented range; on failure names the field in `error`.
int validate_options(const wf_localizer_options &o, std::string &error);

class ParticleFilter {
public:
    ParticleFilter(LocalizerMap map, const wf_localizer_options &opts, uint64_t seed);

    int init_floor_only(int32_t floor);
    int init_start_point(int32_t floor, double x, double y, double radius_m);
    int set_compass_prior(double heading_in_map_rad, double sigma_rad);
    int predict(const wf_vio_sample &s);
    /// The VIO origin was reset: the next usable sample's delta is a snap (wf_localizer_note_vio_reset).
    int note_vio_reset();
    int update_signs(const wf_sign_observation *obs, size_t count, double t);
    /// The same for a frame on which the detector did not look for the kinds `unsearched_kinds` (ids; count
    /// `unsearched_count`): no negative information for their signs (sign_log_likelihood). Ids outside the
    /// map's kinds are ignored and reported (WF_LOC_ERR_INVALID_ARGUMENT after the update).
    int update_signs(const wf_sign_observation *obs, size_t count, double t, const int32_t *unsearched_kinds,
                     size_t unsearched_count);
    int update_altitude(double relative_altitude_m, double t);
    /// Compass evidence (sensors/compass_model): camera heading in the map `heading_in_map_rad` (CCW from +x)
    /// with accuracy `accuracy_rad` (<= 0: unknown) at time t. Applied at most once per
    /// CompassModelParams::min_distance_m walked; readings in between are ignored (status OK).
    int update_compass(double heading_in_map_rad, double accuracy_rad, double t);
    /// Sets / reads an internal model parameter by name ("compass.kappa", ...; see parameter_names()).
    int set_parameter(const std::string &name, double value);
    int get_parameter(const std::string &name, double &value);
    /// Every name set_parameter knows, comma-separated.
    static const char *parameter_names();
    /// Compass readings applied so far (diagnostics, tests).
    size_t compass_update_count() const { return compass_update_count_; }
    /// Vertical-plane update (sensors/plane_measurement_model; defined in pf/particle_filter_planes.cpp):
    /// likelihood field of the planes against the walls, tempered, then normalisation and resampling as
    /// after a sign update. Non-finite planes are skipped (WF_LOC_ERR_NON_FINITE_INPUT after the others).
    int update_planes(const wf_plane_observation *obs, size_t count, double t);
    /// Plane-model state (parameters, wall fields, per-anchor gate, last update's counts).
    PlaneModelState &plane_model() { return planes_; }

    /// Current estimate, recomputed (clustering) when particles changed since the last call. The localized
    /// flag's hysteresis advances on these reads, with the time of the last input: read it once per frame.
    const wf_localizer_estimate &estimate();

    /// Hypotheses of the last estimate (clusters holding >= 1 % of the weight, and every lighter rival that keeps
    /// the flag off, down to LocalizedHysteresisParams::thin_rival_min_weight; at most 16): the dominant one
    /// first, then the others heaviest first.
    const std::vector<wf_localizer_hypothesis> &hypotheses() const { return hypotheses_; }

    bool initialized() const { return initialized_; }
    const ParticleSet &particles() const { return p_; }
    /// The clustering behind the estimate and the hypothesis-preserving resampling (tests, diagnostics).
    const ParticleClusterer &clusterer() const { return clusterer_; }
    /// Heading of particle i = vio_yaw() + yaw_offset[i].
    float vio_yaw() const { return static_cast<float>(vio_yaw_); }
    const LocalizerMap &map() const { return map_; }
    const wf_localizer_options &options() const { return opts_; }
    const std::string &error() const { return error_; }
    void clear_error() { error_.clear(); }
    /// Augmented-MCL averages (PR Table 8.3), per-sighting geometric mean of the frame likelihood.
    double w_slow() const { return w_slow_; }
    double w_fast() const { return w_fast_; }
    /// Number of resamplings so far and particles injected by recovery in total (diagnostics, tests).
    size_t resample_count() const { return resample_count_; }
    size_t injected_count() const { return injected_count_; }
    /// Likelihood exponent used by the last sign update (1 = no tempering).
    double last_tempering_exponent() const { return last_beta_; }

private:
    int fail(int status, std::string message);
    bool sample_walkable(int16_t floor, float &x, float &y);
    float sample_yaw_offset();
    /// Particle count of a fresh initialisation: the configured count, within the KLD bounds when adaptive.
    size_t initial_particle_count() const;
    /// Fills particle i at (x, y) on `floor` with a fresh yaw offset and scale drawn from the priors.
    void init_particle(size_t i, float x, float y, int16_t floor, float weight);
    bool sample_from_sighting(int16_t floor, float &x, float &y, float &yaw_offset);
    void reset_filter_state();
    /// Sizes every per-frame work array (resampling copy and draws, grouping, KLD bins, clustering) for the
    /// largest particle count a resampling can produce, so that no frame after an init allocates or
    /// zero-fills them on first use (the steady state of the frame loop from the first frame on).
    void size_work_arrays();
    void normalize(double sum);
    void maybe_resample(bool after_measurement);
    /// Resamples; `weight_sum` is the weights' lane sum (effective_sample_size's), the
    /// total of the systematic draws over the whole set.
    void resample(double inject_fraction, double weight_sum);
    void apply_compass_reweight();
    double tempering_exponent(float max_ll);
    void apply_floor_change(double delta_m);
    /// Adds (ll - max ll), floored at -50 nats, to each particle's recent evidence, forgetting the old with the
    /// evidence time constant since the last evidence at time t.
    void accumulate_evidence(const float *ll, float max_ll, double t);
    /// After a sign update's likelihoods (log_likelihood_) and before the reweighting: when the last estimate's
    /// dominant cluster explains the frame's sightings only as false positives (the weighted mean of its
    /// particles' likelihoods is less than twice the clutter-only likelihood), records the frame with the sum
    /// of -log(false-positive probability) of its sightings, for the localized flag
    /// (HysteresisInput::unexplained_sighting_nats).
    void note_unexplained_sightings(const std::vector<PreparedSighting> &z, double t);
    /// Sum of the recorded frames of the last explain_window_s (LocalizedHysteresisParams) before time t, nats;
    /// older ones are dropped.
    double unexplained_sighting_nats(double t);
    void compute_estimate();
    /// Replaces `fraction` of the particles with poses drawn from the current sightings (last_sightings_) on the
    /// estimate's floor, holding that share of the weight and the best evidence present: rival explanations of
    /// the same sightings, which the lock must refute before it turns on. Defined in
    /// pf/particle_filter_corroboration.cpp.
    void draw_corroboration_rivals(double fraction);
    /// One rival pose for draw_corroboration_rivals: a heading from the compass prior, then the position from
    /// which a random sign of a current sighting's kind appears at its bearing and range (visible, walkable).
    bool sample_rival_pose(int16_t floor, float &x, float &y, float &yaw_offset);
    /// A random sign of `kind` on floor `f` (each equally likely), or -1 when the floor has none.
    int32_t random_sign_of_kind(const FloorData &f, int32_t kind);
    /// Arms (or disarms) the corroboration requirement for the next lock.
    void arm_corroboration(bool on) {
        awaiting_corroboration_ = on;
        corroboration_candidates_drawn_ = false;
    }
    /// Cheap estimate between two clusterings: the last dominant cluster's particles, re-averaged (while
    /// localized, its core's: pf/cluster_core).
    void follow_dominant_cluster();
    /// Sets the pose part of `e` (position, covariance, heading, their spreads, confidence from e's dominant
    /// weight) from a cluster's moments (the locked cluster's core, or all of the dominant cluster's particles).
    void set_pose_from_core(wf_localizer_estimate &e, const ClusterCore &core) const;
    /// Puts the first hypothesis (the dominant cluster) at the pose of `e` (position, heading, spread).
    void place_front_hypothesis(const wf_localizer_estimate &e);
    /// Longest time between two full clusterings of the estimate, seconds.
    static constexpr double kFullEstimateIntervalS = 0.2;

    LocalizerMap map_;
    wf_localizer_options opts_;
    MotionNoise motion_;
    SignModelParams sign_model_;
    /// Named parameter kld.min_particles_unlocalized: the fewest particles a resampling keeps while the filter is
    /// not localized (before the first lock and after a lock breaks), capped at the init's particle_count and at
    /// max_particles (0 = opts_.min_particles only). Default 20,000: while unsure the cloud is not thinned below
    /// that (the pipeline starts with 100,000), nor below a smaller init's size.
    /// KLD-sampling counts occupied bins, and a hypothesis that shares its bins with a look-alike (the same place
    /// turned 20-50 degrees about the sign it watches) needs particles of its own to survive: with the 2,000 floor
    /// the right heading died between sightings and a quarter-turned pose locked (docs/benchmarks.md "Thirtieth
    /// stop"; "Thirteenth stop" for the first measurement).
    size_t min_particles_unlocalized_ = 20000;
    Rng rng_;
    VioDeltaTracker tracker_;
    MotionNoiseAccumulator motion_acc_;
    ParticleSet p_, scratch_;
    std::vector<float> log_likelihood_;
    std::vector<float> tempering_w_, tempering_d_;  // tempering_exponent's subsample
    std::vector<PreparedSighting> last_sightings_;  // sightings of the update being resampled
    /// Sighting frames the dominant hypothesis explained only as false positives: (time s, nats), oldest first
    /// (note_unexplained_sightings).
    std::vector<std::pair<double, double>> unexplained_frames_;
    /// The estimate's sightings_unexplained: set when the hold period's unexplained sightings reach
    /// rival_refute_nats, cleared by a later sighting frame the dominant hypothesis explains (no sighting since
    /// says nothing new: the cloud that could not explain them still holds no better place).
    bool sightings_unexplained_ = false;
    std::vector<uint32_t> indices_;
    /// Hypothesis-preserving resampling: particle indices grouped by cluster (group g is
    /// group_members_[group_start_[g] .. group_start_[g + 1])).
    std::vector<uint32_t> group_members_;
    std::vector<size_t> group_start_, group_fill_;
    /// Weights of group_members_ (same order) and each group's mass (their sum in that order).
    std::vector<float> group_weights_;
    std::vector<double> group_mass_;
    /// Group of each particle, when there are at most kCompactionGroups groups (one compaction pass each).
    std::vector<uint8_t> group_of_;
    static constexpr int32_t kCompactionGroups = 4;
    /// Resampling draws: source particle and new weight of each kept particle.
    std::vector<uint32_t> resample_src_;
    std::vector<float> resample_w_;
    BinCounter kld_bins_;
    DenseBins kld_dense_;
    std::vector<uint8_t> kld_seen_;
    ParticleClusterer clusterer_;
    PlaneModelState planes_;
    std::string error_;

    bool initialized_ = false;
    int16_t init_floor_ = 0;
    double vio_yaw_ = 0;
    double t_last_ = 0;

    bool compass_set_ = false;
    bool compass_pending_ = false;
    double compass_heading_ = 0, compass_sigma_ = 0;

    double w_slow_ = 0, w_fast_ = 0;
    double last_beta_ = 1;
    double evidence_t_ = 0;
    bool has_evidence_t_ = false;
    size_t resample_count_ = 0, injected_count_ = 0;

    BarometricFloorParams floor_params_;
    BarometricFloorDetector floor_detector_;
    CompassModel compass_;
    size_t compass_update_count_ = 0;
    LocalizedHysteresis hysteresis_;
    /// Symmetric twins of the dominant hypothesis (pf/twin_guard) and their log-likelihoods' scratch.
    TwinGuard twin_;
    std::vector<float> twin_x_, twin_y_, twin_yaw_;  // the cloud's twin poses under one symmetry (scratch)
    /// Scores the cloud's twins under symmetry k: swaps their poses into the particle set, calls score() (a
    /// measurement model on p_, read only), swaps back. False (score not called) when there is nothing to do.
    template <class Score>
    bool score_twins(size_t k, Score &&score) {
        if (!twin_.twin_poses(p_, map_, k, twin_x_, twin_y_, twin_yaw_)) return false;
        p_.x.swap(twin_x_);
        p_.y.swap(twin_y_);
        p_.yaw_offset.swap(twin_yaw_);
        score();
        p_.x.swap(twin_x_);
        p_.y.swap(twin_y_);
        p_.yaw_offset.swap(twin_yaw_);
        return true;
    }
    /// For each of the floor's symmetries: `score(out)` adds the measurement's log-likelihoods of the particles'
    /// twins into `out` (zeroed, size n; the twin poses are swapped in by score_twins), then the twin ratios
    /// take the difference against `log_likelihood_` (TwinGuard::accumulate). The plane and compass updates.
    template <class Score>
    void accumulate_twin_ratios(Score &&score) {
        for (size_t k = 0; k < p_.twin_arrays; ++k) {
            const auto scored = [&] {
                twin_ll_.assign(p_.size(), 0.0f);
                score(twin_ll_.data());
            };
            if (score_twins(k, scored)) {
                twin_.accumulate(p_, map_, k, log_likelihood_.data(), twin_ll_.data());
            }
        }
    }
    std::vector<float> twin_ll_;  // twin log-likelihoods of one symmetry (planes, compass)
    std::array<std::vector<float>, ParticleSet::kMaxTwins> twin_lls_;  // twin sign log-likelihoods per symmetry
    /// Tracked objects (pf/track_evidence), the frame's slot per sighting, each slot's own sign terms and the
    /// frame's pointer per sighting to them (nullptr: not tracked) (scratch, kept so a frame allocates nothing).
    TrackEvidence tracks_;
    std::vector<int> track_slot_of_;
    std::vector<uint8_t> track_first_;
    std::array<std::vector<float>, ParticleSet::kMaxTracks> track_terms_;
    std::vector<float *> track_own_terms_;
    /// After a measurement update: reseeds the dominant hypothesis's twins (TwinGuard::reseed) and marks the
    /// clusters and the estimate stale when particles moved.
    void reseed_twins();
    /// Adds the compass prior's log ratio (at each particle's heading against at its twin's) to the twin ratios:
    /// after a draw the prior shaped and after its reweighting (apply_compass_reweight).
    void add_compass_prior_to_twins();
    /// The compass prior's mixture density at a map heading (radians), relative to its Gaussian peak: the
    /// weight factor of apply_compass_reweight and the density of sample_yaw_offset's draw.
    double compass_prior_density(double heading_in_map_rad) const;

    bool estimate_dirty_ = true;
    /// The lock must be earned against rivals that explain the same sightings (pf/particle_filter_corroboration):
    /// set after init_start_point (with a doubt share) and after a lock the evidence broke; cleared by a lock.
    /// No localized flag while awaiting and before the first sighting.
    bool awaiting_corroboration_ = false;
    /// Whether the rivals of the current awaiting phase were drawn (at its first frame with sightings).
    bool corroboration_candidates_drawn_ = false;
    /// The flag at the previous estimate (a lock break re-arms the corroboration).
    bool was_localized_ = false;
    /// Time of the last sign update with sightings, seconds (-infinity before the first).
    double last_sighting_t_ = -std::numeric_limits<double>::infinity();
    wf_localizer_estimate estimate_{};
    std::vector<wf_localizer_hypothesis> hypotheses_;
    std::vector<uint32_t> dominant_members_;
    bool dominant_members_valid_ = false;
    /// cluster_core's histogram, reused.
    std::vector<double> core_scratch_;
    /// The dominant cluster's members whose history explains a sighting (the lock's sighted core).
    std::vector<uint32_t> sighted_members_;
    /// Per cluster of the last estimate, the weight of its sighted particles (thin rivals' test), reused.
    std::vector<double> cluster_sighted_weight_;
    /// True while the lock stands on its sighted core (the whole core's spread or weight would break it): the
    /// reported pose is then the sighted core's, at the last full estimate and between full estimates.
    bool pose_from_sighted_core_ = false;
    /// Centre of the locked pose's core disc at the last full estimate (m, map frame), valid when the core was
    /// computed there (localized before it): between full estimates the pose follows that disc's particles.
    bool pose_core_valid_ = false;
    double pose_core_x_ = 0, pose_core_y_ = 0;
    double full_estimate_t_ = 0;
};

}  // namespace wf::loc
