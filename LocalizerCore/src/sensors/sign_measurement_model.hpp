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
// Range bias (Rao-Blackwellised static parameter; Storvik 2002, Carvalho et al. 2010 "particle learning"): a
// detector reads every range off by a common factor exp(b) (the cascade's box reads faces tall, a U-Net's mask
// reads them short or long, by up to 25 % on real photos), and a hypothesis that the walls also fit can match
// the biased ranges better than the truth, which then pays on every sighting (docs/benchmarks.md, sixth and
// seventh stops). b is unknown but the same for every sighting, so each particle keeps the sufficient statistics
// of its own history (bias_s1 = sum w e, bias_s0 = sum w over its matched sightings, e = log(measured /
// distance), w = (distance / s_r(distance))^2 its precision in log units); with the prior b ~ N(0, sigma_b^2) the
// posterior is N(m, 1 / P), P = 1 / sigma_b^2 + bias_s0, m = bias_s1 / P, and the range is predicted as
// r_j = distance * exp(m) with s_r grown to sqrt(s_r(r_j)^2 + r_j^2 / P). A sighting updates the statistics with
// the candidate that explains it best, when that candidate outweighs the clutter term. Being a function of the
// particle's history, the estimate cannot degenerate under resampling as a sampled static state does (tried in
// the seventh stop: tracking 0.20 -> 0.65-1.18 m). sigma_b = 0 is the model without the bias term, exactly.
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
    /// Prior std of the detector's log range bias b (see "Range bias" above), log units; 0 = no bias term.
    /// Internal parameter `sign.range_bias_sigma`. 0.07: a 10 % bias is 1.5 sigma, 25 % is 4 sigma.
    float range_bias_sigma = 0.07f;
    /// Cap on bias_s0 (log-unit precision): the posterior std of b stays >= 1 / sqrt(cap) (0.03), so a bias that
    /// changes with the scene (lighting, another kind of sign) can still be followed.
    float range_bias_max_precision = 1000.0f;

    static SignModelParams from_options(const wf_localizer_options &o);
    /// Density of a false positive over range and bearing, u = 1 / (max_range_m * field of view), per meter and
    /// radian: where clutter puts a sighting, uniformly.
    float clutter_density() const { return 1.0f / (max_range_m * 2.0f * half_fov_rad); }
};

/// A sighting prepared for the model: kind id known to the map, finite range/bearing, effective clutter
/// probability (1 - (1 - p_clutter) * score).
struct PreparedSighting {
    int32_t kind;
    float range_m;
    float bearing_rad;
    float clutter_probability;
    /// wf_sign_observation::track_id (0 = not tracked).
    uint32_t track_id = 0;
    /// wf_sign_observation::track_range_m and track_bearing_rad (range <= 0: unknown).
    float track_range_m = 0, track_bearing_rad = 0;
};

/// Converts raw observations: skips non-finite ones (counted in *non_finite) and kinds outside the map
/// (they carry no information about the pose: every particle would explain them as clutter).
std::vector<PreparedSighting> prepare_sightings(const wf_sign_observation *obs, size_t count, const SignModelParams &m,
                                                int32_t kind_count, size_t *non_finite);

/// Log-likelihood of the frame's sightings for a particle that sees no sign of their kinds: each sighting a
/// false positive, p_clutter * u with u = 1 / (max_range_m * field of view). sign_log_likelihood gives such a
/// particle exactly this value (it calls this function).
float clutter_only_log_likelihood(const SignModelParams &m, const PreparedSighting *sightings, size_t count);

/// Log-likelihood of the frame's sightings for every particle (heading = vio_yaw + yaw_offset), written to
/// `log_likelihood` (size p.size()). Returns the maximum. With no sighting and negative information off,
/// every value is 0. With `bias_s1_out` and `bias_s0_out` (p.bias_s1.data() and p.bias_s0.data(): updated in
/// place, only for particles that see a sign of a sighted kind) the range-bias statistics take this frame's
/// sightings (range_bias_sigma > 0); nullptr = read only. `unsearched_kind` (nullptr = every kind was searched;
/// else map.kind_count flags, nonzero for a kind the detector did not look for on this frame, e.g. SignDetector's
/// wall kinds searched in turn): the signs of such a kind take no negative information, their absence from the
/// frame saying nothing, unless the frame holds a sighting of that kind (then it was searched after all).
/// `per_sighting_ll` (nullptr = none; else `count` pointers, each nullptr or an array of p.size()) receives
/// sighting o's own term of each particle's sum (its mixture's log, or its clutter-only value), for the
/// tracked-object evidence (pf/track_evidence); the sums are the same either way.
float sign_log_likelihood(const ParticleSet &p, float vio_yaw_rad, const LocalizerMap &map, const SignModelParams &m,
                          const PreparedSighting *sightings, size_t count, float *log_likelihood,
                          float *bias_s1_out = nullptr, float *bias_s0_out = nullptr,
                          const uint8_t *unsearched_kind = nullptr, float *const *per_sighting_ll = nullptr);

}  // namespace wf::loc
