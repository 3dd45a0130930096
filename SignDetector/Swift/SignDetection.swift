/// One detected sign, measured on the unrolled image (the raw frame rotated by the camera roll so that the
/// horizon is horizontal; pixel-centre coordinates, u right, v down). Range and bearing are computed from
/// these by LocalizerCore's RangeEstimator, never here.
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
