// Measurement model for sign sightings (kind, range, bearing), the absolute fix of the method (Fusco &
// Coughlan 2020 section 2). For one particle and one sighting of kind k the likelihood is a mixture
// (multi-hypothesis data association, Probabilistic Robotics section 7.5 in spirit, with the clutter term of
// the beam model, section 6.3):
//
//   L = p_clutter * u  +  (1 - p_clutter) * (1 / n_vis) * sum_{j visible, kind k} N(r; r_j, s_r(r_j)) N(b; b_j, s_b)
//
// where the visible signs j are those whose visibility bit is set in the particle's cell (range, facing and
// walls, precomputed) and whose predicted bearing b_j lies inside the horizontal field of view;
// s_r(r) = range_sigma_base_m + range_sigma_per_meter * r; u = 1 / (max_range * fov) is the density of a
// false positive spread uniformly over the sensor's range x bearing space; p_clutter grows as the detector
// score drops. Sightings of one frame are independent (product of likelihoods).
// Negative information (optional): each sign predicted plainly visible (close but not overhead, near the image
// centre) that no sighting of its kind matches within 3 sigma multiplies the weight by negative_info_miss_weight.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "map/localizer_map.hpp"
#include "pf/particle_set.hpp"
#include "wf_localizer.h"

namespace wf::loc {

struct SignModelParams {
    float half_fov_rad = 0.41887902f;
    float max_range_m = 12;
    float range_sigma_base_m = 0.1f;
    float range_sigma_per_meter = 0.12f;
    float bearing_sigma_rad = 0.05235988f;
    float clutter_probability = 0.1f;
    bool negative_information = true;
    float negative_info_max_range_m = 5;
    /// A sign nearer than this is not "plainly visible", meters: Exit signs hang about 1-1.3 m above a
    /// camera held at chest height, so under about 2.5 m the face leaves the top of a portrait frame (vertical
    /// half field of view about 0.54 rad) unless the camera pitches up, and a face the frame cuts is not
    /// ranged (SignDetector's frameEdgeMarginPx). Internal parameter `sign.negative_info_min_range_m`.
    float negative_info_min_range_m = 2.5f;
    float negative_info_fov_fraction = 0.6f;
    float negative_info_miss_weight = 0.8f;

    static SignModelParams from_options(const wf_localizer_options &o);
};

/// A sighting prepared for the model: kind id known to the map, finite range/bearing, effective clutter
/// probability (1 - (1 - p_clutter) * score).
struct PreparedSighting {
    int32_t kind;
    float range_m;
    float bearing_rad;
    float clutter_probability;
};

/// Converts raw observations: skips non-finite ones (counted in *non_finite) and kinds outside the map
/// (they carry no information about the pose: every particle would explain them as clutter).
std::vector<PreparedSighting> prepare_sightings(const wf_sign_observation *obs, size_t count, const SignModelParams &m,
                                                int32_t kind_count, size_t *non_finite);

/// Log-likelihood of the frame's sightings for every particle (heading = vio_yaw + yaw_offset), written to
/// `log_likelihood` (size p.size()). Returns the maximum. With no sighting and negative information off,
/// every value is 0.
float sign_log_likelihood(const ParticleSet &p, float vio_yaw_rad, const LocalizerMap &map, const SignModelParams &m,
                          const PreparedSighting *sightings, size_t count, float *log_likelihood);

}  // namespace wf::loc
