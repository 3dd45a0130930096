/*
 * wf_status.h: the one status vocabulary of Wayfinder's C ABIs (LocalizerCore's wf_localizer.h, SignDetector's
 * wf_sign_detector.h and wf_range.h). Every function of those headers that can fail returns an int:
 *   0           WF_STATUS_OK
 *   > 0         a warning: the call did its job, with a remark (e.g. a dark frame skipped)
 *   < 0         an error: nothing was written to the outputs; the library's last-error function says why
 * Codes are unique across the libraries, so a status can be printed with wf_status_string whichever library
 * returned it. Plain #defines (not an enum) so that Swift imports them as Int32 constants.
 */
#ifndef WF_STATUS_H
#define WF_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Success and warnings ------------------------------------------------------------------------------ */

/** Success. */
#define WF_STATUS_OK 0
/** Warning (detector): the frame was skipped (mean luma < 2: lens covered, phone in a pocket); no signs. */
#define WF_STATUS_SKIPPED_DARK_FRAME 1
/** Warning (detector): more signs were found than the output capacity; the highest-scoring ones were written. */
#define WF_STATUS_TRUNCATED 2

/* ---- Errors shared by every library --------------------------------------------------------------------- */

/** A NULL pointer, a count out of range, or an option outside its documented range (the message names it). */
#define WF_STATUS_INVALID_ARGUMENT (-1)
/** Allocation failed. */
#define WF_STATUS_OUT_OF_MEMORY (-2)
/** A struct carries a version this library does not know (localizer map and options, range observation). */
#define WF_STATUS_VERSION (-3)
/** An input carried NaN or infinity. */
#define WF_STATUS_NON_FINITE_INPUT (-7)
/** An unexpected internal failure (a caught C++ exception; a bug); the message says what. */
#define WF_STATUS_INTERNAL (-8)

/* ---- Localizer ------------------------------------------------------------------------------------------ */

/** The map is unusable (no floors, non-finite coordinates, a floor index out of range). */
#define WF_STATUS_INVALID_MAP (-4)
/** The requested floor has no walkable cell, or the start point is not inside the map. */
#define WF_STATUS_NO_WALKABLE_SPACE (-5)
/** The filter has not been initialised yet (call an init function first). */
#define WF_STATUS_NOT_INITIALIZED (-6)

/* ---- Sign perception: detector -------------------------------------------------------------------------- */

/** A model file (cascade XML, ONNX, classes.json) is missing or unreadable. */
#define WF_STATUS_MODEL_LOAD (-20)
/** The frame was rejected: empty, a stride or size that does not match its pixel format or its intrinsics,
 *  non-finite intrinsics, pitch or roll. */
#define WF_STATUS_BAD_FRAME (-21)
/** An image file could not be read or decoded. */
#define WF_STATUS_IMAGE_READ (-22)
/** The sign-kind catalogue is empty where sizes are needed, names a kind twice with different sizes, or gives
 *  a size that is not a positive finite number of meters. */
#define WF_STATUS_INVALID_CATALOGUE (-23)

/* ---- Sign perception: range ----------------------------------------------------------------------------- */

/** A size is zero or negative: sign height or width, focal length, image size, pixel height. */
#define WF_STATUS_NONPOSITIVE_SIZE (-30)
/** The four corners are not a convex, non-degenerate quadrilateral in TL, TR, BR, BL order, or a
 *  construction from them is at infinity. */
#define WF_STATUS_DEGENERATE_CORNERS (-31)
/** The geometry has no finite positive range (sign of no angular height or upside down, an angle at or beyond
 *  +-90 degrees, the camera looking straight up or down, a horizon-method sign at camera height). */
#define WF_STATUS_DEGENERATE_GEOMETRY (-32)
/** The 3x3 block of a camera-to-world matrix is not a rotation (tolerance 1e-3). */
#define WF_STATUS_NOT_A_ROTATION (-33)
/** OpenCV's solvePnP failed or returned a pose with the sign behind the camera. */
#define WF_STATUS_PNP_FAILED (-34)
/** The chosen method needs an input given as NaN (absent), or an enum value is unknown. */
#define WF_STATUS_MISSING_INPUT (-35)

/** A static English description of a status code, e.g. "invalid argument" (never NULL; do not free).
 *  Unknown codes give "unknown status". */
const char *wf_status_string(int status);

#ifdef __cplusplus
}
#endif

#endif /* WF_STATUS_H */
