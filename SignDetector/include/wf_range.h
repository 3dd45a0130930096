/*
 * wf_range.h: range and bearing to a rectangular sign (Exit sign) of known size, seen by a calibrated
 * camera whose gravity direction is known. C ABI of SignDetector's range estimation (the sign-perception library).
 *
 * Methods (docs/range-estimation.md derives each one):
 *   - apparent height (the product's method): Fusco, Cheraghi, Neat & Coughlan 2020, section 3,
 *     equation (3): Z = h0 / (tan(pitch + alpha + delta) - tan(pitch + alpha)). Two forms:
 *       * wf_range_apparent_height_slices: from the slice medians of a segmentation in the unrolled image
 *         (the paper's measurement);
 *       * wf_range_apparent_height_exact: from the raw-image points of the sign's top-centre and
 *         bottom-centre and the full camera rotation, Z = h0 / (tan(e_top) - tan(e_bottom)), where e is the
 *         elevation of a ray above the horizontal plane. Exact for any roll and pitch.
 *   - horizon (older baseline): Z = (sign centre height - camera height) / tan(elevation of sign centre);
 *   - PnP: OpenCV solvePnP (IPPE and SQPnP candidates, LM refinement) on the four corners with the sign's
 *     width and height.
 *
 * Conventions (App/SessionFormat/CameraPose.swift, ../shared/reference/arkit-frames.md):
 *   - world: gravity aligned, y up, x and z horizontal (ARKit); only the rotation of a pose is used;
 *   - camera: x along image u (right), y along image -v (up), looks along -z; a raw pixel (u, v) is the
 *     world ray R * [(u - cx)/fx, -(v - cy)/fy, -1] with R the camera-to-world rotation;
 *   - 4x4 poses are 16 doubles in column-major order (ARKit/simd), translation in elements 12..14;
 *   - pitch: elevation of the optical axis above the horizon, positive looking up; roll: angle of world up
 *     in the camera x-y plane, atan2(up_x, up_y): 0 = landscape upright, -pi/2 = portrait (camera x down);
 *   - range: horizontal distance from the camera centre to the sign's centre line, meters;
 *   - bearing: horizontal angle of the sign centre from the camera's forward direction (projected on the
 *     horizontal plane), radians, positive to the LEFT (counter-clockwise seen from above), in (-pi, pi];
 *   - corners: raw-image pixels of the sign's top-left, top-right, bottom-right, bottom-left corners as
 *     the upright sign is seen (TL, TR, BR, BL), which is clockwise on the screen (v down).
 *
 * ABI rules: every function returns an int status, 0 (WF_STATUS_OK) on success and a negative
 * wf_status.h code on failure; outputs come first and are written only on success; no C++ exception
 * crosses this boundary; no function returns memory to free, keeps a pointer after it returns, or has
 * global state (all are thread-safe). Inputs are borrowed for the duration of the call.
 */
#ifndef WF_RANGE_H
#define WF_RANGE_H

#include <stddef.h>

#include "wf_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes: the shared vocabulary of wf_status.h. Range functions return WF_STATUS_OK or one of
 * WF_STATUS_INVALID_ARGUMENT (a NULL pointer), WF_STATUS_NON_FINITE_INPUT, WF_STATUS_NONPOSITIVE_SIZE,
 * WF_STATUS_DEGENERATE_CORNERS, WF_STATUS_DEGENERATE_GEOMETRY, WF_STATUS_NOT_A_ROTATION, WF_STATUS_PNP_FAILED,
 * WF_STATUS_VERSION, WF_STATUS_MISSING_INPUT, WF_STATUS_INTERNAL; wf_status_string describes each. */

/** A point in image pixels (u right, v down, continuous coordinates: the same ones as the principal
 * point). */
typedef struct wf_range_point {
    /** Column coordinate, pixels (right). */
    double u;
    /** Row coordinate, pixels (down). */
    double v;
} wf_range_point;

/** Pinhole intrinsics of the raw (sensor-orientation) image, pixels. No lens distortion (ARKit images are
 * rectified enough for this use). fx and fy may differ. */
typedef struct wf_range_intrinsics {
    /** Focal length along u, pixels (> 0). */
    double fx;
    /** Focal length along v, pixels (> 0). */
    double fy;
    /** Principal point u, pixels. */
    double cx;
    /** Principal point v, pixels. */
    double cy;
} wf_range_intrinsics;

/** Result of a range estimate. */
typedef struct wf_range_result {
    /** Horizontal distance from the camera centre to the sign's vertical centre line, meters (> 0). */
    double range_m;
    /** Horizontal angle of the sign centre from the camera forward direction, radians, positive to the
     * left (CCW seen from above), in (-pi, pi]. */
    double bearing_rad;
    /** Height of the sign's centre above the camera centre, meters (negative below), as this method sees it
     * (for the horizon method, the given heights' difference). */
    double center_height_above_camera_m;
} wf_range_result;

/* ------------------------------------------------------------------------------------------------------
 * Camera orientation helpers
 * ---------------------------------------------------------------------------------------------------- */

/** Builds the column-major 4x4 camera-to-world transform (zero translation) of a camera with the given
 * pitch and roll whose forward direction projects on world -z (yaw irrelevant for range and bearing):
 * R = Rx(pitch_rad) * Rz(roll_rad), the CameraPose.swift construction with VIO yaw pi/2. */
int wf_range_camera_to_world_from_pitch_roll(double out_camera_to_world[16], double pitch_rad, double roll_rad);

/** Pitch (asin of forward's world-y component) and roll (atan2(up_x, up_y), up = R^T * world up) of a
 * column-major camera-to-world transform; the same definitions as CameraPose.pitchRad / rollRad. */
int wf_range_pitch_roll_from_camera_to_world(double *out_pitch_rad, double *out_roll_rad,
                                             const double camera_to_world[16]);

/* ------------------------------------------------------------------------------------------------------
 * Unrolling of points
 *
 * The unrolled image is the image of a virtual camera at the same centre, with the same optical axis, rotated
 * about that axis by -roll so that its roll is 0: world-vertical planes through the camera centre and the
 * optical axis appear as the centre column, and the horizon is horizontal. The mapping goes through
 * normalised coordinates, so it is exact when fx != fy:
 *   x = (u - cx) / fx,  y = (v - cy) / fy                       (raw, v down)
 *   [x'; y'] = [cos r, sin r; -sin r, cos r] * [x; y]          (r = roll_rad; rotation by -r in u-v)
 *   u' = cx' + f' x',  v' = cy' + f' y'                         (unrolled, square pixels f' = sqrt(fx fy))
 * When fx == fy this is the rotation of pixel coordinates by -roll about the principal point, i.e. what
 * an image rotation does (for roll = -pi/2 the 1920 x 1440 image becomes 1440 x 1920). The unrolled
 * canvas is the bounding box of the mapped raw image corners, and (cx', cy') the principal point in it.
 * ---------------------------------------------------------------------------------------------------- */

/** The mapping between raw and unrolled pixels for one camera roll. Plain data; fill with
 * wf_range_unroll_map_make. */
typedef struct wf_range_unroll_map {
    /** Raw intrinsics. */
    wf_range_intrinsics raw;
    /** Camera roll, radians (see conventions). */
    double roll_rad;
    /** Unrolled intrinsics: square pixels of focal f' = sqrt(fx * fy) and the principal point (cx', cy') in
     * the unrolled canvas; unrolled.fx == unrolled.fy. */
    wf_range_intrinsics unrolled;
    /** Width of the unrolled canvas (bounding box of the raw image's mapped corners), pixels. */
    double unrolled_width_px;
    /** Height of the unrolled canvas, pixels. */
    double unrolled_height_px;
} wf_range_unroll_map;

/** Fills out_map for raw intrinsics, a roll and the raw image size (pixels, > 0). */
int wf_range_unroll_map_make(wf_range_unroll_map *out_map, const wf_range_intrinsics *raw, double roll_rad,
                             double image_width_px, double image_height_px);

/** Maps a raw pixel to the unrolled image. */
int wf_range_unroll_point(wf_range_point *out_unrolled, const wf_range_unroll_map *map,
                          const wf_range_point *raw);

/** Maps an unrolled pixel back to the raw image (exact inverse of wf_range_unroll_point). */
int wf_range_reroll_point(wf_range_point *out_raw, const wf_range_unroll_map *map,
                          const wf_range_point *unrolled);

/* ------------------------------------------------------------------------------------------------------
 * Apparent-height method, from slice medians (the paper's measurement)
 * ---------------------------------------------------------------------------------------------------- */

/** A camera described in the unrolled image: intrinsics of the unrolled image (pixels), the pitch of the
 * optical axis and, for reference only, the raw camera's roll that was undone. */
typedef struct wf_range_unrolled_camera {
    /** Focal length along u of the unrolled image, pixels. */
    double fx;
    /** Focal length along v of the unrolled image, pixels. */
    double fy;
    /** Principal point u in the unrolled image, pixels. */
    double cx;
    /** Principal point v in the unrolled image, pixels. */
    double cy;
    /** Elevation of the optical axis, radians, positive up, |pitch| < pi/2. */
    double pitch_rad;
    /** Roll of the raw camera that the unrolling removed, radians (not used by the computation). */
    double roll_rad;
} wf_range_unrolled_camera;

/** The sign as measured in the unrolled image from vertical slices (columns) of its segmentation. Rows are
 * continuous pixel coordinates of the sign's edges: for a mask whose pixel centres are at integer
 * coordinates and a column covering rows top..bottom inclusive, bottom edge = bottom + 0.5 and height =
 * bottom - top + 1. */
typedef struct wf_range_slice_measurement {
    /** Median over the columns of the sign's bottom edge row, unrolled pixels (v down). */
    double median_bottom_row_px;
    /** Median over the columns of the sign's height (bottom edge - top edge), pixels, > 0. */
    double median_height_px;
    /** The sign's centre column, unrolled pixels (midpoint of the columns' extent). */
    double center_column_px;
    /** Slope dv/du of the bottom edge in the unrolled image (robust: median of slopes between column pairs
     * half the extent apart). 0 = level, the assumption when unknown. */
    double bottom_edge_slope;
    /** Slope dv/du of the top edge, as bottom_edge_slope. */
    double top_edge_slope;
    /** Width of the columns' extent (max - min column), pixels; 0 = unknown. With the slopes it locates the
     * sign's corners, hence its centre line, which is off the extent's middle for a sign not facing the
     * camera (the nearer half looks wider). */
    double extent_width_px;
} wf_range_slice_measurement;

/** How a slice measurement becomes two elevations. */
typedef enum wf_range_slice_model {
    /** Elevations of two points of the sign's vertical centre line. The corners are reconstructed in the
     * unrolled image: edge lines from the medians (at the extent's middle) and slopes; side edges through
     * the vertical vanishing point (cx, cy - fy / tan(pitch)) and the extent's ends; then the centre line's
     * top and bottom points by the construction of wf_range_sign_center_points. Without an extent (or if that
     * degenerates): the bottom point (center column, median bottom row) and the top point where the image
     * of the world vertical through it meets the top edge line. Equals the paper's formula at the centre
     * column of a level sign; off-axis it also corrects what the planar formula gets wrong: that it gives
     * the depth in the optical axis's vertical plane (about range * cos(bearing)), and that under pitch
     * world verticals slant in the image. Exact on exact masks up to the column sampling. The default. */
    WF_RANGE_SLICE_MODEL_RAY_ELEVATION = 0,
    /** The paper's equation (3) verbatim: alpha = atan((cy - v_bottom) / fy), alpha + delta =
     * atan((cy - v_top) / fy), the column and slopes ignored for the range. */
    WF_RANGE_SLICE_MODEL_PAPER_PLANAR = 1,
    /** Not a model: makes the enum int-sized, so that any int a C caller passes is a valid value in C++
     * (and is rejected with WF_STATUS_MISSING_INPUT rather than being undefined behaviour). */
    WF_RANGE_SLICE_MODEL_MAX_ENUM = 0x7FFFFFFF
} wf_range_slice_model;

/** Paper equation (3): out_range_m = h0 / (tan(pitch + alpha + delta) - tan(pitch + alpha)). Both angle
 * sums must lie in (-pi/2, pi/2) and the difference of tangents be > 0. */
int wf_range_paper_equation3(double *out_range_m, double pitch_rad, double alpha_rad, double delta_rad,
                             double sign_height_m);

/** Range and bearing from slice medians in the unrolled image (apparent-height method). The bearing is
 * the azimuth of the bottom and top rays of the RAY_ELEVATION model for both models.
 * center_height_above_camera_m is computed from the top and bottom elevations. sign_height_m: physical
 * height h0 of the sign face, m. */
int wf_range_apparent_height_slices(wf_range_result *out, const wf_range_unrolled_camera *camera,
                                    const wf_range_slice_measurement *measurement, double sign_height_m,
                                    wf_range_slice_model model);

/** Slice medians from per-column edges of a segmentation in the unrolled image: column_u[i], top_row[i]
 * and bottom_row[i] (continuous edge rows, top < bottom) for count >= 1 columns, in increasing column
 * order. The centre column is the midpoint of min and max column_u, the extent width max - min. Medians and
 * slopes use the columns of the central 60 % of the extent only (the SignDetector's default slice band):
 * near the ends a column's top or bottom is a slanted side edge. The edge slopes are the medians of the
 * slopes between band columns j and j + n / 2 (0 for a single column). Non-finite values are an error. */
int wf_range_slice_measurement_from_columns(wf_range_slice_measurement *out, const double *column_u,
                                            const double *top_row, const double *bottom_row, size_t count);

/* ------------------------------------------------------------------------------------------------------
 * Exact methods on raw-image points with the full rotation
 * ---------------------------------------------------------------------------------------------------- */

/** Apparent-height method, exact: top_center and bottom_center are raw pixels of the images of two points
 * on the same vertical world line (the sign's top-centre and bottom-centre). With e the elevation of a
 * ray, atan2(ray_y, hypot(ray_x, ray_z)), range = h0 / (tan(e_top) - tan(e_bottom)); bearing from the
 * rays' azimuth. camera_to_world: column-major 4x4, only its rotation is used. */
int wf_range_apparent_height_exact(wf_range_result *out, const wf_range_point *top_center,
                                   const wf_range_point *bottom_center, const wf_range_intrinsics *intrinsics,
                                   const double camera_to_world[16], double sign_height_m);

/** Horizon method: range = (sign_center_height_m - camera_height_m) / tan(e_center), heights above the
 * floor in meters, e_center the elevation of the ray through the raw pixel center. */
int wf_range_horizon(wf_range_result *out, const wf_range_point *center, const wf_range_intrinsics *intrinsics,
                     const double camera_to_world[16], double camera_height_m, double sign_center_height_m);

/** Images of the sign's centre, top-centre and bottom-centre from its four corners (TL, TR, BR, BL raw
 * pixels), exact under perspective: the centre is the intersection of the diagonals; the vertical centre
 * line joins it to the vanishing point of the left and right edges (homogeneous, so parallel edges work);
 * top- and bottom-centre are that line's intersections with the top and bottom edges. */
int wf_range_sign_center_points(wf_range_point *out_center, wf_range_point *out_top_center,
                                wf_range_point *out_bottom_center, const wf_range_point corners[4]);

/** PnP: pose of the sign (width x height rectangle) from its four corners with OpenCV, no distortion.
 * Candidates: both solutions of SOLVEPNP_IPPE (solvePnPGeneric; a planar target's two-fold ambiguity) and
 * SOLVEPNP_SQPNP's, each refined with solvePnPRefineLM; the one of least reprojection error with the sign
 * in front wins. The translation (sign centre in the camera) is rotated to the world; range is its
 * horizontal norm. */
int wf_range_pnp(wf_range_result *out, const wf_range_point corners[4], const wf_range_intrinsics *intrinsics,
                 const double camera_to_world[16], double sign_width_m, double sign_height_m);

/* ------------------------------------------------------------------------------------------------------
 * One entry point for all methods on the same inputs
 * ---------------------------------------------------------------------------------------------------- */

/** Range estimation methods. */
typedef enum wf_range_method {
    /** wf_range_apparent_height_exact on the top/bottom-centre points from the corners. */
    WF_RANGE_METHOD_APPARENT_HEIGHT = 0,
    /** wf_range_horizon on the centre point from the corners. */
    WF_RANGE_METHOD_HORIZON = 1,
    /** wf_range_pnp on the corners. */
    WF_RANGE_METHOD_PNP = 2,
    /** Not a method: makes the enum int-sized (see WF_RANGE_SLICE_MODEL_MAX_ENUM). */
    WF_RANGE_METHOD_MAX_ENUM = 0x7FFFFFFF
} wf_range_method;

/** Current version of wf_range_observation. */
#define WF_RANGE_OBSERVATION_VERSION 1

/** One sign seen in one frame. Initialise with WF_RANGE_OBSERVATION_INIT, then fill the fields. Optional
 * numbers are NaN when absent. */
typedef struct wf_range_observation {
    /** Must be WF_RANGE_OBSERVATION_VERSION. */
    unsigned int version;
    /** Raw-image corners TL, TR, BR, BL of the upright sign, pixels. */
    wf_range_point corners[4];
    /** Raw-image intrinsics, pixels. */
    wf_range_intrinsics intrinsics;
    /** Camera-to-world transform, column-major 4x4 (only the rotation is used). */
    double camera_to_world[16];
    /** Physical height of the sign face, meters (required). */
    double sign_height_m;
    /** Physical width of the sign face, meters (PnP only; NaN when absent). */
    double sign_width_m;
    /** Camera height above the floor, meters (horizon only; NaN when absent). */
    double camera_height_m;
    /** Height of the sign's centre above the floor, meters (horizon only; NaN when absent). */
    double sign_center_height_m;
} wf_range_observation;

/** Initialiser: version set, everything else zero, optional fields NaN (uses the compiler's NaN builtin). */
#define WF_RANGE_OBSERVATION_INIT                                                                           \
    {WF_RANGE_OBSERVATION_VERSION, {{0, 0}, {0, 0}, {0, 0}, {0, 0}}, {0, 0, 0, 0},                         \
     {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, 0, __builtin_nan(""), __builtin_nan(""),              \
     __builtin_nan("")}

/** Runs one method on an observation. */
int wf_range_estimate(wf_range_result *out, wf_range_method method, const wf_range_observation *observation);

#ifdef __cplusplus
}
#endif

#endif /* WF_RANGE_H */
