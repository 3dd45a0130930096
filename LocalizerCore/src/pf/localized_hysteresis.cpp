#include "pf/localized_hysteresis.hpp"

#include <algorithm>
#include <cmath>

namespace wf::loc {

double lightest_counted_rival_weight(const LocalizedHysteresisParams &p) {
    return p.thin_rival_min_weight > 0 ? std::min(p.rival_min_weight, p.thin_rival_min_weight) : p.rival_min_weight;
}

void LocalizedHysteresis::reset() {
    localized_ = false;
    has_candidate_ = false;
    has_last_ = false;
    has_break_ = false;
}

bool LocalizedHysteresis::update(const HysteresisInput &in) {
    advance(in);
    // Tracking lost for long enough that the traveler may have walked farther than the flag's spread limit from
    // the locked pose: no estimate can claim the traveler's position now (a lock held or just reached).
    if (localized_ && p_.lost_walk_speed_mps > 0 && in.tracking_lost_s * p_.lost_walk_speed_mps > p_.unlocalize_std_m) {
        drop();
    }
    return localized_;
}

void LocalizedHysteresis::advance(const HysteresisInput &in) {
    // A jump on the same floor means another hypothesis became the dominant cluster. A floor change that
    // the cloud followed (barometer) is not one.
    const bool jumped = has_last_ && in.floor == last_floor_ && std::hypot(in.x - last_x_, in.y - last_y_) > p_.lock_jump_m;
    has_last_ = true;
    last_x_ = in.x;
    last_y_ = in.y;
    last_floor_ = in.floor;
    if (localized_) {
        const double std_m = in.core_std_m >= 0 ? in.core_std_m : in.std_m;
        const double weight = in.core_weight >= 0 ? in.core_weight : in.dominant_weight;
        // Weight that recovery injection handed to fresh particles (no sighting behind them) is not weight the
        // sightings took from the lock: a spread or a weight loss breaks it only when its sighted particles show
        // it too (the sighted core weighed against the sighted weight that contests it). The rule only relaxes.
        const bool discount = p_.discount_unsighted && in.contested_weight >= 0 && in.sighted_core_weight > 0;
        const double sighted_share = discount ? in.sighted_core_weight / (in.sighted_core_weight + in.contested_weight) : 0;
        const bool spread = std_m > p_.unlocalize_std_m && (!discount || in.sighted_core_std_m > p_.unlocalize_std_m);
        // The weight left the locked cluster. Kept only when it went to a heavy rival that explains the recent
        // evidence clearly worse (revived by injection); a rival that explains it as well, or weight diffused
        // over the floor (the sightings refuted the lock), drops the flag; below lock_min_weight it always drops.
        const bool heavy_rival = in.strongest_rival_evidence_margin > -1e299;
        const bool only_poor_rival = heavy_rival && in.strongest_rival_evidence_margin < -p_.lock_rival_margin_nats;
        const bool weak = weight < p_.unlocalize_weight && !only_poor_rival &&
                          (!discount || sighted_share < p_.unlocalize_weight);
        const bool lost = weight < p_.lock_min_weight;
        const bool twin_ahead = in.twin_log_ratio < -p_.lock_rival_margin_nats;
        // A weight loss breaks the lock once it has lasted lock_break_hold_s; a spread (the pose itself is no
        // longer sure), another hypothesis taking over (a jump) or the twin ahead at once.
        const bool light = weak || lost;
        if (!light) {
            has_break_ = false;
        } else if (!has_break_) {
            has_break_ = true;
            break_since_t_ = in.t;
        }
        if ((light && in.t - break_since_t_ >= p_.lock_break_hold_s) || spread || jumped || twin_ahead) {
            localized_ = false;
            has_candidate_ = false;
            has_break_ = false;
        }
        return;
    }
    // Sightings the dominant hypothesis calls false positives, less likely than the refutation margin allows:
    // some pose outside the cloud explains them, a rival no particle represents.
    const bool unexplained = p_.explain_sightings && in.unexplained_sighting_nats >= p_.rival_refute_nats;
    const bool ambiguous = in.unrefuted_rival_weight > 0 || in.twin_log_ratio < p_.rival_refute_nats || unexplained;
    // Limited tracking: the displacement the hypotheses were weighed over is the least trustworthy; no lock is
    // earned on it, unless the spell has lasted long enough to be the place's normal.
    const bool limited = p_.no_lock_while_limited && in.tracking_limited_s >= 0 &&
                         in.tracking_limited_s <= p_.limited_spell_max_s;
    if (in.dominant_weight > p_.localize_weight && in.std_m < p_.localize_std_m && !ambiguous && !jumped && !limited) {
        if (!has_candidate_) {
            has_candidate_ = true;
            candidate_since_t_ = in.t;
        }
        if (in.t - candidate_since_t_ >= p_.localize_hold_s) localized_ = true;
    } else {
        has_candidate_ = false;
    }
}

}  // namespace wf::loc
