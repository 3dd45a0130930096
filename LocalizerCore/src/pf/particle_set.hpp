// Particles as a structure of arrays (one contiguous float array per state variable), so the motion and
// measurement loops stream through memory and the compiler can vectorise the arithmetic parts.
// State of particle i (docs/localizer.md):
//   x[i], y[i]       position in the map frame of its floor, meters;
//   yaw_offset[i]    map yaw minus VIO yaw, radians (heading in map = VIO yaw + yaw_offset);
//   scale[i]         VIO scale factor (map meters per VIO meter);
//   floor[i]         floor index;
//   weight[i]        importance weight (normalised to sum 1 after every update);
//   evidence[i]      recent sign log-likelihood of the particle's history, exponentially forgotten (nats,
//                    relative): used to tell a refuted hypothesis from one that is merely lighter;
//   bias_s1[i], bias_s0[i]  sufficient statistics of the detector's range bias along this particle's history:
//                    sums of w e and w over its matched sightings, e = log(measured / predicted range), w its
//                    precision (sensors/sign_measurement_model, "Range bias");
//   twin_llr[k][i]   on a floor with rotational symmetries (map/floor_symmetry): log-likelihood of this particle's
//                    history minus that of its twin under the floor's k-th symmetry, signs and compass (nats;
//                    pf/twin_guard); only the first `twin_arrays` arrays are used, none on a map without symmetry;
//   track_llr[k][i]  for the tracked object in slot k (pf/track_evidence): log-likelihood ratio of its sightings
//                    between "a map sign, seen from this pose" and "a look-alike" (nats); only the slots in use
//                    follow the particles through resampling;
//   compass_ll[i]    compass log-weight this particle's history has received so far (nats, <= 0), so that the
//                    total compass evidence against a hypothesis stays within a cap (sensors/compass_model).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace wf::loc {

struct ParticleSet {
    std::vector<float> x, y, yaw_offset, scale, weight, evidence, compass_ll, bias_s1, bias_s0;
    std::vector<int16_t> floor;
    /// Most symmetries per floor that carry a twin log-likelihood ratio.
    static constexpr size_t kMaxTwins = 3;
    std::array<std::vector<float>, kMaxTwins> twin_llr;
    /// Number of twin_llr arrays in use (sized with the others): 0 unless some floor is symmetric.
    size_t twin_arrays = 0;
    /// Tracked objects carried at a time (pf/track_evidence).
    static constexpr size_t kMaxTracks = 4;
    std::array<std::vector<float>, kMaxTracks> track_llr;
    /// Number of track_llr arrays sized with the others: kMaxTracks while the tracked-object evidence is on, else 0
    /// (no memory or copy cost when it is off).
    size_t track_arrays = 0;

    size_t size() const { return x.size(); }
    void resize(size_t n) {
        x.resize(n); y.resize(n); yaw_offset.resize(n); scale.resize(n); weight.resize(n); evidence.resize(n);
        compass_ll.resize(n);
        bias_s1.resize(n);
        bias_s0.resize(n);
        floor.resize(n);
        for (size_t k = 0; k < twin_arrays; ++k) twin_llr[k].resize(n);
        for (size_t k = 0; k < track_arrays; ++k) track_llr[k].resize(n);
    }
    void swap(ParticleSet &o) {
        x.swap(o.x); y.swap(o.y); yaw_offset.swap(o.yaw_offset); scale.swap(o.scale); weight.swap(o.weight);
        evidence.swap(o.evidence);
        compass_ll.swap(o.compass_ll);
        bias_s1.swap(o.bias_s1);
        bias_s0.swap(o.bias_s0);
        floor.swap(o.floor);
        twin_llr.swap(o.twin_llr);
        std::swap(twin_arrays, o.twin_arrays);
        track_llr.swap(o.track_llr);
        std::swap(track_arrays, o.track_arrays);
    }
    /// Clears particle i's tracked-object ratios (a fresh particle: even odds for every object).
    void clear_tracks(size_t i) {
        for (size_t k = 0; k < track_arrays; ++k) track_llr[k][i] = 0;
    }
    /// Clears particle i's twin ratios (a fresh particle: no evidence either way).
    void clear_twins(size_t i) {
        for (size_t k = 0; k < twin_arrays; ++k) twin_llr[k][i] = 0;
    }
    /// Bytes of state per particle (one copy), without the twin and track ratios.
    static constexpr size_t kBytesPerParticle = 9 * sizeof(float) + sizeof(int16_t);
};

}  // namespace wf::loc
