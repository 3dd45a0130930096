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
        if (const SignKindSpec* previous = findKind(*out, spec.kind)) {
            if (previous->faceHeightMeters != spec.faceHeightMeters || previous->faceWidthMeters != spec.faceWidthMeters ||
                previous->doubleSided != spec.doubleSided) {
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

const SignKindSpec* findKind(const std::vector<SignKindSpec>& catalogue, const std::string& kind) {
    for (const SignKindSpec& s : catalogue) {
        if (s.kind == kind) return &s;
    }
    return nullptr;
}

}  // namespace wf::sign
