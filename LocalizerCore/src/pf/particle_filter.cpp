#include "pf/particle_filter.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "common/fast_math.hpp"
#include "common/lane_sums.hpp"
#include "pf/locked_hypothesis.hpp"
#include "pf/reweighting.hpp"

namespace wf::loc {

namespace {

bool in_range(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

}  // namespace

int validate_options(const wf_localizer_options &o, std::string &error) {
    if (o.version != WF_LOCALIZER_OPTIONS_VERSION) {
        error = "options version " + std::to_string(o.version) + " is not supported (expected " +
                std::to_string(WF_LOCALIZER_OPTIONS_VERSION) + ")";
        return WF_LOC_ERR_VERSION;
    }
    struct Check {
        const char *name;
        double value, lo, hi;
    };
    const double big = 1e9;
    const Check checks[] = {
        {"particle_count", double(o.particle_count), 1, 10'000'000},
        {"min_particles", double(o.min_particles), 1, 10'000'000},
        {"max_particles", double(o.max_particles), 1, 10'000'000},
        {"kld_epsilon", o.kld_epsilon, 1e-6, 1},
        {"kld_z", o.kld_z, 0, 10},
        {"kld_bin_m", o.kld_bin_m, 1e-3, 100},
        {"kld_bin_yaw_rad", o.kld_bin_yaw_rad, 1e-3, 2 * kPiD},
        {"resample_ess_fraction", o.resample_ess_fraction, 0, 1},
        {"hypothesis_particle_share", o.hypothesis_particle_share, 0, 1},
        {"recovery_alpha_slow", o.recovery_alpha_slow, 0, 1},
        {"recovery_alpha_fast", o.recovery_alpha_fast, 0, 1},
        {"recovery_max_fraction", o.recovery_max_fraction, 0, 1},
        {"position_noise_per_sqrt_meter", o.position_noise_per_sqrt_meter, 0, 10},
        {"position_noise_per_sqrt_rad", o.position_noise_per_sqrt_rad, 0, 10},
        {"yaw_noise_per_sqrt_meter", o.yaw_noise_per_sqrt_meter, 0, 10},
        {"yaw_noise_per_sqrt_rad", o.yaw_noise_per_sqrt_rad, 0, 10},
        {"scale_noise_per_sqrt_meter", o.scale_noise_per_sqrt_meter, 0, 10},
        {"initial_scale_sigma", o.initial_scale_sigma, 0, 1},
        {"scale_min", o.scale_min, 1e-3, 1},
        {"scale_max", o.scale_max, 1, 100},
        {"limited_tracking_noise_factor", o.limited_tracking_noise_factor, 0, 1000},
        {"jump_distance_m", o.jump_distance_m, 0, big},
        {"jump_yaw_rad", o.jump_yaw_rad, 0, 2 * kPiD},
        {"jump_position_sigma_m", o.jump_position_sigma_m, 0, 100},
        {"jump_yaw_sigma_rad", o.jump_yaw_sigma_rad, 0, 2 * kPiD},
        {"lost_tracking_speed_mps", o.lost_tracking_speed_mps, 0, 100},
        {"wall_crossing_weight", o.wall_crossing_weight, 0, 1},
        {"horizontal_fov_rad", o.horizontal_fov_rad, 1e-3, 2 * kPiD},
        {"max_sign_range_m", o.max_sign_range_m, 0.1, 1000},
        {"range_sigma_base_m", o.range_sigma_base_m, 0, 100},
        {"range_sigma_per_meter", o.range_sigma_per_meter, 0, 10},
        {"bearing_sigma_rad", o.bearing_sigma_rad, 1e-4, kPiD},
        {"clutter_probability", o.clutter_probability, 1e-6, 1},
        {"tempering_min_ess_fraction", o.tempering_min_ess_fraction, 0, 1},
        {"negative_info_max_range_m", o.negative_info_max_range_m, 0, 1000},
        {"negative_info_fov_fraction", o.negative_info_fov_fraction, 0, 1},
        {"negative_info_miss_weight", o.negative_info_miss_weight, 1e-6, 1},
        {"grid_cell_m", o.grid_cell_m, 0.02, 10},
        {"wall_index_cell_m", o.wall_index_cell_m, 0.05, 100},
        {"wall_clearance_m", o.wall_clearance_m, 0, 10},
        {"cluster_cell_m", o.cluster_cell_m, 0.05, 100},
        {"cluster_yaw_bin_rad", o.cluster_yaw_bin_rad, 0.01, 2 * kPiD},
        {"hypothesis_min_weight", o.hypothesis_min_weight, 0, 1},
        {"localize_weight", o.localize_weight, 0, 1},
        {"localize_std_m", o.localize_std_m, 0, big},
        {"localize_hold_s", o.localize_hold_s, 0, big},
        {"unlocalize_weight", o.unlocalize_weight, 0, 1},
        {"unlocalize_std_m", o.unlocalize_std_m, 0, big},
        {"rival_min_weight", o.rival_min_weight, 0, 1},
        {"rival_refute_nats", o.rival_refute_nats, 0, 1e6},
        {"evidence_time_constant_s", o.evidence_time_constant_s, 1e-3, 1e6},
        {"storey_threshold_m", o.storey_threshold_m, 0.1, 1000},
        {"altitude_settle_tolerance_m", o.altitude_settle_tolerance_m, 0, 1000},
        {"altitude_settle_s", o.altitude_settle_s, 0, big},
        {"link_radius_m", o.link_radius_m, 0, 1000},
        {"far_from_link_weight", o.far_from_link_weight, 0, 1},
        {"max_view_angle_from_normal_rad", o.max_view_angle_from_normal_rad, 0.01, 1.5707963267948966},
        {"start_point_doubt_share", o.start_point_doubt_share, 0, 1},
    };
    for (const Check &c : checks) {
        if (!in_range(c.value, c.lo, c.hi)) {
            error = std::string("option ") + c.name + " = " + std::to_string(c.value) + " is outside [" +
                    std::to_string(c.lo) + ", " + std::to_string(c.hi) + "]";
            return WF_LOC_ERR_INVALID_ARGUMENT;
        }
    }
    if (o.min_particles > o.max_particles) {
        error = "option min_particles is larger than max_particles";
        return WF_LOC_ERR_INVALID_ARGUMENT;
    }
    if (o.unlocalize_weight > o.localize_weight || o.unlocalize_std_m < o.localize_std_m) {
        error = "options unlocalize_* must be looser than localize_* (hysteresis)";
        return WF_LOC_ERR_INVALID_ARGUMENT;
    }
    return WF_LOC_OK;
}

ParticleFilter::ParticleFilter(LocalizerMap map, const wf_localizer_options &opts, uint64_t seed)
    : map_(std::move(map)),
      opts_(opts),
      motion_(MotionNoise::from_options(opts)),
      sign_model_(SignModelParams::from_options(opts)),
      rng_(seed),
      tracker_(opts) {
    // A ratio array per symmetry of the most symmetric floor (none on an asymmetric map: no cost there).
    p_.twin_arrays = scratch_.twin_arrays = TwinGuard::twin_arrays_for(map_);
    p_.track_arrays = scratch_.track_arrays = tracks_.params().enabled ? ParticleSet::kMaxTracks : 0;
    floor_params_.storey_threshold_m = opts.storey_threshold_m;
    floor_params_.settle_tolerance_m = opts.altitude_settle_tolerance_m;
    floor_params_.settle_s = opts.altitude_settle_s;
    floor_params_.link_radius_m = opts.link_radius_m;
    floor_params_.far_from_link_weight = opts.far_from_link_weight;
    floor_detector_ = BarometricFloorDetector(floor_params_);
    LocalizedHysteresisParams hp;
    hp.localize_weight = opts.localize_weight;
    hp.localize_std_m = opts.localize_std_m;
    hp.localize_hold_s = opts.localize_hold_s;
    hp.unlocalize_weight = opts.unlocalize_weight;
    hp.unlocalize_std_m = opts.unlocalize_std_m;
    hp.rival_min_weight = opts.rival_min_weight;
    hp.rival_refute_nats = opts.rival_refute_nats;
    hysteresis_ = LocalizedHysteresis(hp);
    estimate_.floor_index = -1;
    estimate_.scale = 1;
}

int ParticleFilter::fail(int status, std::string message) {
    error_ = std::move(message);
    return status;
}

bool ParticleFilter::sample_walkable(int16_t floor, float &x, float &y) {
    const FloorData &f = map_.floors[floor];
    if (f.walkable_cells.empty()) return false;
    const int32_t c = f.walkable_cells[rng_.below(static_cast<uint32_t>(f.walkable_cells.size()))];
    const int32_t ix = c % f.grid.nx, iy = c / f.grid.nx;
    x = f.grid.x0 + (static_cast<float>(ix) + rng_.uniform_float()) * f.grid.cell_m;
    y = f.grid.y0 + (static_cast<float>(iy) + rng_.uniform_float()) * f.grid.cell_m;
    return true;
}

float ParticleFilter::sample_yaw_offset() {
    // Compass prior as a mixture: indoors the field is often disturbed by steel, so a share of the yaw offsets
    // stays uniform and a wrong reading cannot rule out the true heading.
    if (compass_set_ && tracker_.has_yaw() && rng_.uniform(0.0, 1.0) >= kCompassUniformShare) {
        return static_cast<float>(
            wrap_angle(compass_heading_ - vio_yaw_ + compass_sigma_ * static_cast<double>(rng_.normal())));
    }
    return static_cast<float>(rng_.uniform(-kPiD, kPiD));
}

int32_t ParticleFilter::random_sign_of_kind(const FloorData &f, int32_t kind) {
    // Reservoir choice: each sign of the kind with equal probability, one pass, no allocation.
    int32_t chosen = -1;
    uint32_t seen = 0;
    for (size_t j = 0; j < f.signs.size(); ++j) {
        if (f.signs.kind[j] != kind) continue;
        if (rng_.below(++seen) == 0) chosen = static_cast<int32_t>(j);
    }
    return chosen;
}

bool ParticleFilter::sample_from_sighting(int16_t floor, float &x, float &y, float &yaw_offset) {
    if (last_sightings_.empty()) return false;
    const FloorData &f = map_.floors[floor];
    const PreparedSighting &z = last_sightings_[rng_.below(static_cast<uint32_t>(last_sightings_.size()))];
    const int32_t chosen = random_sign_of_kind(f, z.kind);
    if (chosen < 0) return false;
    const double sx = f.signs.x[chosen], sy = f.signs.y[chosen];
    const double facing = std::atan2(f.signs.facing_y[chosen], f.signs.facing_x[chosen]);
    for (int attempt = 0; attempt < 8; ++attempt) {
        // Direction sign -> camera: in front of the face (within 80 deg of its normal) unless double-sided.
        const double phi = f.signs.double_sided[chosen] ? rng_.uniform(-kPiD, kPiD)
                                                        : facing + rng_.uniform(-1.396, 1.396);
        const double r = z.range_m * (1.0 + 0.1 * rng_.normal());
        const float cx = static_cast<float>(sx + r * std::cos(phi)), cy = static_cast<float>(sy + r * std::sin(phi));
        if (!f.is_walkable(cx, cy)) continue;
        const uint64_t *vis = f.visibility_at(cx, cy);
        if (!vis || !((vis[chosen / 64] >> (chosen % 64)) & 1u)) continue;
        // The camera looks at the sign, turned by the sighting's bearing: heading = (phi + pi) - bearing.
        const double heading = phi + kPiD - z.bearing_rad + opts_.bearing_sigma_rad * rng_.normal();
        x = cx;
        y = cy;
        yaw_offset = static_cast<float>(wrap_angle(heading - vio_yaw_));
        return true;
    }
    return false;
}

void ParticleFilter::reset_filter_state() {
    initialized_ = true;
    clusterer_.forget_carried_bins();
    w_slow_ = w_fast_ = 0;
    has_evidence_t_ = false;
    motion_acc_.clear();
    hysteresis_.reset();
    twin_.reset();
    tracks_.reset();
    compass_.reset();
    arm_corroboration(false);
    was_localized_ = false;
    last_sighting_t_ = -std::numeric_limits<double>::infinity();
    unexplained_frames_.clear();
    sightings_unexplained_ = false;
    estimate_dirty_ = true;
    dominant_members_valid_ = false;
    // A compass prior given before the first VIO yaw is applied at the next predict.
    compass_pending_ = compass_set_ && !tracker_.has_yaw();
    size_work_arrays();
}

void ParticleFilter::size_work_arrays() {
    // A resampling produces at most max_particles (KLD-sampling) or particle_count particles; the set itself may
    // hold more after an init outside those bounds.
    const size_t cap = std::max(p_.size(), static_cast<size_t>(opts_.adaptive_particle_count ? opts_.max_particles
                                                                                              : opts_.particle_count));
    // Only grown: a later init with fewer particles keeps what an earlier one sized (sizes within capacity do
    // not allocate, and resizing down does not fill).
    if (scratch_.size() < cap) scratch_.resize(cap);
    if (log_likelihood_.size() < cap) log_likelihood_.resize(cap);
    if (resample_src_.size() < cap) resample_src_.resize(cap);
    if (resample_w_.size() < cap) resample_w_.resize(cap);
    if (indices_.size() < cap) indices_.resize(cap);
    if (group_members_.size() < cap + 1) group_members_.resize(cap + 1);
    if (group_of_.size() < cap) group_of_.resize(cap);
    if (group_weights_.size() < cap) group_weights_.resize(cap);
    kld_dense_.reserve(cap);
    clusterer_.reserve(cap);
}

size_t ParticleFilter::initial_particle_count() const {
    return static_cast<size_t>(opts_.adaptive_particle_count
                                   ? std::clamp(opts_.particle_count, opts_.min_particles, opts_.max_particles)
                                   : opts_.particle_count);
}

void ParticleFilter::init_particle(size_t i, float x, float y, int16_t floor, float weight) {
    p_.x[i] = x;
    p_.y[i] = y;
    p_.yaw_offset[i] = sample_yaw_offset();
    p_.scale[i] = std::clamp(1.0f + static_cast<float>(opts_.initial_scale_sigma) * rng_.normal(),
                             motion_.scale_min, motion_.scale_max);
    p_.floor[i] = floor;
    p_.weight[i] = weight;
    p_.evidence[i] = 0;
    p_.compass_ll[i] = 0;
    p_.bias_s1[i] = 0;
    p_.bias_s0[i] = 0;
    p_.clear_twins(i);
    p_.clear_tracks(i);
}

int ParticleFilter::init_floor_only(int32_t floor) {
    if (floor < 0 || static_cast<size_t>(floor) >= map_.floors.size()) {
        return fail(WF_LOC_ERR_INVALID_ARGUMENT, "floor index " + std::to_string(floor) + " is outside [0, " +
                                                     std::to_string(map_.floors.size()) + ")");
    }
    const auto f16 = static_cast<int16_t>(floor);
    if (map_.floors[floor].walkable_cells.empty()) {
        return fail(WF_LOC_ERR_NO_WALKABLE_SPACE,
                    "floor " + std::to_string(floor) + " has no walkable cell (no area inside its walls)");
    }
    const size_t n = initial_particle_count();
    p_.resize(n);
    const float w = 1.0f / static_cast<float>(n);
    for (size_t i = 0; i < n; ++i) {
        float px, py;
        sample_walkable(f16, px, py);
        init_particle(i, px, py, f16, w);
    }
    init_floor_ = f16;
    reset_filter_state();
    // Headings drawn from a compass prior: the twins' headings are less likely by the prior's ratio.
    if (compass_set_ && tracker_.has_yaw()) add_compass_prior_to_twins();
    return WF_LOC_OK;
}

int ParticleFilter::init_start_point(int32_t floor, double x, double y, double radius_m) {
    if (floor < 0 || static_cast<size_t>(floor) >= map_.floors.size()) {
        return fail(WF_LOC_ERR_INVALID_ARGUMENT, "floor index " + std::to_string(floor) + " is outside [0, " +
                                                     std::to_string(map_.floors.size()) + ")");
    }
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(radius_m)) {
        return fail(WF_LOC_ERR_NON_FINITE_INPUT, "start point or radius is not finite");
    }
    if (radius_m < 0 || radius_m > 1000) {
        return fail(WF_LOC_ERR_INVALID_ARGUMENT, "start radius " + std::to_string(radius_m) + " m is outside [0, 1000]");
    }
    const FloorData &fd = map_.floors[floor];
    if (fd.grid.index(static_cast<float>(x), static_cast<float>(y)) < 0) {
        return fail(WF_LOC_ERR_NO_WALKABLE_SPACE, "start point (" + std::to_string(x) + ", " + std::to_string(y) +
                                                      ") is outside floor " + std::to_string(floor));
    }
    const auto f16 = static_cast<int16_t>(floor);
    const size_t n = initial_particle_count();
    p_.resize(n);
    const float w = 1.0f / static_cast<float>(n);
    const float cx = static_cast<float>(x), cy = static_cast<float>(y), r = static_cast<float>(radius_m);
    const double doubt = opts_.start_point_doubt_share;
    for (size_t i = 0; i < n; ++i) {
        float px = cx, py = cy;
        // The traveler may have named the wrong place: a share of the particles covers the whole floor.
        if (doubt > 0 && rng_.uniform(0.0, 1.0) < doubt && sample_walkable(f16, px, py)) {
            init_particle(i, px, py, f16, w);
            continue;
        }
        // Uniform in the disc, rejecting points behind a wall as seen from the centre (another room).
        for (int attempt = 0; attempt < 32; ++attempt) {
            const float rr = r * std::sqrt(rng_.uniform_float());
            const float a = kTwoPi * rng_.uniform_float();
            float s, c;
            fast_sincos(a, s, c);
            const float qx = cx + rr * c, qy = cy + rr * s;
            if (!fd.walls.crosses(cx, cy, qx, qy)) {
                px = qx;
                py = qy;
                break;
            }
        }
        init_particle(i, px, py, f16, w);
    }
    init_floor_ = f16;
    reset_filter_state();
    // On a symmetric floor the named start's twin is unlikely before any evidence: the twin ratios start at the
    // prior's (the disc's density plus the doubt share spread over the walkable cells, at the particle against
    // at its twin), not at 0.
    if (p_.twin_arrays > 0) {
        const double cell_area = static_cast<double>(fd.grid.cell_m) * fd.grid.cell_m;
        const double walkable_m2 = std::max(1.0, static_cast<double>(fd.walkable_cells.size()) * cell_area);
        const double disc_r = std::max(0.25, radius_m);
        const double d_disc = (1.0 - doubt) / (kPiD * disc_r * disc_r), d_uniform = doubt / walkable_m2;
        twin_.set_prior_ratios(p_, map_, [&](int16_t, float qx, float qy) {
            const bool in_disc = std::hypot(qx - cx, qy - cy) <= disc_r + 0.25;
            return std::log(std::max(1e-12, (in_disc ? d_disc : 0.0) + d_uniform));
        });
        if (compass_set_ && tracker_.has_yaw()) add_compass_prior_to_twins();
    }
    // The traveler's word is not evidence: a named start may be wrong (Tests/Recovery), and in a parallel
    // corridor nothing contradicts it for many meters. The flag waits for a sign sighting the named start
    // must explain better than the other places that explain it (pf/particle_filter_corroboration).
    arm_corroboration(opts_.start_point_doubt_share > 0);
    return WF_LOC_OK;
}

int ParticleFilter::set_compass_prior(double heading_in_map_rad, double sigma_rad) {
    if (!std::isfinite(heading_in_map_rad) || !std::isfinite(sigma_rad)) {
        return fail(WF_LOC_ERR_NON_FINITE_INPUT, "compass heading or sigma is not finite");
    }
    if (sigma_rad <= 0 || sigma_rad > 2 * kPiD) {
        return fail(WF_LOC_ERR_INVALID_ARGUMENT, "compass sigma " + std::to_string(sigma_rad) + " rad is outside (0, 2 pi]");
    }
    compass_set_ = true;
    compass_heading_ = wrap_angle(heading_in_map_rad);
    compass_sigma_ = sigma_rad;
    if (initialized_) compass_pending_ = true;
    return WF_LOC_OK;
}

double ParticleFilter::compass_prior_density(double heading_in_map_rad) const {
    // (1 - u) N(heading - compass; 0, sigma) + u / (2 pi), scaled by its Gaussian peak: the mixture of
    // sample_yaw_offset, so a wrong compass (magnetic disturbance indoors is common) only lowers the other
    // headings, by about u / (1 - u) * sigma / sqrt(2 pi) relative to the reading's direction (0.05 for 30 deg).
    const double floor_rel = kCompassUniformShare / (1.0 - kCompassUniformShare) * compass_sigma_ / std::sqrt(2.0 * kPiD);
    const double e = wrap_angle(heading_in_map_rad - compass_heading_) * (1.0 / compass_sigma_);
    return std::exp(-0.5 * e * e) + floor_rel;
}

void ParticleFilter::apply_compass_reweight() {
    double sum = 0;
    for (size_t i = 0; i < p_.size(); ++i) {
        p_.weight[i] *= static_cast<float>(compass_prior_density(vio_yaw_ + p_.yaw_offset[i]));
        sum += p_.weight[i];
    }
    normalize(sum);
    compass_pending_ = false;
    add_compass_prior_to_twins();
}

void ParticleFilter::add_compass_prior_to_twins() {
    if (p_.twin_arrays == 0 || !compass_set_ || !twin_.params().enabled) return;
    // The prior's density at the particle's heading against at its twin's (turned by the symmetry's angle).
    const double cap = twin_.params().max_step_nats;
    for (size_t k = 0; k < p_.twin_arrays; ++k) {
        for (size_t i = 0; i < p_.size(); ++i) {
            const FloorSymmetry *sym = TwinGuard::symmetry_of(map_, p_.floor[i], k);
            if (!sym) continue;
            const double h = vio_yaw_ + p_.yaw_offset[i];
            const double r = std::log(compass_prior_density(h)) - std::log(compass_prior_density(h + sym->angle_rad));
            p_.twin_llr[k][i] += static_cast<float>(std::clamp(r, -cap, cap));
        }
    }
}

void ParticleFilter::normalize(double sum) {
    const size_t n = p_.size();
    if (n == 0) return;
    if (!(sum > 0) || !std::isfinite(sum)) {
        // Every hypothesis was rejected (e.g. all crossed walls): keep them all, equally weighted, rather
        // than dividing by zero.
        std::fill(p_.weight.begin(), p_.weight.end(), 1.0f / static_cast<float>(n));
        return;
    }
    const float inv = static_cast<float>(1.0 / sum);
    float *w = p_.weight.data();
    for (size_t i = 0; i < n; ++i) w[i] *= inv;
}

int ParticleFilter::note_vio_reset() {
    tracker_.note_origin_reset();
    return WF_LOC_OK;
}

int ParticleFilter::predict(const wf_vio_sample &s) {
    if (!std::isfinite(s.t) || !std::isfinite(s.east_m) || !std::isfinite(s.north_m) || !std::isfinite(s.yaw_rad)) {
        return fail(WF_LOC_ERR_NON_FINITE_INPUT, "VIO sample has a non-finite value (ignored)");
    }
    if (s.tracking < WF_VIO_TRACKING_NORMAL || s.tracking > WF_VIO_TRACKING_NOT_AVAILABLE) {
        return fail(WF_LOC_ERR_INVALID_ARGUMENT, "VIO tracking state " + std::to_string(s.tracking) + " is unknown");
    }
    t_last_ = s.t;
    clusterer_.forget_carried_bins();  // the particles move or the VIO yaw turns
    const VioDelta d = tracker_.push(s);
    if (tracker_.has_yaw()) vio_yaw_ = wrap_angle(tracker_.last_yaw());
    if (!initialized_) return WF_LOC_OK;
    if (compass_pending_ && tracker_.has_yaw()) apply_compass_reweight();
    if (d.kind == DeltaKind::kMove) compass_.add_distance(std::hypot(d.d_east, d.d_north));
    // The traveler walked unobserved while tracking was lost: the hypothesis where they really are may have no
    // particle left (tests: office-tracking-loss, a lock 10 m off after the loss). The next lock, or a lock
    // that survives, must be corroborated against rivals drawn from the next sighting.
    if (d.kind == DeltaKind::kJump && d.after_tracking_loss) arm_corroboration(opts_.start_point_doubt_share > 0);
    if (d.kind != DeltaKind::kNone) {
        const double sum = apply_motion(p_, d, motion_, map_, rng_, &motion_acc_);
        normalize(sum);
        maybe_resample(false);
    }
    estimate_dirty_ = true;
    return WF_LOC_OK;
}

void ParticleFilter::note_unexplained_sightings(const std::vector<PreparedSighting> &z, double t) {
    if (z.empty() || !dominant_members_valid_ || !hysteresis_.params().explain_sightings) return;
    // The dominant hypothesis's likelihood of the frame is the weighted mean of its particles' (its predictive
    // distribution, spread and all). It explains the frame when that is at least twice the likelihood the
    // sightings have as false positives alone (for one sighting: the sign term outweighs the clutter term, the
    // range-bias statistics' test, applied to the hypothesis instead of one particle).
    const double clutter_ll = clutter_only_log_likelihood(sign_model_, z.data(), z.size());
    double w_all = 0, w_ratio = 0;
    for (uint32_t i : dominant_members_) {
        const double w = p_.weight[i];
        w_all += w;
        w_ratio += w * std::exp(std::min(static_cast<double>(log_likelihood_[i]) - clutter_ll, 700.0));
    }
    if (!(w_all > 0)) return;
    if (!(w_ratio < 2.0 * w_all)) {
        sightings_unexplained_ = false;  // explained: set again below only while the hold period still holds enough
        return;
    }
    double nats = 0;
    for (const PreparedSighting &s : z) nats -= std::log(std::max(static_cast<double>(s.clutter_probability), 1e-6));
    unexplained_frames_.emplace_back(t, nats);
}

double ParticleFilter::unexplained_sighting_nats(double t) {
    const double since = t - hysteresis_.params().explain_window_s;
    size_t drop = 0;
    while (drop < unexplained_frames_.size() && !(unexplained_frames_[drop].first > since)) ++drop;
    unexplained_frames_.erase(unexplained_frames_.begin(), unexplained_frames_.begin() + static_cast<std::ptrdiff_t>(drop));
    double nats = 0;
    for (const auto &f : unexplained_frames_) {
        if (f.first <= t) nats += f.second;
    }
    return nats;
}

int ParticleFilter::update_signs(const wf_sign_observation *obs, size_t count, double t) {
    return update_signs(obs, count, t, nullptr, 0);
}

int ParticleFilter::update_signs(const wf_sign_observation *obs, size_t count, double t,
                                 const int32_t *unsearched_kinds, size_t unsearched_count) {
    if (!initialized_) return fail(WF_LOC_ERR_NOT_INITIALIZED, "update_signs before an init");
    if (count > 0 && obs == nullptr) return fail(WF_LOC_ERR_INVALID_ARGUMENT, "observations is NULL with count > 0");
    if (unsearched_count > 0 && unsearched_kinds == nullptr) {
        return fail(WF_LOC_ERR_INVALID_ARGUMENT, "unsearched_kinds is NULL with unsearched_count > 0");
    }
    if (!std::isfinite(t)) return fail(WF_LOC_ERR_NON_FINITE_INPUT, "update_signs time is not finite");
    t_last_ = t;
    size_t bad = 0;
    const std::vector<PreparedSighting> z = prepare_sightings(obs, count, sign_model_, map_.kind_count, &bad);
    // Kinds the detector did not look for on this frame: flags by kind id (empty: every kind searched).
    std::vector<uint8_t> unsearched;
    size_t bad_kinds = 0;
    for (size_t i = 0; i < unsearched_count; ++i) {
        const int32_t k = unsearched_kinds[i];
        if (k < 0 || k >= map_.kind_count) {
            ++bad_kinds;
            continue;
        }
        unsearched.resize(static_cast<size_t>(map_.kind_count), 0);
        unsearched[static_cast<size_t>(k)] = 1;
    }
    const uint8_t *unsearched_flags = unsearched.empty() ? nullptr : unsearched.data();
    if (!z.empty() || sign_model_.negative_information) {
        const size_t n = p_.size();
        log_likelihood_.resize(n);
        // The twins are scored with the cloud's states as they are now (before the bias statistics update); read
        // only: the twins' ranges are scored with their particles' range-bias statistics.
        std::array<bool, ParticleSet::kMaxTwins> twin_scored{};
        for (size_t k = 0; k < p_.twin_arrays; ++k) {
            twin_lls_[k].resize(n);
            twin_scored[k] = score_twins(k, [&] {
                sign_log_likelihood(p_, static_cast<float>(vio_yaw_), map_, sign_model_, z.data(), z.size(),
                                    twin_lls_[k].data(), nullptr, nullptr, unsearched_flags);
            });
        }
        // Tracked objects: each tracked sighting's own term is kept for the object-level mixture below.
        tracks_.assign(p_, z, t, track_slot_of_, track_first_);
        track_own_terms_.assign(z.size(), nullptr);
        bool any_tracked = false;
        for (size_t o = 0; o < z.size(); ++o) {
            if (track_slot_of_[o] < 0) continue;
            std::vector<float> &terms = track_terms_[static_cast<size_t>(track_slot_of_[o])];
            terms.resize(n);
            track_own_terms_[o] = terms.data();
            any_tracked = true;
        }
        float max_ll = sign_log_likelihood(p_, static_cast<float>(vio_yaw_), map_, sign_model_, z.data(), z.size(),
                                           log_likelihood_.data(), p_.bias_s1.data(), p_.bias_s0.data(),
                                           unsearched_flags, any_tracked ? track_own_terms_.data() : nullptr);
        // Whether the dominant hypothesis explains the sightings, and the twins' ratios, read each sighting's own
        // geometry (the per-frame terms); the weights take the tracked objects' bounded evidence.
        note_unexplained_sightings(z, t);
        for (size_t k = 0; k < p_.twin_arrays; ++k) {
            if (twin_scored[k]) twin_.accumulate(p_, map_, k, log_likelihood_.data(), twin_lls_[k].data());
        }
        if (any_tracked) {
            max_ll = tracks_.apply(p_, sign_model_, z, track_slot_of_, track_first_, track_own_terms_.data(),
                                   log_likelihood_.data());
        }
        if (!z.empty()) {
            accumulate_evidence(log_likelihood_.data(), max_ll, t);
            last_sighting_t_ = t;
        }
        const double beta = tempering_exponent(max_ll);
        last_beta_ = beta;
        // w_i <- w_i * L_i^beta / sum_j w_j L_j^beta, in the log domain relative to the best particle (no
        // underflow). s_full = sum w_i L_i / L_max (untempered) feeds the recovery averages.
        double s_full = 0;
        const double s = reweight(p_.weight.data(), log_likelihood_.data(), n, max_ll, static_cast<float>(beta), &s_full);
        if (s > 0 && std::isfinite(s) && std::isfinite(max_ll)) {
            normalize(s);
            if (!z.empty() && opts_.recovery) {
                // PR Table 8.3 lines 8-10: w_avg = sum w_i L_i (prior weights normalised) = exp(max) * s,
                // taken per sighting (geometric mean) so frames with 1 or 3 sightings are comparable.
                const double log_avg = (static_cast<double>(max_ll) + std::log(std::max(s_full, 1e-300))) /
                                       static_cast<double>(z.size());
                const double w_avg = std::exp(std::clamp(log_avg, -700.0, 700.0));
                if (w_slow_ == 0 && w_fast_ == 0) {
                    w_slow_ = w_fast_ = w_avg;  // start both at the first value (no spurious injection)
                } else {
                    w_slow_ += opts_.recovery_alpha_slow * (w_avg - w_slow_);
                    w_fast_ += opts_.recovery_alpha_fast * (w_avg - w_fast_);
                }
            } else if (z.empty() && opts_.recovery && w_slow_ > 0) {
                // A frame without sightings while the cloud expected a plainly visible sign: the expected miss
                // likelihood m = sum w_i L_i (< 1) is fed to the recovery averages as w_slow * m, so a
                // hypothesis walking past signs that never show up triggers injection too. Frames where
                // nothing was expected carry no information and leave the averages alone.
                const double m = std::exp(static_cast<double>(max_ll)) * s_full;
                if (m < 1.0 - 1e-6) {
                    const double w_avg = w_slow_ * m;
                    w_slow_ += opts_.recovery_alpha_slow * (w_avg - w_slow_);
                    w_fast_ += opts_.recovery_alpha_fast * (w_avg - w_fast_);
                }
            }
            last_sightings_ = z;
            if (awaiting_corroboration_ && !corroboration_candidates_drawn_ && !z.empty()) {
                draw_corroboration_rivals(opts_.start_point_doubt_share);
            } else {
                maybe_resample(opts_.recovery != 0);
            }
            last_sightings_.clear();
            reseed_twins();
        } else {
            normalize(0);
        }
        estimate_dirty_ = true;
    }
    // The estimate (clustering) is computed when it is read: estimate() after each frame.
    if (bad > 0) {
        return fail(WF_LOC_ERR_NON_FINITE_INPUT,
                    std::to_string(bad) + " sighting(s) with a non-finite or negative value were ignored");
    }
    if (bad_kinds > 0) {
        return fail(WF_LOC_ERR_INVALID_ARGUMENT, std::to_string(bad_kinds) +
                                                     " unsearched kind id(s) outside the map's kinds were ignored");
    }
    return WF_LOC_OK;
}

double ParticleFilter::tempering_exponent(float max_ll) {
    const double target = opts_.tempering_min_ess_fraction;
    const size_t n = p_.size();
    if (target <= 0 || n == 0) return 1.0;
    // ESS fraction of w * L^beta, estimated on an even subsample of at most 8192 particles (the exponent
    // only needs to be roughly right, and this keeps the bisection cheap for 100k particles).
    const size_t stride = std::max<size_t>(1, n / 8192);
    const float *w = p_.weight.data();
    const float *ll = log_likelihood_.data();
    // The subsample's weights and log-likelihoods (relative to the best), gathered once for the bisection.
    tempering_w_.clear();
    tempering_d_.clear();
    for (size_t i = 0; i < n; i += stride) {
        tempering_w_.push_back(w[i]);
        tempering_d_.push_back(ll[i] - max_ll);
    }
    const size_t m = tempering_w_.size();
    auto ess_fraction = [&](double beta) {
        return tempered_ess_fraction(tempering_w_.data(), tempering_d_.data(), m, static_cast<float>(beta));
    };
    // Compare with the ESS before the update (the prior weights may already be uneven).
    const double goal = std::min(target, ess_fraction(0.0));
    if (ess_fraction(1.0) >= goal) return 1.0;
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 12; ++it) {
        const double mid = 0.5 * (lo + hi);
        (ess_fraction(mid) >= goal ? lo : hi) = mid;
    }
    return std::max(lo, 1e-3);
}

void ParticleFilter::maybe_resample(bool after_measurement) {
    const size_t n = p_.size();
    if (n == 0) return;
    double weight_sum = 0;
    const double ess = effective_sample_size(p_.weight.data(), n, &weight_sum);
    double inject = 0;
    if (opts_.recovery && after_measurement && w_slow_ > 0) {
        inject = std::clamp(1.0 - w_fast_ / w_slow_, 0.0, opts_.recovery_max_fraction);
    }
    if (ess < opts_.resample_ess_fraction * static_cast<double>(n) || inject > 0.01) resample(inject, weight_sum);
}

void ParticleFilter::resample(double inject_fraction, double weight_sum) {
    const size_t n = p_.size();
    size_t target = static_cast<size_t>(opts_.particle_count);
    if (opts_.adaptive_particle_count) {
        // KLD-sampling (Fox 2003): k = bins occupied by a systematic draw of the current size. A spread-out
        // cloud occupies far more bins than the bound needs to reach max_particles: the first draws are
        // counted alone, and when they already occupy enough bins (kld_bins_reaching) the count is
        // max_particles whatever the rest occupy (the same result as counting them all).
        const double u0 = rng_.uniform();
        const auto count_bins = [&] {
            return count_occupied_bins(p_, indices_, static_cast<float>(vio_yaw_), static_cast<float>(opts_.kld_bin_m),
                                       static_cast<float>(opts_.kld_bin_yaw_rad), kld_bins_, kld_dense_, kld_seen_);
        };
        const size_t max_n = static_cast<size_t>(opts_.max_particles);
        // While not localized the cloud keeps at least min_particles_unlocalized_, never more than an init starts
        // with (particle_count) nor max_particles: the KLD bound counts occupied bins, but a hypothesis that shares
        // its bins with a look-alike needs particles of its own to survive (docs/localizer.md "More particles
        // while not localized").
        const size_t unlocalized_floor =
            was_localized_ ? size_t{0} : std::min(min_particles_unlocalized_, initial_particle_count());
        const size_t min_n = std::min(max_n, std::max(static_cast<size_t>(opts_.min_particles), unlocalized_floor));
        const size_t k_enough = kld_bins_reaching(max_n, opts_.kld_epsilon, opts_.kld_z);
        bool at_max = false;
        if (k_enough != SIZE_MAX && 4 * k_enough < n) {
            systematic_resample_with_total(p_.weight.data(), n, n, u0, weight_sum, indices_, 2 * k_enough);
            at_max = count_bins() >= k_enough;
        }
        if (at_max) {
            target = max_n;  // std::clamp's value: min_n <= max_n
        } else {
            systematic_resample_with_total(p_.weight.data(), n, n, u0, weight_sum, indices_);
            target = std::clamp(kld_sample_count(count_bins(), opts_.kld_epsilon, opts_.kld_z), min_n, max_n);
        }
    }
    // Injection goes to the floor of the best hypothesis (the estimate's floor), else the init floor.
    const int16_t inject_floor =
        estimate_.floor_index >= 0 ? static_cast<int16_t>(estimate_.floor_index) : init_floor_;
    size_t n_inject = static_cast<size_t>(std::lround(inject_fraction * static_cast<double>(target)));
    if (map_.floors[inject_floor].walkable_cells.empty()) n_inject = 0;
    const size_t n_keep = target - n_inject;
    const double kept_mass = n_inject > 0 ? 1.0 - static_cast<double>(n_inject) / static_cast<double>(target) : 1.0;
    // The draws are collected first (source index and new weight), then each state array is gathered in its
    // own loop (streams through memory instead of touching eight arrays per particle).
    resample_src_.resize(target);
    resample_w_.resize(target);
    size_t out = 0;
    auto copy_particle = [&](uint32_t i, float w) {
        resample_src_[out] = i;
        resample_w_[out] = w;
        ++out;
    };
    const double share = opts_.hypothesis_particle_share;
    bool grouped = false, clustered = false;
    if (share > 0) {
        clustered = true;
        // Groups = clusters holding >= 1 % of the weight, plus one group for every other particle.
        ClusterParams cp;
        cp.cell_m = static_cast<float>(opts_.cluster_cell_m);
        cp.yaw_bin_rad = static_cast<float>(opts_.cluster_yaw_bin_rad);
        cp.weights_only = true;  // the groups need the partition and the weights only
        const std::vector<ClusterSummary> &clusters = clusterer_.run(p_, static_cast<float>(vio_yaw_), cp);
        const std::vector<int32_t> &cluster_of = clusterer_.particle_clusters();
        int32_t significant = 0;
        while (significant < static_cast<int32_t>(clusters.size()) && clusters[significant].weight >= 0.01) ++significant;
        if (significant >= 2 || (significant == 1 && clusters[0].weight < 0.99)) {
            grouped = true;
            const int32_t groups = significant + 1;  // last group: the rest
            group_start_.assign(static_cast<size_t>(groups) + 1, 0);
            // Members of each group in particle order, as one array sorted by group (no per-group allocation).
            // With few groups (the usual case: one or two hypotheses and the rest), one branch-free compaction
            // pass per group over a byte of group per particle; with more, a counting sort. Either way the
            // same array.
            group_members_.resize(n + 1);  // + 1: a compaction pass writes one slot past its last member
            uint32_t *members_out = group_members_.data();
            if (groups <= kCompactionGroups) {
                group_of_.resize(n);
                uint8_t *gid = group_of_.data();
                for (size_t i = 0; i < n; ++i) {
                    const int32_t c = cluster_of[i];
                    gid[i] = static_cast<uint8_t>((c >= 0 && c < significant) ? c : significant);
                }
                size_t pos = 0;
                for (int32_t g = 0; g < groups; ++g) {
                    const auto gg = static_cast<uint8_t>(g);
                    for (size_t i = 0; i < n; ++i) {
                        members_out[pos] = static_cast<uint32_t>(i);
                        pos += gid[i] == gg ? 1 : 0;
                    }
                    group_start_[g + 1] = pos;
                }
            } else {
                for (size_t i = 0; i < n; ++i) {
                    const int32_t c = cluster_of[i];
                    ++group_start_[((c >= 0 && c < significant) ? c : significant) + 1];
                }
                for (int32_t g = 0; g < groups; ++g) group_start_[g + 1] += group_start_[g];
                group_fill_.assign(group_start_.begin(), group_start_.end() - 1);
                for (size_t i = 0; i < n; ++i) {
                    const int32_t c = cluster_of[i];
                    const int32_t g = (c >= 0 && c < significant) ? c : significant;
                    members_out[group_fill_[g]++] = static_cast<uint32_t>(i);
                }
            }
            // The members' weights in group order, and each group's mass: their lane sum (common/lane_sums), which
            // is also the total that the group's systematic resampling forms (so it is passed on, not summed
            // again).
            group_weights_.resize(n);
            for (size_t k = 0; k < n; ++k) group_weights_[k] = p_.weight[members_out[k]];
            group_mass_.assign(static_cast<size_t>(groups), 0.0);
            for (int32_t g = 0; g < groups; ++g) {
                group_mass_[g] = lane_sum(group_weights_.data() + group_start_[g], group_start_[g + 1] - group_start_[g]);
            }
            const double *mass = group_mass_.data();
            double total = 0;
            int32_t nonempty = 0;
            for (int32_t g = 0; g < groups; ++g) {
                total += mass[g];
                nonempty += mass[g] > 0 ? 1 : 0;
            }
            for (int32_t g = 0; g < groups; ++g) {
                if (!(mass[g] > 0) || !(total > 0)) continue;
                const double wg = mass[g] / total;
                if (out >= n_keep) break;
                const size_t remaining = n_keep - out;
                size_t ng = static_cast<size_t>(std::lround(static_cast<double>(n_keep) *
                                                            ((1.0 - share) * wg + share / nonempty)));
                ng = std::clamp<size_t>(ng, 1, std::max<size_t>(1, remaining));
                if (g == groups - 1 || out + ng > n_keep) ng = std::max<size_t>(1, remaining);
                const uint32_t *members = members_out + group_start_[g];
                const size_t count = group_start_[g + 1] - group_start_[g];
                systematic_resample_with_total(group_weights_.data() + group_start_[g], count, ng, rng_.uniform(),
                                               mass[g], indices_);
                const float w = static_cast<float>(kept_mass * wg / static_cast<double>(ng));
                for (uint32_t k : indices_) copy_particle(members[k], w);
                if (out >= n_keep) break;
            }
        }
    }
    if (!grouped) {
        systematic_resample_with_total(p_.weight.data(), n, n_keep, rng_.uniform(), weight_sum, indices_);
        const float w = static_cast<float>(kept_mass / static_cast<double>(std::max<size_t>(1, n_keep)));
        for (uint32_t i : indices_) copy_particle(i, w);
    }
    const size_t kept = out;
    const size_t total_out = kept + n_inject;
    scratch_.resize(total_out);
    {
        const uint32_t *src = resample_src_.data();
        auto gather = [&](const auto &from, auto &to) {
            for (size_t k = 0; k < kept; ++k) to[k] = from[src[k]];
        };
        // Three arrays per pass: one read of each source index serves three loads, and three write streams
        // (measured on the spread-out cloud: nine arrays one by one 0.58 ms, three at a time 0.32 ms, all in
        // one pass 0.66 ms).
        const auto gather3 = [&](const auto *__restrict a, const auto *__restrict b, const auto *__restrict c,
                                 auto *__restrict oa, auto *__restrict ob, auto *__restrict oc) {
            for (size_t k = 0; k < kept; ++k) {
                const uint32_t s = src[k];
                oa[k] = a[s];
                ob[k] = b[s];
                oc[k] = c[s];
            }
        };
        ParticleSet &o = scratch_;
        gather3(p_.x.data(), p_.y.data(), p_.yaw_offset.data(), o.x.data(), o.y.data(), o.yaw_offset.data());
        gather3(p_.scale.data(), p_.evidence.data(), p_.compass_ll.data(), o.scale.data(), o.evidence.data(),
                o.compass_ll.data());
        gather3(p_.bias_s1.data(), p_.bias_s0.data(), p_.floor.data(), o.bias_s1.data(), o.bias_s0.data(),
                o.floor.data());
        for (size_t k = 0; k < p_.twin_arrays; ++k) gather(p_.twin_llr[k], scratch_.twin_llr[k]);
        for (size_t k = 0; k < ParticleSet::kMaxTracks; ++k) {
            if (tracks_.active(k)) gather(p_.track_llr[k], scratch_.track_llr[k]);
        }
        std::copy(resample_w_.begin(), resample_w_.begin() + static_cast<std::ptrdiff_t>(kept), scratch_.weight.begin());
    }
    const float inject_w = static_cast<float>((1.0 - kept_mass) / static_cast<double>(std::max<size_t>(1, n_inject)));
    // Injected particles start with the worst evidence present: a fresh guess is not a proven hypothesis.
    float worst_evidence = 0;
    if (n_inject > 0) {
        for (float e : p_.evidence) worst_evidence = std::min(worst_evidence, e);
    }
    for (size_t k = kept; k < total_out; ++k) {
        // Augmented MCL: a random particle ("kidnapped traveler" recovery). Every other one is drawn from
        // the current sightings when there are some (sensor resetting, Lenser & Veloso 2000), the rest
        // uniformly over the walkable space.
        if (!(k % 2 == 0 && sample_from_sighting(inject_floor, scratch_.x[k], scratch_.y[k], scratch_.yaw_offset[k]))) {
            sample_walkable(inject_floor, scratch_.x[k], scratch_.y[k]);
            scratch_.yaw_offset[k] = sample_yaw_offset();
        }
        scratch_.scale[k] = std::clamp(1.0f + static_cast<float>(opts_.initial_scale_sigma) * rng_.normal(),
                                       motion_.scale_min, motion_.scale_max);
        scratch_.floor[k] = inject_floor;
        scratch_.weight[k] = inject_w;
        scratch_.evidence[k] = worst_evidence;
        scratch_.compass_ll[k] = 0;
        scratch_.bias_s1[k] = 0;  // a fresh guess has no sightings behind it
        scratch_.bias_s0[k] = 0;
        scratch_.clear_twins(k);
        scratch_.clear_tracks(k);
    }
    p_.swap(scratch_);
    // The kept particles are unchanged copies of clustered ones: the estimate's clustering, when nothing
    // moves before it, takes their bins from the sources (the same clusters, without binning them again).
    if (clustered && n_inject == 0) {
        clusterer_.carry_bins(resample_src_.data(), kept);
    } else {
        clusterer_.forget_carried_bins();
    }
    normalize(lane_sum(p_.weight.data(), p_.size()));
    ++resample_count_;
    injected_count_ += n_inject;
    estimate_dirty_ = true;
    dominant_members_valid_ = false;
}

int ParticleFilter::update_altitude(double relative_altitude_m, double t) {
    if (!std::isfinite(relative_altitude_m) || !std::isfinite(t)) {
        return fail(WF_LOC_ERR_NON_FINITE_INPUT, "relative altitude or time is not finite (ignored)");
    }
    t_last_ = t;
    const double delta = floor_detector_.push(relative_altitude_m, t);
    if (delta != 0 && initialized_) apply_floor_change(delta);
    return WF_LOC_OK;
}

void ParticleFilter::apply_floor_change(double delta_m) {
    dominant_members_valid_ = false;
    clusterer_.forget_carried_bins();
    const double sum = wf::loc::apply_floor_change(p_, map_, delta_m, floor_params_, rng_,
                                                    [this] { return sample_yaw_offset(); });
    // A new floor has its own symmetries: every twin ratio starts again, from the ride's prior: a traveler
    // leaving an elevator or stairs is near a vertical link, so a twin pose far from every link (the turn does
    // not map the links onto links) is less likely by the weight the ride gives such poses.
    if (p_.twin_arrays > 0) {
        const double link_r = floor_params_.link_radius_m;
        const double far = std::log(std::max(1e-6, floor_params_.far_from_link_weight));
        twin_.set_prior_ratios(p_, map_, [&](int16_t f, float qx, float qy) {
            return map_.floors[static_cast<size_t>(f)].distance_to_link(qx, qy) <= link_r ? 0.0 : far;
        });
    }
    twin_.reset();
    tracks_.reset();  // the objects seen so far are on the floor left behind
    normalize(sum);
    maybe_resample(false);
    estimate_dirty_ = true;
    compute_estimate();
}

void ParticleFilter::set_pose_from_core(wf_localizer_estimate &e, const ClusterCore &core) const {
    e.x = core.x;
    e.y = core.y;
    e.cov_xx = core.cov_xx;
    e.cov_xy = core.cov_xy;
    e.cov_yy = core.cov_yy;
    e.yaw_offset_rad = std::atan2(core.yaw_sin_sum, core.yaw_cos_sum);
    e.heading_rad = wrap_angle(vio_yaw_ + e.yaw_offset_rad);
    const double rlen =
        std::min(1.0, std::sqrt(core.yaw_cos_sum * core.yaw_cos_sum + core.yaw_sin_sum * core.yaw_sin_sum) / core.weight);
    e.heading_std_rad = rlen > 1e-12 ? std::sqrt(std::max(0.0, -2.0 * std::log(rlen))) : kPiD;
    e.position_std_m = core.position_std_m();
    e.confidence = e.dominant_weight / (1.0 + e.position_std_m * e.position_std_m);
}

void ParticleFilter::place_front_hypothesis(const wf_localizer_estimate &e) {
    if (hypotheses_.empty()) return;
    wf_localizer_hypothesis &h = hypotheses_.front();
    h.x = e.x;
    h.y = e.y;
    h.heading_rad = e.heading_rad;
    h.position_std_m = e.position_std_m;
    h.heading_std_rad = e.heading_std_rad;
}

void ParticleFilter::follow_dominant_cluster() {
    estimate_dirty_ = false;
    // The moments of the dominant cluster's particles (while localized, of its core, as in compute_estimate).
    ClusterCore m;
    double w = 0;
    for (uint32_t i : dominant_members_) w += p_.weight[i];
    if (hysteresis_.localized()) {
        // Around the disc of the last full estimate: the median taken again over a cluster that recovery
        // injection merged with particles along the corridor may fall on their side (docs/benchmarks.md,
        // "Thirtieth stop": 11 m for a tenth of a second).
        const std::vector<uint32_t> &members = pose_from_sighted_core_ ? sighted_members_ : dominant_members_;
        const double radius_m = hysteresis_.params().lock_core_radius_m;
        m = pose_core_valid_ ? cluster_core_around(p_, members, pose_core_x_, pose_core_y_, radius_m)
                             : cluster_core(p_, members, radius_m, core_scratch_);
    } else {
        double sx = 0, sy = 0, oc = 0, os = 0;
        for (uint32_t i : dominant_members_) {
            const double wi = p_.weight[i];
            float so, co;
            fast_sincos(p_.yaw_offset[i], so, co);
            sx += wi * p_.x[i];
            sy += wi * p_.y[i];
            oc += wi * co;
            os += wi * so;
        }
        m.weight = w;
        m.x = sx / w;
        m.y = sy / w;
        m.yaw_cos_sum = oc;
        m.yaw_sin_sum = os;
        if (w > 0) {
            for (uint32_t i : dominant_members_) {
                const double wi = p_.weight[i] / w, dx = p_.x[i] - m.x, dy = p_.y[i] - m.y;
                m.cov_xx += wi * dx * dx;
                m.cov_xy += wi * dx * dy;
                m.cov_yy += wi * dy * dy;
            }
        }
    }
    if (!(m.weight > 0) || !std::isfinite(m.x) || !std::isfinite(m.y)) {
        compute_estimate();
        return;
    }
    wf_localizer_estimate &e = estimate_;
    e.t = t_last_;
    e.dominant_weight = std::clamp(w, 0.0, 1.0);
    set_pose_from_core(e, m);
    place_front_hypothesis(e);
    if (!hypotheses_.empty()) hypotheses_.front().weight = e.dominant_weight;
}

void ParticleFilter::accumulate_evidence(const float *ll, float max_ll, double t) {
    const double dt = has_evidence_t_ ? std::max(0.0, t - evidence_t_) : 0.0;
    const float decay = static_cast<float>(std::exp(-dt / opts_.evidence_time_constant_s));
    float *ev = p_.evidence.data();
    const size_t n = p_.size();
    for (size_t i = 0; i < n; ++i) ev[i] = decay * ev[i] + std::max(ll[i] - max_ll, -50.0f);
    evidence_t_ = t;
    has_evidence_t_ = true;
}

int ParticleFilter::update_compass(double heading_in_map_rad, double accuracy_rad, double t) {
    if (!std::isfinite(heading_in_map_rad) || !std::isfinite(t)) {
        return fail(WF_LOC_ERR_NON_FINITE_INPUT, "compass heading or time is not finite (ignored)");
    }
    if (!initialized_) return fail(WF_LOC_ERR_NOT_INITIALIZED, "update_compass before an init");
    if (std::isnan(accuracy_rad) || accuracy_rad > kPiD) {
        return fail(WF_LOC_ERR_INVALID_ARGUMENT, "compass accuracy " + std::to_string(accuracy_rad) +
                                                     " rad is outside [0, pi] (reading ignored)");
    }
    t_last_ = t;
    if (!tracker_.has_yaw() || !compass_.due()) return WF_LOC_OK;
    const size_t n = p_.size();
    log_likelihood_.resize(n);
    compass_.log_likelihood(p_, static_cast<float>(vio_yaw_), heading_in_map_rad, accuracy_rad, log_likelihood_.data());
    accumulate_twin_ratios([&](float *out) {
        compass_.log_likelihood(p_, static_cast<float>(vio_yaw_), heading_in_map_rad, accuracy_rad, out);
    });
    compass_.mark_applied();
    ++compass_update_count_;
    // Each particle's history keeps its compass log-weight relative to the best history (max 0), floored at
    // -max_total_nats: the weight changes only by what keeps it inside that band, so repeated readings with a
    // persistent bias cannot push a hypothesis further than the cap. The same totals count as evidence for
    // refuting rivals (clustering adds them to the sign evidence); they do not decay with time, since a
    // heading seen 20 m ago is still the heading.
    float *total = p_.compass_ll.data();
    const float *ll = log_likelihood_.data();
    float best = -std::numeric_limits<float>::infinity();
    for (size_t i = 0; i < n; ++i) best = std::max(best, total[i] + ll[i]);
    const float cap = static_cast<float>(-compass_.params().max_total_nats);
    double s = 0;
    float *w = p_.weight.data();
    for (size_t i = 0; i < n; ++i) {
        const float next = std::max(total[i] + ll[i] - best, cap);
        w[i] *= std::exp(next - total[i]);
        total[i] = next;
        s += w[i];
    }
    normalize(s);
    maybe_resample(false);
    reseed_twins();
    estimate_dirty_ = true;
    return WF_LOC_OK;
}

void ParticleFilter::reseed_twins() {
    if (twin_.reseed(p_, map_) > 0) {  // mass moved, not created: the weights stay normalised
        clusterer_.forget_carried_bins();
        dominant_members_valid_ = false;
        estimate_dirty_ = true;
    }
}

namespace {

/// One named internal parameter: where it lives and its allowed range.
struct NamedParameter {
    const char *name;
    double lo, hi;
};

constexpr NamedParameter kParameters[] = {
    {"compass.enabled", 0, 1},
    {"compass.kappa", 0.01, 1e4},
    {"compass.outlier_share", 1e-4, 1},
    {"compass.min_distance_m", 0, 1e4},
    {"compass.max_nats", 0, 50},
    {"compass.max_total_nats", 0, 1e3},
    {"lock.rival_weight", 0, 1},
    {"lock.rival_margin_nats", 0, 1e3},
    {"lock.thin_rival_weight", 0, 1},
    {"lock.thin_rival_refute_nats", 0, 1e3},
    {"lock.thin_rival_sighted_share", 0, 1},
    {"lock.jump_m", 0.1, 1e4},
    {"lock.core_radius_m", 0.5, 1e4},
    {"lock.explain_sightings", 0, 1},
    {"lock.explain_window_s", 0, 1e3},
    {"lock.lost_walk_speed_mps", 0, 100},
    {"lock.discount_unsighted", 0, 1},
    {"lock.break_hold_s", 0, 1e3},
    {"lock.follow_locked", 0, 1},
    {"lock.none_while_limited", 0, 1},
    {"lock.limited_spell_max_s", 0, 1e6},
    {"kld.min_particles_unlocalized", 0, 1e7},
    {"motion.walk_on_share", 0, 1},
    {"motion.walk_on_max_lost_s", 0, 1e4},
    {"motion.loss_frame_kept_share", 0, 1},
    {"motion.loss_measured_share", 0, 1},
    {"plane.weight", 0, 10},
    {"plane.min_interval_s", 0, 1e4},
    {"sign.negative_info_min_range_m", 0, 1e3},
    {"sign.range_bias_sigma", 0, 1},
    {"twin.enabled", 0, 1},
    {"track.enabled", 0, 1},
    {"track.lookalike_share", 1e-6, 0.999999},
    {"track.forget_s", 0, 1e4},
    {"track.variance_factor", 1, 1e4},
};

}  // namespace

const char *ParticleFilter::parameter_names() {
    // Joined once from kParameters, so the list cannot miss a name the table has.
    static const std::string names = [] {
        std::string joined;
        for (const NamedParameter &p : kParameters) joined += (joined.empty() ? "" : ",") + std::string(p.name);
        return joined;
    }();
    return names.c_str();
}

int ParticleFilter::set_parameter(const std::string &name, double value) {
    const NamedParameter *found = nullptr;
    for (const NamedParameter &p : kParameters) {
        if (name == p.name) found = &p;
    }
    if (!found) {
        return fail(WF_LOC_ERR_INVALID_ARGUMENT, "unknown parameter '" + name + "' (known: " + parameter_names() + ")");
    }
    if (!in_range(value, found->lo, found->hi)) {
        return fail(WF_LOC_ERR_INVALID_ARGUMENT, "parameter " + name + " = " + std::to_string(value) + " is outside [" +
                                                     std::to_string(found->lo) + ", " + std::to_string(found->hi) + "]");
    }
    CompassModelParams &c = compass_.mutable_params();
    LocalizedHysteresisParams &h = hysteresis_.mutable_params();
    if (name == "compass.enabled") c.enabled = value != 0;
    else if (name == "compass.kappa") c.kappa = value;
    else if (name == "compass.outlier_share") c.outlier_share = value;
    else if (name == "compass.min_distance_m") c.min_distance_m = value;
    else if (name == "compass.max_nats") c.max_nats = value;
    else if (name == "compass.max_total_nats") c.max_total_nats = value;
    else if (name == "lock.rival_weight") h.lock_rival_weight = value;
    else if (name == "lock.rival_margin_nats") h.lock_rival_margin_nats = value;
    else if (name == "lock.thin_rival_weight") h.thin_rival_min_weight = value;
    else if (name == "lock.thin_rival_refute_nats") h.thin_rival_refute_nats = value;
    else if (name == "lock.thin_rival_sighted_share") h.thin_rival_min_sighted_share = value;
    else if (name == "lock.jump_m") h.lock_jump_m = value;
    else if (name == "lock.core_radius_m") h.lock_core_radius_m = value;
    else if (name == "lock.explain_sightings") {
        h.explain_sightings = value != 0;
        if (value == 0) {
            unexplained_frames_.clear();
            sightings_unexplained_ = false;
        }
    }
    else if (name == "lock.explain_window_s") h.explain_window_s = value;
    else if (name == "lock.lost_walk_speed_mps") h.lost_walk_speed_mps = value;
    else if (name == "lock.discount_unsighted") h.discount_unsighted = value != 0;
    else if (name == "lock.break_hold_s") h.lock_break_hold_s = value;
    else if (name == "lock.follow_locked") h.follow_locked_hypothesis = value != 0;
    else if (name == "lock.none_while_limited") h.no_lock_while_limited = value != 0;
    else if (name == "lock.limited_spell_max_s") h.limited_spell_max_s = value;
    else if (name == "kld.min_particles_unlocalized") min_particles_unlocalized_ = static_cast<size_t>(value);
    else if (name == "motion.walk_on_share") tracker_.mutable_walk_on().share = value;
    else if (name == "motion.walk_on_max_lost_s") tracker_.mutable_walk_on().max_lost_s = value;
    else if (name == "motion.loss_frame_kept_share") tracker_.mutable_walk_on().frame_kept_share = value;
    else if (name == "motion.loss_measured_share") tracker_.mutable_walk_on().measured_share = value;
    else if (name == "plane.weight") planes_.params.weight = static_cast<float>(value);
    else if (name == "plane.min_interval_s") planes_.params.min_interval_s = value;
    else if (name == "sign.negative_info_min_range_m") sign_model_.negative_info_min_range_m = static_cast<float>(value);
    else if (name == "sign.range_bias_sigma") sign_model_.range_bias_sigma = static_cast<float>(value);
    else if (name == "twin.enabled") {
        twin_.mutable_params().enabled = value != 0;
        if (value == 0) twin_.reset();
    }
    else if (name == "track.enabled") {
        tracks_.mutable_params().enabled = value != 0;
        tracks_.reset();
        // The ratio arrays exist only while the evidence is on (sized now for the particles there are).
        p_.track_arrays = scratch_.track_arrays = value != 0 ? ParticleSet::kMaxTracks : 0;
        p_.resize(p_.size());
        scratch_.resize(scratch_.size());
    }
    else if (name == "track.lookalike_share") tracks_.mutable_params().lookalike_share = value;
    else if (name == "track.forget_s") tracks_.mutable_params().forget_s = value;
    else if (name == "track.variance_factor") tracks_.mutable_params().variance_factor = value;
    return WF_LOC_OK;
}

int ParticleFilter::get_parameter(const std::string &name, double &value) {
    const CompassModelParams &c = compass_.params();
    const LocalizedHysteresisParams &h = hysteresis_.params();
    if (name == "compass.enabled") value = c.enabled ? 1 : 0;
    else if (name == "compass.kappa") value = c.kappa;
    else if (name == "compass.outlier_share") value = c.outlier_share;
    else if (name == "compass.min_distance_m") value = c.min_distance_m;
    else if (name == "compass.max_nats") value = c.max_nats;
    else if (name == "compass.max_total_nats") value = c.max_total_nats;
    else if (name == "lock.rival_weight") value = h.lock_rival_weight;
    else if (name == "lock.rival_margin_nats") value = h.lock_rival_margin_nats;
    else if (name == "lock.thin_rival_weight") value = h.thin_rival_min_weight;
    else if (name == "lock.thin_rival_refute_nats") value = h.thin_rival_refute_nats;
    else if (name == "lock.thin_rival_sighted_share") value = h.thin_rival_min_sighted_share;
    else if (name == "lock.jump_m") value = h.lock_jump_m;
    else if (name == "lock.core_radius_m") value = h.lock_core_radius_m;
    else if (name == "lock.explain_sightings") value = h.explain_sightings ? 1 : 0;
    else if (name == "lock.explain_window_s") value = h.explain_window_s;
    else if (name == "lock.lost_walk_speed_mps") value = h.lost_walk_speed_mps;
    else if (name == "lock.discount_unsighted") value = h.discount_unsighted ? 1 : 0;
    else if (name == "lock.break_hold_s") value = h.lock_break_hold_s;
    else if (name == "lock.follow_locked") value = h.follow_locked_hypothesis ? 1 : 0;
    else if (name == "lock.none_while_limited") value = h.no_lock_while_limited ? 1 : 0;
    else if (name == "lock.limited_spell_max_s") value = h.limited_spell_max_s;
    else if (name == "kld.min_particles_unlocalized") value = static_cast<double>(min_particles_unlocalized_);
    else if (name == "motion.walk_on_share") value = tracker_.walk_on().share;
    else if (name == "motion.walk_on_max_lost_s") value = tracker_.walk_on().max_lost_s;
    else if (name == "motion.loss_frame_kept_share") value = tracker_.walk_on().frame_kept_share;
    else if (name == "motion.loss_measured_share") value = tracker_.walk_on().measured_share;
    else if (name == "plane.weight") value = planes_.params.weight;
    else if (name == "plane.min_interval_s") value = planes_.params.min_interval_s;
    else if (name == "sign.negative_info_min_range_m") value = sign_model_.negative_info_min_range_m;
    else if (name == "sign.range_bias_sigma") value = sign_model_.range_bias_sigma;
    else if (name == "twin.enabled") value = twin_.params().enabled ? 1 : 0;
    else if (name == "track.enabled") value = tracks_.params().enabled ? 1 : 0;
    else if (name == "track.lookalike_share") value = tracks_.params().lookalike_share;
    else if (name == "track.forget_s") value = tracks_.params().forget_s;
    else if (name == "track.variance_factor") value = tracks_.params().variance_factor;
    else return fail(WF_LOC_ERR_INVALID_ARGUMENT, "unknown parameter '" + name + "' (known: " + parameter_names() + ")");
    return WF_LOC_OK;
}

void ParticleFilter::compute_estimate() {
    estimate_dirty_ = false;
    wf_localizer_estimate e{};
    e.t = t_last_;
    e.floor_index = -1;
    e.scale = 1;
    e.particle_count = static_cast<int32_t>(p_.size());
    hypotheses_.clear();
    if (!initialized_ || p_.size() == 0) {
        estimate_ = e;
        return;
    }
    ClusterParams cp;
    cp.cell_m = static_cast<float>(opts_.cluster_cell_m);
    cp.yaw_bin_rad = static_cast<float>(opts_.cluster_yaw_bin_rad);
    // Only the dominant cluster and the rivals the lock's guard can count are read below (rivals, hypotheses;
    // lighter ones count by weight only): the others are not summarised (half the threshold, so that a
    // cluster whose particle sum reaches it is summarised whatever the summation order).
    const double lightest_rival = lightest_counted_rival_weight(hysteresis_.params());
    cp.summary_min_weight = 0.5 * lightest_rival;
    // Right after a resampling with nothing moved since (the usual order in a frame: signs, planes, then this
    // read), the clusters are those the resampling grouped by, weighed and summarised with the current weights.
    cp.reuse_carried_partition = true;
    const std::vector<ClusterSummary> &clusters = clusterer_.run(p_, static_cast<float>(vio_yaw_), cp);
    if (clusters.empty()) {
        estimate_ = e;
        return;
    }
    // The dominant hypothesis: the heaviest cluster, or while localized the one still holding the locked pose
    // when the heaviest is a rival the evidence refutes against it (pf/locked_hypothesis).
    const LocalizedHysteresisParams &hp = hysteresis_.params();
    LockedPose locked;
    const bool has_lock = hysteresis_.localized() && hysteresis_.last_pose(locked.x, locked.y, locked.floor);
    const size_t dom = dominant_cluster_index(clusters, has_lock ? &locked : nullptr, hp);
    const ClusterSummary &d = clusters[dom];
    {
        const std::vector<int32_t> &cluster_of = clusterer_.particle_clusters();
        // Branch-free compaction (the members of a spread-out cloud's dominant cluster are scattered).
        dominant_members_.resize(cluster_of.size() + 1);  // + 1: the pass writes one slot past the last member
        size_t members = 0;
        for (size_t i = 0; i < cluster_of.size(); ++i) {
            dominant_members_[members] = static_cast<uint32_t>(i);
            members += cluster_of[i] == static_cast<int32_t>(dom) ? 1 : 0;
        }
        dominant_members_.resize(members);
        dominant_members_valid_ = !dominant_members_.empty() && cluster_of.size() == p_.size();
        full_estimate_t_ = t_last_;
    }
    int32_t hyps = 0;
    for (const ClusterSummary &c : clusters) hyps += c.weight > opts_.hypothesis_min_weight ? 1 : 0;
    Eigen::Matrix2d cov;
    cov << d.cov_xx, d.cov_xy, d.cov_xy, d.cov_yy;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov, Eigen::EigenvaluesOnly);
    const double std_m = std::sqrt(std::max(0.0, eig.eigenvalues().maxCoeff()));
    e.x = d.x;
    e.y = d.y;
    e.floor_index = d.floor;
    e.heading_rad = wrap_angle(d.heading);
    e.cov_xx = d.cov_xx;
    e.cov_xy = d.cov_xy;
    e.cov_yy = d.cov_yy;
    e.heading_std_rad = d.heading_std;
    e.scale = d.scale;
    e.yaw_offset_rad = wrap_angle(d.yaw_offset);
    e.dominant_weight = std::clamp(d.weight, 0.0, 1.0);
    e.position_std_m = std_m;
    e.confidence = e.dominant_weight / (1.0 + std_m * std_m);
    e.hypothesis_count = hyps;
    // Ambiguity: the heaviest rival that the recent evidence has not refuted; and for the lock, the rival
    // (heavy enough to matter) whose evidence comes closest to the dominant's.
    twin_.observe_dominant(d.floor, d.x, d.y, d.yaw_offset, std_m);
    HysteresisInput hin;
    hin.t = t_last_;
    if (dominant_members_valid_) {
        hin.twin_log_ratio = twin_.log_ratio(p_, map_, dominant_members_.data(), dominant_members_.size());
    }
    hin.dominant_weight = e.dominant_weight;
    hin.std_m = std_m;
    hin.x = d.x;
    hin.y = d.y;
    hin.floor = d.floor;
    // A rival the guard counts (rival_unrefuted). A thin one also needs most of its weight on particles that have
    // explained a sighting (fresh injections carry the worst evidence present, not evidence of their own): the
    // clusters' sighted weights take one pass over the particles, made for the first thin rival that asks.
    bool sighted_ready = false;
    const auto counted_rival = [&](size_t k) {
        const ClusterSummary &r = clusters[k];
        return rival_unrefuted(hp, r.weight, d.evidence - r.evidence, [&] {
            if (sign_model_.range_bias_sigma <= 0) return 0.0;  // no sighting statistics: no particle is sighted
            if (!sighted_ready) {
                sighted_weight_per_cluster(p_, clusterer_.particle_clusters(), clusters.size(), cluster_sighted_weight_);
                sighted_ready = true;
            }
            return cluster_sighted_weight_[k];
        });
    };
    for (size_t k = 0; k < clusters.size(); ++k) {
        if (k == dom) continue;
        const ClusterSummary &r = clusters[k];
        if (r.weight < lightest_rival) break;  // sorted by weight
        // The dominant's own twin is judged by the twin ratio (the whole history, pf/twin_guard), not by the
        // recent evidence that fades: a twin the guard keeps alive is refuted when the ratio says so.
        if (twin_.is_twin_of_dominant(map_, r.floor, r.x, r.y, r.yaw_offset)) continue;
        if (counted_rival(k)) {
            hin.unrefuted_rival_weight = std::max(hin.unrefuted_rival_weight, r.weight);
        }
        if (r.weight >= hp.lock_rival_weight) {
            hin.strongest_rival_evidence_margin = std::max(hin.strongest_rival_evidence_margin, r.evidence - d.evidence);
        }
    }
    if (awaiting_corroboration_ && !corroboration_candidates_drawn_) {
        hin.unrefuted_rival_weight = std::max(hin.unrefuted_rival_weight, 1.0);
    }
    // While localized, the locked pose is the dominant cluster's core (pf/cluster_core): the flag's spread and
    // weight tests and the reported pose read it, so particles injected along the same corridor neither move
    // the estimate nor break the lock.
    pose_from_sighted_core_ = false;
    pose_core_valid_ = false;
    if (hysteresis_.localized() && dominant_members_valid_) {
        const ClusterCore core = cluster_core(p_, dominant_members_, hp.lock_core_radius_m, core_scratch_);
        ClusterCore pose = core;
        if (core.weight > 0) {
            hin.core_weight = core.weight;
            // The lock's sighted figures: its core among the particles whose history explains a sighting, and the
            // sighted weight held elsewhere. Needed only when the whole core's spread or weight would break the
            // lock (the rule only relaxes those tests); read when most of the core is sighted (with the range-bias
            // statistics off no particle records a sighting, and the rule is off).
            const double core_std_m = core.position_std_m();
            const bool core_would_break = core.weight < hp.unlocalize_weight || core_std_m > hp.unlocalize_std_m;
            if (hp.discount_unsighted && sign_model_.range_bias_sigma > 0 && core_would_break) {
                const double sighted_total = sighted_members(p_, dominant_members_, sighted_members_);
                const ClusterCore sighted = cluster_core(p_, sighted_members_, hp.lock_core_radius_m, core_scratch_);
                if (sighted.weight > 0.5 * core.weight) {
                    hin.sighted_core_weight = sighted.weight;
                    hin.sighted_core_std_m = sighted.position_std_m();
                    hin.contested_weight = std::max(0.0, sighted_total - sighted.weight);
                    // The lock stands on the sighted core: the pose is its, not the whole core's, which unsighted
                    // particles spread along the corridor pull off the locked pose (a relocalizing spell on a
                    // SKERI tour: 3.3 m, docs/benchmarks.md "Twenty-ninth stop").
                    pose = sighted;
                    pose_from_sighted_core_ = true;
                }
            }
            hin.core_std_m = core_std_m;
            pose_core_valid_ = true;
            pose_core_x_ = pose.centre_x;
            pose_core_y_ = pose.centre_y;
            hin.x = pose.x;
            hin.y = pose.y;
            set_pose_from_core(e, pose);
        }
    }
    hin.unexplained_sighting_nats = unexplained_sighting_nats(t_last_);
    e.unexplained_sighting_nats = hin.unexplained_sighting_nats;
    if (hysteresis_.params().explain_sightings && hin.unexplained_sighting_nats >= hysteresis_.params().rival_refute_nats) {
        sightings_unexplained_ = true;
    }
    e.sightings_unexplained = sightings_unexplained_ ? 1 : 0;
    hin.tracking_lost_s = tracker_.lost_since() >= 0 ? t_last_ - tracker_.lost_since() : 0;
    hin.tracking_limited_s = tracker_.tracking_limited_s();
    const bool localized = hysteresis_.update(hin);
    // A new lock is corroborated. A lock that sightings break (within a second of one) must be earned again
    // against fresh rivals: the cloud that was wrong may have no particle left where the traveler is. (A
    // tracking loss arms the rule in predict(); a lock held through it stays armed until the rivals drawn at the
    // next sighting have been refuted or have won. A lock lost to the redraw after a floor ride is only unsure.)
    if (localized && !was_localized_) {
        arm_corroboration(false);
    } else if (!localized && was_localized_ && t_last_ - last_sighting_t_ <= 1.0) {
        arm_corroboration(opts_.start_point_doubt_share > 0);
    }
    was_localized_ = localized;
    hypotheses_.clear();
    // Hypotheses: the clusters holding >= 1 % of the weight, and every lighter one that keeps the flag off (an
    // unrefuted rival): guidance while unsure must be safe under each live hypothesis, however light.
    // The dominant hypothesis first, then the others by weight.
    for (size_t k = 0; k < clusters.size(); ++k) {
        const size_t ck = k == 0 ? dom : (k <= dom ? k - 1 : k);
        const ClusterSummary &c = clusters[ck];
        if (hypotheses_.size() >= 16 || c.weight < lightest_rival) break;
        const bool live_rival = &c != &d &&
                                (twin_.is_twin_of_dominant(map_, c.floor, c.x, c.y, c.yaw_offset)
                                     ? c.weight >= opts_.rival_min_weight && hin.twin_log_ratio < opts_.rival_refute_nats
                                     : counted_rival(ck));
        if (c.weight < 0.01 && !live_rival) continue;
        Eigen::Matrix2d cc;
        cc << c.cov_xx, c.cov_xy, c.cov_xy, c.cov_yy;
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> ce(cc, Eigen::EigenvaluesOnly);
        wf_localizer_hypothesis h{};
        h.weight = c.weight;
        h.floor_index = c.floor;
        h.x = c.x;
        h.y = c.y;
        h.heading_rad = wrap_angle(c.heading);
        h.position_std_m = std::sqrt(std::max(0.0, ce.eigenvalues().maxCoeff()));
        h.evidence_nats = c.evidence - d.evidence;
        h.heading_std_rad = c.heading_std;
        hypotheses_.push_back(h);
    }
    // The locked hypothesis is reported where the estimate is: at its core.
    if (hin.core_weight >= 0 && d.weight >= 0.01) place_front_hypothesis(e);
    e.localized = localized ? 1 : 0;
    // Never hand out NaN: fall back to zeros (cannot happen with finite particles; kept as a guard).
    const double fields[] = {e.x, e.y, e.heading_rad, e.cov_xx, e.cov_xy, e.cov_yy, e.heading_std_rad, e.confidence};
    for (double v : fields) {
        if (!std::isfinite(v)) {
            e.localized = 0;
            hysteresis_.drop();
            e.x = e.y = e.heading_rad = e.cov_xy = e.confidence = 0;
            e.cov_xx = e.cov_yy = 1e6;
            e.heading_std_rad = kPiD;
            break;
        }
    }
    estimate_ = e;
}

const wf_localizer_estimate &ParticleFilter::estimate() {
    if (estimate_dirty_) {
        // Clustering 100k particles costs more than the motion update; between two clusterings (at most
        // kFullEstimateIntervalS apart, and after every resampling, init or floor change) the estimate follows
        // the dominant cluster's own particles, which only moved and were reweighted since.
        const bool full_due = !dominant_members_valid_ || !(t_last_ - full_estimate_t_ < kFullEstimateIntervalS);
        if (full_due) {
            compute_estimate();
        } else {
            follow_dominant_cluster();
        }
    }
    estimate_.particle_count = static_cast<int32_t>(p_.size());
    return estimate_;
}

}  // namespace wf::loc
