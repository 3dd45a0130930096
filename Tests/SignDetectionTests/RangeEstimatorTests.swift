import Foundation
import XCTest
@testable import SignDetection

/// Synthetic scene for the Swift range tests: a sign at a known horizontal range and bearing, projected by a
/// pinhole camera with the ARKit rotation R = Ry(yaw) Rx(pitch) Rz(roll) (world y up, camera looks along -z,
/// pixel = (cx + fx x / -z, cy - fy y / -z)). Written independently of the C++ test helper.
struct SyntheticSignScene {
    var intrinsics = RangeEstimator.Intrinsics(fx: 1602, fy: 1602, cx: 960, cy: 720)
    var yawRad = 0.0, pitchRad = 0.0, rollRad = 0.0
    var rangeMeters = 3.0, bearingRad = 0.0, centerHeightAboveCameraMeters = 0.3, facingRad = 0.0
    var signHeightMeters = 0.21, signWidthMeters = 0.33

    typealias Vec = (x: Double, y: Double, z: Double)

    /// Rows of R = Ry(yaw) Rx(pitch) Rz(roll).
    var rotation: [[Double]] {
        func mul(_ a: [[Double]], _ b: [[Double]]) -> [[Double]] {
            (0..<3).map { i in (0..<3).map { j in (0..<3).reduce(0) { $0 + a[i][$1] * b[$1][j] } } }
        }
        let (cy, sy) = (cos(yawRad), sin(yawRad)), (cp, sp) = (cos(pitchRad), sin(pitchRad))
        let (cr, sr) = (cos(rollRad), sin(rollRad))
        let ry = [[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]]
        let rx = [[1, 0, 0], [0, cp, -sp], [0, sp, cp]]
        let rz = [[cr, -sr, 0], [sr, cr, 0], [0, 0, 1]]
        return mul(mul(ry, rx), rz)
    }

    /// Column-major 4x4 camera-to-world (zero translation).
    var cameraToWorld: [Double] {
        let r = rotation
        return [r[0][0], r[1][0], r[2][0], 0, r[0][1], r[1][1], r[2][1], 0, r[0][2], r[1][2], r[2][2], 0, 0, 0, 0, 1]
    }

    /// World corners TL, TR, BR, BL.
    var cornersInWorld: [Vec] {
        let r = rotation
        let forward = (x: -r[0][2], z: -r[2][2])
        let azimuth = atan2(-forward.z, forward.x) + bearingRad
        let d = (x: cos(azimuth), z: -sin(azimuth))
        let center: Vec = (rangeMeters * d.x, centerHeightAboveCameraMeters, rangeMeters * d.z)
        // Normal toward the camera, turned by facingRad about up; right = (-n) x up.
        let n0 = (x: -d.x, z: -d.z)
        let n = (x: cos(facingRad) * n0.x + sin(facingRad) * n0.z, z: -sin(facingRad) * n0.x + cos(facingRad) * n0.z)
        let right = (x: n.z, z: -n.x)  // (-n) x (0,1,0) = (n.z, 0, -n.x)
        let (hw, hh) = (signWidthMeters / 2, signHeightMeters / 2)
        func corner(_ sx: Double, _ sy: Double) -> Vec {
            (center.x + sx * hw * right.x, center.y + sy * hh, center.z + sx * hw * right.z)
        }
        return [corner(-1, 1), corner(1, 1), corner(1, -1), corner(-1, -1)]
    }

    /// Projection of a world point; nil behind the camera.
    func project(_ p: Vec) -> (u: Double, v: Double)? {
        let r = rotation
        let c = (x: r[0][0] * p.x + r[1][0] * p.y + r[2][0] * p.z,
                 y: r[0][1] * p.x + r[1][1] * p.y + r[2][1] * p.z,
                 z: r[0][2] * p.x + r[1][2] * p.y + r[2][2] * p.z)
        guard c.z < -1e-9 else { return nil }
        return (intrinsics.cx + intrinsics.fx * c.x / -c.z, intrinsics.cy - intrinsics.fy * c.y / -c.z)
    }

    /// Raw corners, nil unless all are in front and inside the 1920 x 1440 image.
    var corners: [(u: Double, v: Double)]? {
        let p = cornersInWorld.compactMap(project)
        guard p.count == 4, p.allSatisfy({ $0.u > 2 && $0.u < 1918 && $0.v > 2 && $0.v < 1438 }) else { return nil }
        return p
    }
}

final class RangeEstimatorTests: XCTestCase {
    private func deg(_ d: Double) -> Double { d * .pi / 180 }

    /// Calls body for each visible scene of pitch x roll x range x bearing (sign 5 deg above the axis).
    private func forEachScene(_ body: (SyntheticSignScene, [(u: Double, v: Double)]) throws -> Void) rethrows -> Int {
        var n = 0
        for pitch in [-30.0, -10, 0, 15, 30] {
            for roll in [-90.0, -45, 0, 30, 90] {
                for range in [1.0, 3, 7, 15] {
                    for bearing in [-12.0, 0, 9] {
                        var s = SyntheticSignScene()
                        s.yawRad = -1.1
                        s.pitchRad = deg(pitch)
                        s.rollRad = deg(roll)
                        s.rangeMeters = range
                        s.bearingRad = deg(bearing)
                        s.facingRad = deg(-15)
                        var elevation = s.pitchRad + deg(5)
                        if abs(elevation) < deg(1) { elevation = s.pitchRad - deg(5) }
                        s.centerHeightAboveCameraMeters = range * tan(elevation)
                        guard let corners = s.corners else { continue }
                        n += 1
                        try body(s, corners)
                    }
                }
            }
        }
        return n
    }

    func testEveryMethodIsExactOnExactCornersForAnyRollAndPitch() throws {
        let n = try forEachScene { s, corners in
            for method in RangeMethod.allCases {
                for orientation in [RangeEstimator.Orientation.cameraToWorld(s.cameraToWorld),
                                    .pitchRoll(pitchRad: s.pitchRad, rollRad: s.rollRad)] {
                    let e = try RangeEstimator.estimate(
                        method: method, corners: corners, intrinsics: s.intrinsics, orientation: orientation,
                        signHeightMeters: s.signHeightMeters, signWidthMeters: s.signWidthMeters,
                        cameraHeightMeters: 1.4, signCenterHeightMeters: 1.4 + s.centerHeightAboveCameraMeters)
                    XCTAssertEqual(e.rangeMeters, s.rangeMeters, accuracy: 1e-6 * s.rangeMeters,
                                   "\(method) pitch \(s.pitchRad) roll \(s.rollRad) range \(s.rangeMeters)")
                    XCTAssertEqual(e.bearingRad, s.bearingRad, accuracy: 1e-6, "\(method)")
                }
            }
        }
        XCTAssertGreaterThan(n, 150)
    }

    /// The slice path on ideal medians: the unrolled images of the sign's bottom-centre and top-centre give
    /// the bottom row and height at the centre column; for a sign facing the camera on the optical axis's
    /// vertical plane the paper's formula is exact.
    func testApparentHeightFromSliceMediansOnTheCentreColumn() throws {
        for pitch in [-20.0, 0, 10, 25] {
            for roll in [-90.0, 0, 60] {
                var s = SyntheticSignScene()
                s.pitchRad = deg(pitch)
                s.rollRad = deg(roll)
                s.rangeMeters = 4
                s.centerHeightAboveCameraMeters = 4 * tan(s.pitchRad + deg(4))
                let corners = try XCTUnwrap(s.corners)
                let points = try RangeEstimator.centerPoints(corners: corners)
                let mapping = try UnrollMapping(intrinsics: s.intrinsics, rollRad: s.rollRad, imageWidthPx: 1920,
                                                imageHeightPx: 1440)
                let top = try mapping.unroll(points.topCenter), bottom = try mapping.unroll(points.bottomCenter)
                XCTAssertEqual(top.u, bottom.u, accuracy: 1e-6)  // on the centre column: no bearing
                let m = SignImageMeasurement(medianBottomRowPx: bottom.v, medianHeightPx: bottom.v - top.v,
                                             centerColumnPx: bottom.u)
                let camera = mapping.unrolledCamera(pitchRad: s.pitchRad)
                for model in [RangeEstimator.SliceModel.rayElevation, .paperPlanar] {
                    let e = try RangeEstimator.apparentHeight(m, camera: camera, signHeightMeters: 0.21, model: model)
                    XCTAssertEqual(e.rangeMeters, 4, accuracy: 1e-6)
                    XCTAssertEqual(e.bearingRad, 0, accuracy: 1e-9)
                }
            }
        }
    }

    /// Slice medians of an exact mask (columns of the unrolled polygon) over the grid: the ray-elevation model
    /// reconstructs the sign's centre line; exact up to the column sampling of the extent (C++ suite: worst
    /// 0.014 %, 0.02 deg).
    func testApparentHeightFromMaskColumnsIsWithinTolerance() throws {
        var worst = 0.0
        _ = try forEachScene { s, corners in
            let mapping = try UnrollMapping(intrinsics: s.intrinsics, rollRad: s.rollRad, imageWidthPx: 1920,
                                            imageHeightPx: 1440)
            let polygon = try corners.map { try mapping.unroll($0) }
            let columns = Self.columns(of: polygon)
            let m = try SignImageMeasurement(columns: columns)
            let e = try RangeEstimator.apparentHeight(m, camera: mapping.unrolledCamera(pitchRad: s.pitchRad),
                                                      signHeightMeters: s.signHeightMeters)
            worst = max(worst, abs(e.rangeMeters - s.rangeMeters) / s.rangeMeters)
            XCTAssertEqual(e.bearingRad, s.bearingRad, accuracy: deg(0.05))
        }
        XCTAssertLessThan(worst, 0.0005)
    }

    /// Top and bottom edge rows of a convex polygon at each integer column.
    static func columns(of polygon: [(u: Double, v: Double)]) -> [(u: Double, topRowPx: Double, bottomRowPx: Double)] {
        let us = polygon.map(\.u)
        var out: [(u: Double, topRowPx: Double, bottomRowPx: Double)] = []
        var u = us.min()!.rounded(.up)
        while u <= us.max()! {
            var top = Double.infinity, bottom = -Double.infinity
            for i in 0..<4 {
                let a = polygon[i], b = polygon[(i + 1) % 4]
                guard u >= min(a.u, b.u), u <= max(a.u, b.u), abs(b.u - a.u) > 1e-12 else { continue }
                let v = a.v + (u - a.u) / (b.u - a.u) * (b.v - a.v)
                top = min(top, v)
                bottom = max(bottom, v)
            }
            if bottom > top { out.append((u, top, bottom)) }
            u += 1
        }
        return out
    }

    /// ../shared/reference/arkit-frames.md: a real portrait shot of an Exit sign 2 m away had ARKit
    /// eulerAngles (pitch 0.093, yaw -0.006, roll -1.580); a 0.21 m face seen that way reads 2 m.
    func testArkitPortraitShotAtTwoMetersGivesTwoMeters() throws {
        var s = SyntheticSignScene()
        s.pitchRad = 0.093
        s.yawRad = -0.006
        s.rollRad = -1.580
        s.rangeMeters = 2
        s.centerHeightAboveCameraMeters = 2 * tan(0.093 + deg(2))
        s.signHeightMeters = 0.21
        let corners = try XCTUnwrap(s.corners)
        // On its side in the raw image: the sign's height runs along u.
        XCTAssertGreaterThan(abs(corners[3].u - corners[0].u), 100)
        let (pitch, roll) = try RangeEstimator.Orientation.cameraToWorld(s.cameraToWorld).pitchAndRoll()
        XCTAssertEqual(pitch, 0.093, accuracy: 1e-12)
        XCTAssertEqual(roll, -1.580, accuracy: 1e-12)
        let exact = try RangeEstimator.estimate(method: .apparentHeight, corners: corners, intrinsics: s.intrinsics,
                                                orientation: .cameraToWorld(s.cameraToWorld), signHeightMeters: 0.21)
        XCTAssertEqual(exact.rangeMeters, 2, accuracy: 2e-6)
        // The product path: unroll by the gravity roll, measure slices, apply the pitch.
        let mapping = try UnrollMapping(intrinsics: s.intrinsics, rollRad: roll, imageWidthPx: 1920, imageHeightPx: 1440)
        // Nearly portrait: the canvas is about 1440 wide (a bit more, the roll being 0.5 deg off -pi/2).
        XCTAssertEqual(mapping.unrolledSizePx.width, 1440, accuracy: 20)
        let m = try SignImageMeasurement(columns: Self.columns(of: try corners.map { try mapping.unroll($0) }))
        let sliced = try RangeEstimator.apparentHeight(m, camera: mapping.unrolledCamera(pitchRad: pitch),
                                                       signHeightMeters: 0.21)
        XCTAssertEqual(sliced.rangeMeters, 2, accuracy: 0.001)
    }

    func testUnrollMappingRoundTripsAndPortraitCanvas() throws {
        let k = RangeEstimator.Intrinsics(fx: 1500, fy: 1650, cx: 955, cy: 731)
        for roll in stride(from: -3.0, through: 3.0, by: 0.37) {
            let mapping = try UnrollMapping(intrinsics: k, rollRad: roll, imageWidthPx: 1920, imageHeightPx: 1440)
            for p in [(u: 0.0, v: 0.0), (u: 1919.5, v: 3.25), (u: 640, v: 1200)] {
                let back = try mapping.reroll(try mapping.unroll(p))
                XCTAssertEqual(back.u, p.u, accuracy: 1e-9)
                XCTAssertEqual(back.v, p.v, accuracy: 1e-9)
            }
        }
        let portrait = try UnrollMapping(intrinsics: .init(fx: 1602, fy: 1602, cx: 960, cy: 720), rollRad: -.pi / 2,
                                         imageWidthPx: 1920, imageHeightPx: 1440)
        XCTAssertEqual(portrait.unrolledIntrinsics.cx, 720, accuracy: 1e-9)
        XCTAssertEqual(portrait.unrolledIntrinsics.cy, 960, accuracy: 1e-9)
        let down = try portrait.unroll((u: 1060, v: 720))  // raw +u = camera x = world down in portrait
        XCTAssertEqual(down.u, 720, accuracy: 1e-9)
        XCTAssertEqual(down.v, 1060, accuracy: 1e-9)
    }

    func testPaperEquation3() throws {
        // Bottom 0.3 m above the camera at 4 m, pitch 10 deg.
        let p = deg(10), z = 4.0, h0 = 0.21
        let alpha = atan(0.3 / z) - p, delta = atan(0.51 / z) - atan(0.3 / z)
        XCTAssertEqual(try RangeEstimator.paperEquation3(pitchRad: p, alphaRad: alpha, deltaRad: delta,
                                                         signHeightMeters: h0), z, accuracy: 1e-12)
    }

    // MARK: Bad input

    private func validScene() -> (SyntheticSignScene, [(u: Double, v: Double)]) {
        var s = SyntheticSignScene()
        s.rollRad = -.pi / 2
        s.pitchRad = deg(5)
        s.rangeMeters = 4
        s.centerHeightAboveCameraMeters = 0.6
        return (s, s.corners!)
    }

    private func expectError(_ expected: RangeEstimationError, _ body: () throws -> Any,
                             file: StaticString = #filePath, line: UInt = #line) {
        XCTAssertThrowsError(try body(), file: file, line: line) { error in
            XCTAssertEqual(error as? RangeEstimationError, expected, file: file, line: line)
            XCTAssertFalse("\(error)".isEmpty)
        }
    }

    func testNaNZeroHeightAndDegenerateCornersAreErrors() {
        let (s, corners) = validScene()
        let orientation = RangeEstimator.Orientation.pitchRoll(pitchRad: s.pitchRad, rollRad: s.rollRad)
        func run(_ method: RangeMethod, _ c: [(u: Double, v: Double)], height: Double = 0.21, width: Double? = 0.33,
                 cameraHeight: Double? = 1.4, signHeight: Double? = 2.0) throws -> Any {
            try RangeEstimator.estimate(method: method, corners: c, intrinsics: s.intrinsics, orientation: orientation,
                                        signHeightMeters: height, signWidthMeters: width,
                                        cameraHeightMeters: cameraHeight, signCenterHeightMeters: signHeight)
        }
        var nan = corners
        nan[1].v = .nan
        var repeated = corners
        repeated[2] = repeated[1]
        var mirrored = corners
        mirrored.swapAt(1, 3)
        for method in RangeMethod.allCases {
            expectError(.notFinite) { try run(method, nan) }
            expectError(.degenerateCorners) { try run(method, repeated) }
            expectError(.degenerateCorners) { try run(method, mirrored) }
            expectError(.wrongCornerCount(3)) { try run(method, Array(corners.prefix(3))) }
        }
        expectError(.nonpositiveSize) { try run(.apparentHeight, corners, height: 0) }
        expectError(.nonpositiveSize) { try run(.pnp, corners, height: -1) }
        expectError(.missingInput) { try run(.pnp, corners, width: nil) }
        expectError(.missingInput) { try run(.horizon, corners, cameraHeight: nil) }
        expectError(.degenerateGeometry) { try run(.horizon, corners, signHeight: 1.4) }
        expectError(.wrongMatrixCount(9)) {
            try RangeEstimator.estimate(method: .apparentHeight, corners: corners, intrinsics: s.intrinsics,
                                        orientation: .cameraToWorld(Array(repeating: 0, count: 9)), signHeightMeters: 0.21)
        }
        expectError(.notARotation) {
            try RangeEstimator.estimate(method: .apparentHeight, corners: corners, intrinsics: s.intrinsics,
                                        orientation: .cameraToWorld(Array(repeating: 0, count: 16)), signHeightMeters: 0.21)
        }
        let camera = UnrolledCamera(fx: 1602, fy: 1602, cx: 720, cy: 960, pitchRad: 0.1, rollRad: -.pi / 2)
        expectError(.nonpositiveSize) {
            try RangeEstimator.apparentHeight(SignImageMeasurement(medianBottomRowPx: 900, medianHeightPx: 0,
                                                                   centerColumnPx: 700),
                                              camera: camera, signHeightMeters: 0.21)
        }
        expectError(.notFinite) {
            try RangeEstimator.apparentHeight(SignImageMeasurement(medianBottomRowPx: .nan, medianHeightPx: 30,
                                                                   centerColumnPx: 700),
                                              camera: camera, signHeightMeters: 0.21)
        }
        expectError(.nonpositiveSize) {
            try RangeEstimator.apparentHeight(SignImageMeasurement(medianBottomRowPx: 900, medianHeightPx: 30,
                                                                   centerColumnPx: 700),
                                              camera: camera, signHeightMeters: 0)
        }
        expectError(.degenerateGeometry) {
            try RangeEstimator.paperEquation3(pitchRad: 0.1, alphaRad: 0.1, deltaRad: -0.01, signHeightMeters: 0.21)
        }
        expectError(.nonpositiveSize) { try SignImageMeasurement(columns: []) }
    }

    func testMethodNamesRoundTrip() {
        for m in RangeMethod.allCases { XCTAssertEqual(RangeMethod(commandLineName: m.commandLineName), m) }
        XCTAssertNil(RangeMethod(commandLineName: "apparentHeight"))
        XCTAssertEqual(RangeMethod.allCases.map(\.rawValue), ["apparentHeight", "horizon", "pnp"])
    }
}
