import XCTest
import SessionFormat
@testable import WayfinderCore

/// The iOS frame adapter's conversion logic.
final class FrameConversionTests: XCTestCase {
    let intrinsicsColumns: [[Float]] = [[1602, 0, 0], [0, 1602, 0], [960, 720, 1]]

    func columns(of pose: CameraPose) -> [[Float]] {
        (0..<4).map { c in (0..<4).map { r in Float(pose.element(row: r, column: c)) } }
    }

    func testTransformColumnsKeepTranslationLast() {
        let pose = CameraPose(positionInWorld: (1.5, 1.3, -4), yawRad: 0.2, pitchRad: 0.1, rollRad: -1.58)
        let converted = FrameConversion.columnMajor(columns: columns(of: pose))!
        XCTAssertEqual(converted.positionInWorld.x, 1.5, accuracy: 1e-6)
        XCTAssertEqual(converted.positionInWorld.z, -4, accuracy: 1e-6)
        XCTAssertEqual(converted.rollRad, -1.58, accuracy: 1e-5)
    }

    func testIntrinsicsFromColumnMajorMatrix() {
        let k = FrameConversion.intrinsics(columns: intrinsicsColumns, width: 1920, height: 1440)!
        XCTAssertEqual(k, CameraIntrinsics.iPhone8Full)
        XCTAssertNil(FrameConversion.intrinsics(columns: [[0, 0, 0], [0, 1602, 0], [960, 720, 1]], width: 1920, height: 1440))
        XCTAssertNil(FrameConversion.intrinsics(columns: [[.nan, 0, 0], [0, 1602, 0], [960, 720, 1]], width: 1920, height: 1440))
    }

    func testCompassAccuracyIsKeptOnlyWhenValidAndRecorded() {
        let c = columns(of: CameraPose(positionInWorld: (0, 1.3, 0), yawRad: 0, pitchRad: 0, rollRad: -1.57))
        func frame(_ accuracy: Double?) -> PipelineFrame? {
            FrameConversion.pipelineFrame(t: 1, transformColumns: c, intrinsicsColumns: intrinsicsColumns, imageWidth: 1920,
                                          imageHeight: 1440, trackingState: "normal", trackingReason: nil,
                                          relativeAltitudeMeters: nil, compassHeadingDeg: 90, compassAccuracyDeg: accuracy)
        }
        XCTAssertEqual(frame(12)?.compassAccuracyDeg, 12)
        XCTAssertNil(frame(-1)?.compassAccuracyDeg)      // Core Location's "invalid"
        XCTAssertNil(frame(.nan)?.compassAccuracyDeg)
        let recorded = FrameConversion.record(of: frame(12)!, imageName: nil)
        XCTAssertEqual(recorded?.compassAccuracyDeg, 12)  // the recorder keeps it for replay
    }

    func testNaNPoseBecomesLostTrackingNotACrash() {
        var c = columns(of: CameraPose(positionInWorld: (0, 0, 0), yawRad: 0, pitchRad: 0, rollRad: 0))
        c[3][0] = .nan
        let frame = FrameConversion.pipelineFrame(t: 1, transformColumns: c, intrinsicsColumns: intrinsicsColumns,
                                                  imageWidth: 1920, imageHeight: 1440, trackingState: "normal",
                                                  trackingReason: nil, relativeAltitudeMeters: nil, compassHeadingDeg: nil)!
        XCTAssertNil(frame.cameraPose)
        XCTAssertEqual(frame.tracking, .notAvailable)
        XCTAssertNil(FrameConversion.record(of: frame, imageName: nil), "a frame without a pose is not recorded")
    }

    func testTrackingStates() {
        XCTAssertEqual(FrameConversion.tracking(state: "limited", reason: "excessiveMotion").0, .limited)
        XCTAssertEqual(FrameConversion.tracking(state: "limited", reason: "excessiveMotion").1, .excessiveMotion)
        XCTAssertEqual(FrameConversion.tracking(state: "normal", reason: nil).0, .normal)
        XCTAssertEqual(FrameConversion.tracking(state: "bogus", reason: nil).0, .notAvailable)
        XCTAssertNil(FrameConversion.compassHeadingDeg(-1, accuracyDeg: 5))
        XCTAssertEqual(FrameConversion.compassHeadingDeg(370, accuracyDeg: 5)!, 10, accuracy: 1e-9)
    }
}
