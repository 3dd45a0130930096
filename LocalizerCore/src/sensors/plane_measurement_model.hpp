// Measurement model for vertical planes reported by ARKit plane detection (ARPlaneAnchor, alignment
// vertical): a likelihood field against the map's walls, the way nav2 AMCL's likelihood-field model scores a
// laser scan (Thrun, Burgard & Fox, Probabilistic Robotics section 6.4).
//
// A plane is given on the VIO floor plane (center, normal yaw, horizontal width). For each particle it is
// sampled as K points along its width, each moved into the map with the particle's VIO->map transform
// (the camera is at the particle's position; a VIO vector v maps to scale * Rot(yaw_offset) * v). At each
// point the precomputed wall field gives d, the distance to the nearest wall, and the direction of that wall
// (modulo pi). With delta the angle between the plane's direction in the map and that wall's direction:
//
//   p_point = z_hit * exp(-d^2 / (2 sigma_d^2)) * exp(-delta^2 / (2 sigma_a^2)) + z_rand
//   log L_plane = (1/K) * sum_points log p_point        (one plane = one measurement, whatever K)
//
// d saturates at max_distance_m (AMCL's laser_likelihood_max_dist), z_rand is the share of planes that are
// not walls (furniture, open doors, glass) or are badly placed; the frame's log-likelihood is the sum over
// planes times `weight` (< 1: ARKit re-reports the same wall, so successive planes are correlated).
// Each anchor is applied at most once per `min_interval_s` (PlaneGate).
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "map/localizer_map.hpp"
#include "pf/particle_set.hpp"
#include "wf_localizer.h"

namespace wf::loc {

/// Internal parameters of the plane model (not part of the C ABI options, so tuning is not an ABI change).
struct PlaneModelParams {
    /// Std of the distance from a plane point to the nearest map wall, meters (ARKit plane placement error
    /// plus map error plus the particle's own spread).
    float sigma_distance_m = 0.2f;
    /// Std of the angle between the plane and the nearest wall, radians (8 degrees).
    float sigma_angle_rad = 0.14f;
    /// Mixture weights: a plane point near a wall (z_hit) or anywhere (z_rand: furniture, doors, glass).
    float z_hit = 0.7f;
    float z_rand = 0.3f;
    /// The wall field saturates at this distance, meters.
    float max_distance_m = 1.0f;
    /// Planes narrower than this are ignored (ARKit's first estimate of a plane is a small patch), meters.
    float min_width_m = 0.3f;
    /// Planes whose center is farther than this from the camera are ignored (VIO drift between the camera
    /// and an old anchor makes them unreliable), meters.
    float max_range_m = 8.0f;
    /// Sample points along a plane: about one every point_spacing_m, between 2 and max_points.
    float point_spacing_m = 0.75f;
    int32_t max_points = 4;
    /// Exponent on each plane's likelihood (correlation of successive reports of one wall).
    float weight = 0.5f;
    /// An anchor is applied at most once per this interval, seconds.
    double min_interval_s = 1.0;
    /// Cell of the wall field, meters.
    float field_cell_m = 0.1f;
};

/// Distance to the nearest wall and that wall's direction on a uniform grid over one floor (a distance
/// transform computed exactly per segment within max_distance_m of it), packed in 2 bytes per cell:
/// code = distance level << 7 | direction level, with 64 distance levels of max_distance_m / 63 (63 = at
/// least max_distance_m) and 128 direction levels of pi / 128 over [0, pi). The grid extends two cells past
/// the saturation distance on every side, so its border cells are saturated and a point outside the grid can
/// be clamped onto the border.
struct WallField {
    static constexpr int32_t kDistanceLevels = 64;
    static constexpr int32_t kDirectionLevels = 128;
    float x0 = 0, y0 = 0, cell_m = 0.1f, inv_cell = 10;
    int32_t nx = 0, ny = 0;
    float max_distance_m = 1;
    std::vector<uint16_t> code;

    bool empty() const { return code.empty(); }
    /// Distance level of cell c (kDistanceLevels - 1 = saturated) and its value in meters.
    int32_t distance_level(size_t c) const { return code[c] >> 7; }
    float distance_m(size_t c) const {
        return static_cast<float>(distance_level(c)) * max_distance_m / static_cast<float>(kDistanceLevels - 1);
    }
    /// Direction of the nearest wall modulo pi, radians (centre of its level).
    float direction_rad(size_t c) const {
        return (static_cast<float>(code[c] & 127) + 0.5f) * 3.14159265f / static_cast<float>(kDirectionLevels);
    }
};

/// Builds the wall field of a floor from its wall index (segments and bounds).
WallField build_wall_field(const WallIndex &walls, float cell_m, float max_distance_m);

/// A plane prepared for the model: finite, wide enough, within range of the camera.
struct PreparedPlane {
    uint64_t anchor_id;
    /// Center relative to the camera on the VIO plane, meters.
    float rel_east_m, rel_north_m;
    /// Unit tangent (horizontal direction along the plane) on the VIO plane.
    float tangent_east, tangent_north;
    /// Tangent direction, radians CCW from VIO east.
    float tangent_yaw_rad;
    float width_m;
};

/// Counts of what `prepare_planes` skipped.
struct PlanePrepareStats {
    size_t non_finite = 0;
    size_t too_narrow = 0;
    size_t too_far = 0;
    size_t gated = 0;
};

/// Per-anchor time of the last application (at most once per min_interval_s).
class PlaneGate {
public:
    /// True when the anchor may be applied at t (and records t); false when applied less than
    /// `min_interval_s` ago.
    bool admit(uint64_t anchor_id, double t, double min_interval_s);
    void clear() { last_t_.clear(); }

private:
    std::unordered_map<uint64_t, double> last_t_;
};

/// Converts raw observations: skips non-finite ones, planes narrower than min_width_m (zero extent), planes
/// farther than max_range_m from the camera at (cam_east_m, cam_north_m), and anchors the gate refuses
/// (gate may be null: no gating).
std::vector<PreparedPlane> prepare_planes(const wf_plane_observation *obs, size_t count, double cam_east_m,
                                          double cam_north_m, double t, const PlaneModelParams &m, PlaneGate *gate,
                                          PlanePrepareStats *stats);

/// log p_point for every (distance level, direction difference) pair: 64 distance levels times 128
/// differences of pi / 128 between the wall's and the plane's direction levels (folded into [0, pi/2]), so
/// the per-particle loop does no exp or log and indexes the table with the cell code directly:
/// index = (code & ~127) | ((code - plane level) & 127). 32 KiB. Built once per parameter set.
struct PlaneLikelihoodTable {
    std::vector<float> log_p;  // [distance level << 7 | direction difference]
    bool empty() const { return log_p.empty(); }
};

/// Fills the table for `m` (saturation distance max_distance_m).
PlaneLikelihoodTable build_plane_likelihood_table(const PlaneModelParams &m);

/// Adds to `log_likelihood[i]` (size p.size()) each particle's plane log-likelihood (times m.weight), using
/// `fields[floor]` for the particle's floor (an empty field leaves the particle unchanged). Returns the
/// largest resulting value.
float plane_log_likelihood(const ParticleSet &p, const std::vector<WallField> &fields,
                           const PlaneLikelihoodTable &table, const PlaneModelParams &m, const PreparedPlane *planes,
                           size_t count, float *log_likelihood);

/// State of the plane update held by the filter: the wall fields (built on first use) and the gate.
struct PlaneModelState {
    PlaneModelParams params;
    std::vector<WallField> fields;
    PlaneLikelihoodTable table;
    PlaneGate gate;
    std::vector<float> log_likelihood;
    /// Planes applied and skipped by the last update (diagnostics, tests).
    size_t last_applied = 0;
    PlanePrepareStats last_stats;
    /// Builds the fields for every floor of `map` and the likelihood table when not built yet.
    void ensure_fields(const LocalizerMap &map);
};

}  // namespace wf::loc
