/*
 * wf_localizer.h - C ABI of the Wayfinder particle-filter localizer (LocalizerCore).
 *
 * The filter fuses ARKit visual-inertial odometry (VIO) with sign sightings (kind, range, bearing) on a 2D
 * floor-plan map with walls, as in Fusco & Coughlan (ICCHP 2018, W4A 2020); see docs/localizer.md.
 *
 * Conventions (docs/HELPERS.md, App/SessionFormat/CameraPose.swift):
 *  - map frame: x east, y north, meters; angles radians, counter-clockwise from +x;
 *  - VIO plane: (east, north) = (x_w, -z_w) of the ARKit world; VIO yaw CCW from VIO east;
 *  - particle heading in the map = VIO yaw + particle yaw offset;
 *    map displacement = scale * Rot(yaw offset) * (dEast, dNorth);
 *  - sign bearing: horizontal angle from camera forward, positive to the LEFT (CCW); range: horizontal m.
 *
 * ABI rules (libgit2 / sqlite style):
 *  - every function returns int: WF_LOC_OK (0) on success, a negative wf_localizer_status on failure;
 *  - outputs come first; handles are opaque; wf_localizer_free(NULL) is a no-op;
 *  - no C++ exception crosses this boundary; the last error message is kept per handle
 *    (wf_localizer_last_error);
 *  - OWNERSHIP: the caller owns every struct and array it passes in; wf_localizer_create copies the map,
 *    so the map arrays may be freed as soon as create returns. The handle owns everything it allocates
 *    and releases it in wf_localizer_free. Output structs/arrays are caller-allocated and filled in.
 *  - a handle is not thread-safe: call it from one thread at a time.
 */
#ifndef WF_LOCALIZER_H
#define WF_LOCALIZER_H

#include <stddef.h>
#include <stdint.h>

#include "wf_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Status codes: the shared vocabulary of wf_status.h (the same numbers as WF_STATUS_*, which every C ABI of
 *  the project returns). The WF_LOC_ names are this header's spelling of those codes, kept so that the filter's
 *  sources and bindings read as before; new code may use either. 0 is success; every error is negative. */
typedef enum wf_localizer_status {
    WF_LOC_OK = WF_STATUS_OK,
    /** A NULL pointer, a count out of range, or an option outside its documented range. */
    WF_LOC_ERR_INVALID_ARGUMENT = WF_STATUS_INVALID_ARGUMENT,
    /** Allocation failed. */
    WF_LOC_ERR_OUT_OF_MEMORY = WF_STATUS_OUT_OF_MEMORY,
    /** The options or map struct carries a version this library does not know. */
    WF_LOC_ERR_VERSION = WF_STATUS_VERSION,
    /** The map is unusable (no floors, non-finite coordinates, a floor index out of range). */
    WF_LOC_ERR_INVALID_MAP = WF_STATUS_INVALID_MAP,
    /** The requested floor has no walkable cell (zero-area floor, seeds outside the walls) or the start
     *  point is not inside the map. */
    WF_LOC_ERR_NO_WALKABLE_SPACE = WF_STATUS_NO_WALKABLE_SPACE,
    /** The filter has not been initialised yet (call an init function first). */
    WF_LOC_ERR_NOT_INITIALIZED = WF_STATUS_NOT_INITIALIZED,
    /** An input carried NaN or infinity; it was ignored and the filter state is unchanged. */
    WF_LOC_ERR_NON_FINITE_INPUT = WF_STATUS_NON_FINITE_INPUT,
    /** An unexpected internal failure (a bug); the message says what. */
    WF_LOC_ERR_INTERNAL = WF_STATUS_INTERNAL
} wf_localizer_status;

/** Opaque filter handle. */
typedef struct wf_localizer wf_localizer;

/** VIO tracking state (ARKit ARCamera.TrackingState). */
typedef enum wf_vio_tracking {
    WF_VIO_TRACKING_NORMAL = 0,
    WF_VIO_TRACKING_LIMITED = 1,
    WF_VIO_TRACKING_NOT_AVAILABLE = 2
} wf_vio_tracking;

/** A sign on a floor. */
typedef struct wf_localizer_sign {
    /** Sign kind as a small id, 0 <= kind < wf_localizer_map.kind_count (e.g. 0 = "exit"). */
    int32_t kind;
    /** Centre of the sign face projected on the plan, meters, map frame. */
    float x, y;
    /** Unit normal of the face pointing to where it can be read from (normalised by create). */
    float facing_x, facing_y;
    /** Nonzero when readable from both sides (facing is then ignored). */
    int32_t double_sided;
    /** Farthest horizontal range at which this sign is recognised, meters; 0 = options.max_sign_range_m.
     *  Each kind has its own (docs/map-format.md "signKinds": a room-number placard is read from 2.5 m, an
     *  Exit sign found from 12 m); the smaller of the two is used. A zero-initialised sign keeps the options'. */
    float max_range_m;
    /** Largest angle between the face normal and the line of sight at which it is recognised, radians; 0 =
     *  options.max_view_angle_from_normal_rad; the smaller of the two is used (text is read only facing it). */
    float max_view_angle_rad;
} wf_localizer_sign;

/** One floor of the map. Every array may be NULL when its count is 0. */
typedef struct wf_localizer_floor {
    /** Floor elevation above the building reference, meters (for barometric floor changes). */
    double elevation_m;
    /** Wall segments: 4 floats each (ax, ay, bx, by), meters, map frame. */
    const float *walls;
    size_t wall_count;
    /** Signs on this floor. */
    const wf_localizer_sign *signs;
    size_t sign_count;
    /** Vertical-link points (elevator / stairs graph nodes): 2 floats each (x, y), meters. */
    const float *link_points;
    size_t link_point_count;
    /** Seeds for the walkable flood fill (navigation-graph node positions of this floor): 2 floats each.
     *  With no seed, every cell of the floor's bounding box away from walls counts as walkable. */
    const float *seed_points;
    size_t seed_point_count;
} wf_localizer_floor;

#define WF_LOCALIZER_MAP_VERSION 1

/** The whole map. Floor index = position in `floors`. */
typedef struct wf_localizer_map {
    /** WF_LOCALIZER_MAP_VERSION. */
    unsigned int version;
    const wf_localizer_floor *floors;
    size_t floor_count;
    /** Number of sign kinds; sign and observation kinds are ids in [0, kind_count). */
    int32_t kind_count;
} wf_localizer_map;

#define WF_LOCALIZER_OPTIONS_VERSION 2

/**
 * Filter options. Fill with wf_localizer_options_init() or WF_LOCALIZER_OPTIONS_INIT (same defaults), then
 * change fields. Units are in the names; textbook aliases (Probabilistic Robotics, Thrun, Burgard, Fox 2005
 * = "PR") in the comments. docs/localizer.md explains each default.
 */
typedef struct wf_localizer_options {
    /** WF_LOCALIZER_OPTIONS_VERSION. */
    unsigned int version;

    /* --- particle count --- */
    /** Particles after an init (and the fixed count when adaptive_particle_count is 0). Default 20000. */
    int32_t particle_count;
    /** KLD-sampling bounds (Fox 2003). Defaults 2000 and 100000. */
    int32_t min_particles;
    int32_t max_particles;
    /** Nonzero: KLD-sampling picks the count at each resampling. Default 1. */
    int32_t adaptive_particle_count;
    /** KLD bound epsilon (Fox 2003 "epsilon"), default 0.05; upper 1-delta quantile z, default 2.326 (delta 0.01). */
    double kld_epsilon;
    double kld_z;
    /** KLD histogram bin size: meters in x and y, radians in heading. Defaults 0.5 m, 10 deg. */
    double kld_bin_m;
    double kld_bin_yaw_rad;

    /* --- resampling and recovery --- */
    /** Resample (systematic, PR Table 4.4) when ESS < this fraction of N. Default 0.5. */
    double resample_ess_fraction;
    /** Hypothesis-preserving resampling (the mixture particle filter of Vermaak, Doucet & Perez 2003, with
     *  clusters as mixture components): resampling happens within each cluster holding >= 1 % of the
     *  weight, the cluster keeps its total weight exactly, and this fraction of the particles is shared
     *  equally among clusters (the rest in proportion to weight). A light hypothesis thus keeps enough
     *  particles to be tracked as well as a heavy one, instead of fading by resampling noise ("rich get
     *  richer") while it is still as likely. 0 = plain systematic resampling. Default 0.5. */
    double hypothesis_particle_share;
    /** Nonzero: augmented MCL random-particle injection (PR Table 8.3). Default 1. */
    int32_t recovery;
    /** PR Table 8.3 alpha_slow, alpha_fast. Defaults 0.001 and 0.1. */
    double recovery_alpha_slow;
    double recovery_alpha_fast;
    /** Cap on the fraction of particles injected at one resampling. Default 0.1. */
    double recovery_max_fraction;

    /* --- motion model (VIO deltas) ---
     * Noise is a random walk: its VARIANCE grows linearly with the distance walked and the angle turned
     * (std = k * sqrt(distance) per frame), so the spread after a walk does not depend on the frame rate. */
    /** Position std per sqrt(meter walked), m/sqrt(m) (isotropic). Default 0.15 (15 cm after 1 m, 47 cm after
     *  10 m): wider than VIO drift alone, it keeps each hypothesis diverse enough to be weighed fairly. */
    double position_noise_per_sqrt_meter;
    /** Position std per sqrt(radian turned), m/sqrt(rad). Default 0.03. */
    double position_noise_per_sqrt_rad;
    /** Yaw-offset std per sqrt(meter walked), rad/sqrt(m) (VIO heading drift). Default 0.02. */
    double yaw_noise_per_sqrt_meter;
    /** Yaw-offset std per sqrt(radian of VIO turn), rad/sqrt(rad). Default 0.04. */
    double yaw_noise_per_sqrt_rad;
    /** Scale-factor std per sqrt(meter walked), 1/sqrt(m). Default 0.003. */
    double scale_noise_per_sqrt_meter;
    /** Std of the initial scale factor around 1. Default 0.03. Scale is clamped to [scale_min, scale_max]. */
    double initial_scale_sigma;
    double scale_min;
    double scale_max;
    /** Noise multiplier while tracking is limited. Default 3. */
    double limited_tracking_noise_factor;
    /** A delta longer than this (m) plus 2 m/s times the frame interval, or turning more than jump_yaw_rad plus
     *  3 rad/s times the interval, is a VIO relocalization / origin reset: skipped, and noise inflated.
     *  Defaults 0.5 m (0.57 m at 30 Hz: no camera on a walking person moves that far in one frame; ARKit's
     *  relocalization snaps are 0.2-1.5 m), 45 deg. */
    double jump_distance_m;
    double jump_yaw_rad;
    /** Noise added after a skipped jump: position std (m) and yaw-offset std (rad). Defaults 0.5 m, 0.2 rad. */
    double jump_position_sigma_m;
    double jump_yaw_sigma_rad;
    /** Assumed walking speed while tracking was unavailable, m/s (inflates position noise). Default 0.7. */
    double lost_tracking_speed_mps;
    /** Weight factor of a particle whose move crosses a wall. Default 1e-3. */
    double wall_crossing_weight;

    /* --- sign measurement model --- */
    /** Horizontal field of view, radians. Default 48 deg (portrait iPhone). */
    double horizontal_fov_rad;
    /** Signs farther than this are never predicted visible, meters. Default 12. */
    double max_sign_range_m;
    /** Range std = range_sigma_base_m + range_sigma_per_meter * range. Defaults 0.1 m and 0.12 (median
     *  |error| 0.6745 sigma ~ 8 % of range, paper Table 1). */
    double range_sigma_base_m;
    double range_sigma_per_meter;
    /** Bearing std, radians. Default 3 deg. */
    double bearing_sigma_rad;
    /** Probability that a sighting is clutter / a false positive (PR z_rand). Default 0.1. */
    double clutter_probability;
    /** Likelihood tempering (annealing, Deutscher et al. 2000; adaptive exponent as in SMC samplers): each
     *  sign update multiplies the weights by L^beta with the largest beta <= 1 that keeps the effective
     *  sample size >= this fraction of N (0 disables). It stops a sparse cloud from collapsing on the few
     *  particles that happen to sit in a sharp likelihood peak, which would decide between mirror-image
     *  hypotheses by chance. Default 0.2. */
    double tempering_min_ess_fraction;
    /** Nonzero: plainly visible signs that were not detected lower the weight. Default 1. */
    int32_t negative_information;
    /** "Plainly visible": closer than this (m) and within this fraction of the half FOV. Defaults 5 m, 0.6. */
    double negative_info_max_range_m;
    double negative_info_fov_fraction;
    /** Weight factor per plainly visible but undetected sign per frame (= miss probability). Default 0.8. */
    double negative_info_miss_weight;

    /* --- map grids --- */
    /** Cell of the visibility and walkable grids, meters. Default 0.25. Enlarged automatically for huge floors. */
    double grid_cell_m;
    /** Cell of the wall spatial index, meters. Default 0.5 (most particles then sit in wall-free cells). */
    double wall_index_cell_m;
    /** Walkable cells keep this clearance from walls, meters. Default 0.2. */
    double wall_clearance_m;

    /* --- estimate --- */
    /** Clustering cell: meters in x,y and radians in heading. Defaults 1 m and 45 deg. */
    double cluster_cell_m;
    double cluster_yaw_bin_rad;
    /** A cluster counts as a hypothesis above this weight. Default 0.05. */
    double hypothesis_min_weight;
    /** Becomes localized when dominant weight > localize_weight and position std < localize_std_m for
     *  localize_hold_s. Defaults 0.8, 1 m, 1 s. */
    double localize_weight;
    double localize_std_m;
    double localize_hold_s;
    /** Stops being localized when dominant weight < unlocalize_weight or std > unlocalize_std_m.
     *  Defaults 0.5 and 2 m. */
    double unlocalize_weight;
    double unlocalize_std_m;
    /** Ambiguity guard. A rival cluster holding >= rival_min_weight blocks localization unless the evidence
     *  has refuted it: its recent sign log-likelihood (exponentially forgotten with time constant
     *  evidence_time_constant_s) is at least rival_refute_nats below the dominant cluster's. In a
     *  symmetric building the mirror hypothesis explains every sighting as well as the true one, so it is
     *  never refuted, however its weight drifts (particle-filter Monte Carlo noise). A localized filter
     *  drops the flag when an unrefuted rival reaches 0.2. Defaults 0.001, 4 nats, 5 s. Lighter rivals, down to
     *  the internal parameter "lock.thin_rival_weight" (1e-4), also block it while their evidence is less than
     *  "lock.thin_rival_refute_nats" (3) below the dominant's (wf_localizer_set_parameter). */
    double rival_min_weight;
    double rival_refute_nats;
    double evidence_time_constant_s;

    /* --- floors --- */
    /** Relative-altitude change from the last settled altitude that means a floor change, m. Default 2. */
    double storey_threshold_m;
    /** Altitude is settled after staying within altitude_settle_tolerance_m for altitude_settle_s.
     *  Defaults 0.3 m, 1.5 s. */
    double altitude_settle_tolerance_m;
    double altitude_settle_s;
    /** Particles within this distance of a vertical link change floor, meters. Default 3. */
    double link_radius_m;
    /** Weight factor of particles that cannot explain a floor change (far from links). Default 0.05. */
    double far_from_link_weight;

    /* --- added in options version 2 --- */
    /** A sign is predicted visible only from where the line to the camera is at most this far from its face
     *  normal, radians (either face of a double-sided sign). Seen more obliquely a face is a sliver no
     *  detector finds (cos 80 deg = 0.17 of its width); predicting it visible would dilute the association of
     *  real sightings and feed negative information with misses that were never possible. Default 80 deg,
     *  looser than detectors manage (about 75 deg, the simulator's limit); pi/2 = any point in front. */
    double max_view_angle_from_normal_rad;
    /** Share of the particles that wf_localizer_init_start_point spreads uniformly over the floor instead of the
     *  disc: the traveler may have named the wrong start. Those hypotheses keep the `localized` flag off
     *  (ambiguity guard) until the signs agree with the named start, and carry the recovery when they do not.
     *  Default 0.05 (sparse enough, a few particles per clustering bin, not to join the start's cluster);
     *  0 = trust the start completely. */
    double start_point_doubt_share;
} wf_localizer_options;

/** Same defaults as wf_localizer_options_init(); a test checks they agree. */
#define WF_LOCALIZER_OPTIONS_INIT { WF_LOCALIZER_OPTIONS_VERSION, \
    20000, 2000, 100000, 1, 0.05, 2.326, 0.5, 0.17453292519943295, \
    0.5, 0.5, 1, 0.001, 0.1, 0.1, \
    0.15, 0.03, 0.02, 0.04, 0.003, 0.03, 0.8, 1.25, 3.0, 0.5, 0.7853981633974483, 0.5, 0.2, 0.7, 1e-3, \
    0.8377580409572781, 12.0, 0.1, 0.12, 0.05235987755982988, 0.1, 0.2, 1, 5.0, 0.6, 0.8, \
    0.25, 0.5, 0.2, \
    1.0, 0.7853981633974483, 0.05, 0.8, 1.0, 1.0, 0.5, 2.0, 0.001, 4.0, 5.0, \
    2.0, 0.3, 1.5, 3.0, 0.05, \
    1.3962634015954636, 0.05 }

/** One VIO sample (one ARKit frame). */
typedef struct wf_vio_sample {
    /** Timestamp, seconds (monotonic). */
    double t;
    /** Camera position on the VIO plane, meters. */
    double east_m, north_m;
    /** Camera forward yaw on the VIO plane, radians CCW from VIO east. */
    double yaw_rad;
    /** A wf_vio_tracking value. */
    int32_t tracking;
} wf_vio_sample;

/** One sign sighting in the current frame. */
typedef struct wf_sign_observation {
    /** Sign kind id; ids the map does not have are treated as clutter. */
    int32_t kind;
    /** Horizontal range, meters (> 0). */
    double range_m;
    /** Horizontal bearing from camera forward, radians, positive to the LEFT. */
    double bearing_rad;
    /** Detector score in [0, 1]; scales the sighting's trust (clutter probability grows as score drops). */
    double score;
    /** The object this sighting sees, as the caller tracks it from frame to frame (the same poster or sign seen
     * again at one place of the VIO plane carries the same id); 0 = not tracked. Sightings of one tracked object
     * are not independent evidence of a sign: the filter bounds what one object can say against a pose that
     * has no sign there (a look-alike that stays put) while keeping each sighting's geometry for the poses that
     * do (docs/localizer.md "Tracked objects"). Zero-initialised callers keep the per-frame model. */
    uint32_t track_id;
    /** Where the tracked object's earlier sightings put it, seen from this frame's camera: horizontal range
     * (meters, > 0) and bearing (radians, positive to the left), e.g. the mean of their positions on the VIO plane.
     * It is where a look-alike would be seen again. A range <= 0 or a non-finite value: unknown. */
    double track_range_m, track_bearing_rad;
} wf_sign_observation;

/** One vertical plane reported by ARKit plane detection (an ARPlaneAnchor with alignment vertical), projected
 *  on the VIO floor plane; in the same VIO frame as the wf_vio_sample poses. */
typedef struct wf_plane_observation {
    /** Stable id of the anchor (e.g. a hash of its UUID): the filter applies each anchor at most once per
     *  short interval (about 1 s), however often it is reported. */
    uint64_t anchor_id;
    /** Plane center on the VIO plane, meters: (east, north) = (x_w, -z_w) of the ARKit world. */
    double center_east_m, center_north_m;
    /** Direction of the plane's normal on the VIO plane, radians CCW from VIO east (either side). */
    double normal_yaw_rad;
    /** Horizontal extent of the plane along the wall, meters. Planes narrower than about 0.3 m (zero extent
     *  included) are ignored. */
    double width_m;
} wf_plane_observation;

/** Pose estimate (from the dominant particle cluster). */
typedef struct wf_localizer_estimate {
    /** Time of the last input, seconds. */
    double t;
    /** Weighted mean position of the dominant cluster, meters, map frame. */
    double x, y;
    /** Floor index of the dominant cluster (-1 before init). */
    int32_t floor_index;
    /** Camera heading in the map (circular mean), radians CCW from +x, in (-pi, pi]. */
    double heading_rad;
    /** Position covariance of the dominant cluster, m^2. */
    double cov_xx, cov_xy, cov_yy;
    /** Circular std of heading in the dominant cluster, radians. */
    double heading_std_rad;
    /** Mean VIO scale factor and yaw offset (map minus VIO yaw, radians) of the dominant cluster. */
    double scale;
    double yaw_offset_rad;
    /** Weight of the dominant cluster, 0..1. */
    double dominant_weight;
    /** sqrt of the largest eigenvalue of the position covariance, meters. */
    double position_std_m;
    /** dominant_weight / (1 + (position_std_m / 1 m)^2), 0..1. */
    double confidence;
    /** Nonzero when localized (hysteresis, see options); the navigator guides only then. */
    int32_t localized;
    /** Clusters holding more than hypothesis_min_weight. */
    int32_t hypothesis_count;
    /** Current particle count. */
    int32_t particle_count;
    /** Sighting frames of the last 4 s (internal parameter lock.explain_window_s) that the dominant cluster
     *  explains only as false positives (the weighted mean of its particles' likelihoods below twice the
     *  clutter-only likelihood): the sum of
     *  -log(false-positive probability) of their sightings, nats; 0 when it explains them all. */
    double unexplained_sighting_nats;
    /** Nonzero from the estimate where unexplained_sighting_nats reaches rival_refute_nats (with the lock rule
     *  that uses it on) until a later sighting frame that the dominant cluster explains: some sign the dominant
     *  hypothesis does not place there was seen, so the traveler may stand where no hypothesis is, and frames
     *  without sightings change nothing about that. The navigator gives no directional instruction while it is
     *  set and the traveler is not localized. */
    int32_t sightings_unexplained;
} wf_localizer_estimate;

/** One pose hypothesis: a cluster of the particle cloud (the estimate is the first, the dominant one). */
typedef struct wf_localizer_hypothesis {
    /** Normalised weight of the cluster, 0..1. */
    double weight;
    /** Floor index. */
    int32_t floor_index;
    /** Weighted mean position, meters, map frame; camera heading (circular mean), radians CCW from +x. */
    double x, y, heading_rad;
    /** sqrt of the largest eigenvalue of the position covariance, meters. */
    double position_std_m;
    /** Recent evidence (sign and compass log-likelihood, exponentially forgotten) relative to the dominant
     *  cluster's, nats (0 for the dominant; negative = explains the recent sightings worse). */
    double evidence_nats;
    /** Circular std of the camera heading, sqrt(-2 ln R) of the weighted resultant R, radians (>= 0; above pi for
     *  headings spread all round). Added at the nineteenth stop: guidance while unsure checks walks within this
     *  spread; 0 in a zero-initialised struct. */
    double heading_std_rad;
} wf_localizer_hypothesis;

/** A rotation that maps a floor's walls onto themselves (docs/localizer.md "Symmetric twins"): on such a floor
 *  every hypothesis has a twin the evidence must refute before the localized flag is set. */
typedef struct wf_localizer_floor_symmetry {
    /** Rotation angle, radians: pi/2, pi or 3 pi/2. */
    double angle_rad;
    /** Fixed point, meters, map frame. */
    double center_x_m, center_y_m;
    /** Share of the floor's wall length the rotation lands on a wall, 0..1. */
    double matched_fraction;
} wf_localizer_floor_symmetry;

/** One particle, for drawing. */
typedef struct wf_localizer_particle {
    float x, y;
    /** Heading in the map, radians. */
    float heading_rad;
    float scale;
    /** Normalised weight (sums to 1 over all particles, not over the copied subset). */
    float weight;
    int32_t floor_index;
} wf_localizer_particle;

/** Fills *opts with the defaults for `version` (must be WF_LOCALIZER_OPTIONS_VERSION). */
int wf_localizer_options_init(wf_localizer_options *opts, unsigned int version);

/**
 * Creates a filter over `map` (copied; see OWNERSHIP) with `opts` (NULL = defaults) and the RNG `seed`.
 * Precomputes the wall index, walkable space and per-sign visibility grids. *out is NULL on failure.
 * The filter starts uninitialised: call wf_localizer_init_floor_only or wf_localizer_init_start_point.
 */
int wf_localizer_create(wf_localizer **out, const wf_localizer_map *map, const wf_localizer_options *opts,
                        uint64_t seed);

/** Frees the filter. NULL is a no-op. */
void wf_localizer_free(wf_localizer *loc);

/** Message of the last failure on this handle ("" if none). Owned by the handle, valid until the next call.
 *  With NULL: why the calling thread's last wf_localizer_create failed (e.g. "floor 0: extent ... is larger
 *  than 100 km"), "" when it succeeded; owned by the library, valid until that thread's next create. */
const char *wf_localizer_last_error(const wf_localizer *loc);

/** Static description of a status code (never NULL, not owned by the caller). */
const char *wf_localizer_status_string(int status);

/** Spreads particle_count particles uniformly over the walkable space of `floor_index`, yaw offset uniform
 *  (or from the compass prior), scale ~ N(1, initial_scale_sigma). */
int wf_localizer_init_floor_only(wf_localizer *loc, int32_t floor_index);

/** Spreads particles uniformly in the disc (x, y, radius_m) on `floor_index` (not across walls from the
 *  centre), yaw offset uniform (or from the compass prior). */
int wf_localizer_init_start_point(wf_localizer *loc, int32_t floor_index, double x, double y, double radius_m);

/** Compass prior: camera heading in the map `heading_in_map_rad` +- `sigma_rad` (Gaussian). Used by the
 *  next init (when a VIO yaw is known) or else applied as a reweighting at the next predict. */
int wf_localizer_set_compass_prior(wf_localizer *loc, double heading_in_map_rad, double sigma_rad);

/** Motion update from one VIO sample (before init it only records the sample). Non-finite samples return
 *  WF_LOC_ERR_NON_FINITE_INPUT and are ignored. A sample less than 1/30 s - 4 ms after the last one used is
 *  merged into the next (the motion noise is calibrated at 30 Hz; docs/localizer.md "Motion model"). */
int wf_localizer_predict(wf_localizer *loc, const wf_vio_sample *sample);

/** The VIO origin was reset (world tracking restarted: ARKit initializing again, ARSession.run with
 *  .resetTracking): the next usable sample starts a new VIO frame. Its delta from the last sample is skipped and
 *  the camera's map heading is kept (each particle's yaw offset absorbs the new frame's yaw), with the jump noise,
 *  as for a relocalization snap; unlike a return from a tracking loss, no particle takes the yaw change as a turn
 *  or the displacement as walked (the old frame is gone). Works before init too. */
int wf_localizer_note_vio_reset(wf_localizer *loc);

/** Measurement update with the `count` sightings of one frame at time t (count 0 = a frame with no
 *  detection: negative information only). Non-finite observations are skipped (status
 *  WF_LOC_ERR_NON_FINITE_INPUT after applying the finite ones). */
int wf_localizer_update_signs(wf_localizer *loc, const wf_sign_observation *observations, size_t count, double t);

/** The same for a frame on which the detector did not look for the kinds `unsearched_kinds` (kind ids,
 *  `unsearched_count` of them; NULL with 0 = every kind searched, exactly wf_localizer_update_signs): signs of those
 *  kinds take no negative information on this frame, since their absence says nothing (SignDetector searches its
 *  wall kinds in turn: wf_detector_kind_searched). A kind that the frame has a sighting of counts as searched. Ids
 *  outside the map's kinds are ignored (status WF_LOC_ERR_INVALID_ARGUMENT after the update); NULL with a count is
 *  WF_LOC_ERR_INVALID_ARGUMENT (nothing applied). */
int wf_localizer_update_signs_searched(wf_localizer *loc, const wf_sign_observation *observations, size_t count,
                                       double t, const int32_t *unsearched_kinds, size_t unsearched_count);

/**
 * Measurement update with the `count` vertical planes currently reported by ARKit at time t (seconds): a
 * likelihood field against the map's walls (the nav2 AMCL likelihood-field model applied to planes; see
 * docs/localizer.md): each plane is sampled as a few points along its width, moved into the map by each
 * particle's pose, yaw offset and scale relative to the camera's last VIO position (the last
 * wf_localizer_predict sample), and scored by the distance to the nearest wall and the angle between the plane
 * and that wall, with a uniform share for planes that are no wall (furniture, open doors). Tempered, and each
 * anchor counts at most once per short interval. Pass the anchors valid in the current VIO session only
 * (drop those from before a tracking reset). Non-finite planes are skipped (status
 * WF_LOC_ERR_NON_FINITE_INPUT after applying the finite ones); narrow or zero-width planes and planes far from
 * the camera are ignored. Before an init: WF_LOC_ERR_NOT_INITIALIZED.
 */
int wf_localizer_update_planes(wf_localizer *loc, const wf_plane_observation *planes, size_t count, double t);

/** Barometric relative altitude (meters, arbitrary origin) at time t: floor changes near vertical links. */
int wf_localizer_update_altitude(wf_localizer *loc, double relative_altitude_m, double t);

/** Compass evidence: the camera heading in the map `heading_in_map_rad` (radians CCW from map +x; from Core
 *  Location's magnetic heading and the map's recorded north) with Core Location's heading accuracy
 *  `accuracy_rad` (0 or negative = unknown; NaN or > pi is rejected) at time t. A robust von Mises + uniform
 *  mixture on each particle's implied heading, applied at most once per "compass.min_distance_m" walked,
 *  capped at "compass.max_nats" per application and "compass.max_total_nats" over a particle's history
 *  (spatially correlated indoor disturbance, docs/compass.md); readings in
 *  between return WF_LOC_OK and change nothing. Give every reading; the filter decides. */
int wf_localizer_update_compass(wf_localizer *loc, double heading_in_map_rad, double accuracy_rad, double t);

/** Sets an internal model parameter by name (tuning knobs that are not part of the options struct, so that
 *  adding one is no ABI change): "compass.enabled" (0/1), "compass.kappa", "compass.outlier_share",
 *  "compass.min_distance_m", "compass.max_nats", "compass.max_total_nats", "lock.rival_weight", "lock.rival_margin_nats",
 *  "lock.jump_m", "lock.explain_sightings" (0/1), "lock.lost_walk_speed_mps", "lock.discount_unsighted" (0/1), "lock.follow_locked" (0/1), "lock.none_while_limited" (0/1), "lock.limited_spell_max_s", "lock.break_hold_s",
 *  "kld.min_particles_unlocalized", "motion.walk_on_share", "motion.walk_on_max_lost_s",
 *  "motion.loss_frame_kept_share", "motion.loss_measured_share", "sign.negative_info_min_range_m"
 *  (docs/localizer.md "Internal parameters by name" lists them all). Unknown names and values out of range: WF_LOC_ERR_INVALID_ARGUMENT with
 *  the known names or the range in wf_localizer_last_error. `name` is NUL-terminated, owned by the caller. */
int wf_localizer_set_parameter(wf_localizer *loc, const char *name, double value);

/** Reads an internal model parameter by name into *value. */
int wf_localizer_get_parameter(wf_localizer *loc, const char *name, double *value);

/** Fills *out with the current estimate (valid fields also before init: particle_count 0, floor -1). */
int wf_localizer_get_estimate(wf_localizer *loc, wf_localizer_estimate *out);

/** Copies up to `capacity` hypotheses of the last estimate (clusters holding >= 1 % of the weight, and every
 *  lighter rival that keeps the localized flag off, down to 0.01 % ("lock.thin_rival_weight"); at most 16) into
 *  `out`: the dominant one the estimate describes first (the heaviest, or while localized the locked one
 *  against a refuted heavier rival; between two clusterings only its weight is refreshed, so it may read a little
 *  lighter than the second), then the others heaviest first; *count receives the number written. Read after
 *  wf_localizer_get_estimate. */
int wf_localizer_get_hypotheses(wf_localizer *loc, wf_localizer_hypothesis *out, size_t capacity, size_t *count);

/** Copies up to `capacity` particles (an even subsample when there are more) into `out`; *count receives
 *  the number written. */
int wf_localizer_get_particles(const wf_localizer *loc, wf_localizer_particle *out, size_t capacity,
                               size_t *count);

/** Copies up to `capacity` symmetries of floor `floor_index` of the map (found when the localizer was created)
 *  into `out`; *count receives the number written (0 for an asymmetric floor). */
int wf_localizer_get_floor_symmetries(const wf_localizer *loc, int32_t floor_index, wf_localizer_floor_symmetry *out,
                                      size_t capacity, size_t *count);

/** Current particle count (0 before init, or on a NULL handle). */
size_t wf_localizer_particle_count(const wf_localizer *loc);

#ifdef __cplusplus
}
#endif

#endif /* WF_LOCALIZER_H */
