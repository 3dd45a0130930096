/// One detected sign, measured on the unrolled image (the raw frame rotated by the camera roll so that the
/// horizon is horizontal; pixel-centre coordinates, u right, v down). `SignDetector.detect` returns these;
/// `SignDetector.sense` also ranges them (`SensedSign`) in the same C call.
public struct SignDetection: Sendable {
    /// Kind name from the model ("exit", ...).
    public var kind: String
    /// Cascade index, or the U-Net class index (>= 1).
    public var kindIndex: Int
    /// Confidence: cascade neighbour count, or U-Net mean class probability in [0, 1].
    public var score: Double
    /// Bounding box in unrolled pixels: left edge, top edge, width, height.
    public var boxInUnrolled: (x: Double, y: Double, width: Double, height: Double)
    /// Median over vertical slices of the sign's bottom edge, unrolled v, pixels.
    public var medianBottomRowPx: Double
    /// Median over vertical slices of the apparent height (bottom edge - top edge), pixels.
    public var medianHeightPx: Double
    /// Unrolled u of the sign's centre column, pixels.
    public var centerColumnPx: Double
    /// Last - first sign column, unrolled pixels.
    public var extentWidthPx: Double
    /// Slopes dv/du of the bottom and top edges (0 for cascade boxes).
    public var bottomEdgeSlope: Double
    public var topEdgeSlope: Double
    /// Intrinsics of the unrolled image, pixels (fx/fy swapped from the raw ones for a +-90 degree roll).
    public var unrolledFx: Double
    public var unrolledFy: Double
    public var unrolledCx: Double
    public var unrolledCy: Double
    /// Size of the unrolled image, pixels.
    public var unrolledWidth: Int
    public var unrolledHeight: Int
    /// Number of slices the medians were taken over.
    public var sliceCount: Int
    /// Roll removed, radians (snapped to a multiple of pi/2 when configured).
    public var appliedRollRad: Double
    /// Affine map unrolled -> raw pixels, row-major 2x3.
    public var unrolledToRaw: [Double]

    /// Maps an unrolled pixel position to the raw camera image (exact).
    public func rawPoint(u: Double, v: Double) -> (u: Double, v: Double) {
        let m = unrolledToRaw
        return (m[0] * u + m[1] * v + m[2], m[3] * u + m[4] * v + m[5])
    }
}

/// One sign seen and ranged in one frame (`SignDetector.sense`, one C call per frame: wf_detector_sense): the
/// apparent-height range from the sign's slices and its kind's face height in the catalogue.
public struct SensedSign: Sendable, Equatable {
    /// Kind name ("exit"...), always a kind of the detector's catalogue.
    public var kind: String
    /// Horizontal distance from the camera centre to the sign's vertical centre line, meters.
    public var rangeMeters: Double
    /// Horizontal angle of the sign centre from the camera's forward direction, radians, positive to the left.
    public var bearingRad: Double
    /// Confidence: cascade neighbour count, or U-Net mean class probability in [0, 1].
    public var score: Double
    /// Height of the sign's centre above the camera centre, meters (negative below).
    public var centerHeightAboveCameraMeters: Double
    /// The face's corners in the raw image, pixels: top-left, top-right, bottom-right, bottom-left.
    public var cornersRaw: [PixelPoint]
    /// Legend text read off the sign (a room-number placard), letters, digits and '-'; nil = not read or the kind
    /// has none. On the iPhone the detector reads none and the app fills it from Vision (App/iOS).
    public var text: String?

    /// Creates a sensed sign (normally from `SignDetector.sense`).
    public init(kind: String, rangeMeters: Double, bearingRad: Double, score: Double,
                centerHeightAboveCameraMeters: Double, cornersRaw: [PixelPoint], text: String? = nil) {
        self.kind = kind; self.rangeMeters = rangeMeters; self.bearingRad = bearingRad; self.score = score
        self.centerHeightAboveCameraMeters = centerHeightAboveCameraMeters; self.cornersRaw = cornersRaw
        self.text = text
    }
}

/// A position in an image, pixels (pixel-centre convention, u right, v down).
public struct PixelPoint: Sendable, Equatable {
    /// Column, pixels.
    public var u: Double
    /// Row, pixels.
    public var v: Double
    /// Creates a point.
    public init(u: Double, v: Double) { self.u = u; self.v = v }
}
