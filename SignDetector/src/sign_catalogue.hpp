// The sign-kind catalogue: each kind's face size (and colours, sidedness), read from the map's "signKinds"
// (Maps/schema/map-v1.schema.json) and handed to wf_detector_create. Range estimation takes the face height
// from here, so no sign size is written anywhere else in the library.
#pragma once

#include "wf_sign_detector.h"

#include <string>
#include <vector>

namespace wf::sign {

/// One kind of sign (wf_sign_kind, copied).
struct SignKindSpec {
    /// Kind name as the detector reports it ("exit").
    std::string kind;
    /// Face height and width, meters (> 0).
    double faceHeightMeters = 0;
    double faceWidthMeters = 0;
    /// Background and legend colours ("" = unknown).
    std::string faceColour, legendColour;
    /// A face on both sides.
    bool doubleSided = false;
    /// Height of the face's centre above the camera for the cascade's placement prior, meters; both 0 = the
    /// detector's defaults (Exit signs).
    double centreAboveCameraMinMeters = 0;
    double centreAboveCameraMaxMeters = 0;
    /// Farthest recognition range, meters; 0 = no limit.
    double maxRangeMeters = 0;
    /// The legend is text to read (a room-number placard).
    bool readsText = false;

    /// True when the kind's legend or face is red or green, or both colours are unknown: the Exit-sign-like kinds
    /// the cascade's red/green colour gate finds. Pictograms (white on blue or dark) and placards are searched
    /// without it.
    bool colourGated() const;
    /// True when the entry gives its own placement band (centreAboveCamera*).
    bool hasPlacement() const { return centreAboveCameraMinMeters != 0 || centreAboveCameraMaxMeters != 0; }
};

/// Copies and checks `count` catalogue entries. A NULL array with count > 0, a NULL, empty or too long name, a
/// face size that is not a positive finite number of meters, or one kind listed twice with different sizes or
/// sidedness is an error (WF_STATUS_INVALID_ARGUMENT for the NULL array, WF_STATUS_INVALID_CATALOGUE otherwise,
/// `error` naming the entry); a kind listed twice identically is kept once. count == 0 gives an empty catalogue.
int parseCatalogue(const wf_sign_kind* entries, size_t count, std::vector<SignKindSpec>* out, std::string* error);

/// The entry of `kind`, or nullptr.
const SignKindSpec* findKind(const std::vector<SignKindSpec>& catalogue, const std::string& kind);

}  // namespace wf::sign
