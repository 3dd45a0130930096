// Tracked objects: one object's sightings are not independent evidence of a sign (docs/localizer.md "Tracked
// objects").
//
// The sign model (sensors/sign_measurement_model) scores each frame on its own: a sighting that a pose does not
// explain costs that pose about 5.8 nats at the default clutter share, every frame. A detector that takes one
// poster or red light for an Exit sign does so frame after frame, at one place of the VIO plane (a look-alike
// that stays put; issue 16 measured 0.06 such false positives per frame on real photos, from posters, ceiling
// lights and fiducial markers), and 45 sightings of one look-alike in 9 s then outweigh every real sign: they
// took the true hypothesis out of the convergence study's conv-3-06 (docs/benchmarks.md, "Twenty-fourth stop").
//
// The caller tracks objects (App/Core/SightingCorroboration gives each sighting the id of the object it sees
// again at about the same place of the VIO plane). Each object has a binary latent state: it is a map sign, or a
// look-alike (prior share c = `lookalike_share`). Per particle and object the filter keeps
//     A = log p(the object's sightings | this pose, a sign) - log p(the same | a look-alike),
// with q the look-alike's re-sighting density (below). The object's first sighting counts
// as the per-frame model has it (A starts at its log-likelihood minus log u); each later one adds
//     f(A_new) - f(A_old),  f(A) = log((1 - c) e^A + c),
// the change of the object-level mixture, instead of its own log-likelihood. For a pose whose sign matches, A
// stays high and the increment is the sighting's geometry (range and bearing against the prediction, as before);
// for a pose with no sign there (or a sign in the wrong place), A falls and its later sightings together cost it at
// most log(((1 - c) p_c1 + c) / c) more than the first did (0.64 nats at the defaults): one object cannot outweigh
// the lock or the other objects however long it is watched. This is the exact Bayes update of the mixture (the
// object's sightings are exchangeable given the latent state), with the first sighting kept per frame so that a
// sighting seen once counts exactly as before.
//
// The look-alike's re-sighting density q is the sign model's own mixture with the object's earlier position (the
// mean of its earlier sightings on the VIO plane, given by the caller as track_range_m / track_bearing_rad) in place
// of a map sign, its variance x `variance_factor` (4) for that mean's own error: both explanations see the
// detector's real noise, whatever the model assumes (with a fixed q, a real sign's A fell on every sighting behind
// noisier detectors). The factor gives a pose whose sign matches up to log 4 nats a sighting over the track, so
// its A does not fall behind a detector 2 x noisier than the model. The frame's likelihoods keep their level
// (+ log q), so the recovery averages read the same scale.
//
// Written here: no particle-filter library bounds the evidence of a tracked object. Four objects are carried at a
// time (ParticleSet::kMaxTracks); a fifth takes the slot of the one seen longest ago.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "pf/particle_set.hpp"
#include "sensors/sign_measurement_model.hpp"

namespace wf::loc {

/// Internal parameters of the tracked-object evidence (not part of the C ABI; "track.*" by name).
struct TrackEvidenceParams {
    /// On (the default): tracked sightings take the object-level mixture; off: every sighting counts on its own and
    /// track ids are ignored. On by default since the twenty-sixth stop (docs/benchmarks.md "Twenty-sixth stop"):
    /// behind look-alikes that stay put it removes every wrong lock measured (6 in filter seeds 1-6 of the
    /// convergence study, each held 25-31 m, to 0) and the missing turn cues; its cost is behind the unrefined
    /// cascade's -25 % range bias, where a real sign's sightings fit the look-alike's self-consistent track better
    /// than any map pose until the bias is learned (wrong locks in filter seeds 1-8 of the scenario suite 1 -> 3,
    /// held 0-7.3 m; within 20 m 67 -> 61 %). CLI `--no-track-objects`. "track.enabled".
    bool enabled = true;
    /// Prior share c of tracked objects that are look-alikes, not map signs (0 < c < 1). The smaller, the more an
    /// object watched for long can say: a pose with no sign there pays at most log(((1 - c) p_c + c) / c) beyond
    /// its first sighting. Default 0.1, the detectors' clutter share. "track.lookalike_share".
    double lookalike_share = 0.1;
    /// A track not seen for this long is forgotten and its slot freed, seconds. "track.forget_s".
    double forget_s = 3.0;
    /// Variance of the look-alike's re-sighting about its track's earlier mean position, in units of the sign
    /// model's variance (>= 1). Default 4: the track's mean has the detector's real error (range bias, noise beyond
    /// the model's) and VIO drift between the sightings; at 1.5, behind detectors noisier than the model (all-rough)
    /// a real sign's later sightings fit the track better than any map pose and convergence within 20 m fell from
    /// 40 to 27 % (docs/benchmarks.md "Twenty-fifth stop"). "track.variance_factor".
    double variance_factor = 4.0;
};

/// The slots of the tracked objects and their per-particle ratio arrays (ParticleSet::track_llr). Value type;
/// reset() on every init of the filter and floor change.
class TrackEvidence {
public:
    explicit TrackEvidence(const TrackEvidenceParams &p = {}) : p_(p) {}
    const TrackEvidenceParams &params() const { return p_; }
    TrackEvidenceParams &mutable_params() { return p_; }

    /// Forgets every track.
    void reset();
    /// True when slot k holds a track (its ratio array must follow the particles through resampling).
    bool active(size_t k) const { return slots_[k].track_id != 0; }

    /// The slot of each of the frame's sightings at time t (-1: not tracked, or the model is off); a new track takes
    /// a free slot (or the least recently seen) and its ratio array is zeroed. Forgets tracks older than forget_s.
    /// `first[o]` is 1 when sighting o is its track's first sighting. Two sightings of one track in a frame: only the
    /// first is tracked (the other counts on its own).
    void assign(ParticleSet &p, const std::vector<PreparedSighting> &z, double t, std::vector<int> &slot_of,
                std::vector<uint8_t> &first);

    /// Replaces, in each particle's frame log-likelihood `ll` (size p.size()), the own term `per_ll[o][i]` of every
    /// tracked sighting that is not its track's first by the change of the object-level mixture, and updates the
    /// particles' ratios A of every tracked sighting. Returns the new maximum of ll.
    float apply(ParticleSet &p, const SignModelParams &m, const std::vector<PreparedSighting> &z,
                const std::vector<int> &slot_of, const std::vector<uint8_t> &first, const float *const *per_ll,
                float *ll) const;

    /// f(A) = log((1 - c) e^A + c), evaluated without overflow. For tests and docs.
    static float mixture_log(float a, float c);
    /// log q: the density of sighting `z` if its object is a look-alike, i.e. seen again where its track puts it
    /// (z.track_range_m, z.track_bearing_rad) under the sign model's noise (variance x variance_factor for the track's own error)
    /// and clutter share; with no track position, the model's expected value.
    static float lookalike_log_density(const SignModelParams &m, const PreparedSighting &z, float variance_factor);

private:
    struct Slot {
        uint32_t track_id = 0;
        double last_t = 0;
    };
    TrackEvidenceParams p_;
    std::array<Slot, ParticleSet::kMaxTracks> slots_{};
};

}  // namespace wf::loc
