// Tests for pf/track_evidence.hpp: one tracked object's sightings say a bounded amount against a pose with no sign
// there, while a pose whose sign matches keeps each sighting's geometry; the first sighting counts as the per-frame
// model has it; slots are found, forgotten and reused; off, every sighting counts on its own.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pf/track_evidence.hpp"
#include "sensors/sign_measurement_model.hpp"
#include "support/filter_fixtures.hpp"

using namespace wf::loc;

namespace {

constexpr float kPiF = 3.14159265f;

/// Three particles on the L world's south corridor at x = 6: facing the west-end Exit sign (P0, exact), facing it
/// from 0.3 m further east (P2, a near match), and facing the south wall (P1, no Exit sign in view).
ParticleSet three_poses() {
    ParticleSet p;
    p.track_arrays = ParticleSet::kMaxTracks;
    p.resize(3);
    const float xs[3] = {6.0f, 6.0f, 6.3f};
    const float hs[3] = {kPiF - 0.1f, -kPiF / 2, kPiF - 0.1f};
    for (size_t i = 0; i < 3; ++i) {
        p.x[i] = xs[i]; p.y[i] = 1.25f; p.yaw_offset[i] = hs[i]; p.scale[i] = 1; p.weight[i] = 1.0f / 3; p.floor[i] = 0;
    }
    return p;
}

struct WatchResult {
    float per_frame[3] = {0, 0, 0};  // the per-frame model's sums
    float tracked[3] = {0, 0, 0};    // with the object-level mixture
    float first_per_frame[3] = {0, 0, 0};
};

/// `frames` sightings of the west-end sign as P0 sees it, all of one track.
WatchResult watch(int frames, double lookalike_share, double variance_factor = 1.5) {
    auto world = wf::test::l_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    SignModelParams m = SignModelParams::from_options(o);
    m.negative_information = false;
    ParticleSet p = three_poses();
    TrackEvidenceParams tp;
    tp.enabled = true;
    tp.lookalike_share = lookalike_share;
    tp.variance_factor = variance_factor;
    TrackEvidence te(tp);
    const float b = static_cast<float>(wf::test::wrap(kPiF - (kPiF - 0.1f)));
    PreparedSighting s{wf::test::kExit, 6.0f, b, 0.1f, 7, 6.0f, b};
    WatchResult r;
    std::vector<int> slot;
    std::vector<uint8_t> first;
    for (int k = 0; k < frames; ++k) {
        std::vector<PreparedSighting> z = {s};
        if (k == 0) z[0].track_range_m = 0;  // a first sighting has no earlier position
        float ll[3], own[3];
        float *own_ptr[1] = {own};
        sign_log_likelihood(p, 0.0f, map, m, z.data(), z.size(), ll, nullptr, nullptr, nullptr, own_ptr);
        for (int i = 0; i < 3; ++i) {
            EXPECT_FLOAT_EQ(own[i], ll[i]);  // one sighting: its own term is the whole sum
            r.per_frame[i] += ll[i];
            if (k == 0) r.first_per_frame[i] = ll[i];
        }
        te.assign(p, z, 0.1 * k, slot, first);
        EXPECT_EQ(slot[0], 0);
        EXPECT_EQ(first[0], k == 0 ? 1 : 0);
        te.apply(p, m, z, slot, first, own_ptr, ll);
        for (int i = 0; i < 3; ++i) r.tracked[i] += ll[i];
        if (k == 0) {
            for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(r.tracked[i], r.per_frame[i]) << "first sighting, pose " << i;
        }
    }
    return r;
}

}  // namespace

TEST(TrackEvidence, MixtureLogIsTheDirectFormulaWithoutOverflow) {
    for (float c : {0.01f, 0.1f, 0.5f}) {
        for (float a : {-20.0f, -3.0f, 0.0f, 2.0f, 15.0f}) {
            const double direct = std::log((1.0 - c) * std::exp(static_cast<double>(a)) + c);
            EXPECT_NEAR(TrackEvidence::mixture_log(a, c), direct, 1e-5) << "a " << a << " c " << c;
        }
        EXPECT_TRUE(std::isfinite(TrackEvidence::mixture_log(1e4f, c)));
        EXPECT_NEAR(TrackEvidence::mixture_log(-1e4f, c), std::log(c), 1e-6);
    }
}

// 40 sightings of one object: per frame, the pose with no sign there falls further behind with every one (about
// 5.8 nats each); as one object, it pays at most log(((1 - c) p_c + c) / c) beyond the first sighting.
TEST(TrackEvidence, OneObjectsEvidenceAgainstAPoseWithoutASignIsBounded) {
    const double c = 0.1, pc = 0.1;
    const WatchResult r = watch(40, c);
    const float first_gap = r.first_per_frame[0] - r.first_per_frame[1];
    EXPECT_GT(first_gap, 4.0f);
    EXPECT_GT(r.per_frame[0] - r.per_frame[1], 40 * 4.0f);
    const float bound = static_cast<float>(std::log(((1 - c) * pc + c) / c));
    const float tracked_gap = r.tracked[0] - r.tracked[1];
    EXPECT_GE(tracked_gap, first_gap - 0.05f);
    // The exact pose's own ratio still grows with each sighting: its sign predicts the sighting exactly, the
    // look-alike's track with 1.5 x the variance (log 1.5 = 0.41 nats a sighting at most; 0.3 here with the clutter
    // share): that growth is allowed, not the per-frame model's 5.7 nats a sighting.
    EXPECT_LE(tracked_gap, first_gap + bound + 39 * 0.35f);
    EXPECT_LT(tracked_gap, 0.2f * (r.per_frame[0] - r.per_frame[1]));
}

// A near match (0.3 m off) keeps falling behind the exact pose sighting after sighting: the object-level mixture
// does not bound the geometry of poses whose sign explains the object.
TEST(TrackEvidence, PosesWhoseSignMatchesKeepEachSightingsGeometry) {
    const WatchResult r = watch(12, 0.1);
    const float per_frame_gap = r.per_frame[0] - r.per_frame[2];
    const float tracked_gap = r.tracked[0] - r.tracked[2];
    EXPECT_GT(per_frame_gap, 0.5f);
    EXPECT_NEAR(tracked_gap, per_frame_gap, 0.1f * per_frame_gap);
}

// Watched for long (a traveler walking toward a sign for 15 s), the ratios of the poses whose sign matches pass the
// clamp that keeps them finite: the exact pose must still gain each sighting's geometry over the near match. Before
// the twenty-ninth stop the clamped ratio also clamped the increment: past about 25 sightings at the default factor
// every pose at the clamp scored log q alike, the locked cluster stopped being told apart from its fringe, and the
// lock thinned out on long tours (docs/benchmarks.md "Twenty-ninth stop").
TEST(TrackEvidence, PosesWhoseSignMatchesKeepEachSightingsGeometryPastTheRatioClamp) {
    const TrackEvidenceParams defaults;
    const WatchResult r = watch(150, defaults.lookalike_share, defaults.variance_factor);
    const float per_frame_gap = r.per_frame[0] - r.per_frame[2];
    const float tracked_gap = r.tracked[0] - r.tracked[2];
    EXPECT_GT(per_frame_gap, 150 * 0.04f);
    EXPECT_NEAR(tracked_gap, per_frame_gap, 0.05f * per_frame_gap);
}

// A look-alike share near 0 is the per-frame model for poses whose ratio stays above log c.
TEST(TrackEvidence, ALookAlikeShareNearZeroIsThePerFrameModelForMatchedPoses) {
    const WatchResult r = watch(10, 1e-6);
    EXPECT_NEAR(r.tracked[0], r.per_frame[0], 1e-3f * 10);
    EXPECT_NEAR(r.tracked[2], r.per_frame[2], 1e-3f * 10);
}

TEST(TrackEvidence, SlotsAreFoundForgottenAndReused) {
    ParticleSet p = three_poses();
    TrackEvidenceParams tp;
    tp.enabled = true;
    tp.forget_s = 3.0;
    TrackEvidence te(tp);
    std::vector<int> slot;
    std::vector<uint8_t> first;
    auto seen = [](uint32_t id) { return PreparedSighting{0, 5.0f, 0.0f, 0.1f, id, 5.0f, 0.0f}; };
    // Four tracks fill the four slots; the same id finds its slot again; untracked sightings get none.
    te.assign(p, {seen(1), seen(2), seen(3), seen(0)}, 0.0, slot, first);
    EXPECT_EQ(slot, (std::vector<int>{0, 1, 2, -1}));
    EXPECT_EQ(first, (std::vector<uint8_t>{1, 1, 1, 0}));
    te.assign(p, {seen(4), seen(2)}, 1.0, slot, first);
    EXPECT_EQ(slot, (std::vector<int>{3, 1}));
    EXPECT_EQ(first, (std::vector<uint8_t>{1, 0}));
    // A fifth takes the slot seen longest ago (track 1 or 3, both last seen at 0 s: the first such, 0).
    te.assign(p, {seen(5)}, 2.0, slot, first);
    EXPECT_EQ(slot, (std::vector<int>{0}));
    EXPECT_TRUE(te.active(0));
    // Two sightings of one track in a frame: the second counts on its own.
    te.assign(p, {seen(5), seen(5)}, 2.5, slot, first);
    EXPECT_EQ(slot, (std::vector<int>{0, -1}));
    // Not seen for longer than forget_s: forgotten (slot 2 held track 3, last seen at 0 s).
    te.assign(p, {}, 3.5, slot, first);
    EXPECT_FALSE(te.active(2));
    EXPECT_TRUE(te.active(0));
    // A new track's ratios start at 0 for every particle.
    p.track_llr[2][1] = 5.0f;
    te.assign(p, {seen(9)}, 3.6, slot, first);
    EXPECT_EQ(slot[0], 2);
    EXPECT_EQ(p.track_llr[2][1], 0.0f);
}

// At the default variance factor (4) the exact pose gains up to log 4 a sighting over the track: still a fraction of
// the per-frame model's gap against a pose with no sign there.
TEST(TrackEvidence, AtTheDefaultsOneObjectSaysAFractionOfThePerFrameModel) {
    const TrackEvidenceParams defaults;
    EXPECT_TRUE(defaults.enabled);  // on unless switched off (docs/localizer.md "Tracked objects")
    const WatchResult r = watch(40, defaults.lookalike_share, defaults.variance_factor);
    const float first_gap = r.first_per_frame[0] - r.first_per_frame[1];
    const float bound = static_cast<float>(std::log(((1 - defaults.lookalike_share) * 0.1 + defaults.lookalike_share) /
                                                    defaults.lookalike_share));
    const float tracked_gap = r.tracked[0] - r.tracked[1];
    EXPECT_LE(tracked_gap, first_gap + bound + 39 * static_cast<float>(std::log(defaults.variance_factor)));
    EXPECT_LT(tracked_gap, 0.3f * (r.per_frame[0] - r.per_frame[1]));
}

TEST(TrackEvidence, OffEverySightingCountsOnItsOwn) {
    ParticleSet p = three_poses();
    TrackEvidenceParams tp;
    tp.enabled = false;
    TrackEvidence te(tp);
    std::vector<int> slot;
    std::vector<uint8_t> first;
    te.assign(p, {PreparedSighting{0, 5.0f, 0.0f, 0.1f, 3, 5.0f, 0.0f}}, 0.0, slot, first);
    EXPECT_EQ(slot, (std::vector<int>{-1}));
}

// The per-sighting terms add up to each particle's sum, on a spread-out cloud (most particles take the fast
// no-candidate path) with two sightings.
TEST(TrackEvidence, PerSightingTermsAddUpToTheFramesLogLikelihood) {
    auto world = wf::test::l_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    SignModelParams m = SignModelParams::from_options(o);
    m.negative_information = false;
    std::mt19937 gen(5);
    std::uniform_real_distribution<float> ux(0.5f, 29.5f), uy(0.5f, 2.0f), uh(-kPiF, kPiF);
    ParticleSet p;
    const size_t n = 3000;
    p.resize(n);
    for (size_t i = 0; i < n; ++i) {
        p.x[i] = ux(gen); p.y[i] = uy(gen); p.yaw_offset[i] = uh(gen); p.scale[i] = 1; p.weight[i] = 1.0f / n; p.floor[i] = 0;
    }
    const std::vector<PreparedSighting> z = {{wf::test::kExit, 4.0f, 0.1f, 0.1f, 1, 0, 0},
                                             {wf::test::kExit, 7.0f, -0.2f, 0.3f, 2, 0, 0}};
    std::vector<float> ll(n), plain(n), a(n), b(n);
    float *terms[2] = {a.data(), b.data()};
    const float mx = sign_log_likelihood(p, 0.0f, map, m, z.data(), z.size(), ll.data(), nullptr, nullptr, nullptr, terms);
    const float mx_plain = sign_log_likelihood(p, 0.0f, map, m, z.data(), z.size(), plain.data());
    EXPECT_EQ(mx, mx_plain);
    size_t seeing = 0;
    for (size_t i = 0; i < n; ++i) {
        EXPECT_EQ(ll[i], plain[i]);
        EXPECT_NEAR(a[i] + b[i], ll[i], 1e-4f * std::fabs(ll[i]) + 1e-5f);
        seeing += a[i] != a[0] || b[i] != b[0];
    }
    EXPECT_GT(seeing, 10u);  // some particles see a sign: both code paths are exercised
}
