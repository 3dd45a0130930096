/* wf_status_string: names of the shared status codes (include/wf_status.h). */
#include "wf_status.h"

const char *wf_status_string(int status) {
    switch (status) {
        case WF_STATUS_OK: return "ok";
        case WF_STATUS_SKIPPED_DARK_FRAME: return "frame skipped: too dark";
        case WF_STATUS_TRUNCATED: return "output truncated to its capacity";
        case WF_STATUS_INVALID_ARGUMENT: return "invalid argument";
        case WF_STATUS_OUT_OF_MEMORY: return "out of memory";
        case WF_STATUS_VERSION: return "unsupported struct version";
        case WF_STATUS_INVALID_MAP: return "invalid map";
        case WF_STATUS_NO_WALKABLE_SPACE: return "no walkable space";
        case WF_STATUS_NOT_INITIALIZED: return "not initialized";
        case WF_STATUS_NON_FINITE_INPUT: return "input is NaN or infinite";
        case WF_STATUS_INTERNAL: return "internal error";
        case WF_STATUS_MODEL_LOAD: return "model file missing or unreadable";
        case WF_STATUS_BAD_FRAME: return "bad frame";
        case WF_STATUS_IMAGE_READ: return "image file unreadable";
        case WF_STATUS_INVALID_CATALOGUE: return "invalid sign-kind catalogue";
        case WF_STATUS_NONPOSITIVE_SIZE: return "a size is zero or negative";
        case WF_STATUS_DEGENERATE_CORNERS: return "degenerate sign corners";
        case WF_STATUS_DEGENERATE_GEOMETRY: return "degenerate geometry: no finite positive range";
        case WF_STATUS_NOT_A_ROTATION: return "camera-to-world block is not a rotation";
        case WF_STATUS_PNP_FAILED: return "PnP failed";
        case WF_STATUS_MISSING_INPUT: return "a required input is absent";
        default: return "unknown status";
    }
}
