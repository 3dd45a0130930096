#include "sign_catalogue.hpp"

#include <cmath>
#include <sstream>

namespace wf::sign {

int parseCatalogue(const wf_sign_kind* entries, size_t count, std::vector<SignKindSpec>* out, std::string* error) {
    out->clear();
    if (count > 0 && entries == nullptr) {
        *error = "catalogue_count is " + std::to_string(count) + " but catalogue is NULL";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    for (size_t i = 0; i < count; ++i) {
        const wf_sign_kind& e = entries[i];
        std::ostringstream where;
        where << "sign-kind catalogue entry " << i;
        if (e.kind == nullptr || e.kind[0] == '\0' || std::string(e.kind).size() >= WF_KIND_NAME_CAPACITY) {
            *error = where.str() + ": kind name must have 1 to " + std::to_string(WF_KIND_NAME_CAPACITY - 1) +
                     " characters";
            return WF_STATUS_INVALID_CATALOGUE;
        }
        SignKindSpec spec;
        spec.kind = e.kind;
        where << " ('" << spec.kind << "')";
        for (const auto& [name, value] : {std::pair<const char*, double>{"face_height_m", e.face_height_m},
                                          std::pair<const char*, double>{"face_width_m", e.face_width_m}}) {
            if (!std::isfinite(value) || value <= 0) {
                std::ostringstream msg;
                msg << where.str() << ": " << name << " " << value << " must be a positive number of meters";
                *error = msg.str();
                return WF_STATUS_INVALID_CATALOGUE;
            }
        }
        spec.faceHeightMeters = e.face_height_m;
        spec.faceWidthMeters = e.face_width_m;
        if (e.face_colour) spec.faceColour = e.face_colour;
        if (e.legend_colour) spec.legendColour = e.legend_colour;
        spec.doubleSided = e.double_sided != 0;
        const bool placementGiven = e.centre_above_camera_min_m != 0 || e.centre_above_camera_max_m != 0;
        if (placementGiven && !(std::isfinite(e.centre_above_camera_min_m) && std::isfinite(e.centre_above_camera_max_m) &&
                                e.centre_above_camera_min_m < e.centre_above_camera_max_m)) {
            std::ostringstream msg;
            msg << where.str() << ": centre_above_camera_min_m " << e.centre_above_camera_min_m
                << " must be finite and below centre_above_camera_max_m " << e.centre_above_camera_max_m;
            *error = msg.str();
            return WF_STATUS_INVALID_CATALOGUE;
        }
        if (!(std::isfinite(e.max_range_m) && e.max_range_m >= 0)) {
            std::ostringstream msg;
            msg << where.str() << ": max_range_m " << e.max_range_m << " must be 0 (no limit) or a positive number of meters";
            *error = msg.str();
            return WF_STATUS_INVALID_CATALOGUE;
        }
        if (e.reads_text != 0 && e.reads_text != 1) {
            *error = where.str() + ": reads_text must be 0 or 1, not " + std::to_string(e.reads_text);
            return WF_STATUS_INVALID_CATALOGUE;
        }
        spec.centreAboveCameraMinMeters = e.centre_above_camera_min_m;
        spec.centreAboveCameraMaxMeters = e.centre_above_camera_max_m;
        spec.maxRangeMeters = e.max_range_m;
        spec.readsText = e.reads_text == 1;
        if (const SignKindSpec* previous = findKind(*out, spec.kind)) {
            if (previous->faceHeightMeters != spec.faceHeightMeters || previous->faceWidthMeters != spec.faceWidthMeters ||
                previous->doubleSided != spec.doubleSided || previous->readsText != spec.readsText ||
                previous->maxRangeMeters != spec.maxRangeMeters ||
                previous->centreAboveCameraMinMeters != spec.centreAboveCameraMinMeters ||
                previous->centreAboveCameraMaxMeters != spec.centreAboveCameraMaxMeters) {
                std::ostringstream msg;
                msg << where.str() << " contradicts an earlier entry of the same kind: " << spec.faceWidthMeters << " x "
                    << spec.faceHeightMeters << " m against " << previous->faceWidthMeters << " x "
                    << previous->faceHeightMeters << " m";
                *error = msg.str();
                return WF_STATUS_INVALID_CATALOGUE;
            }
            continue;  // an identical repeat
        }
        out->push_back(std::move(spec));
    }
    return WF_STATUS_OK;
}

bool SignKindSpec::colourGated() const {
    auto redOrGreen = [](const std::string& c) { return c == "red" || c == "green"; };
    if (faceColour.empty() && legendColour.empty()) return true;
    return redOrGreen(faceColour) || redOrGreen(legendColour);
}

const SignKindSpec* findKind(const std::vector<SignKindSpec>& catalogue, const std::string& kind) {
    for (const SignKindSpec& s : catalogue) {
        if (s.kind == kind) return &s;
    }
    return nullptr;
}

}  // namespace wf::sign
