internal import SignDetector

// Every call into the C range-estimation ABI (LocalizerCore/include/wf_range.h) goes through this file; the
// public Swift API (RangeEstimator.swift) never shows a C type. Status codes become RangeEstimationError.

/// Thin, internal wrappers over wf_range_*. Inputs are plain Swift values; outputs are checked statuses.
enum RangeBridge {
    /// Throws the error of a negative status.
    static func check(_ status: Int32) throws {
        guard status == WF_STATUS_OK else { throw RangeEstimationError(status: status) }
    }

    /// English description of a status code (wf_status_string).
    static func describe(_ status: Int32) -> String { String(cString: wf_status_string(status)) }

    static func cIntrinsics(_ k: RangeEstimator.Intrinsics) -> wf_range_intrinsics {
        wf_range_intrinsics(fx: k.fx, fy: k.fy, cx: k.cx, cy: k.cy)
    }

    static func result(_ r: wf_range_result) -> RangeEstimate {
        RangeEstimate(rangeMeters: r.range_m, bearingRad: r.bearing_rad,
                      centerHeightAboveCameraMeters: r.center_height_above_camera_m)
    }

    /// wf_range_apparent_height_slices.
    static func apparentHeightSlices(_ m: SignImageMeasurement, camera c: UnrolledCamera, signHeightMeters: Double,
                                     model: RangeEstimator.SliceModel) throws -> RangeEstimate {
        var camera = wf_range_unrolled_camera(fx: c.fx, fy: c.fy, cx: c.cx, cy: c.cy, pitch_rad: c.pitchRad,
                                              roll_rad: c.rollRad)
        var measurement = wf_range_slice_measurement(
            median_bottom_row_px: m.medianBottomRowPx, median_height_px: m.medianHeightPx,
            center_column_px: m.centerColumnPx, bottom_edge_slope: m.bottomEdgeSlope,
            top_edge_slope: m.topEdgeSlope, extent_width_px: m.extentWidthPx)
        let cModel: wf_range_slice_model = model == .rayElevation
            ? WF_RANGE_SLICE_MODEL_RAY_ELEVATION : WF_RANGE_SLICE_MODEL_PAPER_PLANAR
        var out = wf_range_result()
        try check(wf_range_apparent_height_slices(&out, &camera, &measurement, signHeightMeters, cModel))
        return result(out)
    }

    /// wf_range_slice_measurement_from_columns.
    static func sliceMeasurement(columnU: [Double], topRow: [Double], bottomRow: [Double]) throws -> SignImageMeasurement {
        var out = wf_range_slice_measurement()
        try check(wf_range_slice_measurement_from_columns(&out, columnU, topRow, bottomRow, columnU.count))
        return SignImageMeasurement(medianBottomRowPx: out.median_bottom_row_px, medianHeightPx: out.median_height_px,
                                    centerColumnPx: out.center_column_px, bottomEdgeSlope: out.bottom_edge_slope,
                                    topEdgeSlope: out.top_edge_slope, extentWidthPx: out.extent_width_px)
    }

    /// wf_range_estimate on one observation.
    static func estimate(method: RangeMethod, corners: [(u: Double, v: Double)], intrinsics: RangeEstimator.Intrinsics,
                         cameraToWorld: [Double], signHeightMeters: Double, signWidthMeters: Double?,
                         cameraHeightMeters: Double?, signCenterHeightMeters: Double?) throws -> RangeEstimate {
        guard corners.count == 4 else { throw RangeEstimationError.wrongCornerCount(corners.count) }
        guard cameraToWorld.count == 16 else { throw RangeEstimationError.wrongMatrixCount(cameraToWorld.count) }
        var o = wf_range_observation()
        o.version = UInt32(WF_RANGE_OBSERVATION_VERSION)
        o.corners = (wf_range_point(u: corners[0].u, v: corners[0].v), wf_range_point(u: corners[1].u, v: corners[1].v),
                     wf_range_point(u: corners[2].u, v: corners[2].v), wf_range_point(u: corners[3].u, v: corners[3].v))
        o.intrinsics = cIntrinsics(intrinsics)
        withUnsafeMutableBytes(of: &o.camera_to_world) { raw in
            let doubles = raw.bindMemory(to: Double.self)
            for i in 0..<16 { doubles[i] = cameraToWorld[i] }
        }
        o.sign_height_m = signHeightMeters
        o.sign_width_m = signWidthMeters ?? .nan
        o.camera_height_m = cameraHeightMeters ?? .nan
        o.sign_center_height_m = signCenterHeightMeters ?? .nan
        let cMethod: wf_range_method
        switch method {
        case .apparentHeight: cMethod = WF_RANGE_METHOD_APPARENT_HEIGHT
        case .horizon: cMethod = WF_RANGE_METHOD_HORIZON
        case .pnp: cMethod = WF_RANGE_METHOD_PNP
        }
        var out = wf_range_result()
        try check(wf_range_estimate(&out, cMethod, &o))
        return result(out)
    }

    /// wf_range_camera_to_world_from_pitch_roll.
    static func cameraToWorld(pitchRad: Double, rollRad: Double) throws -> [Double] {
        var m = [Double](repeating: 0, count: 16)
        try check(wf_range_camera_to_world_from_pitch_roll(&m, pitchRad, rollRad))
        return m
    }

    /// wf_range_pitch_roll_from_camera_to_world.
    static func pitchRoll(cameraToWorld: [Double]) throws -> (pitchRad: Double, rollRad: Double) {
        guard cameraToWorld.count == 16 else { throw RangeEstimationError.wrongMatrixCount(cameraToWorld.count) }
        var pitch = 0.0, roll = 0.0
        try check(wf_range_pitch_roll_from_camera_to_world(&pitch, &roll, cameraToWorld))
        return (pitch, roll)
    }

    /// wf_range_paper_equation3.
    static func paperEquation3(pitchRad: Double, alphaRad: Double, deltaRad: Double, signHeightMeters: Double) throws -> Double {
        var range = 0.0
        try check(wf_range_paper_equation3(&range, pitchRad, alphaRad, deltaRad, signHeightMeters))
        return range
    }

    /// wf_range_unroll_map_make; returns the map's numbers (raw and unrolled intrinsics, canvas size).
    static func makeUnrollMap(_ k: RangeEstimator.Intrinsics, rollRad: Double, imageWidthPx: Double,
                              imageHeightPx: Double) throws -> UnrollMapping.Storage {
        var raw = cIntrinsics(k)
        var map = wf_range_unroll_map()
        try check(wf_range_unroll_map_make(&map, &raw, rollRad, imageWidthPx, imageHeightPx))
        return UnrollMapping.Storage(
            raw: k, rollRad: rollRad,
            unrolled: RangeEstimator.Intrinsics(fx: map.unrolled.fx, fy: map.unrolled.fy, cx: map.unrolled.cx,
                                                cy: map.unrolled.cy),
            unrolledWidthPx: map.unrolled_width_px, unrolledHeightPx: map.unrolled_height_px)
    }

    private static func cMap(_ s: UnrollMapping.Storage) -> wf_range_unroll_map {
        var map = wf_range_unroll_map()
        map.raw = cIntrinsics(s.raw)
        map.roll_rad = s.rollRad
        map.unrolled = cIntrinsics(s.unrolled)
        map.unrolled_width_px = s.unrolledWidthPx
        map.unrolled_height_px = s.unrolledHeightPx
        return map
    }

    /// wf_range_unroll_point.
    static func unroll(_ s: UnrollMapping.Storage, _ p: (u: Double, v: Double)) throws -> (u: Double, v: Double) {
        var map = cMap(s)
        var raw = wf_range_point(u: p.u, v: p.v)
        var out = wf_range_point()
        try check(wf_range_unroll_point(&out, &map, &raw))
        return (out.u, out.v)
    }

    /// wf_range_reroll_point.
    static func reroll(_ s: UnrollMapping.Storage, _ p: (u: Double, v: Double)) throws -> (u: Double, v: Double) {
        var map = cMap(s)
        var unrolled = wf_range_point(u: p.u, v: p.v)
        var out = wf_range_point()
        try check(wf_range_reroll_point(&out, &map, &unrolled))
        return (out.u, out.v)
    }

    /// wf_range_sign_center_points: centre, top-centre and bottom-centre images of the sign.
    static func centerPoints(corners: [(u: Double, v: Double)]) throws
        -> (center: (u: Double, v: Double), topCenter: (u: Double, v: Double), bottomCenter: (u: Double, v: Double)) {
        guard corners.count == 4 else { throw RangeEstimationError.wrongCornerCount(corners.count) }
        let c = corners.map { wf_range_point(u: $0.u, v: $0.v) }
        var center = wf_range_point(), top = wf_range_point(), bottom = wf_range_point()
        try check(wf_range_sign_center_points(&center, &top, &bottom, c))
        return ((center.u, center.v), (top.u, top.v), (bottom.u, bottom.v))
    }

    /// Status codes, for RangeEstimationError's mapping.
    static let statusOK = WF_STATUS_OK
    static let statusNull = WF_STATUS_INVALID_ARGUMENT
    static let statusNotFinite = WF_STATUS_NON_FINITE_INPUT
    static let statusNonpositiveSize = WF_STATUS_NONPOSITIVE_SIZE
    static let statusDegenerateCorners = WF_STATUS_DEGENERATE_CORNERS
    static let statusDegenerateGeometry = WF_STATUS_DEGENERATE_GEOMETRY
    static let statusNotARotation = WF_STATUS_NOT_A_ROTATION
    static let statusPnPFailed = WF_STATUS_PNP_FAILED
    static let statusVersion = WF_STATUS_VERSION
    static let statusMissingInput = WF_STATUS_MISSING_INPUT
}
