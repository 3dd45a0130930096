// The localized flag's state machine (pf/localized_hysteresis): how it turns on, and the steady lock.
#include <gtest/gtest.h>

#include "pf/localized_hysteresis.hpp"

using wf::loc::HysteresisInput;
using wf::loc::LocalizedHysteresis;
using wf::loc::LocalizedHysteresisParams;
using wf::loc::lightest_counted_rival_weight;
using wf::loc::rival_unrefuted;

namespace {

HysteresisInput sure(double t, double x = 10, double y = 5) {
    HysteresisInput in;
    in.t = t;
    in.dominant_weight = 0.95;
    in.std_m = 0.4;
    in.x = x;
    in.y = y;
    in.floor = 0;
    return in;
}

/// `sure(t)` in a limited-tracking spell that has lasted `limited_s` seconds.
HysteresisInput sure_limited(double t, double limited_s) {
    HysteresisInput in = sure(t);
    in.tracking_limited_s = limited_s;
    return in;
}

/// Feeds `in` every 0.1 s from in.t, and last at `seconds` (+ 1 us) after it, as a weight loss that lasts;
/// returns the last flag.
bool update_for(LocalizedHysteresis &h, HysteresisInput in, double seconds) {
    const double t0 = in.t;
    for (int k = 0; 0.1 * k < seconds; ++k) {
        in.t = t0 + 0.1 * k;
        h.update(in);
    }
    in.t = t0 + seconds + 1e-6;
    return h.update(in);
}

LocalizedHysteresis locked() {
    LocalizedHysteresis h;
    for (int k = 0; k <= 12; ++k) h.update(sure(0.1 * k));
    EXPECT_TRUE(h.localized());
    return h;
}

}  // namespace

TEST(LocalizedHysteresis, TurnsOnAfterTheHoldTimeWithoutRivals) {
    LocalizedHysteresis h;
    EXPECT_FALSE(h.update(sure(0.0)));
    EXPECT_FALSE(h.update(sure(0.5)));
    EXPECT_TRUE(h.update(sure(1.0)));
    // An unrefuted rival, however light, keeps it off (the symmetric-building guard).
    LocalizedHysteresis g;
    for (int k = 0; k <= 30; ++k) {
        HysteresisInput in = sure(0.1 * k);
        in.unrefuted_rival_weight = 0.01;
        EXPECT_FALSE(g.update(in));
    }
}

// Which rivals keep the flag off (thirty-first stop): from rival_min_weight (0.1 %) up while their evidence is less
// than rival_refute_nats (4) below the dominant's; thin ones, from thin_rival_min_weight (0.01 %) up, while it is
// less than thin_rival_refute_nats (3) and at least half of their weight has explained a sighting; lighter ones
// never. Weight alone refutes nothing down to 0.01 %.
TEST(LocalizedHysteresis, ThinRivalsCountUntilTheirEvidenceIsThreeNatsShort) {
    const LocalizedHysteresisParams p;
    EXPECT_DOUBLE_EQ(p.thin_rival_min_weight, 1e-4);
    EXPECT_DOUBLE_EQ(p.thin_rival_refute_nats, 3.0);
    EXPECT_DOUBLE_EQ(p.thin_rival_min_sighted_share, 0.5);
    // The sighted weight of a rival whose every particle has explained a sighting; and one that must not be asked.
    const auto all_sighted = [](double w) { return [w] { return w; }; };
    int asked = 0;
    const auto never_asked = [&asked] { ++asked; return 0.0; };
    // Heavy rivals: the full margin, whatever their sighted weight.
    EXPECT_TRUE(rival_unrefuted(p, 0.01, 3.9, never_asked));
    EXPECT_FALSE(rival_unrefuted(p, 0.01, 4.0, never_asked));
    EXPECT_TRUE(rival_unrefuted(p, 0.001, 3.5, never_asked));
    // Thin rivals: the smaller margin (the true pose re-created by injection, 0.8-2.7 nats short, counts).
    EXPECT_TRUE(rival_unrefuted(p, 5e-4, 0.8, all_sighted(5e-4)));
    EXPECT_TRUE(rival_unrefuted(p, 1e-4, 2.9, all_sighted(1e-4)));
    EXPECT_FALSE(rival_unrefuted(p, 5e-4, 3.0, never_asked));
    EXPECT_FALSE(rival_unrefuted(p, 5e-4, 3.5, never_asked));
    // ... and only when at least half of their weight has explained a sighting (a fresh injection has none).
    EXPECT_TRUE(rival_unrefuted(p, 5e-4, 0.8, all_sighted(2.5e-4)));
    EXPECT_FALSE(rival_unrefuted(p, 5e-4, 0.8, all_sighted(2.4e-4)));
    EXPECT_FALSE(rival_unrefuted(p, 5e-4, 0.8, all_sighted(0.0)));
    // Below the thin floor nothing counts, whatever the evidence.
    EXPECT_FALSE(rival_unrefuted(p, 9e-5, -5.0, never_asked));
    EXPECT_DOUBLE_EQ(lightest_counted_rival_weight(p), 1e-4);
    // Off (0, the rule before): the thin ones do not count and the lightest counted rival is rival_min_weight's.
    LocalizedHysteresisParams off = p;
    off.thin_rival_min_weight = 0;
    EXPECT_FALSE(rival_unrefuted(off, 5e-4, 0.0, never_asked));
    EXPECT_TRUE(rival_unrefuted(off, 0.002, 0.0, never_asked));
    EXPECT_DOUBLE_EQ(lightest_counted_rival_weight(off), 1e-3);
    EXPECT_EQ(asked, 0);  // the pass over the particles is made only for a thin rival within the margin
}

TEST(LocalizedHysteresis, InjectedRivalWithPoorEvidenceDoesNotBreakTheLock) {
    LocalizedHysteresis h = locked();
    // Recovery injection took weight: the dominant is down to 0.45 and an unrefuted rival holds 0.3, but its
    // evidence is 3 nats worse than the dominant's: it explains the sightings worse. The lock holds.
    HysteresisInput in = sure(2.0);
    in.dominant_weight = 0.45;
    in.unrefuted_rival_weight = 0.3;
    in.strongest_rival_evidence_margin = -3.0;
    EXPECT_TRUE(h.update(in));
    // The same rival, once the sightings favour it (margin above -1 nat), breaks it (a weight loss that lasts
    // lock_break_hold_s).
    in.t = 2.1;
    in.strongest_rival_evidence_margin = -0.5;
    EXPECT_FALSE(update_for(h, in, h.params().lock_break_hold_s));
}

TEST(LocalizedHysteresis, WeightDiffusedOverTheFloorBreaksTheLock) {
    // The sightings refuted the locked pose: its weight fell to 0.4 with no heavy rival (the mass is spread
    // thin over the floor): the lock breaks (a wrong named start must not stay locked).
    LocalizedHysteresis h = locked();
    HysteresisInput in = sure(2.0);
    in.dominant_weight = 0.4;
    EXPECT_FALSE(update_for(h, in, h.params().lock_break_hold_s));
    // Below lock_min_weight it breaks even when the only heavy rival explains the evidence poorly.
    LocalizedHysteresis g = locked();
    in.dominant_weight = 0.2;
    in.unrefuted_rival_weight = 0.3;
    in.strongest_rival_evidence_margin = -3.0;
    EXPECT_FALSE(update_for(g, in, g.params().lock_break_hold_s));
}

TEST(LocalizedHysteresis, SpreadOrAJumpToAnotherHypothesisBreaksTheLock) {
    LocalizedHysteresis a = locked();
    HysteresisInput wide = sure(2.0);
    wide.std_m = 2.5;
    EXPECT_FALSE(a.update(wide));

    LocalizedHysteresis b = locked();
    EXPECT_TRUE(b.update(sure(2.0, 10.05, 5)));   // walking: 5 cm per frame
    EXPECT_FALSE(b.update(sure(2.1, 18.0, 5)));   // another cluster took over, 8 m away

    // A floor change that the lock followed is not a jump.
    LocalizedHysteresis c = locked();
    HysteresisInput up = sure(2.0);
    up.floor = 1;
    EXPECT_TRUE(c.update(up));
}

TEST(LocalizedHysteresis, WhileLockedTheCoreDecidesSpreadAndWeight) {
    // Injected particles joined the locked cluster far along the corridor: the whole cluster reads 5.4 m of
    // spread, its core 0.4 m and 0.8 of the weight. The lock holds.
    LocalizedHysteresis h = locked();
    HysteresisInput in = sure(2.0);
    in.std_m = 5.4;
    in.core_std_m = 0.4;
    in.core_weight = 0.8;
    EXPECT_TRUE(h.update(in));
    // The core itself spreads: it breaks.
    in.t = 2.1;
    in.core_std_m = 2.3;
    EXPECT_FALSE(h.update(in));
    // Most of the cluster's weight is outside the core (the weight went elsewhere along the corridor): it
    // breaks, as weight diffused over the floor does.
    LocalizedHysteresis g = locked();
    in = sure(2.0);
    in.core_std_m = 0.4;
    in.core_weight = 0.4;
    EXPECT_FALSE(update_for(g, in, g.params().lock_break_hold_s));
    // Becoming localized reads the whole cluster: a tight core with a far tail is not a lock.
    LocalizedHysteresis f;
    for (int k = 0; k <= 20; ++k) {
        HysteresisInput c = sure(0.1 * k);
        c.std_m = 3.0;
        c.core_std_m = 0.3;
        c.core_weight = 0.9;
        EXPECT_FALSE(f.update(c));
    }
}

TEST(LocalizedHysteresis, FreshInjectedParticlesNeitherDiluteNorSpreadASightedLock) {
    // Recovery injection scattered fresh particles (no sighting behind them) over the floor and along the locked
    // corridor: the core reads 0.47 of the weight and 2.2 m of spread, but its particles that have explained
    // sightings sit within 1.0 m, and the sighted weight elsewhere is 0.02. The lock holds.
    HysteresisInput in = sure(2.0);
    in.core_weight = 0.47;
    in.core_std_m = 2.2;
    in.sighted_core_weight = 0.45;
    in.sighted_core_std_m = 1.0;
    in.contested_weight = 0.02;
    LocalizedHysteresis h = locked();
    EXPECT_TRUE(h.update(in));
    // Without the rule the same input breaks it (weight and spread read over the whole core).
    LocalizedHysteresis off = locked();
    off.mutable_params().discount_unsighted = false;
    EXPECT_FALSE(off.update(in));
    // Sighted weight elsewhere (particles that explain sightings the lock does not): it breaks.
    in.t = 2.1;
    in.contested_weight = 0.5;
    EXPECT_FALSE(update_for(h, in, h.params().lock_break_hold_s));
    // The sighted particles themselves spread: it breaks.
    LocalizedHysteresis g = locked();
    in.contested_weight = 0.02;
    in.sighted_core_std_m = 2.3;
    EXPECT_FALSE(g.update(in));
    // Below lock_min_weight the whole core decides, sighted or not.
    LocalizedHysteresis k = locked();
    in.sighted_core_std_m = 1.0;
    in.core_weight = 0.2;
    EXPECT_FALSE(update_for(k, in, k.params().lock_break_hold_s));
}

TEST(LocalizedHysteresis, AWeightLossBreaksTheLockOnlyOnceItHasLasted) {
    // A sighting frame moved the weight off the lock for 0.2 s (one misread sign; the weight returns two
    // estimates later): the lock holds through it.
    LocalizedHysteresis h = locked();
    ASSERT_GE(h.params().lock_break_hold_s, 0.25);
    HysteresisInput in = sure(2.0);
    in.dominant_weight = 0.2;
    EXPECT_TRUE(update_for(h, in, 0.2));
    EXPECT_TRUE(h.update(sure(2.3)));
    // The same loss, begun anew, breaks it once it has lasted lock_break_hold_s (the hold restarted at 2.4 s).
    in.t = 2.4;
    EXPECT_TRUE(update_for(h, in, 0.2));
    in.t = 2.4 + h.params().lock_break_hold_s + 1e-6;
    EXPECT_FALSE(h.update(in));
    // A spread breaks it at once: the pose itself is no longer sure.
    LocalizedHysteresis g = locked();
    HysteresisInput wide = sure(2.0);
    wide.std_m = 2.5;
    EXPECT_FALSE(g.update(wide));
    // With the hold at 0, the weight loss breaks it at once.
    LocalizedHysteresis f = locked();
    f.mutable_params().lock_break_hold_s = 0;
    in.t = 2.0;
    EXPECT_FALSE(f.update(in));
}

// On a symmetric floor (pf/twin_guard): no lock until the evidence against the dominant hypothesis's turned twin
// reaches rival_refute_nats (4); a held lock drops once the twin is ahead by lock_rival_margin_nats (1); a ratio in
// between leaves a lock as it is.
TEST(LocalizedHysteresis, TheTwinMustBeRefutedAndAWinningTwinBreaksTheLock) {
    LocalizedHysteresis h;
    for (int k = 0; k <= 30; ++k) {
        HysteresisInput in = sure(0.1 * k);
        in.twin_log_ratio = 3.9;
        EXPECT_FALSE(h.update(in)) << k;
    }
    for (int k = 31; k <= 45; ++k) {
        HysteresisInput in = sure(0.1 * k);
        in.twin_log_ratio = 4.1;
        h.update(in);
    }
    EXPECT_TRUE(h.localized());
    HysteresisInput in = sure(4.6);
    in.twin_log_ratio = -0.9;  // the evidence moved towards the twin, not past the margin
    EXPECT_TRUE(h.update(in));
    in = sure(4.7);
    in.twin_log_ratio = -1.1;
    EXPECT_FALSE(h.update(in));
}

// Sightings that the dominant hypothesis explains only as false positives: when their false-positive
// probabilities multiply to less than e^-rival_refute_nats over the hold period, some pose the cloud does not
// hold explains them (a rival no particle represents), and the flag waits. Below the margin (an occasional
// false positive) it turns on as before; the rule does not break a lock (the rivals do), and it can be turned
// off for studies.
TEST(LocalizedHysteresis, SightingsTheDominantCallsFalsePositivesKeepItOff) {
    LocalizedHysteresis h;
    for (int k = 0; k <= 30; ++k) {
        HysteresisInput in = sure(0.1 * k);
        in.unexplained_sighting_nats = 4.0;  // e.g. two sightings of a detector score 0.95 (p_fp 0.145 each)
        EXPECT_FALSE(h.update(in)) << "t = " << in.t;
    }
    // One false positive in the hold period (2.3 nats at score 1): the flag comes on after the hold time.
    LocalizedHysteresis g;
    for (int k = 0; k <= 10; ++k) {
        HysteresisInput in = sure(3.0 + 0.1 * k);
        in.unexplained_sighting_nats = 2.3;
        EXPECT_EQ(g.update(in), k == 10) << "t = " << in.t;
    }
    // A lock is not broken by them.
    LocalizedHysteresis l = locked();
    HysteresisInput in = sure(2.0);
    in.unexplained_sighting_nats = 20;
    EXPECT_TRUE(l.update(in));
    // Off: they are ignored.
    wf::loc::LocalizedHysteresisParams off;
    off.explain_sightings = false;
    LocalizedHysteresis f(off);
    bool on = false;
    for (int k = 0; k <= 12; ++k) {
        HysteresisInput x = sure(0.1 * k);
        x.unexplained_sighting_nats = 50;
        on = f.update(x);
    }
    EXPECT_TRUE(on);
}

// Tracking lost: the traveler may walk on unobserved. Once lost_walk_speed_mps (1.4 m/s) times the time lost
// exceeds unlocalize_std_m (2 m, i.e. after 1.43 s) the flag is off, held lock or not; a shorter loss keeps it,
// and 0 keeps it through any loss.
TEST(LocalizedHysteresis, TrackingLostLongerThanTwoMetersOfWalkingVoidsTheLock) {
    LocalizedHysteresis h = locked();
    HysteresisInput in = sure(1.5);
    in.tracking_lost_s = 1.4;
    EXPECT_TRUE(h.update(in));
    in.t = 1.6;
    in.tracking_lost_s = 1.5;
    EXPECT_FALSE(h.update(in));
    // A lock is not reached while the loss lasts, however long the estimate looks sure.
    for (int k = 0; k <= 30; ++k) {
        in.t = 1.7 + 0.1 * k;
        in.tracking_lost_s = 1.6 + 0.1 * k;
        EXPECT_FALSE(h.update(in));
    }
    // With the rule off the lock survives any loss.
    wf::loc::LocalizedHysteresisParams p;
    p.lost_walk_speed_mps = 0;
    LocalizedHysteresis off(p);
    for (int k = 0; k <= 12; ++k) off.update(sure(0.1 * k));
    in.tracking_lost_s = 60;
    EXPECT_TRUE(off.update(in));
}

TEST(LocalizedHysteresis, NoLockIsEarnedWhileTrackingIsLimitedAndAHeldLockIsKept) {
    // A limited spell of 3 s: however sure the estimate looks, the flag stays off.
    LocalizedHysteresis h;
    for (int k = 0; k <= 30; ++k) EXPECT_FALSE(h.update(sure_limited(0.1 * k, 0.1 * k))) << "k=" << k;
    // Tracking normal again: the hold period starts then, and the lock comes localize_hold_s later, not at once.
    EXPECT_FALSE(h.update(sure(3.1)));
    EXPECT_FALSE(h.update(sure(3.6)));
    EXPECT_TRUE(h.update(sure(4.15)));
    // A lock held when tracking turns limited is kept (limited tracking is not evidence against it).
    for (int k = 0; k <= 30; ++k) EXPECT_TRUE(h.update(sure_limited(4.25 + 0.1 * k, 0.1 * k))) << "k=" << k;
    // A spell longer than limited_spell_max_s (10 s) is the place's normal: a lock is earned in it as anywhere.
    LocalizedHysteresis dim;
    for (int k = 0; k <= 100; ++k) EXPECT_FALSE(dim.update(sure_limited(0.1 * k, 0.1 * k))) << "k=" << k;
    bool locked_in_spell = false;
    for (int k = 101; k <= 125; ++k) locked_in_spell = dim.update(sure_limited(0.1 * k, 0.1 * k));
    EXPECT_TRUE(locked_in_spell);
    // With the rule off, a limited spell earns a lock as a normal one does.
    wf::loc::LocalizedHysteresisParams p;
    p.no_lock_while_limited = false;
    LocalizedHysteresis off(p);
    EXPECT_FALSE(off.update(sure_limited(0.0, 0.0)));
    EXPECT_TRUE(off.update(sure_limited(1.0, 1.0)));
}
