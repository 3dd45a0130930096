// Barometric floor changes (Core Motion relative altitude): a settled altitude step of more than a storey
// means the traveler rode an elevator or took the stairs. Two parts:
//  - BarometricFloorDetector turns the altitude stream into floor-change events: the altitude must stay
//    within `settle_tolerance_m` for `settle_s` (the ride is over) and differ from the last settled altitude by
//    more than `storey_threshold_m`; slow barometric drift below the tolerance is absorbed.
//  - apply_floor_change moves the particles: each floor's destination is the floor whose elevation matches
//    elevation + change (within half the change, at least 1 m). Particles within `link_radius_m` of a vertical
//    link (elevator, stairs) change floor beside the same link on the destination floor: where the two floors'
//    plans draw it at different map coordinates (the destination's link nearest to it, if within
//    `shaft_offset_max_m`), the particle moves by that offset, because the traveler did not move while riding
//    (VIO sees no horizontal motion in an elevator cabin) but the floors' map frames differ. The others cannot
//    explain the change and are re-drawn next to a vertical link of their destination floor (a share
//    `far_from_link_weight` of their weight kept), so that the new floor is searched from where a traveler
//    arriving by elevator or stairs must be, instead of by slow recovery injection.
#pragma once

#include <cstdint>
#include <functional>

#include "common/rng.hpp"
#include "map/localizer_map.hpp"
#include "pf/particle_set.hpp"

namespace wf::loc {

/// Thresholds of the detector (wf_localizer_options storey_threshold_m, altitude_settle_*).
struct BarometricFloorParams {
    double storey_threshold_m = 2.0, settle_tolerance_m = 0.3, settle_s = 1.5;
    /// Particles this close to a link change floor in place, meters; weight factor of the others.
    double link_radius_m = 3.0, far_from_link_weight = 0.05;
    /// The same link drawn on two floors' plans lies at most this far apart, meters: a particle that rides moves
    /// by the offset between its floor's nearest link and the destination's link nearest to that one, when they
    /// are this close. A staircase whose landings are farther apart is walked, and VIO measures that walk.
    double shaft_offset_max_m = 2.0;
};

/// Offset (meters, map frame) from floor `f`'s link point `link` (an index into its link points) to the same
/// link on floor `g` (g's link nearest to it); zero when g has no link or the two lie farther apart than
/// `max_offset_m`.
void link_offset(const LocalizerMap &map, int16_t f, int32_t link, int16_t g, float max_offset_m, float &dx,
                 float &dy);

/// Settled-altitude state machine. Value type.
class BarometricFloorDetector {
public:
    explicit BarometricFloorDetector(const BarometricFloorParams &p = {}) : p_(p) {}
    /// Feeds one relative altitude (m, finite) at time t (s). Returns the altitude change of a completed floor
    /// change (m, signed: positive = up), or 0 when there is none.
    double push(double relative_altitude_m, double t);

private:
    BarometricFloorParams p_;
    bool has_altitude_ = false;
    double settled_altitude_ = 0, stable_ref_altitude_ = 0, stable_since_t_ = 0;
};

/// Destination floor of every floor for an altitude change `delta_m` (-1 when no floor matches).
std::vector<int16_t> floor_change_destinations(const LocalizerMap &map, double delta_m);

/// Applies a floor change of `delta_m` to `p` (see the file comment). `sample_yaw_offset` draws a fresh yaw
/// offset (the filter's, so a compass prior shapes it). Returns the sum of the weights (not normalised).
double apply_floor_change(ParticleSet &p, const LocalizerMap &map, double delta_m, const BarometricFloorParams &params,
                          Rng &rng, const std::function<float()> &sample_yaw_offset);

}  // namespace wf::loc
