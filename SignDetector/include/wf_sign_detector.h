/*
 * wf_sign_detector.h — C ABI of the Wayfinder run-time sign detector (C++17 / OpenCV 4.6 inside).
 *
 * Pipeline per frame (docs/sign-detection.md; Fusco et al. 2020, section 3, in
 * ../shared/reference/paper.md):
 *   1. validate the frame (bad frames are rejected with WF_STATUS_BAD_FRAME or skipped with a positive
 *      warning status, never a crash);
 *   2. "unroll": rotate the raw camera image about the principal point by the camera roll so that the
 *      horizon is horizontal (exact cv::rotate for multiples of 90 degrees, cv::warpAffine otherwise);
 *   3. detect signs on the unrolled image, either with per-kind AdaBoost cascades (a rough box per
 *      sign) or with a U-Net (coarse 224x224 pass, then a zoomed 224x224 pass per candidate);
 *   4. measure each sign by vertical slices: median height, median bottom edge, centre column.
 *   5. (wf_detector_sense) range and bearing of each sign from its slices and its kind's face height in the
 *      sign-kind catalogue (wf_range.h's apparent-height method): one call per frame from frame to sightings.
 *
 * Conventions
 *   - Pixel coordinates are pixel-centre based: pixel (column i, row j) covers [i-0.5, i+0.5] x
 *     [j-0.5, j+0.5]; u right, v down. The same convention is used for the principal point.
 *   - Roll (radians) is ARKit's Euler roll: 0 = landscape with the image top up, -pi/2 = portrait
 *     (the traveler's posture; world up points to raw image -u). Pitch (radians) is positive looking up.
 *   - "Unrolled" quantities live in the rotated image in which world-up is image-up (-v).
 *
 * Conventions of the ABI (libgit2 / sqlite style)
 *   - Every function returns int: 0 = WF_STATUS_OK, > 0 = a warning (the call did its job, see the status
 *     list), < 0 = an error; wf_detector_last_error() then gives a message naming the problem.
 *   - Opaque handles; every allocation has its free function; *_free(NULL) is a no-op.
 *   - Initialise options with WF_DETECTOR_OPTIONS_INIT or wf_detector_options_init() (all zero). Zero in
 *     a numeric option field means "use the default" given in its comment; no behaviour depends on a
 *     version number: every choice is a named option.
 *   - No C++ exception crosses this boundary. A handle is not thread-safe: use one handle per thread
 *     or serialise calls (the Swift wrapper serialises).
 *   - Every type name here must be unique among ALL C headers linked into the app (LocalizerCore's
 *     wf_localizer.h / wf_range.h included). Swift imports every C type into one module (`__C`) and
 *     emits its metadata (size, stride, value witnesses) as weak symbols that the linker merges by
 *     name, so two different structs with one name silently share one layout in Swift. This is why
 *     the detector's output is wf_detector_observation: LocalizerCore already has a 32-byte
 *     wf_sign_observation (kind, range, bearing, score).
 */
#ifndef WF_SIGN_DETECTOR_H
#define WF_SIGN_DETECTOR_H

#include <stddef.h>
#include <stdint.h>

#include "wf_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Status codes ---------------------------------------------------------------------------- */
/* The shared vocabulary of wf_status.h: WF_STATUS_OK; warnings WF_STATUS_SKIPPED_DARK_FRAME, WF_STATUS_TRUNCATED;
 * errors WF_STATUS_INVALID_ARGUMENT, WF_STATUS_MODEL_LOAD, WF_STATUS_BAD_FRAME, WF_STATUS_IMAGE_READ,
 * WF_STATUS_INVALID_CATALOGUE, WF_STATUS_INTERNAL. */

/* ---- Images ---------------------------------------------------------------------------------- */

/** Pixel layout of an input image. */
typedef enum wf_pixel_format {
    /** 8-bit luma, 1 byte per pixel. */
    WF_PIXEL_GRAY8 = 0,
    /** 8-bit B, G, R, A (an iPhone kCVPixelFormatType_32BGRA buffer), 4 bytes per pixel. */
    WF_PIXEL_BGRA8 = 1,
    /** 8-bit R, G, B, 3 bytes per pixel. */
    WF_PIXEL_RGB8 = 2,
    /** Bi-planar 4:2:0 full-range YCbCr (ARKit's capturedImage,
     *  kCVPixelFormatType_420YpCbCr8BiPlanarFullRange): `data` = Y plane (width x height), `data_uv` =
     *  interleaved Cb, Cr plane ((width/2) x (height/2) pairs). `data_uv` may be NULL: the frame is then
     *  processed as gray (enough for cascades; a U-Net sees R = G = B = Y). */
    WF_PIXEL_NV12 = 3
} wf_pixel_format;

/** A borrowed view of caller-owned pixels; the detector never keeps the pointers after a call. */
typedef struct wf_image {
    /** First byte of the first row (for NV12: of the Y plane). */
    const uint8_t *data;
    /** Width and height in pixels (> 0). */
    int width;
    int height;
    /** Bytes from one row to the next (>= width * bytes per pixel). */
    size_t stride;
    /** Layout of `data`. */
    wf_pixel_format format;
    /** NV12 only: first byte of the interleaved CbCr plane, or NULL; ignored for other formats. */
    const uint8_t *data_uv;
    /** NV12 only: bytes per CbCr row (>= 2 * ((width + 1) / 2)). */
    size_t stride_uv;
    /** Bytes readable from `data` (a buffer's length), or 0 = not stated (the caller vouches for the size). When
     *  set, a frame whose rows (stride x (height - 1) + width x bytes per pixel) do not fit is rejected with
     *  WF_STATUS_BAD_FRAME instead of being read past its end. */
    size_t data_bytes;
    /** NV12 with chroma only: bytes readable from `data_uv`, or 0 = not stated; checked like data_bytes. */
    size_t data_uv_bytes;
} wf_image;

/** Pinhole intrinsics of the raw image, pixels (pixel-centre convention). */
typedef struct wf_intrinsics {
    double fx, fy, cx, cy;
} wf_intrinsics;

/** One camera frame: image, intrinsics, and the camera's gravity angles (radians). */
typedef struct wf_frame {
    wf_image image;
    wf_intrinsics intrinsics;
    /** Elevation of the optical axis above the horizon, radians, positive looking up (|pitch| < pi/2). */
    double pitch_rad;
    /** ARKit Euler roll, radians: 0 = landscape upright, -pi/2 = portrait. */
    double roll_rad;
} wf_frame;

/** An image owned by the library (from wf_image_read); free with wf_owned_image_free. */
typedef struct wf_owned_image {
    /** Pixels, `height` rows of `stride` bytes, allocated by the library. */
    uint8_t *data;
    int width;
    int height;
    size_t stride;
    /** WF_PIXEL_GRAY8, WF_PIXEL_RGB8 or WF_PIXEL_BGRA8, as requested. */
    wf_pixel_format format;
} wf_owned_image;

/**
 * Reads and decodes an image file (PNG, JPEG, BMP... anything cv::imread reads) into `*out`, converted
 * to `format` (GRAY8, RGB8 or BGRA8; NV12 is not offered). On error `*out` is zeroed and the message is
 * available from wf_thread_last_error(). The caller frees the pixels with wf_owned_image_free.
 */
int wf_image_read(wf_owned_image *out, const char *path, wf_pixel_format format);

/** Frees the pixels of an image from wf_image_read and zeroes the struct; NULL is a no-op. */
void wf_owned_image_free(wf_owned_image *image);

/** Message of the last failed handle-less call (wf_image_read, wf_detector_create) on this thread;
 *  "" if none. The string is owned by the library and valid until the next call on this thread. */
const char *wf_thread_last_error(void);

/* ---- Detector -------------------------------------------------------------------------------- */

/** Which detector a handle runs. */
typedef enum wf_detector_kind {
    /** One AdaBoost cascade per sign kind (cv::CascadeClassifier::detectMultiScale); rough boxes. */
    WF_DETECTOR_CASCADE = 0,
    /** U-Net segmentation (cv::dnn, ONNX), coarse pass + zoomed pass per candidate; masks. */
    WF_DETECTOR_UNET = 1
} wf_detector_kind;

/** One kind of sign in the catalogue (read from the map's sign kinds; Maps/schema/map-v1.schema.json
 *  "signKinds"): its name and the physical size of its face, which range estimation needs. */
typedef struct wf_sign_kind {
    /** Kind name as the detector reports it ("exit"...), 1 to WF_KIND_NAME_CAPACITY - 1 characters. */
    const char *kind;
    /** Height of the sign face, meters (> 0, finite): h0 of the apparent-height method. */
    double face_height_m;
    /** Width of the sign face, meters (> 0, finite). */
    double face_width_m;
    /** Colour of the face's background and of its legend (lettering, pictogram), e.g. "white", "red";
     *  NULL = unknown. Copied; informative (the colour gate looks for red/green contrast whatever they are). */
    const char *face_colour;
    const char *legend_colour;
    /** 1 = the sign has a face on both sides (hung across a corridor), 0 = one face. */
    int double_sided;
    /** Where signs of this kind hang, for the cascade's placement prior: the height of the face's centre above
     *  the camera, meters (negative below it). Both 0 = the detector's cascade_sign_above_camera_min_m / _max_m
     *  (Exit signs). A room-number placard or a tactile pictogram (ADA 703.4.1: characters 1.22-1.52 m above the
     *  floor) with the phone 1.0-1.7 m up: about -0.45 .. 0.65 m. Min < max when either is set; finite. */
    double centre_above_camera_min_m;
    double centre_above_camera_max_m;
    /** Farthest horizontal range at which the kind is recognised, meters; 0 = no limit. The cascade of this kind
     *  searches no window smaller than the face at this range (fy x face height / range), which is where most of
     *  a search's windows are. Finite and >= 0. */
    double max_range_m;
    /** 1 = the legend is text to read (a room-number placard): wf_detector_sense reads it into the sighting's
     *  `text` (tesseract where the library was built with it, WF_SIGN_DETECTOR_HAS_TEXT_READER; otherwise the text
     *  stays empty and the iPhone reads it with Vision). 0 = a pictogram or word sign with no identity. */
    int reads_text;
} wf_sign_kind;

/**
 * Detector options. Initialise with WF_DETECTOR_OPTIONS_INIT (all defaults) and set what you need.
 * Strings and arrays are borrowed only during wf_detector_create (they are copied).
 */
typedef struct wf_detector_options {
    /** Detector to run. */
    wf_detector_kind kind;

    /* Sign-kind catalogue (sizes for range; wf_detector_sense). */
    /** `catalogue_count` kinds; may be 0 for wf_detector_detect alone (wf_detector_sense then fails with
     *  WF_STATUS_INVALID_CATALOGUE). A kind named twice with different sizes, a size that is not a positive
     *  finite number, or a NULL / empty / too long name is rejected by wf_detector_create with
     *  WF_STATUS_INVALID_CATALOGUE. */
    const wf_sign_kind *catalogue;
    size_t catalogue_count;

    /* Cascade detector: one cascade per sign kind. With WF_DETECTOR_UNET, cascades of kinds the U-Net has no
     * class for (pictograms, placards) run beside it; a kind that is also a U-Net class is rejected at creation.
     * A cascade whose catalogue entry is not Exit-like (SignKindSpec::colourGated: face or legend red or green, or
     * both unknown) is searched without the colour gate, on its placement band (centre_above_camera_*_m) and out to
     * its max_range_m, on the unrolled frame shrunk to a long side of at most 640 px (docs/sign-detection.md
     * "More sign kinds"). */
    /** `cascade_count` paths of OpenCV cascade XML files. */
    const char *const *cascade_paths;
    /** `cascade_count` kind names ("exit", "restroom"...); NULL = every cascade is "exit". */
    const char *const *cascade_kinds;
    size_t cascade_count;
    /** detectMultiScale scale step; 0 = 1.2. */
    double cascade_scale_factor;
    /** detectMultiScale minNeighbors; 0 = 3. The observation score of a cascade hit is its neighbour count. */
    int cascade_min_neighbors;
    /** Smallest search window, pixels; 0 = the cascade's own training window (e.g. 24 x 16), which lets far
     *  signs be boxed at their true size (the reference app used 36 x 24: signs smaller than 24 px, beyond
     *  about 4.7 m at VGA, were boxed too tall). */
    int cascade_min_window_width;
    int cascade_min_window_height;
    /** Largest window as a multiple of the smallest; 0 = no limit. */
    double cascade_max_window_factor;
    /** Which unrolled rows the cascade searches, by ray elevation (pitch + atan((cy' - v) / fy')): signs mounted
     *  above eye level never appear far below the horizon, and the floor and door panels there are where false
     *  alarms come from. 0 = default: rows at elevation >= -0.15 rad (same recall on the rendered test set as
     *  the whole frame, half the false positives, about 0.7 x the time); 1 = rows at elevation >=
     *  cascade_min_elevation_rad; -1 = the whole frame. */
    int cascade_search_above_elevation;
    /** Lowest elevation searched when cascade_search_above_elevation is 1, radians (e.g. -0.15). */
    double cascade_min_elevation_rad;

    /* U-Net detector. */
    /** Path of the ONNX model: input "image" 1x3xSxS float RGB in [0,1], output "logits" 1xKxSxS. */
    const char *unet_path;
    /** `class_count` class names, index 0 = background. If 0, "classes.json" next to the model is read
     *  ({"classes":["background","exit",...]}); if that is absent the classes are "background",
     *  "class1"... */
    const char *const *class_names;
    size_t class_count;
    /** Network input side, pixels; 0 = 224. */
    int unet_input_size;
    /** Probability above which a pixel belongs to a class; 0 = 0.5. */
    double unet_mask_threshold;
    /** Crop side as a multiple of the coarse blob's larger side (unrolled pixels); 0 = 3.5. */
    double unet_zoom_factor;
    /** Smallest crop side in unrolled (original-resolution) pixels; 0 = 64. */
    int unet_min_crop_px;
    /** Smallest coarse blob, in network pixels; 0 = 3. */
    int unet_min_blob_area_px;
    /** At most this many coarse candidates are zoomed, largest first; 0 = 8. */
    int unet_max_candidates;
    /** U-Net coarse pass: unrolled rows whose ray elevation (pitch + atan((cy' - v) / fy')) is below this are
     *  not run through the network, radians. 0 = default -0.10 (Exit signs hang above eye level; the margin
     *  covers a low sign or a pitch error of about 6 degrees); -1.5 or lower = the whole frame (e.g. for
     *  kinds mounted low). Frames without a finite pitch are always searched whole. Must not be NaN. */
    double unet_coarse_min_elevation_rad;

    /* Both. */
    /** Observations scoring below this are dropped (cascade: neighbour count; U-Net: mean class
     *  probability over the mask); 0 = keep all. */
    double min_score;
    /** Slices: 0 = every column of the middle band; N > 0 = N evenly spaced columns in it. */
    int slice_count;
    /** Fraction of the sign's width, centred, that slices sample; 0 = 0.6. */
    double slice_band_fraction;
    /** Rolls within this of a multiple of pi/2 are treated as that multiple (exact, fast cv::rotate);
     *  0 = always rotate by the exact roll. Radians. */
    double roll_snap_tolerance_rad;

    /* Cascade colour gate (docs/sign-detection.md "colour gate"). */
    /** 1 = search the whole (row-limited) frame; 0 = default: when the frame has colour (RGB8, BGRA8, NV12 with
     *  chroma), search only around regions of strong local red-green contrast (Exit-sign lettering); GRAY8 and
     *  NV12 without chroma are always searched whole (about 20 x slower at VGA: send colour). */
    int cascade_full_search;
    /** Minimum |(R - G) - local mean| of a candidate pixel, 8-bit levels; 0 = 25. */
    double cascade_gate_min_contrast;
    /** Crowded frames: when the gate's regions cover more than 15 % of the searched image (or it would fall back
     *  to the full search), the contrast threshold is multiplied by this once and the stricter regions are
     *  searched. 0 = default 2.5; 1 = off; otherwise must be > 1. */
    double cascade_gate_crowded_contrast_factor;
    /** Smallest margin added around a colour blob's region, pixels of the frame; 0 = default 16 (24 was the
     *  earlier setting). Must not be negative. */
    int cascade_gate_min_margin_px;
    /** Large colour components (cut into tiles): the smallest window searched in a tile's region is this fraction
     *  of the whole component's width. 0 = default 0.4; -1 = off (every window size); otherwise in (0, 1]. Gives
     *  up small signs merged into a large coloured component (a stripe, a poster's edge); docs/benchmarks.md has
     *  the measured trade. */
    double cascade_gate_component_window_fraction;

    /* Cascade placement prior (docs/sign-detection.md "placement prior"). */
    /** 1 or 0 = default: at each scale, search only the rows where a sign whose window is that size can hang (its
     *  centre cascade_sign_above_camera_min_m .. _max_m above the camera; pinhole model with the frame's pitch);
     *  -1 = off (every row at every scale). */
    int cascade_placement_prior;
    /** Height of a sign's centre above the camera for the placement prior, metres; 0 = 0.3 and 2.0 (Exit signs:
     *  bottom edge 2.03 to about 2.6 m above the floor; phone 1.0 to 1.7 m). Min < max when both are set. */
    double cascade_sign_above_camera_min_m;
    double cascade_sign_above_camera_max_m;

    /* Cascades of kinds that are not Exit-like (docs/sign-detection.md "More sign kinds"). */
    /** How many of those kinds a searched frame searches, in rotation: 0 = default 2 (with four such kinds, searched
     *  on every second frame, each is searched on every fourth frame: 2.5 times a second at the phone's 10 Hz
     *  detection rate); N > 0 = N; -1 = all of them. See cascade_wall_kind_frame_period for which frames. */
    int cascade_wall_kinds_per_frame;
    /** Cascade detector: the frame is searched shrunk so that its long side is at most this many pixels, and what
     *  is found there is measured (face edges, slices) on the frame itself: 0 = default 640 (VGA: the cascades'
     *  training size and their speed target), N >= 64 = N, -1 = search the frame at its own size. A full frame
     *  (1920 x 1440) is then searched at VGA's cost and its faces measured with three times the pixels, plus the
     *  shrink (2-5 ms on one core: docs/sign-detection.md "Search at VGA, measure at full size"). */
    int cascade_search_max_long_side_px;

    /* Face-edge refinement (both detectors; docs/sign-detection.md "Face-edge refinement"). */
    /** 0 = default: on; 1 = on; -1 = off. Per slice of each detection's rough box (cascade) or mask (U-Net), the
     *  face's top and bottom edges are located in the image (the half-way crossing of the first persistent rise
     *  of the colour distance from the wall), and the slices measured from them; without it a cascade slice has
     *  the box's height. */
    int face_edge_refinement;
    /** How the refiner reads pixel values: 0 = default (linear), 1 = linear (proportional to light, as the
     *  renderer writes them), 2 = sRGB-encoded (decoded to light first). */
    int face_edge_transfer;

    /* U-Net inference. */
    /** How the network's 2 x 2 stride-2 transposed convolutions (its upsampling steps) run: 0 = default, 1 = as a
     *  1 x 1 convolution to 4 x the channels plus a depth-to-space copy (the same logits within about 3e-6; 15-17 %
     *  less time per pass on one core); -1 = OpenCV's own Deconvolution layer (the baseline). Other values are an
     *  error. */
    int unet_transposed_convolution;

    /* Cascades of kinds that are not Exit-like, continued. */
    /** Plate gate (docs/sign-detection.md "Plate gate"): 0 = default: on; 1 = on; -1 = off. On, those cascades
     *  search only around closed contours of strong edges about as large as a plate (a tactile sign's legend and
     *  plate contrast with what surrounds them), with windows about the contour's size, falling back to their whole
     *  placement bands on a frame with more than 128 such contours; off, they always search their whole bands (the
     *  behaviour before). Other values are an error. */
    int cascade_plate_gate;
    /** Those kinds are searched on one frame in this many (the first frame is one): 0 = default, 2 when
     *  cascade_wall_kinds_per_frame is 0 (its default 2), else 1 (every frame, as that count alone asked before this
     *  option); N >= 1 = N. A searched frame's fixed costs (its gray search image, the plate gate: about 2 ms beside
     *  the U-Net) are shared by the kinds it searches, so two kinds every second frame cost less than one every frame
     *  for the same rate per kind (docs/benchmarks.md "Twenty-first stop"). Negative values are an error. */
    int cascade_wall_kind_frame_period;
} wf_detector_options;

/** All defaults (cascade detector, no models: set the paths). */
#define WF_DETECTOR_OPTIONS_INIT { WF_DETECTOR_CASCADE }

/** Fills `opts` with the defaults (all zero, like WF_DETECTOR_OPTIONS_INIT). */
int wf_detector_options_init(wf_detector_options *opts);

/** Opaque detector handle (models loaded once). */
typedef struct wf_detector wf_detector;

/** Longest sign kind name, including the terminating NUL. */
#define WF_KIND_NAME_CAPACITY 32

/** Longest legend text read off a sign (a room number such as "402A"), including the terminating NUL. */
#define WF_SIGN_TEXT_CAPACITY 16

/** One detected sign, measured on the unrolled image. */
typedef struct wf_detector_observation {
    /** Kind name ("exit"...), NUL-terminated. */
    char kind[WF_KIND_NAME_CAPACITY];
    /** Index of the kind: the cascade's index, or the U-Net class index (>= 1). */
    int kind_index;
    /** Confidence: cascade neighbour count, or U-Net mean class probability in [0, 1]. */
    double score;
    /** Bounding box in unrolled pixels: left edge, top edge, width, height (edges, pixel-centre
     *  convention: a box covering columns i..i+w-1 has box_x = i - 0.5). */
    double box_x, box_y, box_width, box_height;
    /** Median over slices of the sign's bottom edge, unrolled v, pixels. */
    double median_bottom_row_px;
    /** Median over slices of the sign's apparent height (bottom edge - top edge), pixels. */
    double median_height_px;
    /** Unrolled u of the sign's centre column (middle of its horizontal extent), pixels. */
    double center_column_px;
    /** Width of the horizontal extent: last - first sign column, unrolled pixels. */
    double extent_width_px;
    /** Slopes dv/du of the bottom and top edges in the unrolled image (median of the slopes between slice
     *  i and slice i + n/2; 0 for cascade boxes). Same meaning as LocalizerCore's wf_range_slice_measurement. */
    double bottom_edge_slope;
    double top_edge_slope;
    /** Intrinsics of the unrolled image (principal point moved; fx/fy swapped for +-90 degrees). */
    double unrolled_fx, unrolled_fy, unrolled_cx, unrolled_cy;
    /** Size of the unrolled image, pixels. */
    int unrolled_width, unrolled_height;
    /** Number of slices the medians were taken over. */
    int slice_count;
    /** Roll actually removed, radians (differs from the frame's roll when snapped). */
    double applied_roll_rad;
    /** Affine map unrolled -> raw pixels, row-major 2x3: u = m[0] u' + m[1] v' + m[2],
     *  v = m[3] u' + m[4] v' + m[5]. */
    double unrolled_to_raw[6];
    /** Legend text read off the sign (kinds with reads_text: a room number), NUL-terminated; "" = not read. Only
     *  letters, digits and '-' are kept. */
    char text[WF_SIGN_TEXT_CAPACITY];
} wf_detector_observation;

/**
 * Creates a detector and loads its models. On success `*out` owns a handle to free with
 * wf_detector_free. On failure `*out` is NULL, the return value is negative and the message is
 * available from wf_thread_last_error().
 */
int wf_detector_create(wf_detector **out, const wf_detector_options *opts);

/** Frees a detector; NULL is a no-op. */
void wf_detector_free(wf_detector *detector);

/**
 * Detects signs in one frame. Writes at most `capacity` observations, highest score first, to `out`
 * (caller-owned) and their number to `*count_out`. Returns WF_STATUS_OK, a warning (WF_STATUS_SKIPPED_DARK_FRAME,
 * WF_STATUS_TRUNCATED) or an error; on error or skip `*count_out` is 0. `out` may be NULL when capacity is 0.
 */
int wf_detector_detect(wf_detector *detector, const wf_frame *frame, wf_detector_observation *out,
                       size_t capacity, size_t *count_out);

/** One sign seen and ranged in one frame: the output of wf_detector_sense. */
typedef struct wf_sign_sighting {
    /** Kind name ("exit"...), NUL-terminated; always a kind of the catalogue. */
    char kind[WF_KIND_NAME_CAPACITY];
    /** Horizontal distance from the camera centre to the sign's vertical centre line, meters (> 0). */
    double range_m;
    /** Horizontal angle of the sign centre from the camera's forward direction, radians, positive to the left
     *  (counter-clockwise seen from above), in (-pi, pi]. */
    double bearing_rad;
    /** Confidence: cascade neighbour count, or U-Net mean class probability in [0, 1]. */
    double score;
    /** Height of the sign's centre above the camera centre, meters (negative below). */
    double center_height_above_camera_m;
    /** The sign face's corners in the raw image, pixels: top-left, top-right, bottom-right, bottom-left of the
     *  upright sign as u0, v0, u1, v1, ...: the measured edge lines (median edges and slopes) at the ends of the
     *  sign's horizontal extent in the unrolled image, mapped back to the raw image. */
    double corners_raw_px[8];
    /** Legend text read off the sign (a room number), NUL-terminated; "" = not read or the kind has none. The
     *  localizer matches a sighting with text to the one map sign of that kind and text. */
    char text[WF_SIGN_TEXT_CAPACITY];
} wf_sign_sighting;

/**
 * The whole perception of one frame in one call: validate, unroll by the frame's roll, detect, measure by
 * slices, and range each sign with the apparent-height method (wf_range_apparent_height_slices, ray-elevation
 * model) using its kind's face height from the catalogue given at creation. `frame` carries the camera pose as
 * the range needs it (pitch and roll from gravity). Detections of a kind absent from the catalogue, and
 * measurements the range estimator rejects (no finite positive range), are left out. Writes at most `capacity`
 * sightings, highest score first, and their number to `*count_out`. Returns WF_STATUS_OK, a warning
 * (WF_STATUS_SKIPPED_DARK_FRAME, WF_STATUS_TRUNCATED) or an error: WF_STATUS_INVALID_CATALOGUE when the detector
 * was created without a catalogue, WF_STATUS_BAD_FRAME for a frame of the wrong size or stride or a non-finite
 * pose; on error or skip `*count_out` is 0.
 */
int wf_detector_sense(wf_detector *detector, const wf_frame *frame, wf_sign_sighting *out, size_t capacity,
                      size_t *count_out);

/** Message of the last non-zero status on this handle ("" if none); owned by the handle, valid until
 *  its next call. NULL handle: same as wf_thread_last_error(). */
const char *wf_detector_last_error(const wf_detector *detector);

/** Number of sign kinds the detector reports (cascades, or U-Net classes without background). */
size_t wf_detector_kind_count(const wf_detector *detector);

/** Name of kind `index` (0-based among the reported kinds); NULL if out of range. Owned by the handle. */
const char *wf_detector_kind_name(const wf_detector *detector, size_t index);

/** 1 when the last wf_detector_detect / wf_detector_sense call looked for kind `index` (0-based among the reported
 *  kinds), 0 when it did not: the frame was rejected (bad frame, too dark or too bright), or the kind's turn in the
 *  wall-kind schedule had not come (cascade_wall_kinds_per_frame, cascade_wall_kind_frame_period); 0 before any
 *  frame. -1 for a NULL handle or an index out of range. A kind not looked for says nothing by its absence: pass it
 *  to the localizer as unsearched (wf_localizer_update_signs_searched). */
int wf_detector_kind_searched(const wf_detector *detector, size_t index);

/** 1 when kind `index` (0-based among the reported kinds) is searched in turn, a wall kind (a cascade that is not
 *  colour-gated; beside a U-Net, every cascade): the kinds wf_detector_request_wall_kinds may choose. 0 for a kind
 *  searched on every frame (the U-Net's classes, colour-gated cascades); -1 for a NULL handle or an index out of
 *  range. */
int wf_detector_is_wall_kind(const wf_detector *detector, size_t index);

/** The next wf_detector_detect / wf_detector_sense call searches exactly the wall kinds `kind_indices[0..count)`
 *  (0-based among the reported kinds; each one for which wf_detector_is_wall_kind is 1, none repeated) instead of
 *  those the schedule would take (cascade_wall_kinds_per_frame, cascade_wall_kind_frame_period); count 0: none of
 *  them. It holds for that one call (a rejected frame uses it up); the schedule's rotation does not advance on it.
 *  For a caller that chooses which wall kinds to look for, e.g. those the localizer expects in view. Returns
 *  WF_STATUS_OK, or WF_STATUS_INVALID_ARGUMENT (NULL handle, NULL indices with count > 0, a bad index; nothing is
 *  requested then; wf_detector_last_error says which). */
int wf_detector_request_wall_kinds(wf_detector *detector, const size_t *kind_indices, size_t count);

/** 1 when the detector reads the text of the kinds that have it (a kind with reads_text is reported and the
 *  text reader loaded), 0 otherwise (none such, or the library was built without tesseract, or its English model
 *  is missing: wf_detector_text_reader_problem says which). */
int wf_detector_reads_text(const wf_detector *detector);

/** Why a kind with reads_text gets no text ("" when the reader is loaded or no kind reads text); owned by the
 *  handle. NULL handle: "". */
const char *wf_detector_text_reader_problem(const wf_detector *detector);

/** Library version string, e.g. "1.0.0"; static storage. */
const char *wf_sign_detector_version(void);

#ifdef __cplusplus
}
#endif

#endif /* WF_SIGN_DETECTOR_H */
