import Foundation

// Range and bearing to a rectangular sign of known size (Exit sign) from one camera frame, over the C++ core
// (LocalizerCore/include/wf_range.h; derivations in docs/range-estimation.md).
//
// Conventions (App/SessionFormat/CameraPose.swift): world y up (ARKit), camera looks along -z, image u right
// and v down; pitch positive looking up; roll 0 = landscape upright, -pi/2 = portrait; range = horizontal
// meters from the camera to the sign's vertical centre line; bearing = horizontal angle of the sign centre
// from the camera's forward direction, radians, positive to the LEFT (counter-clockwise seen from above).

/// A range estimation method. All run on the same inputs (`RangeEstimator.estimate`).
public enum RangeMethod: String, CaseIterable, Sendable {
    /// Apparent height (the product's method; Fusco et al. 2020, eq. 3): the sign's known height h0 and the
    /// elevations e of its top and bottom give range = h0 / (tan e_top - tan e_bottom). Needs no camera or
    /// sign mounting height.
    case apparentHeight
    /// Horizon (older baseline): range = (sign-centre height - camera height) / tan(elevation of the
    /// centre). Needs both heights above the floor; a 5 cm error in either is a 5-8 % range error.
    case horizon
    /// PnP (OpenCV solvePnP, IPPE + refinement) on the four corners with the sign's width and height.
    case pnp

    /// The name used on the command line: "apparent-height", "horizon", "pnp".
    public var commandLineName: String {
        switch self {
        case .apparentHeight: return "apparent-height"
        case .horizon: return "horizon"
        case .pnp: return "pnp"
        }
    }

    /// The method of a command-line name ("apparent-height", "horizon", "pnp"); nil for others.
    public init?(commandLineName: String) {
        guard let m = RangeMethod.allCases.first(where: { $0.commandLineName == commandLineName }) else { return nil }
        self = m
    }
}

/// The sign as measured by vertical slices (columns) of its segmentation in the UNROLLED image (roll undone,
/// horizon horizontal). Rows are continuous pixel coordinates of the sign's edges (v down): for a mask with
/// pixel centres at integers covering rows top...bottom of a column, bottom edge = bottom + 0.5 and height =
/// bottom - top + 1. The SignDetector's `wf_sign_observation` carries the same numbers.
public struct SignImageMeasurement: Sendable, Hashable {
    /// Median over the columns of the bottom edge row, unrolled pixels.
    public var medianBottomRowPx: Double
    /// Median over the columns of the height (bottom edge - top edge), pixels (> 0).
    public var medianHeightPx: Double
    /// Centre column: the middle of the columns' extent, unrolled pixels.
    public var centerColumnPx: Double
    /// Slope dv/du of the bottom edge (robust median of pair slopes); 0 = level (assumed when unknown).
    public var bottomEdgeSlope: Double
    /// Slope dv/du of the top edge; 0 = level.
    public var topEdgeSlope: Double
    /// Width of the columns' extent, pixels; 0 = unknown. With the slopes it locates the sign's centre line
    /// when the sign does not face the camera.
    public var extentWidthPx: Double

    /// Creates a measurement; slopes and extent default to "unknown" (level edges, extent middle = centre).
    public init(medianBottomRowPx: Double, medianHeightPx: Double, centerColumnPx: Double,
                bottomEdgeSlope: Double = 0, topEdgeSlope: Double = 0, extentWidthPx: Double = 0) {
        self.medianBottomRowPx = medianBottomRowPx
        self.medianHeightPx = medianHeightPx
        self.centerColumnPx = centerColumnPx
        self.bottomEdgeSlope = bottomEdgeSlope
        self.topEdgeSlope = topEdgeSlope
        self.extentWidthPx = extentWidthPx
    }

    /// Medians, slopes and extent from per-column edges of a mask in the unrolled image (columns in
    /// increasing u). Throws `RangeEstimationError.nonpositiveSize` for no columns or a non-positive median
    /// height, `.notFinite` for NaN.
    public init(columns: [(u: Double, topRowPx: Double, bottomRowPx: Double)]) throws {
        self = try RangeBridge.sliceMeasurement(columnU: columns.map(\.u), topRow: columns.map(\.topRowPx),
                                                bottomRow: columns.map(\.bottomRowPx))
    }
}

/// A camera described in the unrolled image: its intrinsics (pixels; the principal point is the rotated one)
/// and the pitch of the optical axis. `rollRad` is the raw camera's roll that was undone (for reference).
public struct UnrolledCamera: Sendable, Hashable {
    /// Focal length along u of the unrolled image, pixels.
    public var fx: Double
    /// Focal length along v of the unrolled image, pixels.
    public var fy: Double
    /// Principal point u in the unrolled image, pixels.
    public var cx: Double
    /// Principal point v in the unrolled image, pixels.
    public var cy: Double
    /// Elevation of the optical axis, radians, positive up.
    public var pitchRad: Double
    /// Roll of the raw camera that the unrolling removed, radians.
    public var rollRad: Double

    /// Creates an unrolled camera.
    public init(fx: Double, fy: Double, cx: Double, cy: Double, pitchRad: Double, rollRad: Double) {
        self.fx = fx; self.fy = fy; self.cx = cx; self.cy = cy; self.pitchRad = pitchRad; self.rollRad = rollRad
    }
}

/// A range estimate: `rangeMeters` (horizontal, > 0), `bearingRad` (positive left, (-pi, pi]) and the sign
/// centre's height above the camera in meters as the method sees it.
public struct RangeEstimate: Sendable, Hashable {
    /// Horizontal distance from the camera centre to the sign's vertical centre line, meters.
    public var rangeMeters: Double
    /// Horizontal angle of the sign centre from the camera's forward direction, radians, positive left.
    public var bearingRad: Double
    /// Height of the sign centre above the camera centre, meters (negative below).
    public var centerHeightAboveCameraMeters: Double

    /// Creates an estimate.
    public init(rangeMeters: Double, bearingRad: Double, centerHeightAboveCameraMeters: Double) {
        self.rangeMeters = rangeMeters
        self.bearingRad = bearingRad
        self.centerHeightAboveCameraMeters = centerHeightAboveCameraMeters
    }
}

/// Why a range could not be estimated (the C core's status codes, plus Swift-side shape checks).
public enum RangeEstimationError: Error, Equatable, Sendable, CustomStringConvertible {
    /// An input number is NaN or infinite.
    case notFinite
    /// A size is zero or negative (sign height or width, focal length, pixel height, image size, no columns).
    case nonpositiveSize
    /// The corners are not a convex quadrilateral in TL, TR, BR, BL order (clockwise on screen).
    case degenerateCorners
    /// No finite positive range: tan(top) - tan(bottom) <= 0, an angle beyond 90 degrees, a vertical camera,
    /// or (horizon method) the sign centre at camera height or on the wrong side of the horizon.
    case degenerateGeometry
    /// The camera-to-world matrix's 3x3 block is not a rotation.
    case notARotation
    /// solvePnP failed.
    case pnpFailed
    /// The method needs an input that was not given (sign width for PnP; both heights for horizon).
    case missingInput
    /// Not exactly 4 corners.
    case wrongCornerCount(Int)
    /// Not exactly 16 numbers in a 4x4 matrix.
    case wrongMatrixCount(Int)
    /// Any other status of the C core (a NULL, version or internal error: a bug, not bad input).
    case core(status: Int32)

    init(status: Int32) {
        switch status {
        case RangeBridge.statusNotFinite: self = .notFinite
        case RangeBridge.statusNonpositiveSize: self = .nonpositiveSize
        case RangeBridge.statusDegenerateCorners: self = .degenerateCorners
        case RangeBridge.statusDegenerateGeometry: self = .degenerateGeometry
        case RangeBridge.statusNotARotation: self = .notARotation
        case RangeBridge.statusPnPFailed: self = .pnpFailed
        case RangeBridge.statusMissingInput: self = .missingInput
        default: self = .core(status: status)
        }
    }

    /// An English message.
    public var description: String {
        switch self {
        case .notFinite: return RangeBridge.describe(RangeBridge.statusNotFinite)
        case .nonpositiveSize: return RangeBridge.describe(RangeBridge.statusNonpositiveSize)
        case .degenerateCorners: return RangeBridge.describe(RangeBridge.statusDegenerateCorners)
        case .degenerateGeometry: return RangeBridge.describe(RangeBridge.statusDegenerateGeometry)
        case .notARotation: return RangeBridge.describe(RangeBridge.statusNotARotation)
        case .pnpFailed: return RangeBridge.describe(RangeBridge.statusPnPFailed)
        case .missingInput: return RangeBridge.describe(RangeBridge.statusMissingInput)
        case .wrongCornerCount(let n): return "expected 4 corners (TL, TR, BR, BL), got \(n)"
        case .wrongMatrixCount(let n): return "expected 16 numbers (column-major 4x4), got \(n)"
        case .core(let s): return RangeBridge.describe(s)
        }
    }
}

/// Range estimation entry points. Stateless and thread-safe.
public enum RangeEstimator {
    /// Pinhole intrinsics of an image, pixels (no distortion). fx and fy may differ.
    public struct Intrinsics: Sendable, Hashable {
        /// Focal length along u, pixels.
        public var fx: Double
        /// Focal length along v, pixels.
        public var fy: Double
        /// Principal point u, pixels.
        public var cx: Double
        /// Principal point v, pixels.
        public var cy: Double
        /// Creates intrinsics.
        public init(fx: Double, fy: Double, cx: Double, cy: Double) {
            self.fx = fx; self.fy = fy; self.cx = cx; self.cy = cy
        }
    }

    /// The camera's orientation relative to gravity.
    public enum Orientation: Sendable, Hashable {
        /// An ARKit camera-to-world transform, 16 numbers column-major (only the rotation is used).
        case cameraToWorld([Double])
        /// Pitch and roll (CameraPose.pitchRad / rollRad); yaw is irrelevant to range and bearing.
        case pitchRoll(pitchRad: Double, rollRad: Double)

        /// The column-major 4x4 camera-to-world transform of this orientation.
        public func cameraToWorldMatrix() throws -> [Double] {
            switch self {
            case .cameraToWorld(let m):
                guard m.count == 16 else { throw RangeEstimationError.wrongMatrixCount(m.count) }
                return m
            case .pitchRoll(let pitch, let roll):
                return try RangeBridge.cameraToWorld(pitchRad: pitch, rollRad: roll)
            }
        }

        /// Pitch and roll of this orientation (CameraPose's definitions).
        public func pitchAndRoll() throws -> (pitchRad: Double, rollRad: Double) {
            switch self {
            case .cameraToWorld(let m): return try RangeBridge.pitchRoll(cameraToWorld: m)
            case .pitchRoll(let p, let r): return (p, r)
            }
        }
    }

    /// How slice medians become two elevations (wf_range_slice_model).
    public enum SliceModel: Sendable, Hashable {
        /// Rays through two points of the sign's centre line: exact at the centre column, and corrected
        /// off-axis and under pitch with the edge slopes and extent. The default.
        case rayElevation
        /// The paper's equation (3) verbatim: alpha and delta from the rows with the pinhole model; gives the
        /// depth along the optical axis (about range * cos(bearing)) for off-axis signs.
        case paperPlanar
    }

    /// Z and bearing from slice medians (apparent-height method, the product's path): the measurement and
    /// camera are in the unrolled image; `signHeightMeters` is the physical height h0 of the sign face.
    public static func apparentHeight(_ m: SignImageMeasurement, camera: UnrolledCamera, signHeightMeters: Double,
                                      model: SliceModel = .rayElevation) throws -> (rangeMeters: Double, bearingRad: Double) {
        let e = try apparentHeightEstimate(m, camera: camera, signHeightMeters: signHeightMeters, model: model)
        return (e.rangeMeters, e.bearingRad)
    }

    /// Like `apparentHeight` with the full result (centre height above the camera too).
    public static func apparentHeightEstimate(_ m: SignImageMeasurement, camera: UnrolledCamera, signHeightMeters: Double,
                                              model: SliceModel = .rayElevation) throws -> RangeEstimate {
        try RangeBridge.apparentHeightSlices(m, camera: camera, signHeightMeters: signHeightMeters, model: model)
    }

    /// Range and bearing by `method` from the sign's four raw-image corners, TL, TR, BR, BL of the upright
    /// sign (clockwise on screen), raw intrinsics and the camera orientation. `signWidthMeters` is required by
    /// `.pnp`; `cameraHeightMeters` and `signCenterHeightMeters` (above the floor) by `.horizon`.
    /// `.apparentHeight` here is the exact variant: the images of the sign's top-centre and bottom-centre
    /// (constructed from the corners) and the elevations of their rays with the full rotation.
    public static func estimate(method: RangeMethod, corners rawPixelCorners: [(u: Double, v: Double)],
                                intrinsics: Intrinsics, orientation: Orientation, signHeightMeters: Double,
                                signWidthMeters: Double? = nil, cameraHeightMeters: Double? = nil,
                                signCenterHeightMeters: Double? = nil) throws -> (rangeMeters: Double, bearingRad: Double) {
        let e = try estimateFull(method: method, corners: rawPixelCorners, intrinsics: intrinsics,
                                 orientation: orientation, signHeightMeters: signHeightMeters,
                                 signWidthMeters: signWidthMeters, cameraHeightMeters: cameraHeightMeters,
                                 signCenterHeightMeters: signCenterHeightMeters)
        return (e.rangeMeters, e.bearingRad)
    }

    /// Like `estimate` with the full result.
    public static func estimateFull(method: RangeMethod, corners rawPixelCorners: [(u: Double, v: Double)],
                                    intrinsics: Intrinsics, orientation: Orientation, signHeightMeters: Double,
                                    signWidthMeters: Double? = nil, cameraHeightMeters: Double? = nil,
                                    signCenterHeightMeters: Double? = nil) throws -> RangeEstimate {
        try RangeBridge.estimate(method: method, corners: rawPixelCorners, intrinsics: intrinsics,
                                 cameraToWorld: try orientation.cameraToWorldMatrix(),
                                 signHeightMeters: signHeightMeters, signWidthMeters: signWidthMeters,
                                 cameraHeightMeters: cameraHeightMeters, signCenterHeightMeters: signCenterHeightMeters)
    }

    /// The paper's equation (3): Z = h0 / (tan(pitch + alpha + delta) - tan(pitch + alpha)), meters.
    public static func paperEquation3(pitchRad: Double, alphaRad: Double, deltaRad: Double,
                                      signHeightMeters: Double) throws -> Double {
        try RangeBridge.paperEquation3(pitchRad: pitchRad, alphaRad: alphaRad, deltaRad: deltaRad,
                                       signHeightMeters: signHeightMeters)
    }

    /// Raw-image points of the sign's centre, top-centre and bottom-centre, constructed exactly from the
    /// corners (diagonals, vanishing point of the side edges).
    public static func centerPoints(corners: [(u: Double, v: Double)]) throws
        -> (center: (u: Double, v: Double), topCenter: (u: Double, v: Double), bottomCenter: (u: Double, v: Double)) {
        try RangeBridge.centerPoints(corners: corners)
    }
}

/// The exact mapping between raw pixels and the unrolled image for one camera roll (points only; the
/// SignDetector unrolls images). Through normalised coordinates, so exact when fx != fy; the unrolled image
/// has square pixels of focal sqrt(fx fy) and is the bounding box of the rotated raw image (portrait
/// 1920 x 1440 -> 1440 x 1920, principal point (720, 960)).
public struct UnrollMapping: Sendable, Hashable {
    struct Storage: Sendable, Hashable {
        var raw: RangeEstimator.Intrinsics
        var rollRad: Double
        var unrolled: RangeEstimator.Intrinsics
        var unrolledWidthPx: Double
        var unrolledHeightPx: Double
    }
    let storage: Storage

    /// Builds the mapping for raw intrinsics, the camera roll (radians) and the raw image size (pixels).
    public init(intrinsics: RangeEstimator.Intrinsics, rollRad: Double, imageWidthPx: Double, imageHeightPx: Double) throws {
        storage = try RangeBridge.makeUnrollMap(intrinsics, rollRad: rollRad, imageWidthPx: imageWidthPx,
                                                imageHeightPx: imageHeightPx)
    }

    /// Intrinsics of the unrolled image (fx == fy).
    public var unrolledIntrinsics: RangeEstimator.Intrinsics { storage.unrolled }
    /// Size of the unrolled canvas, pixels.
    public var unrolledSizePx: (width: Double, height: Double) { (storage.unrolledWidthPx, storage.unrolledHeightPx) }

    /// The unrolled camera for a pitch (radians).
    public func unrolledCamera(pitchRad: Double) -> UnrolledCamera {
        let k = storage.unrolled
        return UnrolledCamera(fx: k.fx, fy: k.fy, cx: k.cx, cy: k.cy, pitchRad: pitchRad, rollRad: storage.rollRad)
    }

    /// Maps a raw pixel to the unrolled image.
    public func unroll(_ raw: (u: Double, v: Double)) throws -> (u: Double, v: Double) {
        try RangeBridge.unroll(storage, raw)
    }

    /// Maps an unrolled pixel back to the raw image (exact inverse of `unroll`).
    public func reroll(_ unrolled: (u: Double, v: Double)) throws -> (u: Double, v: Double) {
        try RangeBridge.reroll(storage, unrolled)
    }
}
